#!/usr/bin/env bash
# Stop 41: the hybrid's trace stage on Sponza was 0.13 ms longer than the RT baseline's (whose launch
# holds the same paths; run1-3.sh). Is it the refined pixels' re-trace inside the launch
# (refine="trace", CUDA's default)? The bench as run3.sh, twice, with --refine primary (the refined
# pixels re-traced in the primary stage's kernel, the trace launch the RT baseline's). Carry
# .device, after the extras. Outputs: $OUT/s41_{6,7}_new.tar.xz.
source docs/results/gpu/issue10/stop31/env.sh
for round in 6 7; do
  R=/tmp/s41_$round; mkdir -p $R
  timeout 280 python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy --max-path-spp 1 \
    scenes/sponza_mirror.xml scenes/dining_room.xml scenes/showcase.xml $D --budgets 0.5 --refine primary \
    -o $R/bench_new > $R/bench_new.log 2>&1
  echo "round $round rc=$?"; grep -A5 "^| scene" $R/bench_new/bench.md | tail -3 | cut -d'|' -f2,6-12
  tar -cJf $OUT/s41_${round}_new.tar.xz -C /tmp s41_$round
done
