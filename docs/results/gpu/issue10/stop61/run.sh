#!/usr/bin/env bash
# Stop 61's device runs, from the repository root on a warm machine, after
# `bash docs/results/gpu/issue10/stop31/extras.sh 3`, `… 1`, `… 2` (scenes, Open Image Denoise,
# flip-evaluator), with .device carried (made by `bash docs/results/gpu/issue10/stop45/carries.sh`).
# Since stop 62 the carries are six: `extras.sh N` for N = 1 ... 6, each carrying .device_xN, then this.
#   bash docs/results/gpu/issue10/stop61/run.sh accuracy SCENE...  # the README table's bench, one process per
#     scene: hybrid bench --frames 20 --gt-spp 1024 --max-path-spp 16 (stop 49's, on this tree)
#   bash docs/results/gpu/issue10/stop61/run.sh albedo [SCENE...] [--budgets B...]  # stop60/turn_error.py: the
#     G-buffer's albedo as Mitsuba gives it (before 5fde3f7) and now, in turn with the RT baseline: time, relevance,
#     image error (default: the 226 objects' camera path)
#   bash docs/results/gpu/issue10/stop61/run.sh items   # issue 10's items 3, 4 and 2's scaling on this tree:
#     scripts/trace_overhead.py, scripts/budget_benchmark.py (50 frames), hybrid bench --scaling triangles,
#     and the timing bench of the 226 objects (item 1's ≤ 4 ms)
source docs/results/gpu/issue10/stop31/env.sh
mkdir -p $OUT; T0=$SECONDS
F='^(jit_optix|\t|Info|\s*$)'
mode=$1; shift
case $mode in
  accuracy)
    for s in "$@"; do
      timeout $((590 - SECONDS + T0)) python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 \
        --gt-spp 1024 --max-path-spp 16 $D scenes/$s.xml -o $OUT/$s > $OUT/$s.log 2>&1
      echo "$s rc=$? after $((SECONDS - T0)) s"
      rm -f $OUT/$s/*.exr
    done ;;
  albedo) [ $# -gt 0 ] && [ "${1#--}" = "$1" ] || set -- scenes/many_objects.xml "$@"
    timeout ${LIMIT:-$((590 - SECONDS + T0))} python3 docs/results/gpu/issue10/stop60/turn_error.py "$@" --variant cuda_ad_rgb $D \
      --frames ${FRAMES:-40} --side 'rt={"primary": "raytrace", "stage_times": false}' \
      --side 'mitsuba={"budget": true, "stage_times": false, "albedo": "mitsuba"}' \
      --side 'diffuse={"budget": true, "stage_times": false}' 2>&1 | grep -v -P "$F" | tee $OUT/albedo${RUN:-}.txt ;;
  items)
    timeout 150 python3 scripts/trace_overhead.py --variant cuda_ad_rgb --resx 1280 --resy 720 -o $OUT/trace_overhead \
      > $OUT/trace.log 2>&1
    echo "trace_overhead rc=$? after $((SECONDS - T0)) s"; grep -v -P "$F" $OUT/trace.log | tail -12
    timeout 200 python3 scripts/budget_benchmark.py --variant cuda_ad_rgb --frames 50 --resx 1280 --resy 720 \
      --importance 0.01 -o $OUT/budget > $OUT/budget.log 2>&1
    echo "budget rc=$? after $((SECONDS - T0)) s"; grep "RT / 50 % in turn" $OUT/budget.log
    grep "^| nested\|^| all\|^| RT" $OUT/budget.md 2>/dev/null
    timeout 150 python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy \
      --max-path-spp 1 -D resx=1280 -D resy=720 --scaling triangles --values 10000 100000 1000000 5000000 \
      -o $OUT/scaling_triangles > $OUT/scaling.log 2>&1
    echo "scaling rc=$? after $((SECONDS - T0)) s"; head -14 $OUT/scaling_triangles.md 2>/dev/null
    timeout $((590 - SECONDS + T0)) python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 \
      --no-accuracy --max-path-spp 1 --budgets 0.25 0.5 0.75 $D scenes/many_objects.xml -o $OUT/many_objects \
      > $OUT/many_objects.log 2>&1
    echo "many_objects rc=$? after $((SECONDS - T0)) s" ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
