#!/usr/bin/env bash
# Stop 38's last run, one call after stop31/extras.sh 3, 1 and 2 on the same warm machine (carry
# .device and .w38): the trace call new against old (trace_ab.sh), which inputs the device pass
# takes on the bench scenes (readset_check.py), then the timing bench new against old on three of
# them (bench.sh: Armadillo, Sponza with its textures, the 226 objects).
source docs/results/gpu/issue10/stop31/env.sh
T0=$SECONDS
bash docs/results/gpu/issue10/stop38/trace_ab.sh | grep -v "^  rows\|^  replay"
echo "trace_ab done after $((SECONDS - T0)) s"
python3 docs/results/gpu/issue10/stop38/readset_check.py cuda_ad_rgb $S ${D//-D /} 2>&1 | grep "frame inputs" | tee $OUT/readset_check.txt
echo "readset_check done after $((SECONDS - T0)) s"
SCENES="scenes/armadillo_glass.xml scenes/sponza_mirror.xml scenes/many_objects.xml" \
  timeout $((590 - SECONDS + T0)) bash docs/results/gpu/issue10/stop38/bench.sh 1 "new old"
echo "bench done after $((SECONDS - T0)) s"
