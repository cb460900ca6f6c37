#!/usr/bin/env bash
# Stop 33's GPU run, part 3: stop 32's refine="trace" (the refined pixels' lighting inside the
# launch; a871ef0, its tree in the git-excluded .w32/, made with
# `git archive a871ef0 hybrid_integrator plugins scripts | tar -x -C .w32`) against this stop's
# (their lighting after it), each by scripts/refine_ab.py against the same refine="primary" and RT
# baseline in its own process, the versions alternating, two rounds; then the timing bench on this
# stop's final code (refine="auto": primary where nothing is traced, as in its DR frames).
# Same machine and set-up as refine.sh; carry .device and .w32.
source docs/results/gpu/issue10/stop31/env.sh
ln -sfn ../plugins .w32/hybrid_integrator/plugins
R=/tmp/v33; mkdir -p $R
for round in 1 2; do
  for s in scenes/sponza_mirror.xml scenes/dining_room.xml scenes/armadillo_glass.xml; do
    python3 scripts/refine_ab.py --variant cuda_ad_rgb --repeats 21 $s $D | tail -1 | sed 's/^|/| stop 33 |/' | tee -a $R/versions.md
    PYTHONPATH="$PWD/.w32:$PYTHONPATH" python3 .w32/scripts/refine_ab.py --variant cuda_ad_rgb --repeats 21 $s $D \
      | tail -1 | sed 's/^|/| stop 32 |/' | tee -a $R/versions.md
  done
done
python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy --max-path-spp 1 $S $D \
  --budgets 0.5 -o $R/bench > $R/bench.log 2>&1
grep -A7 "^| scene" $R/bench/bench.md | tail -5 | cut -d'|' -f2,6-12
tar -cJf $OUT/v33.tar.xz -C /tmp v33
