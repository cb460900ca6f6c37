#!/usr/bin/env bash
# Install everything hybrid_integrator needs on Debian 12 (run as root from the repository root):
# the system packages for Dr.Jit's LLVM backend and headless OpenGL (Mesa llvmpipe through EGL),
# a virtual environment in .venv, and the package with its test dependencies.
# Idempotent: what is already there is not fetched again.
set -euo pipefail
cd "$(dirname "$0")/.."

SYSTEM_PACKAGES="libatomic1 libllvm19 libegl1 libgl1 libgl1-mesa-dri"
if ! dpkg -s $SYSTEM_PACKAGES >/dev/null 2>&1; then
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -q
  apt-get install -y -q --no-install-recommends $SYSTEM_PACKAGES
fi

[ -x .venv/bin/python ] || python3 -m venv .venv
.venv/bin/python -m pip install -q --disable-pip-version-check -e '.[dev,ray]'
.venv/bin/python -c "import hybrid_integrator, mitsuba; print('hybrid_integrator', hybrid_integrator.__version__, 'on mitsuba', mitsuba.__version__)"
