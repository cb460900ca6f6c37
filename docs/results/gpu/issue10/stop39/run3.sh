#!/usr/bin/env bash
# Stop 39, the last call (after stop31/extras.sh 3, 1 and 2 on the same warm machine; carry .device
# and .w39): the timing bench's second round on the five scenes, old tree first; trace_ab.sh's third
# batch of three rounds; item 2's scaling with triangles on this stop's code.
source docs/results/gpu/issue10/stop31/env.sh
T0=$SECONDS
bash docs/results/gpu/issue10/stop39/bench.sh 2 "old new" | grep -v "^## \|^$"
echo "bench done after $((SECONDS - T0)) s"
bash docs/results/gpu/issue10/stop39/trace_ab.sh | grep -v "^  rows\|^  replay\|__init__"
echo "trace_ab done after $((SECONDS - T0)) s"
mkdir -p /tmp/scaling
timeout $((585 - SECONDS + T0)) python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy \
  --max-path-spp 1 -D resx=1280 -D resy=720 --scaling triangles --values 10000 100000 1000000 5000000 \
  -o /tmp/scaling/scaling_triangles > /tmp/scaling/scaling.log 2>&1
echo "scaling rc=$? after $((SECONDS - T0)) s"; head -12 /tmp/scaling/scaling_triangles.md 2>/dev/null
tar -cJf $OUT/scaling.tar.xz -C /tmp scaling
