#!/usr/bin/env bash
# Stop 40, the last call (after stop31/extras.sh 3, 1 and 2 on the same warm machine; carry .device
# and .w40): a third bench round on the showcase alone (new, old, new, old: its paired Gain was
# 0.996 in one of the first two rounds), then on this stop's code scripts/budget_benchmark.py
# (item 4: the budgets on the camera path, 50 frames) and the scaling with triangles (item 2).
source docs/results/gpu/issue10/stop31/env.sh
T0=$SECONDS
SCENES=scenes/showcase.xml bash docs/results/gpu/issue10/stop40/bench.sh 3 "new old"
SCENES=scenes/showcase.xml bash docs/results/gpu/issue10/stop40/bench.sh 4 "new old"
echo "bench done after $((SECONDS - T0)) s"
mkdir -p /tmp/budget /tmp/scaling
timeout 300 python3 scripts/budget_benchmark.py --variant cuda_ad_rgb --frames 50 --resx 1280 --resy 720 \
  --importance 0.01 -o /tmp/budget/budget > /tmp/budget/budget.log 2>&1
echo "budget rc=$? after $((SECONDS - T0)) s"; grep "^|" /tmp/budget/budget.md | head -14
timeout $((590 - SECONDS + T0)) python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy \
  --max-path-spp 1 -D resx=1280 -D resy=720 --scaling triangles --values 10000 100000 1000000 5000000 \
  -o /tmp/scaling/scaling_triangles > /tmp/scaling/scaling.log 2>&1
echo "scaling rc=$? after $((SECONDS - T0)) s"; head -12 /tmp/scaling/scaling_triangles.md 2>/dev/null
tar -cJf $OUT/items.tar.xz -C /tmp budget scaling
