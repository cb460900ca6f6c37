#!/usr/bin/env bash
# Stop 41: scripts/frame_timeline.py on Sponza and the showcase, twice, on main: where the hybrid's
# frame spends the time outside its stages that the RT baseline's does not (summary.py's "rest").
# After stop31/extras.sh 3 (and 1, 2: the default frame denoises) on the same warm machine; carry
# .device. Outputs: $OUT/timeline/{scene}_{round}.txt.
source docs/results/gpu/issue10/stop31/env.sh
mkdir -p $OUT/timeline
for round in 1 2; do
  for scene in sponza_mirror showcase; do
    timeout 200 python3 scripts/frame_timeline.py --variant cuda_ad_rgb --frames 20 $D scenes/$scene.xml \
      > $OUT/timeline/${scene}_$round.txt 2>&1
    echo "$scene $round rc=$?"
    grep -E "^(frame time|showcase|sponza|host ms)" $OUT/timeline/${scene}_$round.txt | grep -v "^jit"
  done
done
