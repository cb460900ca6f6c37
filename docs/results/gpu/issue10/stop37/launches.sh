#!/usr/bin/env bash
# Stop 37: scripts/trace_overhead.py with --launches (item 3: which launch grows with the traced
# pixels) -> $OUT/trace_launches.{json,png,log}. Needs no extras (the 226 objects are in scenes/).
source docs/results/gpu/issue10/stop31/env.sh
python3 scripts/trace_overhead.py --variant cuda_ad_rgb --resx 1280 --resy 720 --repeats 21 --launches \
  -o $OUT/trace_launches 2>&1 | tee $OUT/trace_launches.log | grep -v "^warm-up\|^measured"
