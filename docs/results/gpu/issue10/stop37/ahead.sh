#!/usr/bin/env bash
# Stop 37: scripts/ahead_probe.py on the five bench scenes (after stop31/extras.sh 1 and 2 on the
# same machine); $1 names the output ($OUT/ahead_$1.md)
source docs/results/gpu/issue10/stop31/env.sh
python3 scripts/ahead_probe.py --variant cuda_ad_rgb --repeats ${REPEATS:-21} $S $D 2>&1 | tee $OUT/ahead_${1:-1}.md
