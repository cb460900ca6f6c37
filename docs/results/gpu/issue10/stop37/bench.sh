#!/usr/bin/env bash
# Stop 37's timing bench (items 1, 2, 4, 5): this stop's code (new: raster_ahead="auto", on with
# interop) and stop 36's final tree (old: 2b71198 in the git-excluded .w37/, made with
# `rm -rf .w37 && mkdir .w37 && git archive 2b71198 hybrid_integrator plugins scripts scenes | tar -x -C .w37`),
# in the order of $2 ("new old" by default); $1: the round. After stop31/extras.sh 1 and 2; carry .device and .w37.
for tree in ${2:-new old}; do STOP=37 OLD=.w37 bash docs/results/gpu/issue10/stop34/bench.sh $tree $1; done
