#!/usr/bin/env bash
# Stop 42: one of the experiments (new: main with diffs/A_*.diff, B_*.diff or D_*.diff applied
# here with `git apply`, which the device call copies) against main at 4c22693 (old, in the
# git-excluded .w42/: `git archive 4c22693 hybrid_integrator plugins scenes scripts | tar -x -C
# .w42`): first (unless IMAGES=0) the frames drawn ahead against frames that draw their own in the
# new tree (`stop41/ahead_images.py`), then the bench round $1 in the order $2. After
# stop31/extras.sh 3, 1 and 2 on the same warm machine; carry .device and .w42.
# Outputs: $OUT/ahead_images.txt, $OUT/s42_N_{new,old}.tar.xz. Ran: A as `bash ab.sh 1 "new old"`,
# B as `… 2 …` (the images of both from a first call on a machine without the extras, where the
# bench found no scene files; the bench then with IMAGES=0), D as `IMAGES=0 bash ab.sh 3 "new old"`.
if [ "${IMAGES:-1}" = 1 ]; then
  (source docs/results/gpu/issue10/stop31/env.sh
   timeout 150 python3 docs/results/gpu/issue10/stop41/ahead_images.py /tmp/ah_new.npz > $OUT/ahead_images.txt 2>&1
   echo "images rc=$?"; grep -v "^jit" $OUT/ahead_images.txt | tail -4)
fi
for tree in ${2:-new old}; do STOP=42 OLD=.w42 bash docs/results/gpu/issue10/stop34/bench.sh $tree $1; done
