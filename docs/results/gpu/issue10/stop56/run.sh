#!/usr/bin/env bash
# Stop 56's device runs, from the repository root on a warm machine, after
# `bash docs/results/gpu/issue10/stop31/extras.sh 3`, `… 1`, `… 2` (scenes, Open Image Denoise),
# with .device carried (made by `bash docs/results/gpu/issue10/stop45/carries.sh`).
#   bash docs/results/gpu/issue10/stop56/run.sh flight SCENE...   # flight_ab.py: budgeted frames in flight
#     against one at a time and against the RT baseline, in turn, at 25 / 50 / 75 %
#   bash docs/results/gpu/issue10/stop56/run.sh pose [--size N]    # pose_wait.py: does moving the sensor wait for the GPU?
#   bash docs/results/gpu/issue10/stop56/run.sh wall SCENE...      # path_wall.py: wall ms per frame along a camera path,
#     the sensor moved by params.update() or place_sensor, one frame at a time or two in flight
#   bash docs/results/gpu/issue10/stop56/run.sh sync [--path]      # sync_sites.py: where a frame's host waits for the device
#   N=2 bash docs/results/gpu/issue10/stop56/run.sh budget        # scripts/budget_benchmark.py N times in a row
#     (stop 54's mode: item 4 on the 226 objects' camera path; since stop 56 also by blocks)
source docs/results/gpu/issue10/stop31/env.sh
mkdir -p $OUT; T0=$SECONDS
mode=$1; shift
case $mode in
  flight) timeout $((590 - SECONDS + T0)) python3 docs/results/gpu/issue10/stop56/flight_ab.py "$@" --variant cuda_ad_rgb \
            $D --frames ${FRAMES:-40} 2>&1 | grep -v "^\s" | tee $OUT/flight${RUN:-}.txt
          echo "rc=${PIPESTATUS[0]} after $((SECONDS - T0)) s" ;;
  budget) bash docs/results/gpu/issue10/stop54/run.sh budget  # the same runs; by blocks too since stop 56
          grep -h "^The same by blocks" $OUT/budget${RUN:-}_*.md ;;
  pose) python3 docs/results/gpu/issue10/stop56/pose_wait.py --variant cuda_ad_rgb "$@" 2>&1 | grep -v "^\s" \
          | tee $OUT/pose${RUN:-}.txt ;;
  wall) timeout $((590 - SECONDS + T0)) python3 docs/results/gpu/issue10/stop56/path_wall.py "$@" --variant cuda_ad_rgb \
          $D --frames ${FRAMES:-40} 2>&1 | grep -v "^\s" | tee $OUT/wall${RUN:-}.txt ;;
  sync) python3 docs/results/gpu/issue10/stop56/sync_sites.py scenes/many_objects.xml --variant cuda_ad_rgb $D \
          --frames 10 "$@" 2>&1 | grep "queued\|^  [A-Za-z0-9]" | tee -a $OUT/sync_sites.txt ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
