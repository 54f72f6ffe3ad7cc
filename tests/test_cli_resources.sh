#!/bin/bash
# test_cli_resources.sh: resources from the command line. What a
# command would allocate is estimated first and refused above the memory cap
# (--memcap MIB, default half the memory the process may use: prlimit and
# `ulimit -v` lower it) with exit 2 and ONE line naming what, the bytes, the
# cap and how to raise it; an allocation that fails anyway is exit 2 with
# its line, never an abort. The cases: --res 16384x16384, an
# NFF's resolution 1000000 1000000, scene info spd:balls:5:t64, --threads
# 1024 under a limit. Prints "N passed, N failed"; exits 1 on a failure.
set -u
AB=${ACCELBENCH:?set ACCELBENCH to the accelbench binary}
T=$(mktemp -d /tmp/accelbench-cli-resources.XXXXXX)
trap 'rm -rf "$T"' EXIT
GiB=$((1 << 30)) MiB=$((1 << 20))

. "$(dirname "$0")/cli_lib.sh"
# limited BYTES command...: the command under an address-space limit (RLIMIT_AS)
# Under AddressSanitizer (scripts/test.sh's second run) no such case can run: its shadow memory alone
# reserves terabytes of address space, so any limit that means something here kills it at start (exit
# 134). Those cases are counted and named as not run in that build, never as passed; the same script in
# build/ runs them all, in the same CI run.
limited_not_run=0
if ldd "$AB" 2>/dev/null | grep -q libasan; then
    limited() { limited_not_run=$((limited_not_run + 1)); return 99; }
    expect() { local want=$1 pat=$2; shift 3; [ "$1" = limited ] || [ "$1" = bash ] && { limited_not_run=$((limited_not_run + 1)); return; }; expect_run "$want" "$pat" -- "$@"; }
    refused() { local pat=$1; shift 2; [ "$1" = limited ] || [ "$1" = bash ] && { limited_not_run=$((limited_not_run + 1)); return; }; refused_run "$pat" -- "$@"; }
else
    limited() { local as=$1; shift; prlimit --as="$as" -- "$@"; }
fi

RAISE="raise it with --memcap MIB"

# --- --memcap on every command that allocates, with its --help line
for cmd in run verify render; do expect 0 "--memcap MIB" -- "$AB" $cmd --help; done
expect 0 "--memcap MIB" -- "$AB" scene --help
expect 0 "--memcap MIB" -- "$AB" reproduce --help
refused "--memcap 0: expected MiB" -- "$AB" verify --scenes spd:balls:1 --memcap 0
refused "--memcap abc: expected MiB" -- "$AB" run --scenes spd:balls:1 --memcap abc
refused "--memcap -1: expected MiB" -- "$AB" scene info spd:balls:1 --memcap -1
refused "--memcap 2x: expected MiB" -- "$AB" scene export spd:balls:1 --nff "$T/x.nff" --memcap 2x
refused "--memcap x: expected MiB" -- "$AB" reproduce woo92 --quick --memcap x

# --- --res 16384x16384 (the parser's own maximum): 2^28 rays and their answers, refused before any scene loads
refused "primary on spd:balls:1: up to 268435456 rays \(16384x16384 at 1 spp\) and their answers need [0-9]+ bytes.*above the memory cap of 1024 MiB \(--memcap 1024\); $RAISE" \
    -- "$AB" verify --scenes spd:balls:1 --accels exhaustive --res 16384x16384 --memcap 1024
# the default cap, lowered by the process's limit
refused "up to 268435456 rays.*memory cap of [0-9]+ MiB \(default: half of the [0-9]+ MiB left under the address-space limit of 2048 MiB \(RLIMIT_AS, ulimit -v\)\)" \
    -- limited $((2 * GiB)) "$AB" verify --scenes spd:balls:1 --res 16384x16384
