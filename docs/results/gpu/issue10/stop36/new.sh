#!/usr/bin/env bash
# Stop 36's GPU run A, on "A0" (README.md: 74aab01's storage-buffer target and GPU-side wait, the
# frame not yet reordered; scripts/interop_probe.py as at 74aab01): the interop probe on the
# showcase and Sponza, then scripts/gain_anatomy.py on the five scenes (rt / hybrid / no-interop /
# no-raster in turn).
# After stop31/extras.sh 1 and 2 on the same warm machine; carry .device.
source docs/results/gpu/issue10/stop31/env.sh
T0=$SECONDS
timeout 120 python3 scripts/interop_probe.py --variant cuda_ad_rgb --repeats 40 scenes/showcase.xml scenes/sponza_mirror.xml $D 2>&1 | tee $OUT/interop.txt
echo "probe after $((SECONDS - T0)) s"
timeout 420 python3 scripts/gain_anatomy.py --variant cuda_ad_rgb --repeats 21 $S $D 2>&1 | tee $OUT/anatomy.md
echo "anatomy after $((SECONDS - T0)) s"
