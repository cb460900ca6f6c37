#!/usr/bin/env bash
# Stop 53's device runs, from the repository root on a warm machine, after
# `bash docs/results/gpu/issue10/stop31/extras.sh 3`, `… 1`, `… 2` (scenes, Open Image Denoise,
# flip-evaluator), with .device carried.
#   bash docs/results/gpu/issue10/stop53/run.sh exposure SCENE...  # exposure.py: which host work the frame waits for,
#     and (point "late plan") a still camera's plan made once the counts are in, in turn ($FRAMES, $ARGS, $RUN)
#   bash docs/results/gpu/issue10/stop53/run.sh host               # host_work.py: the budgeted frame's host time by method
#   bash docs/results/gpu/issue10/stop53/run.sh ab ROUNDS          # old (.w53: main before the plan ahead moved, its
#     hybrid_integrator package, carried) and new in turn: scripts/budget_ab.py, nested at 25 / 50 / 75 %
#     ($SIDES: label:folder pairs, '' for the tree's own package; default "old:.w53 new:")
#   bash docs/results/gpu/issue10/stop53/run.sh still ROUNDS SCENE...  # the same in turn on still cameras:
#     exposure.py --delay 0 (every point the same: 100 frames of each kind per process)
source docs/results/gpu/issue10/stop31/env.sh
mkdir -p $OUT; T0=$SECONDS
mode=$1; shift
case $mode in
  exposure) timeout 280 python3 docs/results/gpu/issue10/stop53/exposure.py --variant cuda_ad_rgb --frames ${FRAMES:-200} \
              --resx 1280 --resy 720 ${ARGS:-} $D $(for s in "$@"; do echo scenes/$s.xml; done) 2>&1 | grep -v "^jit_\|^Info" \
              | tee $OUT/exposure${RUN:-}.txt ;;
  host) timeout 200 python3 docs/results/gpu/issue10/stop53/host_work.py --variant cuda_ad_rgb --resx 1280 --resy 720 \
          --frames 60 --profile 2>&1 | grep -v "^jit_\|^Info" > $OUT/host_work${RUN:-}.txt
        echo "rc=$? after $((SECONDS - T0)) s"; grep -A12 "^==" $OUT/host_work${RUN:-}.txt | cut -c1-200 | head -80 ;;
  ab) for r in $(seq 1 $1); do for pair in ${SIDES:-old:.w53 new:}; do  # SIDES: label:package folder ('': the tree's)
        side=${pair%%:*}; dir=${pair#*:}
        if [ -n "$dir" ]; then P="$PWD/$dir:$PYTHONPATH"; else P="$PYTHONPATH"; fi
        PYTHONPATH="$P" timeout 150 python3 scripts/budget_ab.py --variant cuda_ad_rgb --selection nested \
          --fractions 0.25 0.5 0.75 --label $side$r 2>&1 | grep "^$side" | tee -a $OUT/ab.txt | grep "RT/"
      done; done ;;
  still) rounds=$1; shift
         for r in $(seq 1 $rounds); do for side in old new; do
           if [ $side = old ]; then P="$PWD/.w53:$PYTHONPATH"; else P="$PYTHONPATH"; fi
           echo "== $side$r" | tee -a $OUT/still.txt
           PYTHONPATH="$P" timeout 200 python3 docs/results/gpu/issue10/stop53/exposure.py --variant cuda_ad_rgb \
             --frames 100 --delay 0 --resx 1280 --resy 720 $D $(for s in "$@"; do echo scenes/$s.xml; done) 2>&1 \
             | grep -v "^jit_\|^Info\|^\s" | tee -a $OUT/still.txt | grep -v "^$"
         done; done ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
