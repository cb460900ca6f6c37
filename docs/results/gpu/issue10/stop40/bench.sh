#!/usr/bin/env bash
# Stop 40's timing bench (items 1, 2, 4, 5): this stop's code (new) and stop 39's final main (old:
# 93a4593 in the git-excluded .w40/), in the order of $2 ("new old" by default); $1: the round;
# $SCENES: a subset of the five. After stop31/extras.sh 3, 1 and 2; carry .device and .w40.
for tree in ${2:-new old}; do STOP=40 OLD=.w40 bash docs/results/gpu/issue10/stop34/bench.sh $tree $1; done
