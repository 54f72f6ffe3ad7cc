#!/bin/bash
# fuzz.sh [SECONDS]: build the libFuzzer harnesses of fuzz/ and run each for
# SECONDS (default 60). Exits non-zero when any of them finds a crash, a
# sanitizer report (ASan, UBSan), a leak (LSan), a timeout (one input over
# 30 s: the instrumented build runs 20-50x slower than release, and the
# octree's default build over coincident surfaces, 0.3 s in release, took
# 14 s there) or runs out of memory (2 GB): libFuzzer leaves the input that did
# it in build-fuzz/artifacts/NAME/ and prints how to replay it. fuzz_mesh and
# fuzz_obj run assimp (uninstrumented) in their own process: a crash there, or
# an allocation over the limit (assimp sizes buffers from the counts a header
# claims; accelbench's reader stops it with its memory cap), is reported, and
# fails the run only when its first frame outside the runtime is the project's,
# or when accelbench does not read the same file with exit 0 or 2 through its
# forked reader (assimp_defect).
#
# The harnesses need clang (installed from Debian when missing); the normal
# build does not. The project's static libraries are built by meson with
# clang in their own folder, build-fuzz/, instrumented with
# -fsanitize=fuzzer-no-link,address,undefined; the harnesses (fuzz/*.c) are
# compiled and linked against them here. Seeds are fuzz/corpus/NAME/ and
# fuzz/NAME.dict, in the repository; what a run adds to the corpus goes to
# build-fuzz/corpus/NAME/, never into the repository.
#
# Replay one input: build-fuzz/fuzz/fuzz_NAME FILE
#
# fuzz.sh --campaign NAME RUNS: one harness for RUNS executions in libFuzzer's
# fork mode (-fork=1), with a random seed. A crash, timeout or out-of-memory
# stops the child it happened in, not the campaign: each is left in
# build-fuzz/artifacts/NAME/ and listed at the end, and the exit status is
# 1 when there is any. fuzz_mesh and fuzz_obj need this: assimp, uninstrumented, runs in
# their process, and a defect of assimp's own (which the product isolates in
# its forked reader) would otherwise end the campaign at the first one.
set -euo pipefail
cd "$(dirname "$0")/.."
USAGE="usage: scripts/fuzz.sh [SECONDS] | scripts/fuzz.sh --campaign NAME RUNS"
HARNESSES=(nff mesh obj rays params scenes)
CAMPAIGN=""
if [ "${1:-}" = --campaign ]; then
    [ $# = 3 ] || { echo "$USAGE" >&2; exit 2; }
    CAMPAIGN=$2 RUNS=$3
    case " ${HARNESSES[*]} " in *" $CAMPAIGN "*) ;; *) echo "fuzz: no harness '$CAMPAIGN' (${HARNESSES[*]})" >&2; exit 2 ;; esac
    case "$RUNS" in '' | *[!0-9]*) echo "$USAGE" >&2; exit 2 ;; esac
else
    SECONDS_EACH=${1:-60}
    case "$SECONDS_EACH" in '' | *[!0-9]*) echo "$USAGE" >&2; exit 2 ;; esac
fi
B=build-fuzz

scripts/setup.sh > /dev/null # the packages and libraries every build needs
if ! command -v clang > /dev/null; then
    SUDO=""
    [ "$(id -u)" = 0 ] || SUDO=sudo
    echo "fuzz: installing clang"
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends clang > /dev/null
fi

# The project's libraries, instrumented for coverage and the sanitizers.
if [ ! -f $B/build.ninja ]; then
    CC=clang CXX=clang++ meson setup $B --buildtype=debugoptimized -Db_sanitize=address,undefined -Db_lundef=false \
        -Dc_args=-fsanitize=fuzzer-no-link -Dcpp_args=-fsanitize=fuzzer-no-link > /dev/null
fi
LIBS=(harness/libharness.a accel/libaccel.a accel/common/libaccel_common.a accel/bvh/libaccel_bvh.a
      scenes/libscenes.a prims/libprims.a)
ninja -C $B "${LIBS[@]}" > /dev/null

