#!/usr/bin/env bash
# Stop 39's timing bench (items 1, 2, 4, 5): this stop's code (new) and stop 38's final main (old:
# 05e335b in the git-excluded .w39/), in the order of $2 ("new old" by default); $1: the round;
# $SCENES: a subset of the five. After stop31/extras.sh 3, 1 and 2; carry .device and .w39.
for tree in ${2:-new old}; do STOP=39 OLD=.w39 bash docs/results/gpu/issue10/stop34/bench.sh $tree $1; done
