#!/bin/bash
# test_docs_params.sh: every registered accelerator has its parameter table
# on exactly one page of docs/accels/, between <!-- params:NAME begin -->
# and <!-- params:NAME end -->, and that section is exactly what
# `accelbench list accels --markdown` prints. On a difference it prints the
# diff and the command that regenerates the sections
# (scripts/docs-params.sh). Prints "N passed, N failed"; exits 1 on a failure.
set -u
AB=${ACCELBENCH:?set ACCELBENCH to the accelbench binary}
SRC=${SRCDIR:-$(cd "$(dirname "$0")/.." && pwd)}
. "$(dirname "$0")/cli_lib.sh"

# The generated text itself: one section per registered accelerator.
n_gen=$("$AB" list accels --markdown | grep -c '^<!-- params:.* begin -->$')
n_reg=$("$AB" list accels | grep -cE '^  [a-z]')
[ "$n_gen" -gt 0 ] && [ "$n_gen" = "$n_reg" ] && ok || bad "list accels --markdown has $n_gen sections, list accels $n_reg accelerators"
expect_run 2 "unknown option" -- "$AB" list accels --bogus

# The pages against it.
if out=$("$SRC/scripts/docs-params.sh" --check "$AB" 2>&1); then ok; else bad "docs/accels/ differs from the parameter tables:"; echo "$out" >&2; fi

echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
