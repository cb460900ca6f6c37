#!/usr/bin/env bash
# Stop 71's runs, from the repository root.
#   bash docs/results/gpu/issue10/stop71/run.sh fill       # on the CPU: fill_probe.py, each --fill rule on the
#     glass Armadillo (the Armadillo, its floor) and the dining room (its two objects traced in part on the H100)
#   bash docs/results/gpu/issue10/stop71/run.sh probe SCENE...   # on a warm device machine, after
#     `bash docs/results/gpu/issue10/stop31/extras.sh N` for N = 1 ... 6 (each carrying .device_xN), carrying .device:
#     stop 69's partial_probe.py with the RT baseline's row (--rt), 1280x720, cuda_ad_rgb
#   bash docs/results/gpu/issue10/stop71/run.sh tiers      # 40 frames of stop 69's partial_diag.py on the dining
#     room, then partial_probe.py at 25 %: the shadow tiers' prior rays per pixel from the tiers traced (heuristic.typical_rays)
mode=$1; shift
case $mode in
  fill)
    mkdir -p docs/results/gpu/issue10/stop71/outputs
    for fill in delta all none; do
      for args in "scenes/armadillo_glass.xml armadillo floor -D models_dir=../shared/scenes/models" \
                  "scenes/dining_room.xml 'shape #39' 'shape #52' -D dining_dir=../shared/scenes/dining-room"; do
        eval .venv/bin/python docs/results/gpu/issue10/stop71/fill_probe.py $args --fill $fill -D resx=320 -D resy=180
      done
    done 2>&1 | grep -v "^Warn\|^Info" | tee docs/results/gpu/issue10/stop71/outputs/fill_probe_cpu_320x180.txt ;;
  probe)
    source docs/results/gpu/issue10/stop31/env.sh
    mkdir -p $OUT; T0=$SECONDS
    for s in "$@"; do
      timeout $((590 - SECONDS + T0)) python3 docs/results/gpu/issue10/stop69/partial_probe.py --variant cuda_ad_rgb --rt \
        $D scenes/$s.xml 2>&1 | grep -v "Warn\|jit_optix_log\|^	\|^Info" | tee -a $OUT/partial_probe.txt
    done ;;
  tiers)
    source docs/results/gpu/issue10/stop31/env.sh
    mkdir -p $OUT
    timeout 60 python3 docs/results/gpu/issue10/stop69/partial_diag.py --variant cuda_ad_rgb --frames 40 $D \
      scenes/dining_room.xml 2>&1 | grep -v "Warn\|jit_optix_log\|^	\|^Info" | tee $OUT/partial_diag_tiers.txt
    timeout 200 python3 docs/results/gpu/issue10/stop69/partial_probe.py --variant cuda_ad_rgb --budgets 0.25 --frames 30 \
      $D scenes/dining_room.xml 2>&1 | grep -v "Warn\|jit_optix_log\|^	\|^Info" | tee $OUT/partial_probe_tiers.txt ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
