#!/usr/bin/env bash
# Stop 38's timing bench (items 1, 2, 4, 5): this stop's code (new: the frozen functions given the
# read set of the scene snapshot) and stop 37's final tree (old: 85a092f in the git-excluded .w38/,
# made with `git archive 85a092f hybrid_integrator plugins scripts scenes | tar -x -C .w38`), in the
# order of $2 ("new old" by default); $1: the round. After stop31/extras.sh 1, 3 and 2; carry .device and .w38.
for tree in ${2:-new old}; do STOP=38 OLD=.w38 bash docs/results/gpu/issue10/stop34/bench.sh $tree $1; done
