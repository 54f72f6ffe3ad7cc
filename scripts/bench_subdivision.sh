#!/bin/bash
# bench_subdivision.sh: the benchmark of the nonuniform space subdivisions
# against the grids and Embree: octree (defaults), bsp with each
# traversal (recursive = Jansen, the default; sequential = Kaplan; havran =
# TA^B_rec) on Kaplan's midpoint planes, bsp split=sah, grid at Havran and
# Sixta's D = 20 (res=cubic:20, its default since this benchmark) and at
# Woo's resolution rule (res=auto), and grid-raybox (Woo's rule), on the SPD databases (set:spd), the
# medium meshes (set:medium) and Sponza's courtyard (an interior view).
# Every cell is verified and paired with Embree (accelbench run), all in one
# matrix.csv: several `run` calls into the same folder, one per parameter
# setting (the cell key holds the parameters, so none overwrites another;
# an interrupted run resumes when started again with the same OUT).
#
# Environment: OUT (default results/subdivision-<date-time>), SCENES,
# WORKLOADS, RES, REPEAT. Extra arguments go to every `accelbench run`
# (e.g. --threads 1).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
AB=build/harness/accelbench
OUT=${OUT:-results/subdivision-$(date -u +%Y%m%d-%H%M%S)}
SCENES=${SCENES:-set:spd,set:medium,sponza}
COMMON=(--scenes "$SCENES" --workloads "${WORKLOADS:-primary,shadow,reflection}" --res "${RES:-128x128}"
        --repeat "${REPEAT:-3}" --out "$OUT" --no-plots "$@")
$AB run --accels grid,grid-raybox,octree,bsp "${COMMON[@]}"
$AB run --accels grid,bsp --param grid.res=auto --param bsp.split=sah "${COMMON[@]}"
$AB run --accels bsp --param bsp.traverse=sequential "${COMMON[@]}"
$AB run --accels bsp --param bsp.traverse=havran "${COMMON[@]}"
scripts/plot.py "$OUT/matrix.csv" --quiet
scripts/summary.py "$OUT/matrix.csv" --out "$OUT/summary.md"
echo "bench_subdivision: results in $OUT"
