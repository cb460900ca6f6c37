#!/usr/bin/env bash
# Stop 41: the three scenes whose paired Gain sat near 1.0 in run1.sh and run2.sh (showcase, Sponza,
# the dining room), three more rounds of the bench as there (max_depth -1). After
# stop31/extras.sh 3, 1 and 2 on the same warm machine; carry .device. Outputs: $OUT/s41_{3,4,5}_new.tar.xz.
for round in 3 4 5; do
  SCENES="scenes/showcase.xml scenes/sponza_mirror.xml scenes/dining_room.xml" STOP=41 \
    bash docs/results/gpu/issue10/stop34/bench.sh new $round
done
