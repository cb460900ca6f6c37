#!/usr/bin/env bash
# Stop 34's GPU run, part 2 (stop 33's owed run, on this stop's code): budget_benchmark.py with the
# default selection's rows (nested at 25 / 50 / 75 %) and item 3's trace_overhead.py. Same machine
# and set-up as bench.sh; carry .device.
source docs/results/gpu/issue10/stop31/env.sh
R=/tmp/o34; mkdir -p $R; T0=$SECONDS
timeout 400 python3 scripts/budget_benchmark.py --variant cuda_ad_rgb --frames 50 --resx 1280 --resy 720 --importance 0.01 -o $R/budget > $R/budget.log 2>&1
echo "budget rc=$? after $((SECONDS - T0)) s"; grep "^|" $R/budget.md | sed -n '3,11p'
tar -cJf $OUT/o34.tar.xz -C /tmp o34
timeout $((570 - SECONDS + T0)) python3 scripts/trace_overhead.py --variant cuda_ad_rgb --resx 1280 --resy 720 --repeats 21 -o $R/trace_overhead > $R/trace.log 2>&1
echo "trace rc=$? after $((SECONDS - T0)) s"; tail -12 $R/trace.log
tar -cJf $OUT/o34.tar.xz -C /tmp o34
