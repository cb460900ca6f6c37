#!/usr/bin/env bash
# Stop 31, a device run's first two calls: what the bundle (.device, ../shared/tools/device-bundle.sh)
# lacks, carried in the git-excluded .device_x1/ and .device_x2/ (a call carries at most 64 MiB with
# the working tree) and unpacked into the machine's /tmp, which the next call on the same (warm)
# machine finds again: Open Image Denoise (pyoidn 2.5.1 with its core, CPU and CUDA libraries only,
# the tarball split in two parts: the wheel's 171 MB do not fit a carry), cffi, pycparser, tqdm
# (cp312 wheels), and the bench scenes' files from ../shared/scenes (scn.tar.xz).
#   call 1: bash extras.sh 1 (carry .device_x1)   call 2: bash extras.sh 2 (carry .device_x2)
# Since stop 37 the tracked tree is too large to carry scn.tar.xz with oidn.part00: it sits in
# .device_x3/ (git-excluded), unpacked by a call of its own, bash extras.sh 3 (carry .device_x3).
set -euo pipefail
mkdir -p /tmp/extra /tmp/scn
if [ "$1" = 1 ]; then
  cp .device_x1/oidn.part00 /tmp/oidn.part00
  if [ -f .device_x1/scn.tar.xz ]; then tar -xJf .device_x1/scn.tar.xz -C /tmp/scn; fi
elif [ "$1" = 3 ]; then
  tar -xJf .device_x3/scn.tar.xz -C /tmp/scn
else
  cat /tmp/oidn.part00 .device_x2/oidn.part01 | tar -xJ -C /tmp/extra
  for w in .device_x2/*.whl; do python3 -m zipfile -e "$w" /tmp/extra; done
  ls /tmp/extra /tmp/scn; nvidia-smi --query-gpu=name,driver_version --format=csv
fi
