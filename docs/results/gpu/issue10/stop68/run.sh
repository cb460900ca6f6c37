#!/usr/bin/env bash
# Stop 68's device runs, from the repository root on a warm machine, after
# `bash docs/results/gpu/issue10/stop31/extras.sh N` for N = 1 ... 6, each carrying .device_xN, with .device carried
# (both made by `bash docs/results/gpu/issue10/stop45/carries.sh`).
#   bash docs/results/gpu/issue10/stop68/run.sh filed SCENE...  # items 2a, 4 and 5 on the frame issue 10 was filed
#     against: the paper's effects (shadows, reflections, refractions) and no denoiser, the default before issue 11
#     (441f583); the timing bench as stop 63's `run.sh gain` runs it
#   N=3 bash docs/results/gpu/issue10/stop68/run.sh refine SCENE  # the default frame's bench (no budgets), N processes per
#     refine mode in turn (trace: the refined pixels re-traced in the trace launch, auto's choice on CUDA; primary:
#     in the primary stage), for the load-dependent trace time (stops 65-68): does one mode avoid its slow time?
#   bash docs/results/gpu/issue10/stop68/run.sh probes SCENE... # crop_probe.py (the denoiser on crops), then
#     host_profile.py per scene (a budgeted frame's host time by Python function)
source docs/results/gpu/issue10/stop31/env.sh
mkdir -p $OUT; T0=$SECONDS
mode=$1; shift
scenes=$(for s in "$@"; do echo scenes/$s.xml; done)
case $mode in
  filed)
    timeout $((590 - SECONDS + T0)) python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 \
      --no-accuracy --max-path-spp 1 --budgets 0.5 --effects shadow,reflection,refraction --no-denoise $D $scenes \
      -o $OUT/gain_filed > $OUT/gain_filed.log 2>&1
    echo "filed rc=$? after $((SECONDS - T0)) s"
    grep "^| [a-z_]* | [0-9]\|^| hybrid\|^| rt-\|^| raster\|^| path" $OUT/gain_filed/bench.md ;;
  probes)
    python3 docs/results/gpu/issue10/stop68/crop_probe.py --variant cuda_ad_rgb $D > $OUT/denoise_crop.txt 2>&1
    for s in "$@"; do
      python3 docs/results/gpu/issue10/stop68/host_profile.py --variant cuda_ad_rgb $D scenes/$s.xml 2>&1 \
        | grep -v "Warn\|jit_optix_log\|^	\|^Info" > $OUT/host_profile_$s.txt
    done ;;
  refine)
    for n in $(seq ${N:-3}); do
      for r in trace primary; do
        timeout $((590 - SECONDS + T0)) python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 \
          --no-accuracy --max-path-spp 1 --budgets --refine $r $D $scenes -o $OUT/refine_${r}_$n > /dev/null 2>&1
        python3 -c "import json, sys; d = json.load(open(sys.argv[1]))[0]; m = {x['method']: x for x in d['methods']}; print(sys.argv[2], d['name'], 'trace stage hybrid %.3f rt %.3f; hybrid %.2f rt %.2f; paired Gain %.3f' % (m['hybrid']['stages_ms']['trace'], m['rt-baseline']['stages_ms']['trace'], d['hybrid_ms'], d['rt_ms'], d['gain_paired']['median']))" $OUT/refine_${r}_$n/bench.json "refine=$r process $n"
      done
    done ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