# The harnesses, linked as meson links accelbench (the same libraries and
# system ones), with libFuzzer's main.
mkdir -p $B/fuzz
SYSLIBS=$(pkg-config --libs assimp libarchive libpng)
# The harnesses that run assimp in their process take its large buffers from reused mappings (fuzz/large_blocks.cc).
# Each is linked beside its place and moved in, so that a campaign running (whose fork mode starts its
# binary again for every job) never starts a half-written one.
clang++ -std=gnu++17 -g -O1 -Wall -Wextra -fsanitize=fuzzer-no-link -c -o $B/fuzz/large_blocks.o.$$ fuzz/large_blocks.cc
mv $B/fuzz/large_blocks.o.$$ $B/fuzz/large_blocks.o
for h in "${HARNESSES[@]}"; do
    blocks=()
    case $h in mesh | obj | scenes) blocks=($B/fuzz/large_blocks.o) ;; esac
    clang++ -x c -std=gnu11 -g -O1 -D_GNU_SOURCE -ffp-contract=off -Wall -Wextra \
        -fsanitize=fuzzer,address,undefined -I. -o $B/fuzz/fuzz_$h.$$ fuzz/fuzz_$h.c fuzz/exercise.c \
        -x none "${blocks[@]}" -Wl,--start-group "${LIBS[@]/#/$B/}" -Wl,--end-group $SYSLIBS -lembree3 -lgmp -lmpfr -lm -pthread
    mv $B/fuzz/fuzz_$h.$$ $B/fuzz/fuzz_$h
done

# Leaks inside Embree, TBB and assimp only are suppressed (fuzz/lsan.supp says why); UBSan stops at its first report.
export ASAN_OPTIONS=halt_on_error=1:detect_leaks=1
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
export LSAN_OPTIONS=suppressions=$PWD/fuzz/lsan.supp
# A fixed seed (FUZZ_SEED, default 1): the same mutations on every run, so a machine that runs fewer executions in
# the time runs a prefix of the same sequence. fuzz_mesh and fuzz_obj run assimp in process: they run in fork mode,
# and a crash counts as a failure only when it is the project's (assimp_defect below sorts them).
SEED=${FUZZ_SEED:-1}
case "$SEED" in '' | *[!0-9]*) echo "fuzz: FUZZ_SEED must be a number" >&2; exit 2 ;; esac
if [ -n "$CAMPAIGN" ]; then
    h=$CAMPAIGN log=$B/fuzz/campaign_$CAMPAIGN.log
    mkdir -p $B/corpus/$h $B/artifacts/$h
    echo "fuzz: campaign of fuzz_$h, $RUNS executions; the log is $log"
    start=$(date +%s)
    stamp=$B/fuzz/campaign_$CAMPAIGN.start
    touch "$stamp" # what this campaign finds is newer than it
    rc=0
    $B/fuzz/fuzz_$h -fork=1 -ignore_crashes=1 -ignore_ooms=1 -ignore_timeouts=1 -seed=0 -runs="$RUNS" -timeout=30 \
        -rss_limit_mb=2048 -dict=fuzz/$h.dict -artifact_prefix=$B/artifacts/$h/ $B/corpus/$h fuzz/corpus/$h > "$log" 2>&1 || rc=$?
    last=$(grep -E '^#[0-9]+:' "$log" | tail -1)
    echo "fuzz_$h: exit $rc after $(($(date +%s) - start)) s; last status: ${last:-none}"
    echo "fuzz_$h: corpus $(find $B/corpus/$h -type f | wc -l) inputs in $B/corpus/$h"
    found=$(find $B/artifacts/$h -type f -newer "$stamp" | sort)
    [ -z "$found" ] && { echo "fuzz_$h: no crash, leak, timeout or out-of-memory"; exit "$rc"; }
    echo "fuzz_$h: found (replay with $B/fuzz/fuzz_$h FILE):"
    echo "$found"
    exit 1
fi

