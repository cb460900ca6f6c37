#!/usr/bin/env bash
# Stop 35's GPU bench (items 1, 2, 4, 5): stop 34's bench.sh with this stop's number, on this
# stop's code ($1 = new) or on stop 34's 1f429f1 ($1 = old: its tree in the git-excluded .w33/, made
# with `rm -rf .w33 && mkdir .w33 && git archive 1f429f1 hybrid_integrator plugins scripts scenes | tar -x -C .w33`).
# After stop31/extras.sh 1 and 2 on the same warm machine; carry .device (and .w33). $2: the round.
STOP=35 bash docs/results/gpu/issue10/stop34/bench.sh "$@"
