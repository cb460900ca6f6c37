#!/usr/bin/env bash
# The GPU measurements of issue 11 (docs/results/README.md): the time–FLIP plane of every bench
# scene (hybrid budgets, spp, denoiser, history; path and path + denoiser), 1280×720, 20 frames.
# On the device machine, from the repository root, with the bundle (../shared/tools/device-bundle.sh),
# the shared scenes as .device/scenes.tar.xz, and pyoidn (trimmed to its CPU and CUDA devices)
# unpacked in /tmp/oidn_site:
#   source .device/prelude.sh; ln -sfn ../plugins hybrid_integrator/plugins; bash scripts/gpu_issue11.sh SCENE...
# $MAX_PATH_SPP (default 64) ends path's curve sooner, for the device time.
R=$OUT/r; mkdir -p $R
source scripts/gpu_scenes.sh  # $S, $D, pyoidn
# one bench per scene, each packed as it ends: a scene takes 100-300 s on an H100, and a device
# command ends at 600 s, so a killed run still returns the scenes it finished
for s in "$@"; do
  python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --gt-spp 1024 --max-path-spp ${MAX_PATH_SPP:-64} $D \
    scenes/$s.xml -o $R/$s > $R/$s.log 2>&1; echo "$s rc=$?"
  tar -czf $OUT/results.tgz -C $OUT r
done
rm -rf $R
