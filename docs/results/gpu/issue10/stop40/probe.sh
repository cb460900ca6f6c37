#!/usr/bin/env bash
# Stop 40's probe on the GPU: probe.py at max_depth 6 and -1 (this stop's code). Carry .device.
source docs/results/gpu/issue10/stop31/env.sh
for depth in 6 -1; do
  PYTHONPATH=/tmp/site:/tmp/extra:$PWD python3 docs/results/gpu/issue10/stop40/probe.py --variant cuda_ad_rgb \
    --resx 1280 --resy 720 --max-depth=$depth 2>&1 | grep -v "^jit\|^drjit\|Warning"
done | tee $OUT/probe.log
