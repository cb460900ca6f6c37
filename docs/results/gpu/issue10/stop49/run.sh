#!/usr/bin/env bash
# Stop 49's device runs, from the repository root on a warm machine, after
# `bash docs/results/gpu/issue10/stop31/extras.sh 3`, `… 1`, `… 2` (scenes, Open Image Denoise), with
# .device and .device_x4 (flip-evaluator) carried.
#   bash docs/results/gpu/issue10/stop49/run.sh accuracy SCENE...   # the time–FLIP plane, path's curve frozen
#     (scripts/gpu_issue11.sh: hybrid bench --frames 20 --gt-spp 1024 --max-path-spp 16, one process per scene)
#   bash docs/results/gpu/issue10/stop49/run.sh rivals SCENE...     # path + OIDN 'fast' at each history's total time
#     (history_rivals.py, on the spp in outputs/SCENE/bench.json)
set -uo pipefail
python3 -m zipfile -e .device_x4/flip_evaluator-*.whl /tmp/extra
source .device/prelude.sh
ln -sfn ../plugins hybrid_integrator/plugins
export PYTHONPATH=/tmp/extra:$PYTHONPATH
mode=$1; shift
case $mode in
  accuracy) MAX_PATH_SPP=16 bash scripts/gpu_issue11.sh "$@" ;;
  rivals) source scripts/gpu_scenes.sh  # $D
          python3 docs/results/gpu/issue10/stop49/history_rivals.py --variant cuda_ad_rgb \
            $(for s in "$@"; do echo scenes/$s.xml; done) $D 2>&1 | grep -v "^jit_\|^\s" ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
