#!/usr/bin/env bash
# Stop 50's device runs, from the repository root on a warm machine, after
# `bash docs/results/gpu/issue10/stop31/extras.sh 3`, `… 1`, `… 2` (scenes, Open Image Denoise),
# with .device carried.
#   bash docs/results/gpu/issue10/stop50/run.sh cost SCENE...    # each kind of frame with the stage times on / off
#     in turn, then path at 1 spp frozen and path + OIDN 'fast' (scripts/history_cost.py, 30 frames each)
#   bash docs/results/gpu/issue10/stop50/run.sh rivals SCENE...  # the default frame against path 1 spp (frozen) and
#     path + OIDN 'fast', frame by frame in turn (probes.py rivals, 30 rounds)
#   bash docs/results/gpu/issue10/stop50/run.sh inflight SCENE...  # frames in flight without / with the kernel
#     history they never read, in turn (probes.py inflight, 40 frames per side)
#   bash docs/results/gpu/issue10/stop50/run.sh bench SCENE...   # the timing bench, hybrid frames timed without
#     the kernel history (hybrid bench --frames 20 --no-accuracy --max-path-spp 1 --budgets 0.25 0.5 0.75)
set -uo pipefail
source .device/prelude.sh
ln -sfn ../plugins hybrid_integrator/plugins
export PYTHONPATH=/tmp/extra:$PYTHONPATH
source scripts/gpu_scenes.sh  # $D
mode=$1; shift
case $mode in
  cost) python3 scripts/history_cost.py --variant cuda_ad_rgb --frames 30 \
          $(for s in "$@"; do echo scenes/$s.xml; done) $D 2>&1 | grep -v "^jit_\|^Info\|^\s*$" ;;
  rivals) python3 docs/results/gpu/issue10/stop50/probes.py rivals --variant cuda_ad_rgb \
            $(for s in "$@"; do echo scenes/$s.xml; done) $D 2>&1 | grep -v "^jit_\|^Info\|^\s" ;;
  inflight) python3 docs/results/gpu/issue10/stop50/probes.py inflight --variant cuda_ad_rgb \
              $(for s in "$@"; do echo scenes/$s.xml; done) $D 2>&1 | grep -v "^jit_\|^Info\|^\s" ;;
  bench) for s in "$@"; do
           python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy --max-path-spp 1 \
             --budgets 0.25 0.5 0.75 $D scenes/$s.xml -o $OUT/bench${RUN:-}/$s > $OUT/$s${RUN:-}.log 2>&1; echo "$s rc=$?"
         done ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