refused "up to 268435456 rays" -- limited $((2 * GiB)) "$AB" run --scenes spd:balls:1 --res 16384x16384 --out "$T/run16k"
[ ! -e "$T/run16k/matrix.csv" ] && ok || bad "a refused run wrote $T/run16k/matrix.csv"
refused "render spd:balls:1: a 16384x16384 at 1 spp image and its 268435456 rays need .*memory cap of 256 MiB" \
    -- "$AB" render --scene spd:balls:1 --accel embree --res 16384x16384 --out "$T/big.png" --memcap 256
[ ! -e "$T/big.png" ] && ok || bad "a refused render wrote $T/big.png"
# more rays than a ray set holds, whatever the cap
refused "16384x16384 at 16 spp makes up to 4294967296 rays, more than a ray set holds" \
    -- "$AB" verify --scenes spd:balls:1 --res 16384x16384 --spp 16 --workloads primary --memcap 1000000000

# a replayed ray file: read whole and copied, with its answers
"$AB" verify --scenes spd:balls:1 --accels exhaustive --workloads primary --res 300x300 --threads 1 --save-rays "$T/r.rays" > /dev/null 2>&1
refused "--rays $T/r.rays: a [0-9]+-byte file of up to [0-9]+ rays and their answers need .*memory cap of 4 MiB" \
    -- "$AB" verify --scenes spd:balls:1 --accels exhaustive --rays "$T/r.rays" --threads 1 --memcap 4
expect 0 "spd:balls:1 +primary +exhaustive +90000" -- "$AB" verify --scenes spd:balls:1 --accels exhaustive --rays "$T/r.rays" --threads 1 --memcap 16

# --- an NFF's resolution: above the largest image side at its line; at it, the cap decides
nff_view() { printf 'v\nfrom 0 0 10\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution %s\ns 0 0 0 1\n' "$1"; }
nff_view "1000000 1000000" > "$T/huge.nff"
refused "$T/huge.nff:7: a width '1000000' is absurd \(more than 16384\)" -- "$AB" render --scene "$T/huge.nff" --accel embree --out "$T/h.png"
refused "$T/huge.nff:7: .*16384" -- "$AB" scene info "$T/huge.nff"
nff_view "16384 16384" > "$T/large.nff"
refused "render $T/large.nff: a 16384x16384 at 1 spp image .*memory cap of 256 MiB.*the scene's own resolution: --res sets another" \
    -- "$AB" render --scene "$T/large.nff" --accel embree --out "$T/l.png" --memcap 256
refused "a 16384x16384 at 1 spp heat map" -- "$AB" render --scene "$T/large.nff" --accel exhaustive --heatmap tests --out "$T/l.png" --memcap 256
expect 0 "wrote $T/l.png: 32x32" -- "$AB" render --scene "$T/large.nff" --accel embree --res 32x32 --out "$T/l.png" --memcap 256

# --- scene info spd:balls:5:t64: 3.26e9 triangles, estimated from the generator's parameters before generating
refused "spd:balls:5:t64: 3265167362 primitives \(triangles\) and 1632716544 vertices need [0-9]+ bytes \([0-9.]+ MiB\), above the memory cap of [0-9]+ MiB \(default: half of .*RLIMIT_AS.*\); $RAISE" \
    -- limited $((2 * GiB)) "$AB" scene info spd:balls:5:t64
refused "spd:balls:5:t64: 3265167362 primitives.*memory cap of 100000 MiB \(--memcap 100000\)" -- "$AB" scene info spd:balls:5:t64 --memcap 100000
refused "spd:balls:5:t64: 3265167362 primitives" -- "$AB" scene export spd:balls:5:t64 --nff "$T/b5.nff" --memcap 1024
[ ! -e "$T/b5.nff" ] && ok || bad "a refused export wrote $T/b5.nff"
# run and verify refuse it before their first scene (at the fewest bytes a primitive takes)
refused "scene spd:balls:5:t64: 3265167362 primitives \(at least [0-9]+ bytes each\) need .*memory cap of 1024 MiB" \
    -- "$AB" run --scenes spd:balls:1,spd:balls:5:t64 --out "$T/runb5" --memcap 1024
