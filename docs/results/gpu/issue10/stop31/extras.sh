#!/usr/bin/env bash
# A device run's first calls: what the working tree lacks, carried in the git-excluded .device_xN/
# (a call carries at most 64 MiB with the working tree) and unpacked into the machine's /tmp, which
# the next call on the same (warm) machine finds again: Open Image Denoise (pyoidn 2.5.1 with its
# core, CPU and CUDA libraries only: the wheel's 171 MB do not fit a carry), cffi, pycparser, tqdm,
# flip-evaluator (cp312 wheels), the bench scenes' files from ../shared/scenes (scn.tar.xz) and,
# since stop 62, the bundle's site packages (../shared/tools/device-bundle.sh; its prelude, in
# .device, finds them in /tmp/site).
#   call N: bash extras.sh N (carry .device_xN), for N = 1 ... 6 in back-to-back calls, any order
# A large archive is split in parts named ARCHIVE.pK-of-N across the carries (stop45/carries.sh
# makes them): each call keeps its parts in /tmp/parts and unpacks an archive once all its parts
# are in. History: stop 31 carried two parts, stop 37 three (the tracked tree had grown); in stop 62
# the tracked tree reached 41 MB, and a call carrying the 24 MB bundle or half of Open Image
# Denoise beside it no longer fitted, so no carry holds more than ~17 MB now.
set -euo pipefail
mkdir -p /tmp/parts /tmp/extra /tmp/scn /tmp/site
cp .device_x$1/* /tmp/parts/
declare -A into=([oidn.tar.xz]=/tmp/extra [site.tar.xz]=/tmp/site [scn.tar.xz]=/tmp/scn)
for archive in "${!into[@]}"; do
  [ -e /tmp/parts/$archive.done ] && continue
  if [ -f /tmp/parts/$archive ]; then
    tar -xJf /tmp/parts/$archive -C ${into[$archive]}
  else
    parts=(/tmp/parts/$archive.p*-of-*)
    [ -f "${parts[0]}" ] || continue
    n=${parts[0]##*-of-}
    [ ${#parts[@]} -eq $n ] || continue
    for ((k = 0; k < n; k++)); do cat /tmp/parts/$archive.p$k-of-$n; done | tar -xJ -C ${into[$archive]}
  fi
  touch /tmp/parts/$archive.done; echo "unpacked $archive"
done
for w in /tmp/parts/*.whl; do
  [ -f "$w" ] && [ ! -e "$w.done" ] && python3 -m zipfile -e "$w" /tmp/extra && touch "$w.done"
done
true
