#!/usr/bin/env bash
# Stop 35's GPU run, part 3: which change since stop 34's 1f429f1 moved the showcase's Gain (0.976-0.981
# with this stop's code, 1.016 / 0.993 with 1f429f1, bench_*). The bench on the showcase and Sponza,
# three trees in turn, two rounds: this stop's code (new), the same without 8e51649's lighting change
# (revert: the git-excluded .w35/, `git archive 9eb161e ... | tar -x -C .w35` with that one
# clock.mark line as before 8e51649), and 1f429f1 (old, .w33/). Carry .device, .w33, .w35.
export SCENES="scenes/showcase.xml scenes/sponza_mirror.xml"
for round in 1 2; do
  for tree in new revert old; do
    OLD=$([ $tree = revert ] && echo .w35 || echo .w33) bash docs/results/gpu/issue10/stop35/bench.sh $tree a$round
  done
done
