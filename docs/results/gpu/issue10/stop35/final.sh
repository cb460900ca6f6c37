#!/usr/bin/env bash
# Stop 35's GPU run, part 4: the final code (c24ae2b: ties, and on CUDA the guides made again in the
# composition) on the bench, two rounds (bench.sh new f1, f2), then item 2's scaling with triangles.
# After stop31/extras.sh 1 and 2 on the same warm machine; carry .device.
T0=$SECONDS
for round in f1 f2; do bash docs/results/gpu/issue10/stop35/bench.sh new $round; done
source docs/results/gpu/issue10/stop31/env.sh
R=/tmp/c35; mkdir -p $R
timeout $((570 - SECONDS + T0)) python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy \
  --max-path-spp 1 -D resx=1280 -D resy=720 --scaling triangles --values 10000 100000 1000000 5000000 \
  -o $R/scaling_triangles > $R/scaling.log 2>&1
echo "scaling rc=$? after $((SECONDS - T0)) s"; head -20 $R/scaling_triangles.md 2>/dev/null
tar -cJf $OUT/c35.tar.xz -C /tmp c35
