#!/usr/bin/env bash
# Stop 34's GPU run, part 3: the primary stage's kernels (scripts/primary_stage.py) with this stop's
# primary_hits (one surface interaction) and stop 33's (two; .w33/), then item 2's scaling with
# triangles on this stop's code (last run: stop 23, an H100). Same machine and set-up as bench.sh;
# carry .device and .w33.
source docs/results/gpu/issue10/stop31/env.sh
R=/tmp/c34; mkdir -p $R; T0=$SECONDS
ln -sfn ../plugins .w33/hybrid_integrator/plugins
for round in 1 2; do
  timeout 100 python3 scripts/primary_stage.py --variant cuda_ad_rgb $S $D -o $R/primary_new_$round.txt > /dev/null 2>&1
  PYTHONPATH="$PWD/.w33:$PYTHONPATH" timeout 100 python3 .w33/scripts/primary_stage.py --variant cuda_ad_rgb $S $D \
    -o $R/primary_old_$round.txt > /dev/null 2>&1
done
echo "primary_stage after $((SECONDS - T0)) s"; tail -n +1 $R/primary_*.txt | grep -v "^$" | head -40
tar -cJf $OUT/c34.tar.xz -C /tmp c34
timeout $((570 - SECONDS + T0)) python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy \
  --max-path-spp 1 -D resx=1280 -D resy=720 --scaling triangles --values 10000 100000 1000000 5000000 \
  -o $R/scaling_triangles > $R/scaling.log 2>&1
echo "scaling rc=$? after $((SECONDS - T0)) s"; head -20 $R/scaling_triangles.md 2>/dev/null
tar -cJf $OUT/c34.tar.xz -C /tmp c34
