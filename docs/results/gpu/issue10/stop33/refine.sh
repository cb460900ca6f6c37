#!/usr/bin/env bash
# Stop 33's GPU run: refine="trace" with the refined pixels' lighting made after the trace launch
# (the launch keeps only their preliminary intersections) against refine="primary" and the RT
# baseline. scripts/refine_ab.py once per scene, each in its own process (stop 32's one process for
# five scenes slowed the later scenes' frames for all three integrators alike: dining_room's RT
# frame read 20.6 ms there against 16.7-17.5 in the bench's own process per scene), then the timing
# bench (its own process per scene) with each refine. One H200, cuda_ad_rgb, 1280x720; after
# stop31/extras.sh 1 and 2 on the same warm machine (carry .device here).
source docs/results/gpu/issue10/stop31/env.sh
R=/tmp/s33; mkdir -p $R
for s in $S; do
  python3 scripts/refine_ab.py --variant cuda_ad_rgb --repeats 21 $s $D | tee -a $R/refine_ab.md
done
for rf in primary trace; do
  python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy --max-path-spp 1 $S \
    --budgets 0.5 --refine $rf $D -o $R/bench_$rf > $R/bench_$rf.log 2>&1
  echo "$rf"; grep -A7 "^| scene" $R/bench_$rf/bench.md | tail -5 | cut -d'|' -f2,6-12
done
tar -cJf $OUT/s33.tar.xz -C /tmp s33
