#!/usr/bin/env bash
# Stop 39, the bench's second call (after stop31/extras.sh 3, 1 and 2 on the same warm machine;
# carry .device and .w39): the timing bench on Sponza and the 226 objects, old tree first this
# time, then scripts/budget_benchmark.py (item 4: the budgets on the camera path, 50 frames) on
# this stop's code.
source docs/results/gpu/issue10/stop31/env.sh
T0=$SECONDS
SCENES="scenes/sponza_mirror.xml scenes/many_objects.xml" bash docs/results/gpu/issue10/stop39/bench.sh 1 "old new"
echo "bench done after $((SECONDS - T0)) s"
mkdir -p /tmp/budget
timeout $((590 - SECONDS + T0)) python3 scripts/budget_benchmark.py --variant cuda_ad_rgb --frames 50 --resx 1280 --resy 720 \
  --importance 0.01 -o /tmp/budget/budget > /tmp/budget/budget.log 2>&1
echo "budget rc=$? after $((SECONDS - T0)) s"; grep "^|" /tmp/budget/budget.md | head -14
tar -cJf $OUT/budget.tar.xz -C /tmp budget
