#!/usr/bin/env bash
# Stop 42: where the hybrid's longer host issue goes (bench "issue": 1.23-1.73 ms against the RT
# baseline's 0.98-1.46): scripts/host_phases.py on a still camera, default frames (--budget 0),
# the raster's primaries and the RT baseline's camera rays, Sponza and the showcase. After
# stop31/extras.sh 3, 1 and 2 on the same warm machine; carry .device. Outputs: $OUT/host/*.txt.
source docs/results/gpu/issue10/stop31/env.sh
mkdir -p $OUT/host
for scene in sponza_mirror showcase; do
  for primary in raster raytrace; do
    timeout 200 python3 scripts/host_phases.py --variant cuda_ad_rgb --resx 1280 --resy 720 --frames 30 --budget 0 \
      --primary $primary --still scenes/$scene.xml $D > $OUT/host/${scene}_$primary.txt 2>&1
    echo "$scene $primary rc=$?"; grep -v "^jit\|^\s*$" $OUT/host/${scene}_$primary.txt | grep -E "budget_ms|host_ms|_device|_visibility|copy|release|_frame |_select|_post|_account|device_array|develop" | head -14
  done
done
