#!/usr/bin/env bash
# Stop 45: every git-excluded carry of the issue-10 device runs, made on a fresh checkout (after
# `bash scripts/install.sh`, from the repository root): .device (../shared/tools/device-bundle.sh,
# then without colour-science's 76 MB htmlcov/, so that the tracked tree, .device and an old tree
# fit a call's 64 MiB), .device_x1 and .device_x2 (Open Image Denoise's libraries in two parts,
# cffi, pycparser, tqdm: stop31/README.md; since stop 46 also flip-evaluator, which the bench's
# accuracy needs and the bundle lacks), .device_x3 (the bench scenes' files that
# scenes/{armadillo_glass,showcase,sponza_mirror,dining_room}.xml name, from ../shared/scenes), and
# the old tree $1 (default e30b528) in .w44. Use: stop31/extras.sh 3, 1, 2 in back-to-back calls
# (the machine forgets /tmp after 30 s idle), then the run's script carrying .device and .w44.
# Since stop 62 (the tracked tree had grown to 41 MB): no carry holds more than ~17 MB. The bundle's
# site packages leave .device (which keeps the GL packages and the prelude) for .device_x5 and
# .device_x6, Open Image Denoise is split over .device_x1, _x2 and _x4, the scenes stay in _x3:
# stop31/extras.sh 1 ... 6, in any order, then the run carrying .device.
set -euo pipefail
for d in .device .device_x1 .device_x2 .device_x3 .device_x4 .device_x5 .device_x6 .w44 .w45s; do
  grep -qx "/$d/" .git/info/exclude 2>/dev/null || echo "/$d/" >> .git/info/exclude
done
split_over() {  # archive (in /tmp) carry...: the archive in as many parts as carries, ARCHIVE.pK-of-N
  local archive=$1; shift
  (cd /tmp && rm -f $archive.p? && split -n $# -d -a 1 $archive $archive.p)
  local k=0; for d in "$@"; do mv /tmp/$archive.p$k $d/$archive.p$k-of-$#; k=$((k + 1)); done
}
rm -rf .device_x1 .device_x2 .device_x3 .device_x4 .device_x5 .device_x6
mkdir -p .device_x1 .device_x2 .device_x3 .device_x4 .device_x5 .device_x6
bash ../shared/tools/device-bundle.sh
rm -rf /tmp/device-bundle/site/colour/htmlcov
# since stop 52, for room in a call's 64 MiB (the tracked tree had grown to 34 MiB): the headers, and
# the Mitsuba plugins that no scene, script or code path of this project loads (media and volumes,
# polarization, curves, ellipsoids, SDF grids, the particle tracer, sensors and films it does not
# use): 37 of the plugins' 84 MB. A run that needs one fails with Mitsuba's "plugin not found".
rm -rf /tmp/device-bundle/site/{mitsuba,drjit}/include /tmp/device-bundle/site/mitsuba/{cmake,pkgconfig}
for p in volpath volpathmis ptracer ellipsoids ellipsoidsmesh bsplinecurve linearcurve sdfgrid timed_sunsky hair \
         measured measured_polarized polarizer retarder pplastic stokes specfilm heterogeneous homogeneous \
         gridvolume constvolume sggx hg rayleigh tabphase blendphase isotropic irradiancemeter radiancemeter batch moment; do
  rm -f /tmp/device-bundle/site/mitsuba/plugins/$p.so
done
tar -cJf /tmp/site.tar.xz -C /tmp/device-bundle/site . && rm -f .device/site.tar.xz && split_over site.tar.xz .device_x5 .device_x6
S=.venv/lib/python3.11/site-packages
rm -rf /tmp/oidnb && mkdir -p /tmp/oidnb/pyoidn/oidn/lib
cp $S/pyoidn/*.py /tmp/oidnb/pyoidn/ && cp -a $S/pyoidn-2.5.1.0.dist-info /tmp/oidnb/
(cd $S/pyoidn/oidn/lib && cp -a libOpenImageDenoise.so libOpenImageDenoise.so.2 libOpenImageDenoise.so.2.5.1 \
  libOpenImageDenoise_core.so.2.5.1 libOpenImageDenoise_device_cuda.so.2.5.1 \
  libOpenImageDenoise_device_cpu.so.2.5.1 libtbb.so.12 libtbb.so.12.19 /tmp/oidnb/pyoidn/oidn/lib/)
tar -cJf /tmp/oidn.tar.xz -C /tmp/oidnb . && split_over oidn.tar.xz .device_x1 .device_x2 .device_x4
python3 -m pip download -q --no-deps --only-binary=:all: --python-version 3.12 --implementation cp \
  --platform manylinux_2_17_x86_64 --platform manylinux2014_x86_64 -d .device_x2 cffi pycparser tqdm flip-evaluator
rm -rf /tmp/scn && mkdir -p /tmp/scn
for f in $(grep -ho '\$[a-z_]*_dir/[^"]*' scenes/armadillo_glass.xml scenes/showcase.xml scenes/sponza_mirror.xml scenes/dining_room.xml | sort -u); do
  case $f in
    \$dining_dir/*) src=dining-room/${f#\$dining_dir/};;
    \$models_dir/*) src=models/${f#\$models_dir/};;
    \$showcase_dir/*) src=cbox/${f#\$showcase_dir/};;
    \$sponza_dir/*) src=sponza-dabrovic/${f#\$sponza_dir/};;
  esac
  mkdir -p /tmp/scn/$(dirname $src) && cp ../shared/scenes/$src /tmp/scn/$src
done
tar -cJf .device_x3/scn.tar.xz -C /tmp/scn .
rm -rf .w44 && mkdir .w44 && git archive ${1:-e30b528} hybrid_integrator plugins scenes scripts | tar -x -C .w44
du -sh .device .device_x* .w44
