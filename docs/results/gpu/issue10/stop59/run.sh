#!/usr/bin/env bash
# Stop 59's device runs, from the repository root on a warm machine, after
# `bash docs/results/gpu/issue10/stop31/extras.sh 3`, `… 1`, `… 2` (scenes, Open Image Denoise),
# with .device carried (made by `bash docs/results/gpu/issue10/stop45/carries.sh`).
#   N=2 bash docs/results/gpu/issue10/stop59/run.sh ab [SCENE...] [--budgets B...]  # plan_ab.py N times: a moving
#     camera's next plan from its raster coverage against from its counts, in turn with the RT baseline
#     (default scene: the 226 objects, whose camera path item 4 is measured on)
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
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
