#!/usr/bin/env bash
# Stop 31, third GPU run: the budgets on the camera path through 226 objects, stop 28's final code
# (29a70fe, copied into the git-excluded .device/base28) against this stop's (= stop 30's) code, in
# turn, two rounds; then the bench's 50 % budget rows on the four scenes (this stop's code).
# One H200, cuda_ad_rgb, 1280x720. Needs extras.sh (calls 1 and 2) first. Results: $OUT/b.tar.xz.
source docs/results/gpu/issue10/stop31/env.sh
ln -sfn ../plugins .device/base28/hybrid_integrator/plugins
R=/tmp/b; mkdir -p $R
budget() { python3 scripts/budget_benchmark.py --variant cuda_ad_rgb --frames 50 --resx 1280 --resy 720 --importance 0.01 -o "$1" > "$1.log" 2>&1; }
for k in 1 2; do
  (cd .device/base28 && PYTHONPATH=$PWD:$PYTHONPATH budget $R/budget_base28_$k)
  budget $R/budget_new_$k
  for c in base28 new; do echo "== $c $k"; grep "^|" $R/budget_${c}_$k.md | sed -n '3,6p'; done
done
python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy --max-path-spp 1 scenes/armadillo_glass.xml scenes/showcase.xml scenes/sponza_mirror.xml scenes/dining_room.xml --budgets 0.5 $D -o $R/bench50 > $R/bench50.log 2>&1
grep -A6 "^| scene" $R/bench50/bench.md | head -7; grep -E "^\| (hybrid|rt-baseline|greedy|nested|budget)" $R/bench50/bench.md | head -20
tar -cJf $OUT/b.tar.xz -C /tmp b
