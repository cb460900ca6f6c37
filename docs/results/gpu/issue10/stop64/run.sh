#!/usr/bin/env bash
# Stop 64's device run, from the repository root on a warm machine, after
# `bash docs/results/gpu/issue10/stop31/extras.sh N` for N = 1 ... 6, each carrying .device_xN, with .device carried
# (both made by `bash docs/results/gpu/issue10/stop45/carries.sh`).
#   bash docs/results/gpu/issue10/stop64/run.sh formats SCENE...  # pipeline.Development on cuda_ad_rgb: each hdrfilm
#     pixel format's default and temporal frame against the rgb(a) frame converted, and its frame time, in turn
source docs/results/gpu/issue10/stop31/env.sh
mkdir -p $OUT; T0=$SECONDS
mode=$1; shift
case $mode in
  formats)
    for s in "$@"; do
      DS=$(for kv in $D; do case $kv in *=*) grep -q "\$${kv%%=*}" scenes/$s.xml && echo "-D $kv";; esac; done)
      timeout $((590 - SECONDS + T0)) python3 docs/results/gpu/issue10/stop64/film_formats.py scenes/$s.xml $DS \
        --variant cuda_ad_rgb > $OUT/formats_$s.json 2> $OUT/formats_$s.log
      echo "$s rc=$? after $((SECONDS - T0)) s"; tail -c 1500 $OUT/formats_$s.json
    done ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
