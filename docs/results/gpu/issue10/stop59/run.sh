#!/usr/bin/env bash
# Stop 59's device runs, from the repository root on a warm machine, after
# `bash docs/results/gpu/issue10/stop31/extras.sh 3`, `… 1`, `… 2` (scenes, Open Image Denoise),
# with .device carried (made by `bash docs/results/gpu/issue10/stop45/carries.sh`).
#   N=2 bash docs/results/gpu/issue10/stop59/run.sh ab [SCENE...] [--budgets B...]  # plan_ab.py N times: a moving
#     camera's next plan from its raster coverage against from its counts, in turn with the RT baseline
#     (default scene: the 226 objects, whose camera path item 4 is measured on)
#   bash docs/results/gpu/issue10/stop59/run.sh timeline             # frame_timeline.py at 50 and 25 %: the 226 objects, the showcase
#   bash docs/results/gpu/issue10/stop59/run.sh history [SCENE...]   # history_cost.py: DR and all-candidates frames,
#     stage times on and off, in turn
#   N=2 bash docs/results/gpu/issue10/stop59/run.sh untimed          # untimed_budget.py: a budget timing every frame
#     against every 4th, in turn with the RT baseline, along the 226 objects' path
#   bash docs/results/gpu/issue10/stop59/run.sh benchab [SCENE...]   # hybrid bench per scene, its budget rows timed on
#     every frame (--timing-interval 1: before) then as shipped (after), one process each
source docs/results/gpu/issue10/stop31/env.sh
mkdir -p $OUT; T0=$SECONDS
mode=$1; shift
case $mode in
  ab) [ $# -gt 0 ] && [ "${1#--}" = "$1" ] || set -- scenes/many_objects.xml "$@"
      for k in $(seq ${N:-1}); do
        timeout $((590 - SECONDS + T0)) python3 docs/results/gpu/issue10/stop59/plan_ab.py "$@" --variant cuda_ad_rgb $D \
          --frames ${FRAMES:-40} 2>&1 | grep -v -P "^(jit_optix|\t|Info|\s*$)" | tee $OUT/ab${RUN:-}_$k.txt
        echo "rc=${PIPESTATUS[0]} after $((SECONDS - T0)) s"
      done ;;
  timeline) for b in 0.5 0.25; do  # scripts/frame_timeline.py: where a budgeted frame's GPU waits for its host
              timeout 250 python3 scripts/frame_timeline.py scenes/many_objects.xml scenes/showcase.xml --variant cuda_ad_rgb \
                $D --frames 30 --budget $b 2>&1 | grep -v -P "^(jit_optix|\t|Info|\s*$)" > $OUT/timeline_$b.txt; done ;;
  history) timeout 500 python3 docs/results/gpu/issue10/stop59/history_cost.py "${@:-scenes/many_objects.xml}" --variant cuda_ad_rgb \
             $D --frames 40 2>&1 | grep -v -P "^(jit_optix|\t|Info|\s*$)" | tee $OUT/history_cost${RUN:-}.txt ;;
  untimed) for k in $(seq ${N:-1}); do  # untimed_budget.py: budgeted frames timed on every frame / every 4th
             timeout $((590 - SECONDS + T0)) python3 docs/results/gpu/issue10/stop59/untimed_budget.py scenes/many_objects.xml \
               --variant cuda_ad_rgb $D --frames 40 "$@" 2>&1 | grep -v -P "^(jit_optix|\t|Info|\s*$)" | tee $OUT/untimed${RUN:-}_$k.txt
           done ;;
  benchab) for s in ${*:-showcase sponza_mirror dining_room armadillo_glass}; do for side in before after; do
             opt=""; [ $side = before ] && opt="--timing-interval 1"  # before: the budget timed on every frame
             python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy --max-path-spp 1 \
               --budgets 0.25 0.5 0.75 $opt $D scenes/$s.xml -o $OUT/bench_$side/$s > $OUT/${s}_$side.log 2>&1
             echo "$s $side rc=$?"; done; done ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
