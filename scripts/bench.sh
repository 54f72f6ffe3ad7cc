#!/bin/bash
# bench.sh [--full] [RUN OPTIONS...]: the default benchmark matrix. Installs
# and builds (setup.sh), then runs every accelerator on every workload over
# one scene of each kind, and writes results/<date-time>/: matrix.csv,
# run.txt, summary.md (the findings), params.csv, the PNG plots and
# report.html (accelbench report: the findings first, then figures and the
# full table). Progress lines give the time left of each pass.
#
# The default matrix takes a few minutes on two cores: SPD balls at size 3
# (820 true spheres), the tessellated balls at size 2 (9,830 triangles) and
# the Stanford bunny (75,408 scanned triangles), 96x96 primary rays, five
# timed repeats each paired with Embree's. --full is the larger matrix (the
# balls, the tessellated balls, CGAL's dragon; the bunny and the head at
# 128x128), about half an hour.
#
# Exhaustive search is quadratic in practice (every ray tests every
# primitive), and ray classification rebuilds itself on every timed pass
# (Arvo and Kirk's hyper-octrees grow lazily while tracing, and the harness
# starts each pass from the post-build state: on the large meshes minutes a
# cell), so those two run on the small scenes only; every other
# accelerator also runs on the meshes. Both passes append to the same CSV.
# Other arguments go to both `accelbench run` calls (e.g. --threads 1);
# SMALL=, LARGE=, RES= and OUT= replace the scenes, image size and folder, and
# the same OUT= again resumes an interrupted run.
set -euo pipefail
cd "$(dirname "$0")/.."
small=spd:balls:3,spd:balls:2:t large=bunny res=96x96
if [ "${1:-}" = --full ]; then
    shift
    small=spd:balls:3,spd:balls:2:t,dragon large=bunny,head res=128x128
fi
SMALL=${SMALL:-$small} LARGE=${LARGE:-$large} RES=${RES:-$res} # the environment may name others
scripts/setup.sh
AB=build/harness/accelbench
OUT=${OUT:-results/$(date -u +%Y%m%d-%H%M%S)}
FAST=$($AB list accels | awk '/^  [a-z]/ && $1 != "exhaustive" && $1 != "raycls" {printf "%s%s", sep, $1; sep=","}')
start=$(date +%s)
echo "bench: pass 1 of 2: every accelerator on $SMALL"
$AB run --scenes "$SMALL" --res "$RES" --repeat 5 --out "$OUT" --no-plots "$@"
echo "bench: pass 2 of 2: all but exhaustive and raycls on $LARGE"
$AB run --scenes "$LARGE" --accels "$FAST" --res "$RES" --repeat 5 --out "$OUT" --report "$@"
echo "bench: results in $OUT after $(($(date +%s) - start)) s (the findings: $OUT/summary.md; the report: $OUT/report.html)"
