# A/B of the long-paths-first lane order: old = HEAD's package (.device/old), new = the working tree
source scripts/gpu_scenes.sh
ln -sfn ../plugins .device/old/hybrid_integrator/plugins
for round in 1 2; do
  for v in old new; do
    dir=$PWD; [ $v = old ] && dir=$PWD/.device/old
    for s in armadillo_glass showcase; do
      (cd $dir && python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy --max-path-spp 1 --budgets $D -o $OUT/ab/$v$round -- scenes/$s.xml > $OUT/ab_$v${round}_$s.log 2>&1)
      python3 - $OUT/ab/$v$round/$s.json $v $round <<'PY'
import json,sys
r=json.load(open(sys.argv[1]))
m={x["method"]:x for x in r["methods"]}
h,rt=m["hybrid"],m["rt-baseline"]
print(sys.argv[3], sys.argv[2], r["name"], "hybrid %.2f trace %.2f | rt %.2f trace %.2f | path %.2f | gain %.3f" % (h["time_ms"], h["stages_ms"]["trace"], rt["time_ms"], rt["stages_ms"]["trace"], r["path_1spp_ms"], r["gain"]))
PY
    done
  done
done
