#!/usr/bin/env bash
# Stop 66: the committed fix (Rasterizer.pass_tables) on one warm device machine (after
# stop31/extras.sh 1-6), against the tree before it (4a5173c, unpacked untracked into ab_old/ by
# `git archive 4a5173c hybrid_integrator plugins scenes | tar -x -C ab_old`) and against main with
# the emitter array made and kept but a literal passed (ab_c/: 4a5173c unpacked the same way, then
# `patch -p1 -d ab_c < docs/results/gpu/issue10/stop66/ab_c.patch`): the showcase's trace stage in turn, 3 rounds, the
# dining room's once; then stop65/ab.sh's paired bench on the showcase (this tree against ab_old).
#   bash docs/results/gpu/issue10/stop66/confirm.sh [ab]
here=docs/results/gpu/issue10/stop66
bash $here/trace_mode.sh 3 . ab_old ab_c > $OUT/trace_mode_2.txt 2>&1
SCENE=dining_room bash $here/trace_mode.sh 1 . ab_old > $OUT/trace_mode_dining.txt 2>&1
for f in $OUT/trace_mode_2.txt $OUT/trace_mode_dining.txt; do
  echo "== $f (round tree trace-stage-ms; the trace stage's kernels of over 999 operations: hash ms)"
  grep -E "^== round|^(showcase|dining_room).xml" $f | paste - - | sed -E "s/.*round ([0-9]) tree ([^:]*):.*'trace': ([0-9.]+).*/\1 \2 \3/"
  grep -E "^trace +[0-9a-f]{8} +JIT +[0-9]+ +[0-9]{4,}" $f | awk '{print $2, $6}' | tr '\n' ' '; echo
  echo "tracebacks: $(grep -c Traceback $f)"
done
[ "${1:-}" = ab ] && bash docs/results/gpu/issue10/stop65/ab.sh showcase > $OUT/ab.txt 2>&1 && cut -c1-250 $OUT/ab.txt
