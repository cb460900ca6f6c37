#!/usr/bin/env bash
# Stop 65: the showcase's timing bench (DR, hybrid, RT baseline) on this tree and on stop 64's (0f468d3, unpacked
# untracked into ab_old/ by `git archive 0f468d3 hybrid_integrator plugins scenes | tar -x -C ab_old`), in turn, twice,
# on one warm device machine (after stop31/extras.sh 1-6): whether this stop moved the DR frame.
source docs/results/gpu/issue10/stop31/env.sh
ln -sfn ../plugins ab_old/hybrid_integrator/plugins
mkdir -p $OUT
for round in 1 2; do
  for tree in new old; do
    dir=.; [ $tree = old ] && dir=ab_old
    (cd $dir && python3 -c "import importlib.util as u; print(u.find_spec('hybrid_integrator').origin)")
    (cd $dir && timeout 200 python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy --max-path-spp 1 \
      --budgets 0.5 $D scenes/showcase.xml -o $OUT/ab_${tree}_$round > $OUT/ab_${tree}_$round.log 2>&1)
    echo "$tree round $round rc=$?"; grep "^| showcase | [0-9]" $OUT/ab_${tree}_$round/bench.md; grep "^| raster |\|^| hybrid |" $OUT/ab_${tree}_$round/bench.md; grep "Host speed" $OUT/ab_${tree}_$round/bench.md | cut -c1-200
  done
done
