#!/bin/bash
# test.sh: install, build and run the whole test suite (meson test), then
# the conformance suite over the registry (tests/test_accels.c) again in a
# second build with AddressSanitizer and UndefinedBehaviorSanitizer
# (build-asan/), so that a memory or UB error in any accelerator fails CI.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
meson test -C build --print-errorlogs --num-processes 2 "$@"

if [ -f build-asan/build.ninja ]; then
    meson setup --reconfigure build-asan > /dev/null
else
    meson setup build-asan --buildtype=debugoptimized -Db_sanitize=address,undefined -Db_lundef=false > /dev/null
fi
ninja -C build-asan tests/test_accels > /dev/null
# halt_on_error: a sanitizer report fails the run; LSan's leak check is on,
# with the suppressions of tests/lsan.supp (leaks inside Embree/TBB only).
ASAN_OPTIONS=halt_on_error=1:detect_leaks=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    LSAN_OPTIONS=suppressions=$PWD/tests/lsan.supp \
    meson test -C build-asan --no-rebuild --print-errorlogs accels
