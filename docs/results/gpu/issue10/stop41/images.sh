#!/usr/bin/env bash
# Stop 41 on the GPU: the images of stop40/same_images.py and env_images.py with cuda_ad_rgb, this
# stop's package (new) and stop 40's final main (old: ec27cdb in the git-excluded .w41/, made with
# `git archive ec27cdb hybrid_integrator plugins scripts scenes | tar -x -C .w41`), compared.
# Carry .device and .w41.
source docs/results/gpu/issue10/stop31/env.sh
ln -sfn ../plugins .w41/hybrid_integrator/plugins
ROOT=$PWD; H=docs/results/gpu/issue10
for way in new old; do
  case $way in new) tree=$ROOT;; old) tree=$ROOT/.w41;; esac
  (cd $tree && PYTHONPATH=/tmp/site:/tmp/extra:$tree python3 $ROOT/$H/stop40/same_images.py /tmp/img_$way.npz cuda_ad_rgb > /tmp/img_$way.log 2>&1
   PYTHONPATH=/tmp/site:/tmp/extra:$tree python3 $ROOT/$H/stop41/env_images.py /tmp/env_$way.npz cuda_ad_rgb >> /tmp/img_$way.log 2>&1)
  echo "$way rc=$?"; grep -v "^\[" /tmp/img_$way.log | tail -12
done
python3 $H/stop41/compare.py /tmp/img_new.npz /tmp/img_old.npz; python3 $H/stop41/compare.py /tmp/env_new.npz /tmp/env_old.npz
