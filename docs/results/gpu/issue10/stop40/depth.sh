#!/usr/bin/env bash
# Stop 40, for item 3's reading: scripts/trace_overhead.py on many_objects at the max_depth its own
# integrator declares (6) and, in turn, at the script's default (-1, unlimited: the bench's), this
# stop's code, $1 rounds (3 by default). Carry .device. Summary: $OUT/depth/summary.txt, the
# outputs as one archive (a first call at 7bfa67a copied them one by one: six of twelve came back).
source docs/results/gpu/issue10/stop31/env.sh
R=/tmp/depth; mkdir -p $R $OUT/depth
exec > >(tee $OUT/depth/summary.txt) 2>&1
for round in $(seq ${1:-3}); do
  for depth in 6 -1; do
    PYTHONPATH=/tmp/site:/tmp/extra:$PWD python3 scripts/trace_overhead.py --variant cuda_ad_rgb --resx 1280 --resy 720 \
      --max-depth=$depth -o $R/d${depth}_$round/trace_overhead > $R/d${depth}_$round.log 2>&1
    echo "max_depth $depth round $round rc=$?"; python3 docs/results/gpu/issue10/stop40/summary.py $R/d${depth}_$round/trace_overhead.json
  done
done
tar -cJf $OUT/depth/outputs.tar.xz -C /tmp depth
