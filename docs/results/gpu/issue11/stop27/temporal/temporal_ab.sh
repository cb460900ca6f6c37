# moving camera with and without history on the GPU: MOTION_FRAMES = 6 (this tree) and 16 (before)
source scripts/gpu_scenes.sh
for s in showcase sponza_mirror; do
  for m in 6 16; do
    python3 -c "
import runpy, sys
import hybrid_integrator.temporal as T
T.MOTION_FRAMES = $m
sys.argv = ['scripts/temporal_path.py', 'scenes/$s.xml', '--variant', 'cuda_ad_rgb'] + '$D'.split() + ['-o', '$OUT/m$m']
runpy.run_path('scripts/temporal_path.py', run_name='__main__')" > $OUT/${s}_m$m.log 2>&1
    echo "$s MOTION_FRAMES=$m rc=$?"; tail -1 $OUT/m$m/$s.md
  done
done
tar -czf $OUT/temporal.tgz -C $OUT m6 m16 && rm -rf $OUT/m6 $OUT/m16
