#!/usr/bin/env bash
# Stop 37, the camera path: scripts/ahead_probe.py --path on the five bench scenes ($OUT/ahead_path.md),
# then item 4's budget benchmark (the 226 objects' camera path, hi.render_sequence) on this stop's
# code and on stop 36's tree in .w37 ($OUT/budget_{new,old}.*). After stop31/extras.sh 1 and 2;
# carry .device and .w37.
source docs/results/gpu/issue10/stop31/env.sh
python3 scripts/ahead_probe.py --path --variant cuda_ad_rgb --repeats ${REPEATS:-21} $S $D 2>&1 | tee $OUT/ahead_path.md
for tree in new old; do
  ( if [ $tree = old ]; then ln -sfn ../plugins .w37/hybrid_integrator/plugins; cd .w37; fi
    timeout 240 python3 scripts/budget_benchmark.py --variant cuda_ad_rgb --frames 50 --resx 1280 --resy 720 \
      --importance 0.01 -o $OUT/budget_$tree > $OUT/budget_$tree.log 2>&1
    echo "budget $tree rc=$?"; grep "^|" $OUT/budget_$tree.md | sed -n '3,4p;9p' )
done
