#!/usr/bin/env bash
# Stop 32's owed GPU run, part 1 of 2 (stop 32 was lent no device; run in stop 33: outputs in out/,
# read in ../stop33/README.md): the raster's refined pixels traced in the trace stage's launch (refine="trace") against the primary
# stage's kernel (refine="primary", the default) and the RT baseline, one process per round, two
# rounds. One H200, cuda_ad_rgb, 1280x720. A device run is three calls on one warm machine:
# stop31/extras.sh 1 (carry .device_x1), stop31/extras.sh 2 (carry .device_x2), then this script
# (carry .device); budgets.sh is part 2 (see stop31/README.md for the carries).
source docs/results/gpu/issue10/stop31/env.sh
R=/tmp/r; mkdir -p $R
for round in 1 2; do
  python3 scripts/refine_ab.py --variant cuda_ad_rgb --repeats 21 $S $D | tee $R/refine_ab_$round.md
done
tar -cJf $OUT/r.tar.xz -C /tmp r
