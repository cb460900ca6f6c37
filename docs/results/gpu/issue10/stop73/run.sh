#!/usr/bin/env bash
# Stop 73's device runs, from the repository root on a warm machine, after
# `bash docs/results/gpu/issue10/stop31/extras.sh N` for N = 1 ... 6, each carrying .device_xN, with .device carried
# (both made by `bash docs/results/gpu/issue10/stop45/carries.sh`).
# Every mode but `bench` compares two trees, one process each, in turn: "before" is e06ce72 (main at this stop's
# start) in .w44, carried, made by
#   rm -rf .w44 && mkdir .w44 && git archive e06ce72 hybrid_integrator plugins | tar -x -C .w44 && ln -sfn ../plugins .w44/hybrid_integrator/plugins
# and "after" is the working tree with the paths' latency applied (`git apply docs/results/gpu/issue10/stop73/diffs/path_latency.diff`;
# tried and not kept, see the README).
#   bash docs/results/gpu/issue10/stop73/run.sh bench           # hybrid bench's timing rows on e06ce72 alone (.w44)
#   bash docs/results/gpu/issue10/stop73/run.sh benchab         # the same, after / before / after
#   bash docs/results/gpu/issue10/stop73/run.sh budgetab        # budget_benchmark.py (item 4, 226 objects' path), before / after
#   bash docs/results/gpu/issue10/stop73/run.sh diag FRACTION SCENE...  # stop 69's partial_diag.py (whole objects, then
#     with a part) at FRACTION of the all-candidates trace, before / after, $ROUNDS rounds (default 3)
#   bash docs/results/gpu/issue10/stop73/run.sh probe SCENE...  # stop 69's partial_probe.py at 50 and 75 %, before / after
#   bash docs/results/gpu/issue10/stop72/run.sh ab SCENE...     # (stop 72's) the same probe at 25 and 50 % with the RT row
# A run here prints `PYTHONPATH=… python3 -P`: -P keeps the working directory off sys.path, so .w44 is imported.
source docs/results/gpu/issue10/stop31/env.sh
mkdir -p $OUT; T0=$SECONDS
mode=$1; shift
benches="scenes/armadillo_glass.xml scenes/showcase.xml scenes/sponza_mirror.xml scenes/dining_room.xml"
tree_path() { [ $1 = before ] && echo $PWD/.w44 || echo $PWD; }
case $mode in
  bench)
    PYTHONPATH=$PWD/.w44:$PYTHONPATH timeout 570 python3 -P -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 \
      --no-accuracy --max-path-spp 1 --budgets 0.25 0.5 0.75 $D $benches -o $OUT/bench > $OUT/bench.log 2>&1
    echo "bench rc=$? after $((SECONDS - T0)) s"
    grep "^| [a-z_]* | [0-9]\|^| hybrid\|^| rt-" $OUT/bench/bench.md ;;
  benchab)
    n=0
    for tree in after before after; do
      n=$((n + 1))
      PYTHONPATH=$(tree_path $tree):$PYTHONPATH timeout 190 python3 -P -m hybrid_integrator.cli bench --variant cuda_ad_rgb \
        --frames 20 --no-accuracy --max-path-spp 1 --budgets 0.25 0.5 0.75 $D $benches -o $OUT/bench_${n}_$tree \
        > $OUT/bench_${n}_$tree.log 2>&1
      echo "$tree rc=$?"; grep "^| hybrid@\|^| rt-" $OUT/bench_${n}_$tree/bench.md
    done ;;
  budgetab)
    for tree in before after; do
      PYTHONPATH=$(tree_path $tree):$PYTHONPATH timeout 200 python3 scripts/budget_benchmark.py --variant cuda_ad_rgb \
        --frames 50 --resx 1280 --resy 720 --importance 0.01 -o $OUT/budget_$tree > $OUT/budget_$tree.log 2>&1
      echo "$tree rc=$?"; grep "^RT baseline / 50\|^As a renderer\|^| nested\|^| greedy" $OUT/budget_$tree.md
    done ;;
  probe)
    for s in "$@"; do
      for tree in before after; do
        echo "== tree $tree"
        PYTHONPATH=$(tree_path $tree):$PYTHONPATH timeout 170 python3 docs/results/gpu/issue10/stop69/partial_probe.py \
          --variant cuda_ad_rgb --budgets 0.5 0.75 --frames 20 --gt-spp 512 $D scenes/$s.xml 2>&1 \
          | grep -v "Warn\|jit_optix_log\|^	\|^Info"
      done
    done | tee $OUT/probe_50_75_ab.txt ;;
  diag)
    fraction=$1; shift
    for round in $(seq ${ROUNDS:-3}); do
      for s in "$@"; do
        for tree in before after; do
          echo "== round $round, tree $tree"
          PYTHONPATH=$(tree_path $tree):$PYTHONPATH timeout $((590 - SECONDS + T0)) python3 docs/results/gpu/issue10/stop69/partial_diag.py \
            --variant cuda_ad_rgb --fraction $fraction --frames ${FRAMES:-14} $D scenes/$s.xml 2>&1 \
            | grep -v "Warn\|jit_optix_log\|^	\|^Info"
        done
      done
    done | tee -a $OUT/diag_$fraction.txt ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
