#!/usr/bin/env bash
# Stop 32's owed GPU run, prepared and NOT yet run (stop 32 was lent no device): the raster's
# refined pixels traced in the trace stage's launch (refine="trace") against the primary stage's
# kernel (refine="primary", the default) and the RT baseline. One H200, cuda_ad_rgb, 1280x720.
# A device run is three calls on one warm machine: stop31/extras.sh 1 (carry .device_x1),
# stop31/extras.sh 2 (carry .device_x2), then this script (carry .device); see stop31/README.md.
source docs/results/gpu/issue10/stop31/env.sh
R=/tmp/r; mkdir -p $R
# 1. one process per scene set, the three integrators in turn: frame, paired ratios, stage times
python3 scripts/refine_ab.py --variant cuda_ad_rgb --repeats 21 $S $D | tee $R/refine_ab_1.md
# 2. the timing bench with refine="trace" (its paired Gain against the bench rounds of stop 31)
python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy --max-path-spp 1 $S \
  --budgets 0.5 --refine trace $D -o $R/bench_trace > $R/bench_trace.log 2>&1
grep -A7 "^| scene" $R/bench_trace/bench.md | tail -5 | cut -d'|' -f2,6-12
# 3. the first measurement again, after the bench (the lent hosts' speed drifts within a run)
python3 scripts/refine_ab.py --variant cuda_ad_rgb --repeats 21 $S $D | tee $R/refine_ab_2.md
tar -cJf $OUT/r.tar.xz -C /tmp r
