#!/usr/bin/env bash
# Stop 34's GPU run: the timing bench (items 1, 2, 4, 5: DR, Gain, the 50 % frame, `path` 1 spp) on
# this stop's code ($1 = new) or on stop 33's (60636ae, its tree in the git-excluded .w33/, made
# with `git archive 60636ae hybrid_integrator plugins scripts scenes | tar -x -C .w33`; $1 = old).
# After stop31/extras.sh 1 and 2 on the same warm machine; carry .device (and .w33).
# $2: the round (1 by default), which names the output folder. $STOP (34 by default) names it too:
# later stops run this script with their own number and their own old tree in .w33.
source docs/results/gpu/issue10/stop31/env.sh
R=/tmp/s${STOP:-34}_${2:-1}; mkdir -p $R; T0=$SECONDS
# any $1 but new: the tree in $OLD (.w33 by default), the output named after $1
if [ "$1" != new ]; then ln -sfn ../plugins ${OLD:-.w33}/hybrid_integrator/plugins; cd ${OLD:-.w33}; fi
timeout 560 python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy --max-path-spp 1 $S $D \
  --budgets 0.5 -o $R/bench_$1 > $R/bench_$1.log 2>&1
echo "rc=$? after $((SECONDS - T0)) s"
grep -A7 "^| scene" $R/bench_$1/bench.md | tail -5 | cut -d'|' -f2,6-12
tar -cJf $OUT/s${STOP:-34}_${2:-1}_$1.tar.xz -C /tmp s${STOP:-34}_${2:-1}
