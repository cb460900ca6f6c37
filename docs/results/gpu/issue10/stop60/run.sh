#!/usr/bin/env bash
# Stop 60's device runs, from the repository root on a warm machine, after
# `bash docs/results/gpu/issue10/stop31/extras.sh 3`, `… 1`, `… 2` (scenes, Open Image Denoise),
# with .device carried (made by `bash docs/results/gpu/issue10/stop45/carries.sh`).
#   bash docs/results/gpu/issue10/stop60/run.sh launch                 # launch_cost.py: a frozen replay's host time per launch
#   bash docs/results/gpu/issue10/stop60/run.sh ahead [SCENE...] [--budgets B...]  # ahead_ab.py: timed / sampled budgets,
#     with and without the raster pass drawn ahead, in turn (default: the Armadillo at 25 and 50 %)
#   bash docs/results/gpu/issue10/stop60/run.sh replay [SCENE...]     # replay_parts.py: the device pass's replay split by input
#   bash docs/results/gpu/issue10/stop60/run.sh plan [SCENE...] [--budgets B...]  # with diffs/plan_ahead_always.diff applied:
#     plan_ahead still / always along the camera path, in turn with the RT baseline: time, relevance, image error
#     (default: the 226 objects; these runs were made by turn_error.py's first version, plan_ahead_ab.py at dbe3b34)
#   bash docs/results/gpu/issue10/stop60/run.sh error [SCENE...] [--budgets B...]  # turn_error.py: the ambient table's
#     fallback before (mean) and now (median, >= 0), in turn with the RT baseline: time, relevance, image error
source docs/results/gpu/issue10/stop31/env.sh
mkdir -p $OUT; T0=$SECONDS
mode=$1; shift
case $mode in
  launch) timeout 120 python3 docs/results/gpu/issue10/stop60/launch_cost.py --variant cuda_ad_rgb 2>&1 \
            | grep -v -P "^(jit_optix|\t|Info|\s*$)" | tee $OUT/launch_cost${RUN:-}.txt ;;
  ahead) [ $# -gt 0 ] && [ "${1#--}" = "$1" ] || set -- scenes/armadillo_glass.xml "$@"
         timeout $((590 - SECONDS + T0)) python3 docs/results/gpu/issue10/stop60/ahead_ab.py "$@" --variant cuda_ad_rgb $D \
           --frames ${FRAMES:-40} 2>&1 | grep -v -P "^(jit_optix|\t|Info|\s*$)" | tee $OUT/ahead${RUN:-}.txt ;;
  replay) timeout 300 python3 docs/results/gpu/issue10/stop60/replay_parts.py ${*:-scenes/many_objects.xml scenes/showcase.xml} \
            --variant cuda_ad_rgb $D 2>&1 | grep -v -P "^(jit_optix|\t|Info|\s*$)" | tee $OUT/replay${RUN:-}.txt ;;
  plan) [ $# -gt 0 ] && [ "${1#--}" = "$1" ] || set -- scenes/many_objects.xml "$@"
        timeout $((590 - SECONDS + T0)) python3 docs/results/gpu/issue10/stop60/turn_error.py "$@" --variant cuda_ad_rgb $D \
          --frames ${FRAMES:-40} --side 'rt={"primary": "raytrace", "stage_times": false}' \
          --side 'still={"budget": true, "stage_times": false}' \
          --side 'always={"budget": true, "stage_times": false, "plan_ahead": "always"}' 2>&1 \
          | grep -v -P "^(jit_optix|\t|Info|\s*$)" | tee $OUT/plan${RUN:-}.txt ;;
  error) [ $# -gt 0 ] && [ "${1#--}" = "$1" ] || set -- scenes/many_objects.xml "$@"
         timeout ${LIMIT:-$((590 - SECONDS + T0))} python3 docs/results/gpu/issue10/stop60/turn_error.py "$@" --variant cuda_ad_rgb $D \
           --frames ${FRAMES:-40} 2>&1 | grep -v -P "^(jit_optix|\t|Info|\s*$)" | tee $OUT/error${RUN:-}.txt ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
