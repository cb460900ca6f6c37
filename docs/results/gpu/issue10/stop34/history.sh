#!/usr/bin/env bash
# Stop 34's GPU run, part 5: what the kernel history costs a frame (scripts/history_cost.py), the
# denoiser off. After stop31/extras.sh 1 (the bench scenes' files) on the same warm machine; carry .device.
source docs/results/gpu/issue10/stop31/env.sh
mkdir -p $OUT/hist
for round in 1 2; do
  timeout 250 python3 scripts/history_cost.py --variant cuda_ad_rgb scenes/many_objects.xml scenes/sponza_mirror.xml \
    scenes/armadillo_glass.xml $D --frames 30 --no-denoise > $OUT/hist/history_$round.txt 2>&1
  tail -10 $OUT/hist/history_$round.txt
done
