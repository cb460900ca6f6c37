#!/usr/bin/env bash
# Owed by stop 34 (prepared, not run: its device time ran out). It answers whether 8e51649 (the
# lighting stage keeps every target; the composition calls no BSDF) made the RT baseline's trace
# stage faster, as its only runs suggested (Sponza 12.12 against 12.86-12.88 ms), or whether that
# machine did. Make the old tree first, locally:
#   rm -rf .w33 && mkdir .w33 && git archive 1f429f1 hybrid_integrator plugins scripts scenes | tar -x -C .w33
# Then, on one warm machine: stop31/extras.sh 1 and 2, then this script (carry .device and .w33).
# Also history.sh, with history_cost.py now rendering 1 spp (Sponza's and the Armadillo's rows).
set -u
for round in 1 2; do
  bash docs/results/gpu/issue10/stop34/bench.sh new n$round
  bash docs/results/gpu/issue10/stop34/bench.sh old o$round
done
