#!/usr/bin/env bash
# Stop 40: scripts/frame_timeline.py on the showcase, this stop's package (new) and stop 39's (old,
# .w40), each in its own process, in turn, $1 rounds (3 by default): which launches of the default
# frame and of the RT baseline changed (the showcase's RT baseline traced 0.5-0.7 ms faster in two
# of four bench processes of the new code, its hybrid frame did not). After stop31/extras.sh 3, 1
# and 2; carry .device and .w40. Outputs: $OUT/timeline/{new,old}_N.txt.
source docs/results/gpu/issue10/stop31/env.sh
ln -sfn ../plugins .w40/hybrid_integrator/plugins
mkdir -p $OUT/timeline; ROOT=$PWD
for round in $(seq ${1:-3}); do
  for way in new old; do
    case $way in new) tree=$ROOT;; old) tree=$ROOT/.w40;; esac
    (cd $tree && PYTHONPATH=/tmp/site:/tmp/extra:$tree timeout 120 python3 scripts/frame_timeline.py --variant cuda_ad_rgb \
      --frames 20 $D scenes/showcase.xml > $OUT/timeline/${way}_$round.txt 2>&1)
    echo "$way $round rc=$?"
    python3 - $OUT/timeline/${way}_$round.txt <<'PY'
import re, sys
kind = None
for line in open(sys.argv[1]):
    if line.startswith("showcase.xml"):
        kind = line.split(",", 1)[1].split(":")[0].strip()
    elif line.startswith("frame time"):
        print(f"  {kind:32s} {line.split(':')[1].strip()}", end="")
    elif kind and re.match(r"^trace\s+\w+\s+JIT\s+921600\s+\d{4,}", line):
        print("  loop", line.split()[-1], end="")
    elif line.startswith("host ms by phase"):
        print()
PY
  done
done
