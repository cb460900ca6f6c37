#!/usr/bin/env bash
# The GPU measurements of issues 12 and 13 (docs/results/README.md), on a machine with two GPUs
# (nvidia-h200-x2), from the repository root, with the bundle (../shared/tools/device-bundle.sh),
# the shared scenes as .device/scenes.tar.xz, pyoidn unpacked in /tmp/oidn_site and Ray (with its
# needs, for Python 3.12) unpacked in /tmp/ray_site:
#   source .device/prelude.sh; ln -sfn ../plugins hybrid_integrator/plugins; bash scripts/gpu_issue12_13.sh WHAT
# WHAT: throughput (a 60-frame Sponza camera path on 1 GPU in one process, then on 2 Ray workers,
# one GPU each), soak (10 000 frames in one process, and one 8192×8192 frame) or bench (the issue-11
# bench of the four scenes, two on each GPU at once).
R=$OUT/r; mkdir -p $R
source scripts/gpu_scenes.sh  # $S, $D, pyoidn
export PYTHONPATH=/tmp/ray_site:$PYTHONPATH RAY_AUTH_MODE=disabled
case "$1" in
throughput)
  python3 scripts/sequence_throughput.py scenes/sponza_mirror.xml --variant cuda_ad_rgb --gpus-per-worker 1 \
    --frames 60 --workers 1 2 -D sponza_dir=$S/sponza-dabrovic -o $R/issue13 2>&1 | grep -v '^frames' ;;
soak)
  python3 scripts/memory_soak.py scenes/showcase.xml -D showcase_dir=$S/cbox --variant cuda_ad_rgb \
    --frames 10000 --large 8192 -o $R/issue12 2>&1 | tr '\r' '\n' | grep -v '^frames' ;;
bench)
  for pair in "0 armadillo_glass showcase" "1 sponza_mirror dining_room"; do
    set -- $pair
    CUDA_VISIBLE_DEVICES=$1 python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --gt-spp 1024 \
      --max-path-spp 64 $D scenes/$2.xml scenes/$3.xml -o $R/bench$1 > $R/bench$1.log 2>&1 &
  done
  wait; echo "bench done" ;;
esac
tar -czf $OUT/results.tgz -C $OUT r && rm -rf $R
