#!/usr/bin/env bash
# Stop 66: the showcase's two trace-stage times (stop 65: 4.97-4.98 or 5.18-5.22 ms on the H100), or
# those of $SCENE (default showcase), one process per tree, the trees in turn for ROUNDS rounds, on one warm device machine (after
# stop31/extras.sh 1-6). Each TREE is a folder holding hybrid_integrator/ and plugins/ (. for this
# tree; the others unpacked untracked, e.g. `git archive d759ad9 hybrid_integrator plugins | tar -x -C ab_old`),
# imported first; scripts/frame_profile.py prints the median stage times of 25 frames and the last
# frame's kernels, of which the trace stage's are kept here.
#   [SCENE=dining_room] bash docs/results/gpu/issue10/stop66/trace_mode.sh ROUNDS TREE...
source docs/results/gpu/issue10/stop31/env.sh
rounds=$1; shift
scene=${SCENE:-showcase}
DS=$(for kv in $D; do case $kv in *=*) grep -q "\$${kv%%=*}" scenes/$scene.xml && echo "-D $kv";; esac; done)
for ((round = 1; round <= rounds; round++)); do
  for tree in "$@"; do
    [ -d $tree/plugins ] && ln -sfn ../plugins $tree/hybrid_integrator/plugins
    echo "== round $round tree $tree: $(cd /tmp && PYTHONPATH="$OLDPWD/$tree:$PYTHONPATH" python3 -c 'import hybrid_integrator as h; print(h.__file__)' 2>&1 | tail -1)"
    PYTHONPATH="$PWD/$tree:$PYTHONPATH" timeout 120 python3 scripts/frame_profile.py scenes/$scene.xml --variant cuda_ad_rgb \
      --frames 25 --kernels --top 0 $DS 2>&1 | grep -E "^($scene|trace |Traceback|[A-Za-z]*Error)" | cut -c1-200
  done
done
