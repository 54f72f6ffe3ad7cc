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
