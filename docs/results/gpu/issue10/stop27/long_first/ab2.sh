# A/B: old = eb1765e (.device/old), new = this tree (glass paths first). Budget path on the 226
# objects (scripts/budget_ab.py, this tree's script with each version's package), then the
# default frames of the Armadillo and the showcase (hybrid bench, timing only)
source scripts/gpu_scenes.sh
ln -sfn ../plugins .device/old/hybrid_integrator/plugins
for r in 1 2; do
  for v in old new; do
    pkg=$PWD; [ $v = old ] && pkg=$PWD/.device/old
    PYTHONPATH=/tmp/site:/tmp/oidn_site:$pkg timeout 140 python3 scripts/budget_ab.py --variant cuda_ad_rgb --label $v$r 2>&1 | grep -v Warn | grep -E "RT/|50%|RT  |all "
    for s in armadillo_glass showcase; do
      (cd $pkg && PYTHONPATH=/tmp/site:/tmp/oidn_site:$pkg python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy --max-path-spp 1 --budgets $D -o $OUT/ab/$v$r -- $OLDPWD/scenes/$s.xml > $OUT/ab_$v${r}_$s.log 2>&1)
      python3 -c "
import json,sys
r=json.load(open('$OUT/ab/$v$r/$s.json')); m={x['method']:x for x in r['methods']}; h,rt=m['hybrid'],m['rt-baseline']
print('$r $v $s hybrid %.2f trace %.2f | rt %.2f trace %.2f | path %.2f | gain %.3f' % (h['time_ms'], h['stages_ms']['trace'], rt['time_ms'], rt['stages_ms']['trace'], r['path_1spp_ms'], r['gain']))"
    done
  done
done
rm -rf $OUT/ab
