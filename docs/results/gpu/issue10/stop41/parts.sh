#!/usr/bin/env bash
# Stop 41: the raster's kernel on the GPU in parts (scripts/primary_stage.py --parts), the five bench
# scenes at 1280×720, against the camera rays'. After stop31/extras.sh 3 on the same warm machine;
# carry .device. Output: $OUT/parts.txt.
source docs/results/gpu/issue10/stop31/env.sh
timeout 560 python3 scripts/primary_stage.py --variant cuda_ad_rgb --parts --repeats 21 $S $D -o $OUT/parts.txt > /tmp/parts.log 2>&1
echo "rc=$?"; grep -v "^\s*$" /tmp/parts.log | grep -v "jit_optix_log\|^\s" | tail -5; cat $OUT/parts.txt
