#!/usr/bin/env bash
# Stop 40, item 3: scripts/trace_overhead.py (many_objects, 1280×720, unlimited depth, --launches)
# on this stop's package ("new") and on stop 39's final main ("old": 93a4593 in the git-excluded
# .w40/, made with `git archive 93a4593 hybrid_integrator plugins scripts scenes | tar -x -C .w40`),
# each with its own script, in turn, $1 rounds (3 by default). Carry .device and .w40. Summary:
# $OUT/trace_ab/summary.txt; the outputs come back as one archive. Later stops set $OLD to their own
# old tree (.w40 by default).
source docs/results/gpu/issue10/stop31/env.sh
OLD=${OLD:-.w40}; ln -sfn ../plugins $OLD/hybrid_integrator/plugins
R=/tmp/trace_ab; mkdir -p $R $OUT/trace_ab; ROOT=$PWD
exec > >(tee $OUT/trace_ab/summary.txt) 2>&1
for round in $(seq ${1:-3}); do
  for way in new old; do
    case $way in new) tree=$ROOT;; old) tree=$ROOT/$OLD;; esac
    (cd $tree && PYTHONPATH=/tmp/site:/tmp/extra:$tree python3 scripts/trace_overhead.py --variant cuda_ad_rgb \
      --resx 1280 --resy 720 --launches -o $R/${way}_$round/trace_overhead > $R/${way}_$round.log 2>&1)
    echo "$way $round rc=$?"; python3 docs/results/gpu/issue10/stop40/summary.py $R/${way}_$round/trace_overhead.json
  done
done
tar -cJf $OUT/trace_ab/outputs.tar.xz -C /tmp trace_ab
