#!/usr/bin/env bash
# Stop 52's device runs, from the repository root on a warm machine, after
# `bash docs/results/gpu/issue10/stop31/extras.sh 3`, `… 1`, `… 2` (scenes, Open Image Denoise,
# flip-evaluator: .device_x2 since stop 45's carries.sh), with .device carried.
#   bash docs/results/gpu/issue10/stop50/run.sh bench SCENE...   # the timing bench (owed since stop 51)
#   bash docs/results/gpu/issue10/stop52/run.sh paper SCENE...   # issue 10's item 5 as it reads: the bench with
#     the paper's effects (--effects shadow,reflection,refraction), FLIP against path at 1024 spp
#   bash docs/results/gpu/issue10/stop52/run.sh rivals SCENE...  # the same frame against path 1 spp (frozen) and
#     path + OIDN 'fast', in turn (stop50/probes.py rivals --property ...), denoised and not
#   bash docs/results/gpu/issue10/stop52/run.sh compare SCENE...  # one frame of each method with the paper's effects
#     and its FLIP against path at 1024 spp (hybrid compare --spp 1 --effects ...), a lighter check than `paper`
#   bash docs/results/gpu/issue10/stop52/run.sh overhead   # item 3: scripts/trace_overhead.py at many_objects.xml's
#     own max_depth (6) and unlimited (-1)
source docs/results/gpu/issue10/stop31/env.sh
R=/tmp/s52; mkdir -p $R $OUT; T0=$SECONDS
PAPER=shadow,reflection,refraction
mode=$1; shift
case $mode in
  paper) for s in "$@"; do
           timeout $((590 - SECONDS + T0)) python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 \
             --gt-spp 1024 --max-path-spp 1 --effects $PAPER $D scenes/$s.xml -o $OUT/paper/$s > $OUT/paper_$s.log 2>&1
           echo "$s rc=$? after $((SECONDS - T0)) s"
         done ;;
  compare) for s in "$@"; do  # Mitsuba refuses a parameter that the scene does not use: this scene's of $D only
             DS=$(for kv in $D; do case $kv in *=*) grep -q "\$${kv%%=*}" scenes/$s.xml && echo "-D $kv";; esac; done)
             timeout $((590 - SECONDS + T0)) python3 -m hybrid_integrator.cli compare --variant cuda_ad_rgb --spp 1 \
               --gt-spp 1024 --effects $PAPER $DS scenes/$s.xml -o $R/compare/$s > $R/compare_$s.log 2>&1
             echo "$s rc=$? after $((SECONDS - T0)) s"; grep "^|" $R/compare/$s/*.md 2>/dev/null
           done
           (cd $R && tar -cJf $OUT/compare.tar.xz compare/*/compare.json compare/*/compare.md compare/*/errors.png compare_*.log) ;;
  rivals) for props in "effects=$PAPER" "effects=$PAPER denoise=false"; do
            python3 docs/results/gpu/issue10/stop50/probes.py rivals --variant cuda_ad_rgb \
              $(for p in $props; do echo --property $p; done) \
              $(for s in "$@"; do echo scenes/$s.xml; done) $D 2>&1 | grep -v "^jit_\|^Info\|^\s"
          done | tee $OUT/rivals.txt ;;
  overhead) for depth in 6 -1; do
              timeout 200 python3 scripts/trace_overhead.py --variant cuda_ad_rgb --resx 1280 --resy 720 --max-depth $depth \
                -o $OUT/trace_overhead_depth$depth > $R/trace$depth.log 2>&1
              echo "max_depth $depth rc=$? after $((SECONDS - T0)) s"; tail -30 $R/trace$depth.log | grep -A3 '"fit"\|no_pixel'
            done ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
