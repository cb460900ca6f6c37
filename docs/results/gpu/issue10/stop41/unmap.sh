#!/usr/bin/env bash
# Stop 41: the visibility texture's unmap on a stream of its own behind Dr.Jit's (new) against main
# at ec27cdb (old, .w41: the unmap on Dr.Jit's stream). $1 = "images": ahead_images.py in both trees
# (drawn ahead vs drawn by the frame itself; the new tree's drawn-ahead images against the old's), then
# the bench round $2 in the order $3; else just the bench round $1 in the order $2. After
# stop31/extras.sh 3, 1 and 2; carry .device and .w41. Outputs: $OUT/s41_N_{new,old}.tar.xz.
H=docs/results/gpu/issue10/stop41
if [ "$1" = images ]; then
  (source docs/results/gpu/issue10/stop31/env.sh; ln -sfn ../plugins .w41/hybrid_integrator/plugins; ROOT=$PWD
   PYTHONPATH=/tmp/site:/tmp/extra:$ROOT python3 $H/ahead_images.py /tmp/ah_new.npz 2>&1 | grep -v "^\s\|jit_optix" | tail -18
   (cd .w41 && PYTHONPATH=/tmp/site:/tmp/extra:$ROOT/.w41 python3 $ROOT/$H/ahead_images.py /tmp/ah_old.npz 2>&1 | tail -1)
   python3 $H/compare.py /tmp/ah_new.npz /tmp/ah_old.npz)
  shift
fi
for tree in ${2:-new old}; do STOP=41 OLD=.w41 bash docs/results/gpu/issue10/stop34/bench.sh $tree $1; done
