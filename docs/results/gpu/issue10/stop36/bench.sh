#!/usr/bin/env bash
# Stop 36's GPU runs B: the timing bench (items 1, 2, 4, 5), this stop's code (new) and stop 35's
# final tree (old: dae1518 in the git-excluded .w36/, made with
# `rm -rf .w36 && mkdir .w36 && git archive dae1518 hybrid_integrator plugins scripts scenes | tar -x -C .w36`),
# one after the other; $1: the round. After stop31/extras.sh 1 and 2; carry .device and .w36.
for tree in new old; do STOP=36 OLD=.w36 bash docs/results/gpu/issue10/stop34/bench.sh $tree $1; done
