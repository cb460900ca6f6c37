#!/usr/bin/env bash
# Stop 35's GPU run, part 5: does keeping the guides out of the lighting kernel on CUDA (c24ae2b)
# pay, on one machine? ab.sh suggested it (Sponza's trace stage 12.77 against 12.90 ms); final.sh,
# on another start, gave 12.91. The bench on the showcase, Sponza and the 226 objects, in turn,
# two rounds: this code (new) and 9eb161e (kept: the git-excluded .w35/,
# `rm -rf .w35 && mkdir .w35 && git archive 9eb161e hybrid_integrator plugins scripts scenes | tar -x -C .w35`).
# After stop31/extras.sh 1 and 2; carry .device and .w35.
export SCENES="scenes/showcase.xml scenes/sponza_mirror.xml scenes/many_objects.xml"
for round in 1 2; do
  for tree in new kept; do OLD=.w35 bash docs/results/gpu/issue10/stop35/bench.sh $tree b$round; done
done
