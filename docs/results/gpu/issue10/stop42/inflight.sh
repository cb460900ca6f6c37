#!/usr/bin/env bash
# Stop 42: inflight_probe.py (what frames in flight would buy) on the five bench scenes. After
# stop31/extras.sh 3 on the same warm machine; carry .device. Output: $OUT/inflight.txt.
source docs/results/gpu/issue10/stop31/env.sh
for scene in $S; do
  timeout 100 python3 docs/results/gpu/issue10/stop42/inflight_probe.py $scene ${D//-D /} 2>&1 | grep "ms/frame"
done | tee $OUT/inflight.txt
