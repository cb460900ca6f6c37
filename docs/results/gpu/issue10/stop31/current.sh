#!/usr/bin/env bash
# Stop 31, first GPU run: the code of stop 30 (frozen.FrozenScene) on one H200, cuda_ad_rgb,
# 1280x720. The timing bench of the five scenes, the trace call, the budgets, host phases.
# Needs extras.sh run first on the same machine. Outputs under $OUT.
source docs/results/gpu/issue10/stop31/env.sh
hybrid() { python3 -m hybrid_integrator.cli "$@"; }
hybrid bench --variant cuda_ad_rgb --frames 20 --no-accuracy --max-path-spp 1 $S --budgets $D -o $OUT/bench > $OUT/bench.log 2>&1
tail -3 $OUT/bench.log; grep -A8 "^| scene" $OUT/bench/bench.md | head -8
python3 scripts/trace_overhead.py --variant cuda_ad_rgb --resx 1280 --resy 720 --repeats 21 -o $OUT/trace_overhead > $OUT/trace.log 2>&1
tail -25 $OUT/trace.log
python3 scripts/budget_benchmark.py --variant cuda_ad_rgb --frames 50 --resx 1280 --resy 720 --importance 0.01 -o $OUT/budget > $OUT/budget.log 2>&1
tail -3 $OUT/budget.log; grep "^|" $OUT/budget.md | head -14
for p in raster raytrace; do
  python3 scripts/host_phases.py --variant cuda_ad_rgb --resx 1280 --resy 720 --frames 40 --budget 0 --primary $p --still scenes/armadillo_glass.xml $D
done > $OUT/host_phases.txt 2>&1
grep -E "^budget|host_ms|^==" $OUT/host_phases.txt