# where the cap falls decides: spd:balls:3:t8 (629,762 triangles, about 31 MB) is refused at 16 MiB, made at 64
refused "spd:balls:3:t8: 629762 primitives \(triangles\) and 316524 vertices need .*memory cap of 16 MiB" \
    -- "$AB" scene info spd:balls:3:t8 --memcap 16
expect 0 "primitives 629762: 629762 triangles" -- "$AB" scene info spd:balls:3:t8 --memcap 64

# --- --threads 1024 under a memory limit: the threads' stacks, refused up front
refused "--threads 1024: the stacks of the 1023 threads it starts \([0-9.]+ MiB of address space each\) need .*above the memory cap.*RLIMIT_AS" \
    -- limited $((2 * GiB)) "$AB" verify --scenes spd:balls:1 --accels exhaustive --res 8x8 --threads 1024
refused "--threads 1024: the stacks of the 1023 threads" -- bash -c "ulimit -v $((2 * GiB / 1024)) && exec '$AB' run --scenes spd:balls:1 --threads 1024 --out '$T/run1024'"
refused "--threads 1024: the stacks of the 1023 threads" -- limited $((2 * GiB)) "$AB" render --scene spd:balls:1 --accel embree --out "$T/t.png" --threads 1024
refused "--threads 1024: the stacks of the 1023 threads" -- limited $((2 * GiB)) "$AB" reproduce woo92 --quick --threads 1024 --out "$T/woo"
refused "--threads 1024: the stacks of the 1023 threads .*memory cap of 1024 MiB" -- "$AB" verify --scenes spd:balls:1 --threads 1024 --memcap 1024
# and a thread count the limit holds still runs
expect 0 "spd:balls:1 +primary +exhaustive" -- limited $((2 * GiB)) "$AB" verify --scenes spd:balls:1 --accels exhaustive --workloads primary --res 8x8 --threads 4

# --- the accelerators' own caps: lowered to --memcap for the build (the label does not hold the cap); memcap is
# no accelerator parameter, --param and --accels point to --memcap
expect 0 "spd:balls:1 +primary +grid +64" -- "$AB" verify --scenes spd:balls:1 --accels grid --workloads primary --res 8x8 --threads 1 --memcap 64
refused "--param grid.memcap=128: grid: memcap is not a parameter: the memory cap is --memcap MIB" \
    -- "$AB" verify --scenes spd:balls:1 --accels grid --param grid.memcap=128 --memcap 64
refused "grid: memcap is not a parameter: the memory cap is --memcap MIB" \
    -- "$AB" verify --scenes spd:balls:1 --accels "grid[memcap=128]" --memcap 64
expect 2 "over memcap=64 MiB" -- "$AB" verify --scenes spd:balls:1 --accels grid --workloads primary --res 8x8 --threads 1 \
    --param grid.res=400x400x400 --memcap 64

# --- an allocation that fails anyway (the cap raised past the limit) is exit 2 naming it, not an abort
refused "out of memory: cannot allocate [0-9]+ bytes \([0-9.]+ MiB\) for the primitive store's" \
    -- limited $((300 * MiB)) "$AB" scene info spd:balls:4:t16 --memcap 100000
expect 2 "out of memory: cannot allocate [0-9]+ bytes \([0-9.]+ MiB\) for a ray set's (rays|pixels)" \
    -- limited $((1 * GiB)) "$AB" verify --scenes spd:balls:1 --accels exhaustive --workloads primary --res 8192x8192 --threads 1 --memcap 100000

[ "$limited_not_run" = 0 ] || echo "$limited_not_run cases under an address-space limit not run: this is an AddressSanitizer build (see limited())"
echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
