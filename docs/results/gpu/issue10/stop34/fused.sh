#!/usr/bin/env bash
# Stop 34's GPU run, part 4: the raster stage in one kernel (the silhouettes' labels read from the
# visibility buffer in the kernel that tests them). scripts/refine_ab.py per scene (primary / trace /
# RT, paired, one process per scene) and scripts/primary_stage.py, then the bench (bench.sh new $1).
# Same machine and set-up as bench.sh; carry .device.
source docs/results/gpu/issue10/stop31/env.sh
R=/tmp/f34_$1; mkdir -p $R; T0=$SECONDS
for s in $S; do
  timeout 110 python3 scripts/refine_ab.py --variant cuda_ad_rgb --repeats 21 $s $D > $R/refine_$(basename $s .xml).txt 2>&1
  tail -1 $R/refine_$(basename $s .xml).txt
done
timeout 100 python3 scripts/primary_stage.py --variant cuda_ad_rgb $S $D -o $R/primary_stage.txt > /dev/null 2>&1
grep -A2 "refined" $R/primary_stage.txt | grep -v "^--"
echo "after $((SECONDS - T0)) s"
tar -cJf $OUT/f34_$1.tar.xz -C /tmp f34_$1
bash docs/results/gpu/issue10/stop34/bench.sh new f$1
