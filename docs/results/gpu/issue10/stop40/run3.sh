#!/usr/bin/env bash
# Stop 40: more bench rounds on the showcase alone (item 2's Gain there: 1.060, 0.996, 0.968, 1.064
# on this stop's code in rounds 1-4 against 1.066, 1.063, 1.058, 1.020 on stop 39's), new and old in
# turn, rounds 5-8. After stop31/extras.sh 3, 1 and 2; carry .device and .w40.
for round in 5 6 7 8; do
  SCENES=scenes/showcase.xml bash docs/results/gpu/issue10/stop40/bench.sh $round "new old" | grep -v "^## \|^$\|^ method\|^---"
done
