#!/usr/bin/env bash
# Stop 43's GPU run (after stop31/extras.sh 3, 1, 2 on the same warm machine; carry .device):
# $1 = wall: wall.py on the five bench scenes; $1 = bench: the timing bench on this stop's code
# (stop34/bench.sh, whose table now has the paired Gain with two frames in flight), round $2.
source docs/results/gpu/issue10/stop31/env.sh
mkdir -p $OUT
if [ "$1" = wall ]; then
  timeout 560 python3 docs/results/gpu/issue10/stop43/wall.py $S $D 2>&1 | grep -v "^\s*$" | tee $OUT/wall.txt
elif [ "$1" = bench ]; then
  STOP=43 bash docs/results/gpu/issue10/stop34/bench.sh new ${2:-1}
fi
if [ "$1" = timeline ]; then
  timeout 560 python3 docs/results/gpu/issue10/stop43/timeline.py $S $D 2>&1 | grep -E "gap|rror" | tee $OUT/timeline.txt
fi
if [ "$1" = copied ]; then  # the gap split at the interop copy (timeline.py with COPIED=1)
  COPIED=1 timeout 560 python3 docs/results/gpu/issue10/stop43/timeline.py $S $D 2>&1 | grep -E "gap|copy done|rror" | tee $OUT/timeline_copied.txt
fi
