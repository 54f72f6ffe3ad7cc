# cli_lib.sh: what every command-line test script shares (sourced, not
# run): the pass/fail counters, ok/bad, and the two checks of a command,
# expect (exit status and an output pattern) and refused (exit 2 and
# exactly one line). The scripts call expect and refused; expect_run and
# refused_run are the checks themselves, so a script can put its own
# expect/refused in front of them (test_cli_resources.sh under ASan).
pass=0 fail=0

ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }

# expect_run STATUS PATTERN -- command...: exit status and a stdout+stderr pattern
expect_run() {
    local want=$1 pat=$2; shift 3
    local out rc
    out=$("$@" 2>&1); rc=$?
    if [ "$rc" != "$want" ]; then bad "exit $rc (want $want): $*"; echo "$out" | tail -5 >&2; return; fi
    if [ -n "$pat" ] && ! grep -qE -- "$pat" <<<"$out"; then bad "no /$pat/ in output of: $*"; echo "$out" | tail -5 >&2; return; fi
    ok
}
# refused_run PATTERN -- command...: exit 2 and exactly one line of output, matching PATTERN
refused_run() {
    local pat=$1; shift 2
    local out rc
    out=$("$@" 2>&1); rc=$?
    if [ "$rc" != 2 ]; then bad "exit $rc (want 2): $*"; echo "$out" | tail -5 >&2; return; fi
    if [ "$(wc -l <<<"$out")" != 1 ]; then bad "$(wc -l <<<"$out") lines (want 1) from: $*"; echo "$out" | head -5 >&2; return; fi
    if ! grep -qE -- "$pat" <<<"$out"; then bad "no /$pat/ in: $out (from: $*)"; return; fi
    ok
}
expect() { expect_run "$@"; }
refused() { refused_run "$@"; }
# require_meshes NAME...: the guard of a script that needs meshes from public repositories (catalogue
# names): when one is absent from the scene path, one line naming it and the command that gets it, then
# exit 77 (meson's SKIP), or exit 1 where the meshes are required (CI=true or ACCELBENCH_REQUIRE_SCENES=1).
# tests/require_meshes.h is the same guard for the C tests.
require_meshes() {
    local listing absent=() n
    listing=$("$AB" list scenes 2>&1)
    for n in "$@"; do grep -qE "^$n +[^ ]+ +\[scene path, absent" <<<"$listing" && absent+=("$n"); done
    [ ${#absent[@]} = 0 ] && return 0
    if [ "${CI:-}" = true ] || [ "${ACCELBENCH_REQUIRE_SCENES:-}" = 1 ]; then
        echo "FAIL: ${absent[*]} not on the scene path; get it with scripts/get-scenes.sh ${absent[*]} (CI=true or ACCELBENCH_REQUIRE_SCENES=1: the meshes are required)"
        exit 1
    fi
    echo "SKIP: ${absent[*]} not on the scene path; get it with scripts/get-scenes.sh ${absent[*]}"
    exit 77
}
