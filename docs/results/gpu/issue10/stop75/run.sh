#!/usr/bin/env bash
# Stop 75's device run, for `partial_objects` on by default: from the repository root on a warm machine, after
# `bash docs/results/gpu/issue10/stop31/extras.sh N` for N = 1 ... 6, each carrying .device_xN, with .device carried
# (`bash docs/results/gpu/issue10/stop45/carries.sh`). Its steps, most wanted first, each within what is left of LIMIT
# seconds (default 585, the call's 600 less a margin). A machine taken back during a call returns nothing of it (stop
# 75 lost `owed` so), so where device time allows, run the three steps as three calls, in this order:
#   bash docs/results/gpu/issue10/stop75/run.sh budget   # budget_benchmark.py (item 4, 226 objects' path), parts off / as shipped (on)
#   bash docs/results/gpu/issue10/stop75/run.sh bench    # stop 74's: hybrid bench's timing rows on the four bench scenes, as shipped
#   bash docs/results/gpu/issue10/stop75/run.sh probe    # stop 74's: stop 69's partial_probe.py, whole / with a part, 25-75 %, RT row
#   bash docs/results/gpu/issue10/stop75/run.sh owed     # the three in one call, ~5 min
source docs/results/gpu/issue10/stop31/env.sh
mkdir -p $OUT; T0=$SECONDS; LIMIT=${LIMIT:-585}
rest() { echo $((LIMIT - SECONDS + T0)); }
# stop 74's `budget` ran its "" side as shipped, then off; since parts are on by default, the off side says so
budget() {
  for part in --no-partial-objects ""; do
    name=budget${part:+_whole}
    timeout $((200 < $(rest) ? 200 : $(rest) > 1 ? $(rest) : 1)) python3 scripts/budget_benchmark.py --variant cuda_ad_rgb \
      --frames 50 --resx 1280 --resy 720 --importance 0.01 $part -o $OUT/$name > $OUT/$name.log 2>&1
    echo "$name rc=$? after $((SECONDS - T0)) s"; grep "^RT baseline / 50\|^As a renderer\|^| nested\|^| greedy" $OUT/$name.md
  done
}
step() { LIMIT=$(rest) bash docs/results/gpu/issue10/stop74/run.sh $1; }
case $1 in
  owed) budget; step bench; step probe ;;
  budget) budget ;;
  bench|probe) step $1 ;;
  *) echo "unknown mode $1" >&2; exit 2 ;;
esac
