#!/usr/bin/env bash
# Stop 49's device runs, from the repository root on a warm machine, after
# `bash docs/results/gpu/issue10/stop31/extras.sh 3`, `… 1`, `… 2` (scenes, Open Image Denoise), with
# .device and .device_x4 (flip-evaluator) carried; where the tracked tree and both pass 64 MiB, the
# flip-evaluator wheel goes into .device_x2 instead (extras.sh 2 unpacks every wheel there), as for
# `rivals` in this stop.
#   bash docs/results/gpu/issue10/stop49/run.sh accuracy SCENE...   # the time–FLIP plane, path's curve frozen
#     (scripts/gpu_issue11.sh: hybrid bench --frames 20 --gt-spp 1024 --max-path-spp 16, one process per scene)
#   bash docs/results/gpu/issue10/stop49/run.sh rivals SCENE...     # path + OIDN 'fast' at each history's total time
#     (history_rivals.py, on the spp in outputs/SCENE/bench.json)
#   bash docs/results/gpu/issue10/stop49/run.sh host SCENE...       # host time by phase and function: all candidates,
#     then 25 % of the bench's all-candidates trace time (scripts/host_phases.py --still, 40 frames)
set -uo pipefail
[ -d .device_x4 ] && python3 -m zipfile -e .device_x4/flip_evaluator-*.whl /tmp/extra
source .device/prelude.sh
ln -sfn ../plugins hybrid_integrator/plugins
export PYTHONPATH=/tmp/extra:$PYTHONPATH
mode=$1; shift
case $mode in
  accuracy) MAX_PATH_SPP=16 bash scripts/gpu_issue11.sh "$@" ;;
  rivals) source scripts/gpu_scenes.sh  # $D
          python3 docs/results/gpu/issue10/stop49/history_rivals.py --variant cuda_ad_rgb \
            $(for s in "$@"; do echo scenes/$s.xml; done) $D 2>&1 | grep -v "^jit_\|^Info\|^\s" ;;
  host) source scripts/gpu_scenes.sh  # $D
        for s in "$@"; do
          b=$(python3 -c "import json; print(round(0.25 * json.load(open('docs/results/gpu/issue10/stop49/outputs/$s/bench.json'))[0]['all_candidates_trace_ms'], 3))")
          echo "== $s budget $b ms"
          python3 scripts/host_phases.py --variant cuda_ad_rgb --resx 1280 --resy 720 --frames 40 --budget $b \
            --still scenes/$s.xml $D 2>&1 | grep -v "^jit_\|^Info\|^\s*$"
        done ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
