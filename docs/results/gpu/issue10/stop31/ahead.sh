#!/usr/bin/env bash
# Stop 31, second GPU run: the raster pass drawn ahead (this stop's code) against stop 30's code
# (2ef826a, copied into the git-excluded .device/base), one H200, cuda_ad_rgb, 1280x720.
# Needs extras.sh (calls 1 and 2) on the same machine first. Everything lands in $OUT/r.tar.xz.
source docs/results/gpu/issue10/stop31/env.sh
ln -sfn ../plugins .device/base/hybrid_integrator/plugins
R=/tmp/r; mkdir -p $R
bench() { python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy --max-path-spp 1 $S --budgets $D -o "$1"; }
# 1. in one process, blocks of still frames with raster_ahead on / off / the RT baseline, 2 rounds
python3 scripts/raster_ahead.py --variant cuda_ad_rgb $S $D --rounds 2 -o $R/raster_ahead.json > $R/raster_ahead.txt 2>&1
cat $R/raster_ahead.txt | grep -v Warn
# 2. the timing bench, new and base in turn, two rounds
for k in 1 2; do
  bench $R/bench_new$k > $R/bench_new$k.log 2>&1
  (cd .device/base && PYTHONPATH=$PWD:$PYTHONPATH bench $R/bench_base$k > $R/bench_base$k.log 2>&1)
  for c in new base; do echo "== $c $k"; grep -A7 "^| scene" $R/bench_$c$k/bench.md | tail -5; done
done
# 3. host phases of the Armadillo's default frame, this stop's code
python3 scripts/host_phases.py --variant cuda_ad_rgb --resx 1280 --resy 720 --frames 40 --budget 0 --still scenes/armadillo_glass.xml $D > $R/host_phases.txt 2>&1
grep -E "^budget|host_ms" $R/host_phases.txt
tar -cJf $OUT/r.tar.xz -C /tmp r
