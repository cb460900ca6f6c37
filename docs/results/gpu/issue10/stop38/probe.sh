#!/usr/bin/env bash
# Stop 38, call 1 (carry .device): the probe (compaction by scatter_inc, the read set of the
# snapshot) and scripts/trace_overhead.py at unlimited depth and at many_objects.xml's max_depth 6.
source docs/results/gpu/issue10/stop31/env.sh
mkdir -p $OUT/probe
python3 docs/results/gpu/issue10/stop38/probe.py --variant cuda_ad_rgb --resx 1280 --resy 720 2>&1 | tee $OUT/probe/probe.log | tail -n 30
for depth in -1 6; do
  python3 scripts/trace_overhead.py --variant cuda_ad_rgb --resx 1280 --resy 720 --launches --max-depth $depth \
    -o $OUT/probe/trace_overhead_depth$depth > $OUT/probe/trace_depth$depth.log 2>&1
  grep -A12 '"fit"' $OUT/probe/trace_depth$depth.log | head -n 12
  grep "pixels:" $OUT/probe/trace_depth$depth.log
done
