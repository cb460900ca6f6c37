#!/usr/bin/env bash
# Stop 44's GPU run (after stop31/extras.sh 3, 1, 2 on the same warm machine; carry .device and .w44,
# main's tree before this stop: git archive e30b528 hybrid_integrator plugins scenes scripts | tar -x -C .w44).
# $1 = same: same.py in both trees, then their images compared. $1 = bench: the timing bench, round
# $2, on main (old), this stop's code (shared) and with the pass drawn ahead flushed after the
# frame's synchronization (late), in the order given by $3 (default "old shared late").
source docs/results/gpu/issue10/stop31/env.sh
mkdir -p $OUT
if [ "$1" = same ]; then
  timeout 250 python3 docs/results/gpu/issue10/stop44/same.py /tmp/same_new.npz $S $D 2>&1 | grep -v "^\s*$" | tee $OUT/same_new.txt
  ln -sfn ../plugins .w44/hybrid_integrator/plugins
  (cd .w44 && PYTHONPATH=$PWD:$PYTHONPATH timeout 250 python3 ../docs/results/gpu/issue10/stop44/same.py /tmp/same_old.npz $S $D 2>&1 | grep -v "^\s*$" | tee $OUT/same_old.txt)
  python3 docs/results/gpu/issue10/stop44/same.py --compare /tmp/same_old.npz /tmp/same_new.npz | tee $OUT/same_compare.txt
elif [ "$1" = bench ]; then  # stop34/bench.sh's command, in the tree and with the setting of each side
  R=/tmp/s44_${2:-1}; mkdir -p $R; ln -sfn ../plugins .w44/hybrid_integrator/plugins
  for side in ${3:-old shared late}; do
    T0=$SECONDS
    if [ $side = late ]; then export HYBRID_PROTO_FLUSH=late; else unset HYBRID_PROTO_FLUSH; fi
    (if [ $side = old ]; then cd .w44; fi
     timeout 300 python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy --max-path-spp 1 $S $D \
       --budgets 0.5 -o $R/bench_$side > $R/bench_$side.log 2>&1)
    echo "$side: rc=$? after $((SECONDS - T0)) s"
    grep -A7 "^| scene" $R/bench_$side/bench.md | tail -5 | cut -d'|' -f2,6-12
  done
  tar -cJf $OUT/s44_${2:-1}.tar.xz -C /tmp s44_${2:-1}
fi
