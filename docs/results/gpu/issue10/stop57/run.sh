#!/usr/bin/env bash
# Stop 57's device runs, from the repository root on a warm machine, after
# `bash docs/results/gpu/issue10/stop31/extras.sh 3`, `… 1`, `… 2` (scenes, Open Image Denoise),
# with .device carried (made by `bash docs/results/gpu/issue10/stop45/carries.sh`).
#   bash docs/results/gpu/issue10/stop57/run.sh rr SCENE...        # rr_cap.py: Russian roulette's cap against
#     trace time and FLIP, caps in turn
#   bash docs/results/gpu/issue10/stop57/run.sh overhead DEPTH...  # scripts/trace_overhead.py at unlimited depth,
#     once per --rr-tail-depth (-1: path's roulette; the first runs of this stop took --rr-max-prob CAP, the
#     cap at every depth, as --rr-tail-depth 0 --rr-tail-prob CAP now)
source docs/results/gpu/issue10/stop31/env.sh
mkdir -p $OUT; T0=$SECONDS
mode=$1; shift
case $mode in
  rr) timeout $((590 - SECONDS + T0)) python3 docs/results/gpu/issue10/stop57/rr_cap.py "$@" --variant cuda_ad_rgb \
        $D --frames ${FRAMES:-20} ${CAPS:+--caps $CAPS} -o $OUT/rr${RUN:-}.json 2>&1 | grep -v "^\s\|jit_optix\|^Info" \
        | tee $OUT/rr${RUN:-}.txt
      echo "rc=${PIPESTATUS[0]} after $((SECONDS - T0)) s" ;;
  overhead) for depth in "$@"; do  # outputs trace_overhead_tailDEPTH.json/.png (DEPTH -1: path's roulette)
              name=$OUT/trace_overhead_tail$depth
              python3 scripts/trace_overhead.py --variant cuda_ad_rgb --resx 1280 --resy 720 --rr-tail-depth $depth \
                -o $name > $name.log 2>&1
              python3 -c "import json, sys; r = json.load(open(sys.argv[1])); print(r['command'], r['fit'], r['no_pixel'])" $name.json
            done ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
