#!/usr/bin/env bash
# Stop 36's first GPU run: where the all-candidates hybrid's frame loses to its RT baseline.
# After stop31/extras.sh 1 and 2 on the same warm machine; carry .device. Outputs under $OUT.
#  - scripts/gain_anatomy.py: rt / hybrid / no-interop / no-raster in turn, 21 rounds, each scene
#    in its own process;
#  - scripts/raster_compute_probe.py: the compute pass's stages (GL timer queries) on Sponza and
#    the dining room;
#  - scripts/frame_timeline.py: host and GPU timeline of the showcase's and Sponza's frames.
source docs/results/gpu/issue10/stop31/env.sh
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
python3 scripts/gain_anatomy.py --variant cuda_ad_rgb --repeats 21 $S $D 2>&1 | tee $OUT/anatomy.md
python3 scripts/raster_compute_probe.py --variant cuda_ad_rgb --repeats 20 scenes/sponza_mirror.xml scenes/dining_room.xml $D 2>&1 | grep -v "^$" | tee $OUT/raster_stages.txt
python3 scripts/frame_timeline.py --frames 20 scenes/showcase.xml scenes/sponza_mirror.xml $D 2>&1 | tee $OUT/timeline.txt
