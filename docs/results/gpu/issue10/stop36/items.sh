#!/usr/bin/env bash
# Stop 36's GPU run C, on the new code: item 4 (scripts/budget_benchmark.py, the 226 objects' camera
# path, 50 frames), item 3 (scripts/trace_overhead.py) and item 2's scaling with triangles.
# After stop31/extras.sh 1 and 2; carry .device. $TAG (g36 by default) names the output: later stops
# run it for their own code.
source docs/results/gpu/issue10/stop31/env.sh
TAG=${TAG:-g36}; R=/tmp/$TAG; mkdir -p $R; T0=$SECONDS
timeout 240 python3 scripts/budget_benchmark.py --variant cuda_ad_rgb --frames 50 --resx 1280 --resy 720 --importance 0.01 -o $R/budget > $R/budget.log 2>&1
echo "budget rc=$? after $((SECONDS - T0)) s"; grep "^|" $R/budget.md | sed -n '3,11p'
timeout 120 python3 scripts/trace_overhead.py --variant cuda_ad_rgb --resx 1280 --resy 720 --repeats 21 -o $R/trace_overhead > $R/trace.log 2>&1
echo "trace_overhead rc=$? after $((SECONDS - T0)) s"; tail -22 $R/trace.log
tar -cJf $OUT/$TAG.tar.xz -C /tmp $TAG
timeout $((570 - SECONDS + T0)) python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy \
  --max-path-spp 1 -D resx=1280 -D resy=720 --scaling triangles --values 10000 100000 1000000 5000000 \
  -o $R/scaling_triangles > $R/scaling.log 2>&1
echo "scaling rc=$? after $((SECONDS - T0)) s"; head -20 $R/scaling_triangles.md 2>/dev/null
tar -cJf $OUT/$TAG.tar.xz -C /tmp $TAG
