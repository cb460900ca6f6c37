#!/usr/bin/env bash
# Stop 37: scripts/ahead_probe.py --path with a budget of about half the all-candidates trace time
# (the 226 objects 2.5 ms, the showcase 2.9 ms) -> $OUT/ahead_path_budget.md. After stop31/extras.sh 1 and 2.
source docs/results/gpu/issue10/stop31/env.sh
for spec in "scenes/many_objects.xml 2.5" "scenes/showcase.xml 2.9"; do
  set -- $spec
  python3 scripts/ahead_probe.py --path --set budget_ms=$2 --variant cuda_ad_rgb --repeats 21 $1 $D 2>&1
done | tee $OUT/ahead_path_budget.md
