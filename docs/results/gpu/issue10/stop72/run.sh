#!/usr/bin/env bash
# Stop 72's device runs, from the repository root on a warm machine, after
# `bash docs/results/gpu/issue10/stop31/extras.sh N` for N = 1 ... 6, each carrying .device_xN, with .device
# carried (both made by `bash docs/results/gpu/issue10/stop45/carries.sh`).
#   bash docs/results/gpu/issue10/stop72/run.sh ab SCENE...   # carrying .w44 too, made by
#     `rm -rf .w44 && mkdir .w44 && git archive 7b7ece8 hybrid_integrator plugins | tar -x -C .w44 && ln -sfn ../plugins .w44/hybrid_integrator/plugins`:
#     stop 69's partial_probe.py at 25 and 50 % with the RT baseline's row, the tree before the tiers' own prior
#     (7b7ece8, in .w44) and this tree in turn, one process each, $ROUNDS rounds (default 1)
source docs/results/gpu/issue10/stop31/env.sh
mkdir -p $OUT; T0=$SECONDS
mode=$1; shift
case $mode in
  ab)
    for round in $(seq ${ROUNDS:-1}); do
      for s in "$@"; do
        for tree in before after; do
          echo "== round $round, tree $tree"
          [ $tree = before ] && pp=$PWD/.w44 || pp=$PWD
          PYTHONPATH=$pp:$PYTHONPATH python3 -P -c "import hybrid_integrator.heuristic as h; print('package:', h.__file__)"
          PYTHONPATH=$pp:$PYTHONPATH timeout $((590 - SECONDS + T0)) python3 docs/results/gpu/issue10/stop69/partial_probe.py \
            --variant cuda_ad_rgb --rt --budgets 0.25 0.5 --frames 20 --gt-spp 512 $D scenes/$s.xml 2>&1 \
            | grep -v "Warn\|jit_optix_log\|^	\|^Info"
        done
      done
    done | tee -a $OUT/tier_prior_ab.txt ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
