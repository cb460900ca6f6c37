#!/usr/bin/env bash
# Stop 41's timing bench (items 1, 2, 4, 5): this stop's code (new) and stop 40's final main (old:
# ec27cdb in the git-excluded .w41/), in the order of $2 ("new old" by default); $1: the round;
# $SCENES: a subset of the five. After stop31/extras.sh 3, 1 and 2; carry .device and .w41.
for tree in ${2:-new old}; do STOP=41 OLD=.w41 bash docs/results/gpu/issue10/stop34/bench.sh $tree $1; done
