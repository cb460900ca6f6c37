#!/usr/bin/env bash
# Stop 35's GPU run, part 6: item 4 on the final code (88e1fb7; ties): budget_benchmark.py with the
# default selection's rows (nested at 25 / 50 / 75 %) on the 226 objects' camera path, 50 frames.
# After stop31/extras.sh 1 and 2 on the same warm machine; carry .device.
source docs/results/gpu/issue10/stop31/env.sh
R=/tmp/g35; mkdir -p $R; T0=$SECONDS
timeout 330 python3 scripts/budget_benchmark.py --variant cuda_ad_rgb --frames 50 --resx 1280 --resy 720 --importance 0.01 -o $R/budget > $R/budget.log 2>&1
echo "budget rc=$? after $((SECONDS - T0)) s"; grep "^|" $R/budget.md | sed -n '3,11p'
tar -cJf $OUT/g35.tar.xz -C /tmp g35
