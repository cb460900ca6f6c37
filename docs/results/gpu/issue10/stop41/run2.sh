#!/usr/bin/env bash
# Stop 41, on the machine of run1.sh: every bench scene at the max_depth its file declares (its
# `path` integrator's: 8 for the Armadillo, Sponza and the dining room, 12 for the showcase, 6 for
# the 226 objects), then the bench as run1.sh runs it (-1) once more. Outputs: $OUT/declared.tar.xz,
# $OUT/s41_2_new.tar.xz.
source docs/results/gpu/issue10/stop31/env.sh
R=/tmp/declared; mkdir -p $R
for pair in armadillo_glass:8 showcase:12 sponza_mirror:8 dining_room:8 many_objects:6; do
  name=${pair%:*}; depth=${pair#*:}
  timeout 150 python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy --max-path-spp 1 \
    scenes/$name.xml $D --budgets 0.5 --max-depth $depth -o $R/${name}_d$depth > $R/${name}_d$depth.log 2>&1
  echo "$name max_depth $depth rc=$?"; grep -A3 "^| scene" $R/${name}_d$depth/bench.md | tail -1 | cut -d'|' -f2,6-12
done
tar -cJf $OUT/declared.tar.xz -C /tmp declared
STOP=41 bash docs/results/gpu/issue10/stop34/bench.sh new 2
