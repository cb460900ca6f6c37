#!/usr/bin/env bash
# Stop 38, item 3: scripts/trace_overhead.py (many_objects, 1280×720, unlimited depth, --launches)
# on this stop's code (new) and on stop 37's final tree (old: 85a092f in the git-excluded .w38/,
# made with `git archive 85a092f hybrid_integrator plugins scripts scenes | tar -x -C .w38`), in
# turn, three times. Carry .device and .w38.
# The summary goes to $OUT/trace_ab/summary.txt; the outputs come back as one archive (a call
# returns few files).
source docs/results/gpu/issue10/stop31/env.sh
ln -sfn ../plugins .w38/hybrid_integrator/plugins
R=/tmp/trace_ab; mkdir -p $R $OUT/trace_ab; ROOT=$PWD
exec > >(tee $OUT/trace_ab/summary.txt) 2>&1
for round in 1 2 3; do
  for tree in new old; do
    if [ $tree = new ]; then dir=$ROOT; else dir=$ROOT/.w38; fi
    (cd $dir && PYTHONPATH=/tmp/site:/tmp/extra:$dir python3 scripts/trace_overhead.py --variant cuda_ad_rgb \
      --resx 1280 --resy 720 --launches -o $R/${tree}_$round/trace_overhead > $R/${tree}_$round.log 2>&1)
    echo "$tree $round rc=$?"; python3 - $R/${tree}_$round/trace_overhead.json <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
print("  fit", {k: (round(v["fixed_ms"], 3), round(v["ms_per_1000_pixels"], 4)) for k, v in r["fit"].items()})
if "fit_with_log_term" in r:
    print("  log fit", {k: tuple(round(v[f], 4) for f in ("fixed_ms", "ms_per_ln_pixels", "ms_per_1000_pixels"))
                        for k, v in r["fit_with_log_term"].items()})
print("  rows", [(x["pixels"], round(x["wall_ms"], 3), round(x["device_ms"], 3)) for x in r["rows"]])
print("  replay", {k: round(v, 3) for k, v in r["frozen_replay"].items()}, r.get("scene_inputs"))
PY
  done
done
tar -cJf $OUT/trace_ab/outputs.tar.xz -C /tmp trace_ab
