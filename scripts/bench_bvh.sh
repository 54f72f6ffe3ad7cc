#!/bin/bash
# bench_bvh.sh: the benchmark of the bounding volume hierarchies
# against Embree: Goldsmith-Salmon's bvh-gs with each insertion order
# (given, sorted, and shuffle with K = 1, 8 and 32 trees, the cheapest by
# eq. (3) kept), Kay-Kajiya's slabs-kk with 3 and 7 plane-set normals and
# heap or depth-first traversal, and the kit's SAH BVH (slabs-kk with the
# three axes, tree=sah, 4 primitives per leaf, depth-first: an AABB BVH
# built by accel/bvh's binned SAH), on the SPD databases (set:spd), the
# medium meshes (set:medium) and Sponza's courtyard (an interior view).
# Every cell is verified and paired with Embree (accelbench run), all in one
# matrix.csv: one `run` per parameter setting into the same folder (the cell
# key holds the parameters; an interrupted run resumes when started again
# with the same OUT). bvh-gs's CSV rows carry eq. (3)'s prediction
# (predicted_tests_per_ray, predicted_box_tests_per_ray) beside the measured
# counters; summary.md gets a table of the two (scripts/summary.py
# --predicted).
#
# Environment: OUT (default results/bvh-<date-time>), SCENES, WORKLOADS,
# RES, REPEAT. Extra arguments go to every `accelbench run` (e.g. --threads 1).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
AB=build/harness/accelbench
OUT=${OUT:-results/bvh-$(date -u +%Y%m%d-%H%M%S)}
SCENES=${SCENES:-set:spd,set:medium,sponza}
COMMON=(--scenes "$SCENES" --workloads "${WORKLOADS:-primary,shadow,reflection}" --res "${RES:-128x128}"
        --repeat "${REPEAT:-3}" --out "$OUT" --no-plots "$@")
$AB run --accels bvh-gs,slabs-kk "${COMMON[@]}"                                  # shuffle K=1; 7 normals, median, heap
$AB run --accels bvh-gs --param bvh-gs.order=given "${COMMON[@]}"
$AB run --accels bvh-gs --param bvh-gs.order=sorted "${COMMON[@]}"
$AB run --accels bvh-gs --param bvh-gs.shuffles=8 "${COMMON[@]}"
$AB run --accels bvh-gs --param bvh-gs.shuffles=32 "${COMMON[@]}"
$AB run --accels slabs-kk --param slabs-kk.traverse=dfs "${COMMON[@]}"
$AB run --accels slabs-kk --param slabs-kk.normals=3 "${COMMON[@]}"
$AB run --accels slabs-kk --param slabs-kk.normals=3 --param slabs-kk.traverse=dfs "${COMMON[@]}"
$AB run --accels slabs-kk --param slabs-kk.normals=3 --param slabs-kk.tree=sah --param slabs-kk.maxleaf=4 \
    --param slabs-kk.traverse=dfs "${COMMON[@]}"                                 # the kit's SAH BVH
scripts/plot.py "$OUT/matrix.csv" --quiet
scripts/summary.py "$OUT/matrix.csv" --predicted --out "$OUT/summary.md"
echo "bench_bvh: results in $OUT"
