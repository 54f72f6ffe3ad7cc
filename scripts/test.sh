#!/bin/bash
# test.sh: install, build and run the whole test suite (meson test), then
# the whole suite again in a second build with AddressSanitizer,
# UndefinedBehaviorSanitizer and LeakSanitizer (build-asan/), so that a
# memory error, undefined behaviour or a leak anywhere fails CI, and last a
# short fuzz run of every libFuzzer harness (scripts/fuzz.sh, 12 s each).
# TEST_NO_FUZZ=1 leaves the fuzz run out (a developer's quick loop).
set -euo pipefail
cd "$(dirname "$0")/.."
# took WHAT: one line with the seconds since the last one, so that a slow
# part of a CI run shows in its log.
mark=$SECONDS
took() {
    echo "test: $1 took $((SECONDS - mark)) s"
    mark=$SECONDS
}
scripts/setup.sh
took "setup and the release build"
meson test -C build --print-errorlogs --num-processes 2 "$@"
took "the release suite"

if [ -f build-asan/build.ninja ]; then
    meson setup --reconfigure build-asan > /dev/null
else
    meson setup build-asan --buildtype=debugoptimized -Db_sanitize=address,undefined -Db_lundef=false > /dev/null
fi
ninja -C build-asan > /dev/null
took "the sanitizer build"
# halt_on_error: a sanitizer report fails the run; LSan's leak check is on,
# with the suppressions of tests/lsan.supp (leaks inside Embree/TBB only).
# The sanitizers slow tests 2-5x: meson's timeouts are doubled.
ASAN_OPTIONS=halt_on_error=1:detect_leaks=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    LSAN_OPTIONS=suppressions=$PWD/tests/lsan.supp \
    meson test -C build-asan --no-rebuild --print-errorlogs --num-processes 2 --timeout-multiplier 2 "$@"
took "the sanitizer suite"

if [ "${TEST_NO_FUZZ:-0}" != 1 ]; then
    scripts/fuzz.sh 12
    took "the fuzz build and run"
fi
