#!/usr/bin/env bash
# Stop 36's second GPU run, on dae1518: the first version of scripts/interop_probe.py (not kept; the
# second is at 74aab01) on the showcase and Sponza.
# Carry .device and .device_s (the two scenes' files: sponza-dabrovic and cbox from ../shared/scenes).
source .device/prelude.sh
ln -sfn ../plugins hybrid_integrator/plugins
mkdir -p /tmp/scn && tar -xJf .device_s/scn.tar.xz -C /tmp/scn
D="-D resx=1280 -D resy=720 -D sponza_dir=/tmp/scn/sponza-dabrovic -D showcase_dir=/tmp/scn/cbox"
python3 scripts/interop_probe.py --variant cuda_ad_rgb --repeats 40 scenes/showcase.xml scenes/sponza_mirror.xml $D 2>&1 | tee $OUT/interop.txt
