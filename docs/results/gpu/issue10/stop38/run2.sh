#!/usr/bin/env bash
# Stop 38's second bench round, one call after stop31/extras.sh 3, 1 and 2 on a fresh warm machine
# (carry .device and .w38): which inputs the device pass takes on the bench scenes
# (readset_check.py), then the timing bench on three scenes in the other order (old, then new).
source docs/results/gpu/issue10/stop31/env.sh
T0=$SECONDS
python3 docs/results/gpu/issue10/stop38/readset_check.py cuda_ad_rgb $S ${D//-D /} > /tmp/readset_check.log 2>&1
grep "frame inputs" /tmp/readset_check.log | tee $OUT/readset_check.txt; tail -n 5 /tmp/readset_check.log | cut -c1-300
echo "readset_check done after $((SECONDS - T0)) s"
SCENES="scenes/armadillo_glass.xml scenes/sponza_mirror.xml scenes/many_objects.xml" \
  timeout $((590 - SECONDS + T0)) bash docs/results/gpu/issue10/stop38/bench.sh 2 "old new"
echo "bench done after $((SECONDS - T0)) s"
