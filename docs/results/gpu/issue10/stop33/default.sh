#!/usr/bin/env bash
# Stop 33's GPU run, part 2: the code as committed, refine="auto" (the trace stage's launch on CUDA)
# by default: the timing bench with its budget rows (items 1, 2, 4, 5) and the budgets on the camera
# path through the 226 objects (item 4). Same machine and set-up as refine.sh.
source docs/results/gpu/issue10/stop31/env.sh
R=/tmp/d33; mkdir -p $R
python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy --max-path-spp 1 $S $D \
  -o $R/bench > $R/bench.log 2>&1
grep -A7 "^| scene" $R/bench/bench.md | tail -5 | cut -d'|' -f2,6-12
python3 scripts/budget_benchmark.py --variant cuda_ad_rgb --frames 50 --resx 1280 --resy 720 --importance 0.01 -o $R/budget > $R/budget.log 2>&1
grep "^|" $R/budget.md | sed -n '3,7p'
tar -cJf $OUT/d33.tar.xz -C /tmp d33
