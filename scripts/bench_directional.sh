#!/bin/bash
# bench_directional.sh: the benchmark of the directional techniques
# against grid-raybox, the kit's SAH BVH (slabs-kk with the three axes,
# tree=sah, 4 primitives per leaf, depth-first) and Embree, on the SPD
# databases at their default sizes with their own lights (set:spd: tree has
# 7 lights, gears 5), the medium meshes (set:medium) and Sponza's courtyard
# (an interior view):
#   - Haines and Greenberg's light buffer (lightbuf) on shadow rays, with its
#     defaults (32 x 32 cells a face, every simplification on), with
#     res=auto (about 4 primitives a cell), and with cull, single and fullocc
#     off, to show what they buy;
#   - Arvo and Kirk's ray classification (raycls) on primary, shadow and
#     reflection rays, lazy (every timed pass starts from the post-build
#     state, so its lazy-build time, stat_lazy_build_ms, is part of every
#     sample), the same timed warm (--warm-passes: the passes after the first,
#     which the lazy build then leaves out) and eager (lazy=off: built to the
#     rays' needs before tracing);
#   - Ohta and Maekawa's ray coherence (raycoh) on the same rays: secondary
#     rays through the direction cube of the cluster they leave, eye rays
#     through its fallback (the wide bvh).
# Every cell is verified and paired with Embree (accelbench run), all in one
# matrix.csv: one `run` per parameter setting into the same folder (the cell
# key holds the parameters; an interrupted run resumes when started again
# with the same OUT). summary.md has the per-workload ratios and the
# per-configuration medians (scripts/summary.py).
#
# Environment: OUT (default results/directional-<date-time>), SCENES, RES,
# REPEAT. Extra arguments go to every `accelbench run` (e.g. --threads 1).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
AB=build/harness/accelbench
OUT=${OUT:-results/directional-$(date -u +%Y%m%d-%H%M%S)}
SCENES=${SCENES:-set:spd,set:medium,sponza}
COMMON=(--scenes "$SCENES" --res "${RES:-128x128}" --repeat "${REPEAT:-3}" --out "$OUT" --no-plots "$@")
SAH=(--param slabs-kk.normals=3 --param slabs-kk.tree=sah --param slabs-kk.maxleaf=4 --param slabs-kk.traverse=dfs)

# The peers on every workload either technique answers.
$AB run --accels grid-raybox,slabs-kk --workloads primary,shadow,reflection "${SAH[@]}" "${COMMON[@]}"
# The light buffer: shadow rays only.
$AB run --accels lightbuf --workloads shadow "${COMMON[@]}"
$AB run --accels lightbuf --workloads shadow --param lightbuf.res=auto "${COMMON[@]}"
$AB run --accels lightbuf --workloads shadow --param lightbuf.cull=off --param lightbuf.single=off \
    --param lightbuf.fullocc=off "${COMMON[@]}"
# Ray coherence (before ray classification, whose lazy passes are the longest).
$AB run --accels raycoh --workloads primary,shadow,reflection "${COMMON[@]}"
# Ray classification: lazy (its default), then eager.
$AB run --accels raycls --workloads primary,shadow,reflection "${COMMON[@]}"
$AB run --accels raycls --workloads primary,shadow,reflection --param raycls.lazy=off "${COMMON[@]}"
# Ray classification lazy, timed warm (--warm-passes): the timed passes trace the hyper-octrees the
# first pass grew, so cold over warm on the same rays is what lazy construction costs a first pass.
$AB run --accels raycls --workloads primary,shadow,reflection --warm-passes "${COMMON[@]}"

scripts/plot.py "$OUT/matrix.csv" --quiet
scripts/summary.py "$OUT/matrix.csv" --out "$OUT/summary.md"
echo "bench_directional: results in $OUT"
