#!/usr/bin/env bash
# Stop 36's GPU run B: scripts/gain_anatomy.py on the new code (the pass issued first in the frame),
# then the timing bench on it (stop34/bench.sh new), round $1.
# After stop31/extras.sh 1 and 2; carry .device and .w36.
source docs/results/gpu/issue10/stop31/env.sh
T0=$SECONDS
timeout 200 python3 scripts/gain_anatomy.py --variant cuda_ad_rgb --repeats 21 $S $D 2>&1 | tee $OUT/anatomy_$1.md
echo "anatomy after $((SECONDS - T0)) s"
STOP=36 OLD=.w36 bash docs/results/gpu/issue10/stop34/bench.sh new $1
echo "bench after $((SECONDS - T0)) s"
