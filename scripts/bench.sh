#!/bin/bash
# bench.sh: the default benchmark matrix. Installs and builds (setup.sh),
# then runs every accelerator on the default scenes and all five workloads,
# writing results/<date-time>/matrix.csv, run.txt, PNG plots and report.html
# (accelbench report: one self-contained page with the table, plots and heat maps).
#
# Exhaustive search is quadratic in practice (every ray tests every
# primitive), and ray classification rebuilds itself on every pass (below),
# so they run on the small scenes only; every other accelerator also runs
# on the larger meshes. Both passes append to the same CSV.
# Extra arguments go to both `accelbench run` calls (e.g. --threads 1).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
AB=build/harness/accelbench
OUT=${OUT:-results/$(date -u +%Y%m%d-%H%M%S)}
SMALL=${SMALL:-spd:balls:3,spd:balls:2:t,dragon}
LARGE=${LARGE:-bunny,head}
# every registered accelerator but exhaustive and raycls: Arvo and Kirk's
# ray classification is built lazily while tracing, and every timed pass
# starts again from its post-build state (the harness resets it), so each
# pass rebuilds its hyper-octrees: on the large meshes minutes a cell (head,
# random rays: 42 s a pass). Both run on the small scenes.
FAST=$($AB list accels | awk '/^  [a-z]/ && $1 != "exhaustive" && $1 != "raycls" {printf "%s%s", sep, $1; sep=","}')
$AB run --scenes "$SMALL" --res 128x128 --repeat 5 --out "$OUT" --no-plots "$@"
$AB run --scenes "$LARGE" --accels "$FAST" --res 128x128 --repeat 5 --out "$OUT" --report "$@"
echo "bench: results in $OUT (the report: $OUT/report.html)"
