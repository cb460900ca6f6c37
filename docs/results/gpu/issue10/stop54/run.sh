#!/usr/bin/env bash
# Stop 54's device runs, from the repository root on a warm machine, after
# `bash docs/results/gpu/issue10/stop31/extras.sh 3`, `… 1`, `… 2` (scenes, Open Image Denoise),
# with .device carried (made by `bash docs/results/gpu/issue10/stop45/carries.sh`).
#   bash docs/results/gpu/issue10/stop50/run.sh bench SCENE...   # the timing bench (owed by stop 53)
#   N=3 bash docs/results/gpu/issue10/stop54/run.sh budget       # scripts/budget_benchmark.py N times in a row:
#     item 4 on the 226 objects' camera path, with the RT / 50 % ratio measured in turn (owed by stop 53)
source docs/results/gpu/issue10/stop31/env.sh
mkdir -p $OUT; T0=$SECONDS
mode=$1; shift
case $mode in
  budget) for k in $(seq 1 ${N:-1}); do
            timeout $((590 - SECONDS + T0)) python3 scripts/budget_benchmark.py --variant cuda_ad_rgb --frames 50 \
              --resx 1280 --resy 720 --importance 0.01 -o $OUT/budget${RUN:-}_$k > $OUT/budget${RUN:-}_$k.log 2>&1
            echo "run $k rc=$? after $((SECONDS - T0)) s"; grep "RT / 50 % in turn" $OUT/budget${RUN:-}_$k.log
            grep "^| nested\|^| all\|^| RT" $OUT/budget${RUN:-}_$k.md 2>/dev/null
          done ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
