#!/usr/bin/env bash
# Stop 58's device runs, from the repository root on a warm machine, after
# `bash docs/results/gpu/issue10/stop31/extras.sh 3`, `… 1`, `… 2` (scenes, Open Image Denoise),
# with .device carried (made by `bash docs/results/gpu/issue10/stop45/carries.sh`).
#   bash docs/results/gpu/issue10/stop58/run.sh driver [--budgets B...]  # driver_calls.py: host ms of each CUDA
#     driver call the package makes, per frame, on the 226 objects' camera path
#   bash docs/results/gpu/issue10/stop58/run.sh cores                    # core_speed.sh: each CPU's speed, pinned, in rounds
#   bash docs/results/gpu/issue10/stop58/run.sh pin SCENE... [--budgets B...]  # pin_ab.py: how long a CPU keeps its
#     speed; the render thread pinned to the CPU fast now against left to the scheduler, in turn
#   bash docs/results/gpu/issue10/stop58/run.sh overhead                 # scripts/trace_overhead.py (the default roulette),
#     its wall-time line also apart for the calls on a fast host and on a slow one (RUN: a suffix)
#   bash docs/results/gpu/issue10/stop58/run.sh ab SCENE... [--budgets B...]  # host_ab.py: this stop's host code
#     against stop 57's, in turn in one process, with the RT baseline
#   bash docs/results/gpu/issue10/stop58/run.sh speed SCENE... [--budgets B...]  # host_speed.py: frames in turn,
#     each classified by the host CPU's speed just before it
source docs/results/gpu/issue10/stop31/env.sh
mkdir -p $OUT; T0=$SECONDS
mode=$1; shift
case $mode in
  driver) timeout $((590 - SECONDS + T0)) python3 docs/results/gpu/issue10/stop58/driver_calls.py --variant cuda_ad_rgb \
            --resx 1280 --resy 720 "$@" 2>&1 | grep -v "jit_optix\|^Info\|^\s*$" | tee $OUT/driver${RUN:-}.txt
          echo "rc=${PIPESTATUS[0]} after $((SECONDS - T0)) s" ;;
  ab) timeout $((590 - SECONDS + T0)) python3 docs/results/gpu/issue10/stop58/host_ab.py "$@" --variant cuda_ad_rgb $D \
        --frames ${FRAMES:-60} 2>&1 | grep -v "jit_optix\|^Info\|^\s*$\|^\t" | tee $OUT/ab${RUN:-}.txt
      echo "rc=${PIPESTATUS[0]} after $((SECONDS - T0)) s" ;;
  speed) timeout $((590 - SECONDS + T0)) python3 docs/results/gpu/issue10/stop58/host_speed.py "$@" --variant cuda_ad_rgb \
           $D --frames ${FRAMES:-80} 2>&1 | grep -v "jit_optix\|^Info\|^\s*$\|^\t" | tee $OUT/speed${RUN:-}.txt
         echo "rc=${PIPESTATUS[0]} after $((SECONDS - T0)) s" ;;
  overhead) name=$OUT/trace_overhead${RUN:-}
            python3 scripts/trace_overhead.py --variant cuda_ad_rgb --resx 1280 --resy 720 -o $name > $name.log 2>&1
            python3 -c "import json, sys; r = json.load(open(sys.argv[1])); print(r['command'], r['fit'], r['no_pixel'], [(row['fast_share'], round(row['host_loop_ms'], 3)) for row in r['rows']])" $name.json ;;
  pin) timeout $((590 - SECONDS + T0)) python3 docs/results/gpu/issue10/stop58/pin_ab.py "$@" --variant cuda_ad_rgb $D \
         --frames ${FRAMES:-60} 2>&1 | grep -P "^(CPU|\S+ \d+% budget|  )" | tee $OUT/pin${RUN:-}.txt
       echo "rc=${PIPESTATUS[0]} after $((SECONDS - T0)) s" ;;
  cores) bash docs/results/gpu/issue10/stop58/core_speed.sh | tee $OUT/cores${RUN:-}.txt ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