# assimp_defect HARNESS FILE: whether a crash or out-of-memory fuzz_mesh or fuzz_obj left in FILE is assimp's own,
# isolated by the product: replayed alone, the first stack frame outside the sanitizer runtime, libFuzzer, the C and
# C++ libraries and the allocators is in libassimp (or it does not crash alone: assimp's heap damage from an earlier input), and
# accelbench reads the same file through its forked reader with exit 0 or 2, never a crash of its own.
assimp_defect() {
    local h=$1 f=$2 replay=$B/fuzz/replay_$1.log file ext
    if ! $B/fuzz/fuzz_$h "$f" > "$replay" 2>&1; then
        grep -E '^ +#[0-9]+ ' "$replay" |
            grep -vE 'libclang_rt|asan|sanitizer|__interceptor|fuzzer::|large_blocks\.cc|/libc\.so|libstdc\+\+|operator (new|delete)|malloc|free\b' |
            head -1 | grep -q libassimp || return 1
    fi
    if [ "$h" = obj ]; then
        ext=obj file=$B/fuzz/replay.obj
        cp "$f" "$file"
    else
        ext=$(printf 'ply\noff\nstl\n' | sed -n "$(($(od -An -tu1 -N1 "$f") % 3 + 1))p") file=$B/fuzz/replay.$ext
        tail -c +2 "$f" > "$file"
    fi
    local rc=0
    build/harness/accelbench scene info "$file" > /dev/null 2>&1 || rc=$?
    [ "$rc" = 0 ] || [ "$rc" = 2 ]
}

failed=()
for h in "${HARNESSES[@]}"; do
    mkdir -p $B/corpus/$h $B/artifacts/$h
    log=$B/fuzz/fuzz_$h.log
    rc=0 isolated=0
    if [ "$h" = mesh ] || [ "$h" = obj ]; then
        # assimp runs in these two processes: fork mode, so that a defect of assimp's own does not end the run;
        # each crash is then sorted into assimp's (reported) and the project's (a failure).
        stamp=$B/fuzz/smoke_$h.start
        touch "$stamp"
        fuzzer_rc=0
        $B/fuzz/fuzz_$h -fork=1 -ignore_crashes=1 -ignore_ooms=1 -seed="$SEED" -max_total_time="$SECONDS_EACH" -timeout=30 \
            -rss_limit_mb=2048 -dict=fuzz/$h.dict -artifact_prefix=$B/artifacts/$h/ $B/corpus/$h fuzz/corpus/$h \
            > "$log" 2>&1 || fuzzer_rc=$?
        runs=$(grep -E '^#[0-9]+:' "$log" | tail -1 | sed 's/^#\([0-9]*\):.*/\1/')
        rate=$(grep -E '^#[0-9]+:' "$log" | tail -1 | sed -n 's/.*exec\/s \([0-9]*\).*/\1/p')
        for f in $(find $B/artifacts/$h -type f -newer "$stamp" | sort); do
            case "$(basename "$f")" in crash-* | leak-* | oom-*) ;; *) rc=1; echo "fuzz_$h: $f" >> "$log"; continue ;; esac
            if assimp_defect "$h" "$f"; then
                echo "fuzz_$h: a defect of assimp's own, which accelbench's forked reader isolates: $f"
                isolated=$((isolated + 1))
            else
                echo "fuzz: $f is the project's defect (or accelbench does not isolate it); replay: $B/fuzz/fuzz_$h $f" >> "$log"
                rc=1
            fi
        done
        # Fork mode ends with the status of the last job that crashed, ignored or not: when every crash was
        # assimp's and the run ended as planned, that status is theirs; otherwise it is libFuzzer's own failure.
        if [ "$fuzzer_rc" != 0 ] && { [ "$isolated" = 0 ] || ! grep -q '^INFO: exiting: ' "$log"; }; then
            rc=$fuzzer_rc
        fi
    else
        $B/fuzz/fuzz_$h -seed="$SEED" -max_total_time="$SECONDS_EACH" -timeout=30 -rss_limit_mb=2048 -print_final_stats=1 \
            -dict=fuzz/$h.dict -artifact_prefix=$B/artifacts/$h/ $B/corpus/$h fuzz/corpus/$h > "$log" 2>&1 || rc=$?
        runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
        rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log")
    fi
    if [ "$rc" = 0 ]; then
        of_assimp=""
        [ "$isolated" = 0 ] || of_assimp=" of the project's ($isolated of assimp's own, isolated)"
        echo "fuzz_$h: ${runs:-?} executions in ${SECONDS_EACH} s (${rate:-?}/s), no crash$of_assimp, leak or timeout"
    else
        echo "fuzz_$h: FAILED (exit $rc) after ${runs:-?} executions; the log is $log:" >&2
        grep -E 'ERROR|WARNING|SUMMARY|runtime error|Test unit written|fuzz:' "$log" | head -20 >&2
        failed+=("$h")
    fi
done
[ ${#failed[@]} = 0 ] || { echo "fuzz: ${failed[*]} failed" >&2; exit 1; }
