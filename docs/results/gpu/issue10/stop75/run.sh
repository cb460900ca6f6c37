#!/usr/bin/env bash
# Stop 75's device run, for `partial_objects` on by default: one call on a warm machine, from the repository root,
# after `bash docs/results/gpu/issue10/stop31/extras.sh N` for N = 1 ... 6, each carrying .device_xN, with .device
# carried (`bash docs/results/gpu/issue10/stop45/carries.sh`). Its steps, most wanted first, each within what is left
# of LIMIT seconds (default 585, the call's 600 less a margin). A machine taken back during a call returns nothing of
# it (stop 75 lost `owed` so), so where device time allows, run the three steps as three calls, in this order:
#   bash docs/results/gpu/issue10/stop75/run.sh budget   # budget_benchmark.py (item 4, 226 objects' path), parts off / as shipped (on)
#   bash docs/results/gpu/issue10/stop75/run.sh bench    # hybrid bench's timing rows on the four bench scenes, as shipped
#   bash docs/results/gpu/issue10/stop75/run.sh probe    # stop 69's partial_probe.py, whole / with a part, 25-75 %, RT row
#   bash docs/results/gpu/issue10/stop75/run.sh owed     # the three in one call, ~5 min
source docs/results/gpu/issue10/stop31/env.sh
mkdir -p $OUT; T0=$SECONDS; LIMIT=${LIMIT:-585}
benches="scenes/armadillo_glass.xml scenes/showcase.xml scenes/sponza_mirror.xml scenes/dining_room.xml"
quiet() { grep -v "Warn\|jit_optix_log\|^	\|^Info"; }
# a step's limit: $1 s, within what is left of LIMIT (at least 1: `timeout 0` would never stop it)
left() { local rest=$((LIMIT - SECONDS + T0)); rest=$((rest < $1 ? rest : $1)); echo $((rest < 1 ? 1 : rest)); }
budget() {
  for part in --no-partial-objects ""; do
    name=budget${part:+_whole}
    timeout $(left 200) python3 scripts/budget_benchmark.py --variant cuda_ad_rgb --frames 50 --resx 1280 --resy 720 \
      --importance 0.01 $part -o $OUT/$name > $OUT/$name.log 2>&1
    echo "$name rc=$? after $((SECONDS - T0)) s"; grep "^RT baseline / 50\|^As a renderer\|^| nested\|^| greedy" $OUT/$name.md
  done
}
bench() {
  timeout $(left 200) python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy --max-path-spp 1 \
    --budgets 0.25 0.5 0.75 $D $benches -o $OUT/bench > $OUT/bench.log 2>&1
  echo "bench rc=$? after $((SECONDS - T0)) s"
  grep "^| [a-z_]* | [0-9]\|^| hybrid\|^| rt-" $OUT/bench/bench.md
}
probe() {
  for s in $benches; do
    timeout $(left 150) python3 docs/results/gpu/issue10/stop69/partial_probe.py --variant cuda_ad_rgb --rt --frames 20 \
      --gt-spp 512 $D $s 2>&1 | quiet
    echo "($s after $((SECONDS - T0)) s)"
  done | tee $OUT/probe.txt
}
case $1 in
  owed) budget; bench; probe ;;
  budget|bench|probe) $1 ;;
  *) echo "unknown mode $1" >&2; exit 2 ;;
esac
