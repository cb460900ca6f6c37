#!/usr/bin/env bash
# Stop 39, item 3: scripts/trace_overhead.py (many_objects, 1280×720, unlimited depth, --launches)
# three ways, in turn, three rounds: "old" = stop 38's final main (05e335b, in the git-excluded
# .w39/, made with `git archive 05e335b hybrid_integrator plugins scripts scenes | tar -x -C .w39`)
# with its own script; "harness" = this stop's script on the old package (wall without the kernel
# history, the hits as flat handles, glass first); "new" = this stop's script and package (the
# two-level compaction too). Carry .device and .w39. Summary: $OUT/trace_ab/summary.txt; the
# outputs come back as one archive.
source docs/results/gpu/issue10/stop31/env.sh
ln -sfn ../plugins .w39/hybrid_integrator/plugins
R=/tmp/trace_ab; mkdir -p $R $OUT/trace_ab; ROOT=$PWD
exec > >(tee $OUT/trace_ab/summary.txt) 2>&1
for round in 1 2 3; do
  for way in new harness old; do
    case $way in new) script=$ROOT; pkg=$ROOT;; harness) script=$ROOT; pkg=$ROOT/.w39;; old) script=$ROOT/.w39; pkg=$ROOT/.w39;; esac
    (cd $script && PYTHONPATH=/tmp/site:/tmp/extra:$pkg python3 -c "import hybrid_integrator as h; print(h.__file__)" &&
     PYTHONPATH=/tmp/site:/tmp/extra:$pkg python3 scripts/trace_overhead.py --variant cuda_ad_rgb \
      --resx 1280 --resy 720 --launches -o $R/${way}_$round/trace_overhead > $R/${way}_$round.log 2>&1)
    echo "$way $round rc=$?"; python3 - $R/${way}_$round/trace_overhead.json <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
print("  fit", {k: (round(v["fixed_ms"], 3), round(v["ms_per_1000_pixels"], 4)) for k, v in r["fit"].items()})
print("  log fit", {k: tuple(round(v[f], 4) for f in ("fixed_ms", "ms_per_ln_pixels", "ms_per_1000_pixels"))
                    for k, v in r["fit_with_log_term"].items()})
print("  rows", [(x["pixels"], round(x["wall_ms"], 3), round(x["device_ms"], 3)) for x in r["rows"]])
print("  replay", {k: round(v, 3) for k, v in r["frozen_replay"].items()}, r.get("scene_inputs"), "glass first", r.get("glass_first"))
PY
  done
done
tar -cJf $OUT/trace_ab/outputs.tar.xz -C /tmp trace_ab
