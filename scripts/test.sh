#!/usr/bin/env bash
# The test suite: set up (idempotent, see install.sh), then pytest on the llvm_ad_rgb variant with
# Mesa llvmpipe. Extra arguments go to pytest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install.sh
exec .venv/bin/python -m pytest "$@"
