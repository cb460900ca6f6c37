#!/usr/bin/env bash
# Stop 43, experiment E (diffs/E_handoff_before_denoiser.diff; reverted): in flight, the hybrid hands its
# target back to OpenGL before issuing the denoiser (after its trace), not after. timeline.py and
# wall.py on four scenes, the experiment's tree (new, the working tree) and the committed one
# (old, in the git-excluded .w43b: git archive e7dc6ec hybrid_integrator plugins scenes scripts
# docs/results/gpu/issue10/stop43), in turn. After stop31/extras.sh 3, 1, 2; carry .device and .w43b.
source docs/results/gpu/issue10/stop31/env.sh
S="scenes/armadillo_glass.xml scenes/showcase.xml scenes/sponza_mirror.xml scenes/many_objects.xml"
mkdir -p $OUT; ROOT=$PWD
for side in new old; do
  cd $ROOT; [ $side = old ] && { ln -sfn ../plugins .w43b/hybrid_integrator/plugins; cd .w43b; }
  export PYTHONPATH="$PWD:$PYTHONPATH"
  timeout 250 python3 docs/results/gpu/issue10/stop43/timeline.py $S $D 2>&1 | grep -E "gap|rror" | sed "s/^/$side /" | tee -a $OUT/exp_e.txt
  timeout 250 python3 docs/results/gpu/issue10/stop43/wall.py $S $D 2>&1 | grep -E "wall ms|RT / hybrid|rror" | sed "s/^/$side /" | tee -a $OUT/exp_e.txt
done
