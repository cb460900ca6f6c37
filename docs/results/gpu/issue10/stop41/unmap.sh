#!/usr/bin/env bash
# Stop 41: the visibility texture's unmap on a stream of its own behind Dr.Jit's (new: a4b4b38, reverted) against main
# at ec27cdb (old, .w41: the unmap on Dr.Jit's stream): the bench round $1 in the order $2 (the images
# were checked before it with `python3 ahead_images.py /tmp/ah_new.npz` in the new tree). After
# stop31/extras.sh 3, 1 and 2; carry .device and .w41. Outputs: $OUT/s41_N_{new,old}.tar.xz.
for tree in ${2:-new old}; do STOP=41 OLD=.w41 bash docs/results/gpu/issue10/stop34/bench.sh $tree $1; done
