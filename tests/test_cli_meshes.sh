#!/bin/bash
# test_cli_meshes.sh: the command line on the scene path's meshes (Sibenik,
# Sponza): their catalogue views load as recorded. Skipped, with the command
# that gets them, where they are absent (cli_lib.sh's require_meshes); CI
# requires them. Prints "N passed, N failed"; exits 1 on a failure.
set -u
AB=${ACCELBENCH:?set ACCELBENCH to the accelbench binary}
. "$(dirname "$0")/cli_lib.sh"
require_meshes sibenik sponza
expect 0 "view +nave: from \(-18 -10 0\) at \(0 -11 0\) up \(0 1 0\) angle 45 .*lights +2: \(-6 -4 0\) \(6 -3 2\)" -- bash -c "'$AB' scene info sibenik@nave | tr '\n' ' '"
expect 0 "view +courtyard: from \(120 18 -2\) at \(-100 30 -2\) up \(0 1 0\) angle 60" -- "$AB" scene info sponza
echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
