#!/usr/bin/env bash
# Stop 48's device runs, from the repository root on a warm machine, after
# `bash docs/results/gpu/issue10/stop31/extras.sh 3`, `… 1`, `… 2` (scenes, Open Image Denoise), with
# .device and .device_x4 (flip-evaluator) carried, and .w46 (the tree at 42baa48:
# `git archive 42baa48 hybrid_integrator plugins`) where a mode runs the old tree.
#   bash docs/results/gpu/issue10/stop48/run.sh profile "old new old new" SCENE   # kernels per tree, in turn
#   bash docs/results/gpu/issue10/stop48/run.sh path SCENE...                     # the hybrid's kernels and path's
#   bash docs/results/gpu/issue10/stop48/run.sh cache SCENE warm|cold...          # one tree in turn, caches kept or emptied
#   bash docs/results/gpu/issue10/stop48/run.sh spills SCENE...                   # OptiX's registers and spills (spills.py)
#   [STOP48_LOOP=…] [HYBRID_SIDES="--hybrid k=v …"] bash …/run.sh context SCENE... # path's kernel against the hybrid's trace (context.py)
#   bash docs/results/gpu/issue10/stop48/run.sh ncu SCENE...                      # Nsight Compute (crashed: exit code 11)
#   bash docs/results/gpu/issue10/stop48/run.sh readout SCENE...                  # the stage times' readout, both readers (readout.py)
#   bash docs/results/gpu/issue10/stop48/run.sh history SCENE...                  # the kernel history on/off (scripts/history_cost.py)
set -uo pipefail
python3 -m zipfile -e .device_x4/flip_evaluator-*.whl /tmp/extra
source .device/prelude.sh
ln -sfn ../plugins hybrid_integrator/plugins
[ -d .w46 ] && ln -sfn ../plugins .w46/hybrid_integrator/plugins 2>/dev/null
export PYTHONPATH=/tmp/extra:$PYTHONPATH
source scripts/gpu_scenes.sh  # $D
mode=$1; shift
case $mode in
  profile)  # the frame's kernels (hash, operations, ms) in each tree, one process per tree, in the given order
    sides=$1; scene=$2
    for side in $sides; do
      tree=$([ "$side" = old ] && echo "$PWD/.w46:" || echo "")
      echo "== $side $scene"
      PYTHONPATH=$tree$PYTHONPATH python3 scripts/frame_profile.py scenes/$scene.xml --variant cuda_ad_rgb \
        --frames 20 --kernels --top 0 $D 2>&1 | grep -v "^ *[0-9]* function calls\|^host profile\|^$"
    done ;;
  path)  # the hybrid's kernels beside path's at 1 spp, this tree
    for scene in "$@"; do
      echo "== $scene"
      python3 scripts/frame_profile.py scenes/$scene.xml --variant cuda_ad_rgb --frames 20 --kernels --path --top 0 $D 2>&1 \
        | grep -v "^ *[0-9]* function calls\|^host profile\|^$"
    done ;;
esac
case $mode in
  cache)  # the same tree in turn, with the kernel caches as they are ("warm") or emptied first ("cold")
    scene=$1; shift
    for c in "$@"; do
      [ "$c" = cold ] && rm -rf ~/.drjit ~/.cache/nvidia/OptixCache /var/tmp/OptixCache_$(whoami)
      echo "== $c $scene"
      python3 scripts/frame_profile.py scenes/$scene.xml --variant cuda_ad_rgb --frames 20 --kernels --top 0 $D 2>&1 \
        | grep "DISKCACHE\|median ms\|^trace .*JIT\|^trace  *[0-9a-f]\{8\}  JIT"
    done ;;
esac
case $mode in
  spills)  # registers and spills of path's and the hybrid's megakernels, compiled afresh, per scene
    for scene in "$@"; do
      rm -rf ~/.drjit ~/.cache/nvidia/OptixCache /var/tmp/OptixCache_$(whoami)
      python3 docs/results/gpu/issue10/stop48/spills.py scenes/$scene.xml $D 2> /tmp/spills_$scene.log
      grep -A6 "^===\|Function properties for __raygen" /tmp/spills_$scene.log | grep "===\|raygen\|register count\|spills\|stack size\|Error"
    done ;;
esac
case $mode in
  context)  # path's kernel before and after the hybrid's sides (HYBRID=(--hybrid k=v …)), in one process, per scene
    HYBRID=(${HYBRID_SIDES:-})
    for scene in "$@"; do
      python3 docs/results/gpu/issue10/stop48/context.py scenes/$scene.xml "${HYBRID[@]}" $D 2>/dev/null
    done ;;
esac
case $mode in
  ncu)  # Nsight Compute on the OptiX launches of path's frame and two hybrid frames (ncu_probe.py), per scene
    for scene in "$@"; do
      ncu -k regex:raygen --launch-count 6 --section LaunchStats --section Occupancy --section SpeedOfLight \
        --section WarpStateStats --section MemoryWorkloadAnalysis --section SchedulerStats \
        python3 docs/results/gpu/issue10/stop48/ncu_probe.py scenes/$scene.xml $D 2>&1 | grep -v "^jit_\|^\s*$" > $OUT/ncu_$scene.txt
      tail -3 $OUT/ncu_$scene.txt
    done ;;
esac
case $mode in
  readout)  # the stage times' readout through drjit.kernel_history and through the C API, per scene
    for scene in "$@"; do
      python3 docs/results/gpu/issue10/stop48/readout.py scenes/$scene.xml --variant cuda_ad_rgb $D 2>/dev/null
    done ;;
esac
case $mode in
  history)  # what the kernel history still costs a frame (scripts/history_cost.py: on / off in turn), no denoiser
    python3 scripts/history_cost.py --variant cuda_ad_rgb --no-denoise $(for s in "$@"; do echo scenes/$s.xml; done) $D 2>/dev/null ;;
esac
