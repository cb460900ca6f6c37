#!/usr/bin/env bash
# Stop 63's device runs, from the repository root on a warm machine, after
# `bash docs/results/gpu/issue10/stop31/extras.sh N` for N = 1 ... 6, each carrying .device_xN, with .device carried
# (both made by `bash docs/results/gpu/issue10/stop45/carries.sh`). Stop 62's `run.sh roulette` and `run.sh paper`
# ran first on the same machine (outputs/roulette.*, outputs/paper_rivals.txt).
#   bash docs/results/gpu/issue10/stop63/run.sh gain SCENE...  # item 2a's Gain (RT baseline / all candidates, and
#     paired in turn) and item 4's 50 % frame, timing bench only (no ground truth), for the default frame and for
#     the paper's (--effects shadow,reflection,refraction), one process per frame kind ($KINDS: default, paper or both)
source docs/results/gpu/issue10/stop31/env.sh
mkdir -p $OUT; T0=$SECONDS
mode=$1; shift
case $mode in
  gain)
    for kind in ${KINDS:-default paper}; do  # $KINDS: one of them per call
      extra=""; [ $kind = paper ] && extra="--effects shadow,reflection,refraction"
      timeout $((590 - SECONDS + T0)) python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 \
        --no-accuracy --max-path-spp 1 --budgets 0.5 $extra $D $(for s in "$@"; do echo scenes/$s.xml; done) \
        -o $OUT/gain_$kind > $OUT/gain_$kind.log 2>&1
      echo "$kind rc=$? after $((SECONDS - T0)) s"
      grep "^| [a-z_]* | [0-9]" $OUT/gain_$kind/bench.md | head -8
    done ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
