#!/usr/bin/env bash
# Stop 65: the timing bench (DR, hybrid, RT baseline, paired Gain) of each SCENE (default: showcase) on this tree
# and on stop 64's (0f468d3, unpacked untracked into ab_old/ by
# `git archive 0f468d3 hybrid_integrator plugins scenes | tar -x -C ab_old`), in turn, twice, on one warm device
# machine (after stop31/extras.sh 1-6): whether this stop moved the default frame.
#   bash docs/results/gpu/issue10/stop65/ab.sh [SCENE...]
source docs/results/gpu/issue10/stop31/env.sh
ln -sfn ../plugins ab_old/hybrid_integrator/plugins
mkdir -p $OUT
for s in ${@:-showcase}; do
  DS=$(for kv in $D; do case $kv in *=*) grep -q "\$${kv%%=*}" scenes/$s.xml && echo "-D $kv";; esac; done)
  for round in 1 2; do
    for tree in new old; do
      dir=.; [ $tree = old ] && dir=ab_old
      (cd $dir && python3 -c "import importlib.util as u; print(u.find_spec('hybrid_integrator').origin)")
      (cd $dir && timeout 200 python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy \
        --max-path-spp 1 --budgets 0.5 $DS scenes/$s.xml -o $OUT/ab_${s}_${tree}_$round > $OUT/ab_${s}_${tree}_$round.log 2>&1)
      echo "$s $tree round $round rc=$?"; grep "^| $s | [0-9]" $OUT/ab_${s}_${tree}_$round/bench.md
      grep "^| raster |\|^| hybrid |" $OUT/ab_${s}_${tree}_$round/bench.md; grep "Host speed" $OUT/ab_${s}_${tree}_$round/bench.md | cut -c1-230
    done
  done
done
