#!/usr/bin/env bash
# The GPU measurements of the compute-shader visibility pass (raster/compute.py; docs/results/README.md,
# stop 23): the probe (draw against compute, per stage), the bench without accuracy with each
# method (--raster draw, --raster compute: the default on CUDA), then the triangle scaling, the trace
# overhead and the budgets with the default. On the device machine, from the repository root, with
# the bundle (../shared/tools/device-bundle.sh), the shared scenes as .device/scenes.tar.xz and
# pyoidn in /tmp/oidn_site (as for gpu_issue11.sh):
#   source .device/prelude.sh; ln -sfn ../plugins hybrid_integrator/plugins; bash scripts/gpu_raster_compute.sh PART
# PART: "bench" (the probe and both benches) or "scripts" (scaling, trace overhead, budgets); a
# device command ends at 600 s, so each part is one command, packed into $OUT/results.tgz as it goes.
R=$OUT/r; mkdir -p $R
source scripts/gpu_scenes.sh  # $S, $D, pyoidn
SCENES="armadillo_glass showcase sponza_mirror dining_room many_objects"
B="python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy --max-path-spp 1"
pack() { echo "$1 rc=$2"; tar -czf $OUT/results.tgz -C $OUT r; }
if [ "$1" = bench ]; then
  python3 scripts/raster_compute_probe.py --variant cuda_ad_rgb $(for s in $SCENES; do echo scenes/$s.xml; done) $D > $R/probe.txt 2>&1; pack probe $?
  for m in draw compute; do
    $B --raster $m $(for s in $SCENES; do echo scenes/$s.xml; done) $D -o $R/$m > $R/$m.log 2>&1; pack "bench $m" $?
  done
else
  $B --scaling triangles --values 10000 100000 1000000 5000000 -o $R/scaling_triangles > $R/scaling.log 2>&1; pack scaling $?
  python3 scripts/trace_overhead.py --variant cuda_ad_rgb --resx 1280 --resy 720 -o $R/trace_overhead > $R/trace.log 2>&1; pack trace $?
  python3 scripts/budget_benchmark.py --variant cuda_ad_rgb --resx 1280 --resy 720 --frames 50 -o $R/budget > $R/budget.log 2>&1; pack budget $?
fi
rm -rf $R
