#!/usr/bin/env bash
# Stop 32's owed GPU run, part 2 of 2 (run in stop 33: outputs in out/, budget.* and bench_trace_1/):
# item 4's budgets with the learnt prior rays per pixel (heuristic.typical_rays) and the pixels' growth (heuristic.pixel_growth),
# with the rays against the plan that budget_benchmark.py now reports; then the timing bench with
# refine="trace" (paired Gain, 50 % budget rows). Same machine and set-up as refine.sh. For an A/B
# against 4ec6947 put its checkout first on PYTHONPATH (the editable install imports this one).
source docs/results/gpu/issue10/stop31/env.sh
R=/tmp/b; mkdir -p $R
python3 scripts/budget_benchmark.py --variant cuda_ad_rgb --frames 50 --resx 1280 --resy 720 --importance 0.01 -o $R/budget > $R/budget.log 2>&1
grep "^|" $R/budget.md | sed -n '3,7p'
python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy --max-path-spp 1 $S \
  --budgets 0.5 --refine trace $D -o $R/bench_trace > $R/bench_trace.log 2>&1
grep -A7 "^| scene" $R/bench_trace/bench.md | tail -5 | cut -d'|' -f2,6-12
tar -cJf $OUT/b.tar.xz -C /tmp b
