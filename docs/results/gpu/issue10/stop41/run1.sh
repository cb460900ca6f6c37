#!/usr/bin/env bash
# Stop 41, after stop31/extras.sh 3, 1 and 2 on the same warm machine (carry .device): the timing
# bench on this stop's main (ec27cdb, stop 40's review commit, which stop 40 did not measure), five
# scenes, then the showcase at the max_depth its file declares (12) and at 8, against the bench's
# unlimited depth (-1, the integrator's and `path`'s default): how much of the showcase's frame is its
# longest glass path. Outputs: $OUT/s41_1_new.tar.xz, $OUT/depth.tar.xz.
STOP=41 bash docs/results/gpu/issue10/stop34/bench.sh new 1
source docs/results/gpu/issue10/stop31/env.sh
R=/tmp/depth; mkdir -p $R
for depth in 12 8; do
  timeout 200 python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy --max-path-spp 1 \
    scenes/showcase.xml $D --budgets 0.5 --max-depth $depth -o $R/showcase_d$depth > $R/showcase_d$depth.log 2>&1
  echo "max_depth $depth rc=$?"; grep -A3 "^| scene" $R/showcase_d$depth/bench.md | tail -2 | cut -d'|' -f2,6-12
done
tar -cJf $OUT/depth.tar.xz -C /tmp depth
