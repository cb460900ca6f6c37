#!/usr/bin/env bash
# Stop 73's CPU A/B of the probes: stop 69's partial_diag.py (whole objects, then with a part) at 320x180, the tree
# before (e06ce72's package, unpacked in $BEFORE) and this tree in turn, one process each, N rounds:
#   BEFORE=/tmp/before; rm -rf $BEFORE && mkdir $BEFORE && git archive e06ce72 hybrid_integrator plugins | tar -x -C $BEFORE
#   bash docs/results/gpu/issue10/stop73/cpu_ab.sh N SCENE FRACTION
set -euo pipefail
n=$1; scene=$2; fraction=$3
for i in $(seq $n); do
  for tree in before after; do
    [ $tree = before ] && pp=$BEFORE || pp=$PWD
    echo "== $tree $i"
    PYTHONPATH=$pp .venv/bin/python docs/results/gpu/issue10/stop69/partial_diag.py --fraction $fraction --frames 12 \
      -D resx=320 -D resy=180 -D models_dir=../shared/scenes/models -D showcase_dir=../shared/scenes/cbox \
      -D sponza_dir=../shared/scenes/sponza-dabrovic -D dining_dir=../shared/scenes/dining-room scenes/$scene.xml 2>&1 \
      | grep -v "^mode\|^Warn\|jit_"
  done
done
