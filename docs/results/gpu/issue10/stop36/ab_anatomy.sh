#!/usr/bin/env bash
# Stop 36's GPU run D: scripts/gain_anatomy.py (this stop's) on this stop's code (new) and on stop
# 35's (old: dae1518 in the git-excluded .w36/, see bench.sh) in alternating processes, three
# rounds, on the showcase, Sponza and the 226 objects. After stop31/extras.sh 1 and 2; carry .device and .w36.
source docs/results/gpu/issue10/stop31/env.sh
ln -sfn ../plugins .w36/hybrid_integrator/plugins
S3="scenes/showcase.xml scenes/sponza_mirror.xml scenes/many_objects.xml"
for r in 1 2 3; do
  timeout 90 python3 scripts/gain_anatomy.py --variant cuda_ad_rgb --repeats 21 $S3 $D > $OUT/anatomy_new_$r.md 2>&1
  PYTHONPATH="$PWD/.w36:$PYTHONPATH" timeout 90 python3 scripts/gain_anatomy.py --variant cuda_ad_rgb --repeats 21 $S3 $D > $OUT/anatomy_old_$r.md 2>&1
done
for f in $OUT/anatomy_*.md; do echo "== $f"; cut -d'|' -f2-9 $f | tail -3; done
