#!/usr/bin/env bash
# Stop 69's device runs, from the repository root on a warm machine, after
# `bash docs/results/gpu/issue10/stop31/extras.sh N` for N = 1 ... 6, each carrying .device_xN, with .device carried
# (both made by `bash docs/results/gpu/issue10/stop45/carries.sh`).
#   bash docs/results/gpu/issue10/stop69/run.sh probe SCENE...   # partial_probe.py: budgets of 25/50/75 % of the
#     all-candidates trace, an object whole or nothing against a part of one more object, time and FLIP
#   bash docs/results/gpu/issue10/stop69/run.sh bench SCENE...   # the timing bench's budgets (item 4's 50 % frame
#     against the RT baseline; 25/50/75 % rows), default frame, no ground truth
#   bash docs/results/gpu/issue10/stop69/run.sh diag SCENE...    # partial_diag.py: why 25 % frames with partial trace less
#   bash docs/results/gpu/issue10/stop69/run.sh budget           # budget_benchmark.py: item 4 on the 226 objects' path
source docs/results/gpu/issue10/stop31/env.sh
mkdir -p $OUT; T0=$SECONDS
mode=$1; shift
scenes=$(for s in "$@"; do echo scenes/$s.xml; done)
case $mode in
  probe)
    for s in $scenes; do
      timeout $((590 - SECONDS + T0)) python3 docs/results/gpu/issue10/stop69/partial_probe.py --variant cuda_ad_rgb \
        $D $s 2>&1 | grep -v "Warn\|jit_optix_log\|^	\|^Info" | tee -a $OUT/partial_probe.txt
    done ;;
  bench)
    timeout $((590 - SECONDS + T0)) python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 \
      --no-accuracy --max-path-spp 1 --budgets 0.25 0.5 0.75 $D $scenes -o $OUT/bench > $OUT/bench.log 2>&1
    echo "bench rc=$? after $((SECONDS - T0)) s"
    grep "^| [a-z_]* | [0-9]\|^| hybrid\|^| rt-" $OUT/bench/bench.md ;;
  budget)
    timeout $((590 - SECONDS + T0)) python3 scripts/budget_benchmark.py --variant cuda_ad_rgb --frames 50 \
      --resx 1280 --resy 720 --importance 0.01 -o $OUT/budget > $OUT/budget.log 2>&1
    echo "budget rc=$? after $((SECONDS - T0)) s"; tail -30 $OUT/budget.md ;;
  diag)  # partial_diag.py: per frame at 25 %, whole against partial: what was traced, predicted against measured
    for s in $scenes; do
      timeout $((590 - SECONDS + T0)) python3 docs/results/gpu/issue10/stop69/partial_diag.py --variant cuda_ad_rgb \
        $D $s 2>&1 | grep -v "Warn\|jit_optix_log\|^	\|^Info" | tee -a $OUT/partial_diag.txt
    done ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
