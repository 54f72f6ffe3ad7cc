#!/bin/bash
# test.sh: install, build and run the whole test suite (meson test).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
meson test -C build --print-errorlogs --num-processes 2 "$@"
