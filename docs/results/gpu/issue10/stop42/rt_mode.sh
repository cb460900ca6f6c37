#!/usr/bin/env bash
# Stop 42: rt_mode.py on the showcase, four processes per mode, the modes in turn; $1 = denoise:
# the frames denoised. After stop31/extras.sh 3 (and 1, 2 with denoise) on the same warm machine;
# carry .device. Output: $OUT/rt_mode${1:+_$1}.txt.
source docs/results/gpu/issue10/stop31/env.sh
for round in 1 2 3 4; do
  for mode in alone hybrid; do
    timeout 60 python3 docs/results/gpu/issue10/stop42/rt_mode.py scenes/showcase.xml $mode ${1:-} ${D//-D /} 2>&1 | grep "RT trace"
  done
done | tee $OUT/rt_mode${1:+_$1}.txt
