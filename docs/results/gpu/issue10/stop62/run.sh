#!/usr/bin/env bash
# Stop 62's device runs, from the repository root on a warm machine, after
# `bash docs/results/gpu/issue10/stop31/extras.sh N` for N = 1 ... 6, each carrying .device_xN (the bundle's
# site packages, scenes, Open Image Denoise, flip-evaluator; since this stop in six carries of at most ~17 MB),
# with .device carried (made by `bash docs/results/gpu/issue10/stop45/carries.sh`).
# The rest of this stop's acceptance run is stop 61's run.sh (`items`, `accuracy SCENE`), on one H100.
#   bash docs/results/gpu/issue10/stop62/run.sh paper SCENE...  # item 5 as it reads: the paper's frame (shadows,
#     reflections, refractions, denoised) against path 1 spp (frozen) and path + OIDN 'fast', frames in turn
#     (stop50/probes.py rivals; stop 52's `rivals` without its undenoised half)
#   bash docs/results/gpu/issue10/stop62/run.sh roulette SCENE...  # the undenoised frame with path's roulette (its
#     default since this stop) against the cap (the default before), in turn: stop57/rr_cap.py --property denoise=false
source docs/results/gpu/issue10/stop31/env.sh
mkdir -p $OUT; T0=$SECONDS
mode=$1; shift
case $mode in
  paper) timeout $((590 - SECONDS + T0)) python3 docs/results/gpu/issue10/stop50/probes.py rivals --variant cuda_ad_rgb \
           --property effects=shadow,reflection,refraction $(for s in "$@"; do echo scenes/$s.xml; done) $D 2>&1 \
           | grep -v "^jit_\|^Info\|^\s" | tee $OUT/paper_rivals.txt
         echo "rc=${PIPESTATUS[0]} after $((SECONDS - T0)) s" ;;
  roulette) timeout $((590 - SECONDS + T0)) python3 docs/results/gpu/issue10/stop57/rr_cap.py \
              $(for s in "$@"; do echo scenes/$s.xml; done) --variant cuda_ad_rgb $D --frames ${FRAMES:-20} \
              --caps 0.95 0.95@16:0.5 --property denoise=false -o $OUT/roulette.json 2>&1 \
              | grep -v "^\s\|jit_optix\|^Info" | tee $OUT/roulette.txt
            echo "rc=${PIPESTATUS[0]} after $((SECONDS - T0)) s" ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
