#!/usr/bin/env bash
# Stop 35's GPU run, part 1: the outline test (primary.OUTLINES, `ties` against `silhouettes`).
# scripts/primary_stage.py (the primary stage's kernel with either test, and camera rays), then
# scripts/refine_ab.py --compare outline per scene (silhouettes / ties / RT, paired, one process per
# scene, refine=auto: the trace stage's launch). After stop31/extras.sh 1 and 2; carry .device.
source docs/results/gpu/issue10/stop31/env.sh
R=/tmp/o35_$1; mkdir -p $R; T0=$SECONDS
timeout 150 python3 scripts/primary_stage.py --variant cuda_ad_rgb $S $D -o $R/primary_stage.txt > $R/primary_stage.log 2>&1
grep -A3 "refined" $R/primary_stage.txt | grep -v "^--"
for s in $S; do
  timeout 110 python3 scripts/refine_ab.py --compare outline --variant cuda_ad_rgb --repeats 21 $s $D > $R/outline_$(basename $s .xml).txt 2>&1
  tail -1 $R/outline_$(basename $s .xml).txt
done
echo "after $((SECONDS - T0)) s"
tar -cJf $OUT/o35_$1.tar.xz -C /tmp o35_$1
