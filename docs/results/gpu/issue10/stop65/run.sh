#!/usr/bin/env bash
# Stop 65's device run, from the repository root on a warm machine, after
# `bash docs/results/gpu/issue10/stop31/extras.sh N` for N = 1 ... 6, each carrying .device_xN, with .device carried
# (both made by `bash docs/results/gpu/issue10/stop45/carries.sh`).
#   bash docs/results/gpu/issue10/stop65/run.sh hide SCENE  # hide_emitters.py check on cuda_ad_rgb, then the
#     scene's default frame with hide_emitters off and on
source docs/results/gpu/issue10/stop31/env.sh
mkdir -p $OUT; T0=$SECONDS
mode=$1; shift
case $mode in
  hide)
    timeout 300 python3 docs/results/gpu/issue10/stop65/hide_emitters.py check --variant cuda_ad_rgb \
      > $OUT/hide_check.json 2> $OUT/hide_check.log
    echo "check rc=$? after $((SECONDS - T0)) s"; cat $OUT/hide_check.json
    for s in "$@"; do
      DS=$(for kv in $D; do case $kv in *=*) grep -q "\$${kv%%=*}" scenes/$s.xml && echo "-D $kv";; esac; done)
      timeout $((590 - SECONDS + T0)) python3 docs/results/gpu/issue10/stop65/hide_emitters.py time scenes/$s.xml $DS \
        --variant cuda_ad_rgb > $OUT/hide_time_$s.json 2> $OUT/hide_time_$s.log
      echo "$s rc=$? after $((SECONDS - T0)) s"; cat $OUT/hide_time_$s.json
    done ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
