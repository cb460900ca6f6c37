#!/usr/bin/env bash
# Owed by stop 33 (prepared, NOT yet run: its device time ran out): budget_benchmark.py with the
# default selection's rows (nested at 25 / 50 / 75 %; does nested trace something in >= 90 % of the
# camera path's frames at 25 %?), and item 3's trace_overhead.py on the current code. After
# stop31/extras.sh 1 and 2 on the same warm machine; carry .device.
source docs/results/gpu/issue10/stop31/env.sh
R=/tmp/o33; mkdir -p $R
python3 scripts/budget_benchmark.py --variant cuda_ad_rgb --frames 50 --resx 1280 --resy 720 --importance 0.01 -o $R/budget > $R/budget.log 2>&1
grep "^|" $R/budget.md | sed -n '3,11p'
python3 scripts/trace_overhead.py --variant cuda_ad_rgb --resx 1280 --resy 720 --repeats 21 -o $R/trace_overhead > $R/trace.log 2>&1
tail -12 $R/trace.log
tar -cJf $OUT/o33.tar.xz -C /tmp o33
