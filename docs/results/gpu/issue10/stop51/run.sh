#!/usr/bin/env bash
# Stop 51's device runs, from the repository root on a warm machine, after
# `bash docs/results/gpu/issue10/stop31/extras.sh 3`, `… 1`, `… 2` (scenes, Open Image Denoise),
# with .device carried (and .device_x4, the flip-evaluator wheel, for `selections`).
#   bash docs/results/gpu/issue10/stop51/run.sh items       # issue 10's items 3, 4 and 2's scaling on this tree:
#     scripts/trace_overhead.py, scripts/budget_benchmark.py (50 frames), hybrid bench --scaling triangles
#   bash docs/results/gpu/issue10/stop51/run.sh selections SCENE...  # what the budgets buy with each selector:
#     stop47/budget_flip.py --selections nested,greedy (25 / 50 / 75 % of the all-candidates trace time, FLIP)
#   bash docs/results/gpu/issue10/stop51/run.sh cost SCENE...   # scripts/history_cost.py on this tree and on
#     ac644ec (.w51 carried), in turn per scene ($SIDES: the order, default "new old")
#   bash docs/results/gpu/issue10/stop51/run.sh budget   # scripts/budget_benchmark.py again (this tree)
source docs/results/gpu/issue10/stop31/env.sh
[ -d .device_x4 ] && python3 -m zipfile -e .device_x4/flip_evaluator-*.whl /tmp/extra
R=/tmp/s51; mkdir -p $R $OUT; T0=$SECONDS
mode=$1; shift
case $mode in
  items)
    timeout 150 python3 scripts/trace_overhead.py --variant cuda_ad_rgb --resx 1280 --resy 720 -o $R/trace_overhead > $R/trace.log 2>&1
    echo "trace_overhead rc=$? after $((SECONDS - T0)) s"; tail -12 $R/trace.log
    timeout 200 python3 scripts/budget_benchmark.py --variant cuda_ad_rgb --frames 50 --resx 1280 --resy 720 \
      --importance 0.01 -o $R/budget > $R/budget.log 2>&1
    echo "budget rc=$? after $((SECONDS - T0)) s"; grep "^|" $R/budget.md | head -14 | cut -d'|' -f1-10
    timeout $((560 - SECONDS + T0)) python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy \
      --max-path-spp 1 -D resx=1280 -D resy=720 --scaling triangles --values 10000 100000 1000000 5000000 \
      -o $R/scaling_triangles > $R/scaling.log 2>&1
    echo "scaling rc=$? after $((SECONDS - T0)) s"; head -14 $R/scaling_triangles.md 2>/dev/null
    tar -cJf $OUT/items.tar.xz -C /tmp s51 ;;
  selections)
    python3 docs/results/gpu/issue10/stop47/budget_flip.py --variant cuda_ad_rgb --label stop51 --selections nested,greedy \
      -o $OUT/selections.jsonl $(for s in "$@"; do echo scenes/$s.xml; done) $D 2>&1 | grep -v "^jit_\|^Info\|^\s*$"
    echo "selections after $((SECONDS - T0)) s" ;;
  cost)  # the kernel history's cost, on / off in turn (scripts/history_cost.py), on this tree (new: the
         # stage times read once the device passes are done) and on ac644ec (old: read after the
         # synchronization): this package with ac644ec's two files that differ, carried in .w51
         # (`git show ac644ec:hybrid_integrator/pipeline.py > .w51/pipeline.py`, history.py alike;
         # the third run, outputs/cost_parse.txt: 59678f1's, the entries parsed after the synchronization)
    rm -rf /tmp/old && mkdir -p /tmp/old && cp -r hybrid_integrator /tmp/old/ && cp .w51/*.py /tmp/old/hybrid_integrator/ && ln -sfn $PWD/plugins /tmp/old/hybrid_integrator/plugins
    for s in "$@"; do for side in ${SIDES:-new old}; do
      (if [ $side = old ]; then export PYTHONPATH=/tmp/old:$PYTHONPATH; fi
       echo "== $s $side: $(cd / && python3 -c 'import hybrid_integrator as h; print(h.__file__)' 2>/dev/null)"
       python3 scripts/history_cost.py --variant cuda_ad_rgb --frames 30 scenes/$s.xml $D 2>&1 | grep -v "^jit_\|^Info\|^\s*$")
    done; done 2>&1 | tee $OUT/cost.txt ;;
  phases)  # host ms per phase of stage-timed frames (phases.py), this tree and ac644ec's two files (as cost)
    rm -rf /tmp/old && mkdir -p /tmp/old && cp -r hybrid_integrator /tmp/old/ && cp .w51/*.py /tmp/old/hybrid_integrator/ && ln -sfn $PWD/plugins /tmp/old/hybrid_integrator/plugins
    for side in ${SIDES:-new old}; do
      (if [ $side = old ]; then export PYTHONPATH=/tmp/old:$PYTHONPATH; fi
       python3 docs/results/gpu/issue10/stop51/phases.py --variant cuda_ad_rgb $(for s in "$@"; do echo scenes/$s.xml; done) $D 2>&1 | grep -v "^jit_\|^Info\|^\s")
    done 2>&1 | tee $OUT/phases.txt ;;
  budget)
    timeout 200 python3 scripts/budget_benchmark.py --variant cuda_ad_rgb --frames 50 --resx 1280 --resy 720 \
      --importance 0.01 -o $R/budget > $R/budget.log 2>&1
    echo "budget rc=$? after $((SECONDS - T0)) s"; grep "^|" $R/budget.md | head -14 | cut -d'|' -f1-10
    cp $R/budget.md $OUT/budget_early.md ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
