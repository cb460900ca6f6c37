#!/usr/bin/env bash
# Stop 42: copy_probe.py (the interop copy's host time, call by call) on the 226 objects, whose
# files are in the repository (no extras needed). Carry .device. Output: $OUT/copy_probe_many.txt
# (kept as outputs/copy_probe_many_objects.txt, OptiX's compile log left out).
source .device/prelude.sh
ln -sfn ../plugins hybrid_integrator/plugins
python3 docs/results/gpu/issue10/stop42/copy_probe.py scenes/many_objects.xml 2>&1 | grep -v "^jit\|^Info" \
  | tee $OUT/copy_probe_many.txt
