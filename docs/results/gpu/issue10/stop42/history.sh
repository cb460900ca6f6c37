#!/usr/bin/env bash
# Stop 42: history_probe.py (the kernel history's cost per frame) on the 226 objects and, after
# stop31/extras.sh 3, the bench scenes. Carry .device. Output: $OUT/history.txt.
source docs/results/gpu/issue10/stop31/env.sh
for scene in ${SCENES:-scenes/many_objects.xml}; do
  timeout 200 python3 docs/results/gpu/issue10/stop42/history_probe.py $scene ${D//-D /} 2>&1 | grep "history"
done | tee $OUT/history.txt
