#!/usr/bin/env bash
# The GPU measurements of issue 10 (docs/results/README.md): before → after in one run, then the
# scripts. On the device machine, from the repository root, with the bundle (../shared/tools/
# device-bundle.sh), the shared scenes as .device/scenes.tar.xz and the code of commit 8782a67 in
# .device/old (git archive 8782a67 hybrid_integrator plugins scenes):
#   source .device/prelude.sh; ln -sfn ../plugins hybrid_integrator/plugins; bash scripts/gpu_issue10.sh
R=$OUT/r; mkdir -p $R/before $R/after
source scripts/gpu_scenes.sh  # $S, $D
SCENES="armadillo_glass sponza_mirror showcase dining_room many_objects"
# before: the code at 8782a67, the same scenes, DR / RT / hybrid only (its scaling-point mode), 20 frames
(cd .device/old && ln -sfn ../plugins hybrid_integrator/plugins && for s in $SCENES; do
  PYTHONPATH=/tmp/site:$PWD timeout 300 python3 -m hybrid_integrator.cli bench --single $R/before/$s.json --scaling-point \
    --variant cuda_ad_rgb --frames 20 $D scenes/$s.xml > $R/before/$s.log 2>&1; echo "before $s rc=$?"; done)
# after: this checkout
B="python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy --max-path-spp 1"
$B $(for s in $SCENES; do echo scenes/$s.xml; done) $D -o $R/after > $R/after.log 2>&1; echo "after rc=$?"
python3 scripts/trace_overhead.py --variant cuda_ad_rgb --resx 1280 --resy 720 -o $R/trace_overhead > $R/trace.log 2>&1; echo "trace rc=$?"
python3 scripts/budget_benchmark.py --variant cuda_ad_rgb --resx 1280 --resy 720 --frames 50 -o $R/budget > $R/budget.log 2>&1; echo "budget rc=$?"
$B --scaling triangles --values 10000 100000 1000000 5000000 -o $R/scaling_triangles > $R/scaling.log 2>&1; echo "scaling rc=$?"
python3 scripts/readback_benchmark.py --variant cuda_ad_rgb $S/cbox/showcase_coloured_glass.xml -o $R/readback_showcase > $R/readback.log 2>&1; echo "readback rc=$?"
for s in showcase many_objects; do python3 scripts/frame_profile.py scenes/$s.xml --variant cuda_ad_rgb $D --frames 50 > $R/profile_$s.txt 2>&1; done
tar -czf $OUT/results.tgz -C $OUT r && rm -rf $R
