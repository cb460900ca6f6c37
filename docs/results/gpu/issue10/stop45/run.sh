#!/usr/bin/env bash
# Stop 45's GPU run (after stop31/extras.sh 3, 1, 2 on the same warm machine; carry .device, .w44 and .w45s,
# main's tree as last measured on the GPU: git archive e30b528 hybrid_integrator plugins scenes scripts | tar -x -C .w44;
# .w45s: git archive ecb29e8 hybrid_integrator/raster | tar -x -C .w45s, this stop's first raster commit).
# $1 = variants: variants.py (the compute visibility pass's versions, one process per scene; $2: the output's name).
# $1 = bench: the timing bench, round $2, on e30b528 (old) and this tree (new), in the order $3 (default "new old").
# $1 = items: this tree's trace_overhead.py (item 3), budget_benchmark.py (item 4), --scaling triangles (item 2).
source docs/results/gpu/issue10/stop31/env.sh
mkdir -p $OUT
if [ "$1" = variants ]; then
  for s in $S; do
    timeout 120 python3 docs/results/gpu/issue10/stop45/variants.py --variant cuda_ad_rgb --repeats 21 \
      --tree old=.w44 --tree mid=.w45s $s $D 2>&1 | grep -v "^\s*$"
  done | tee $OUT/${2:-variants}.txt
elif [ "$1" = bench ]; then  # stop34/bench.sh's command, in the tree of each side
  R=/tmp/s45_${2:-1}; mkdir -p $R; ln -sfn ../plugins .w44/hybrid_integrator/plugins
  for side in ${3:-new old}; do
    T0=$SECONDS
    (if [ $side = old ]; then cd .w44; fi
     timeout 280 python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy --max-path-spp 1 $S $D \
       --budgets 0.5 -o $R/bench_$side > $R/bench_$side.log 2>&1)
    echo "$side: rc=$? after $((SECONDS - T0)) s"
    grep -A7 "^| scene" $R/bench_$side/bench.md | tail -5 | cut -d'|' -f2,6-12
  done
  tar -cJf $OUT/s45_${2:-1}.tar.xz -C /tmp s45_${2:-1}
elif [ "$1" = items ]; then
  R=/tmp/items; mkdir -p $R; T0=$SECONDS
  timeout 150 python3 scripts/trace_overhead.py --variant cuda_ad_rgb --resx 1280 --resy 720 -o $R/trace_overhead > $R/trace.log 2>&1
  echo "trace_overhead rc=$? after $((SECONDS - T0)) s"; tail -12 $R/trace.log
  timeout 200 python3 scripts/budget_benchmark.py --variant cuda_ad_rgb --frames 50 --resx 1280 --resy 720 \
    --importance 0.01 -o $R/budget > $R/budget.log 2>&1
  echo "budget rc=$? after $((SECONDS - T0)) s"; grep "^|" $R/budget.md | head -14
  timeout $((560 - SECONDS + T0)) python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy \
    --max-path-spp 1 -D resx=1280 -D resy=720 --scaling triangles --values 10000 100000 1000000 5000000 \
    -o $R/scaling_triangles > $R/scaling.log 2>&1
  echo "scaling rc=$? after $((SECONDS - T0)) s"; head -14 $R/scaling_triangles.md 2>/dev/null
  tar -cJf $OUT/items.tar.xz -C /tmp items
fi
