#!/bin/bash
# bench_champion.sh: the target matrix of the champion accelerator
# `bvh` against Embree: the medium meshes (set:medium), Sponza's interior
# (`sponza`, whose default view is inside the atrium) and spd:balls:4:t;
# primary, shadow, reflection, diffuse and random rays; 1 and 2 threads.
# `bvh` runs with its defaults (isa=auto: the CSV's params column says which
# kernels ran) beside `embree` (its row gives Embree's build time and bytes
# per primitive at the same thread count); when bvh has a split=sbvh
# parameter, bvh split=sbvh also runs beside Embree quality=high (spatial
# splits on both sides); when bvh has a robust parameter, the like-with-like
# pairs run too: bvh (robust=on, its default) beside embree robust=on, and
# bvh robust=off beside Embree's default. Every cell is verified and paired with Embree
# (accelbench run) in one matrix.csv; an interrupted run resumes when started
# again with the same OUT. scripts/champion_targets.py then writes
# summary.md (each target met or missed, the ISA, the machine) and
# ratios.png (the trace time ratios per scene and workload), every number
# read from the CSV.
#
# For an outside tracer on the same rays and triangles (tinyanchor:
# docs/benchmarks.md), the 1-thread runs save their ray sets into OUT/rays/
# (SCENE__WORKLOAD.rays, ':' and '/' in the scene's name as '_') and every
# scene traced is written as NFF into OUT/nff/ (SCENE.nff, named the same
# way); champion_targets.py --anchor then reads that tracer's logs.
#
# Environment: OUT (default results/champion-<date-time>), SCENES, WORKLOADS,
# RES, REPEAT, THREADS (space-separated thread counts, default "1 2").
# Extra arguments go to every `accelbench run`.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
AB=build/harness/accelbench
OUT=${OUT:-results/champion-$(date -u +%Y%m%d-%H%M%S)}
SCENES=${SCENES:-set:medium,sponza,spd:balls:4:t}
COMMON=(--scenes "$SCENES" --workloads "${WORKLOADS:-primary,shadow,reflection,diffuse,random}" --res "${RES:-256x256}"
        --repeat "${REPEAT:-5}" --out "$OUT" --no-plots "$@")
# bvh's parameter list as `accelbench list accels` prints it: from its name line to the next accelerator's.
bvh_params=$($AB list accels | awk '/^  [^ ]/ {on = ($1 == "bvh")} on')
# One ray set is saved to a file, several to a folder (accelbench run --save-rays): name the file
# of a single scene and workload as the folder would.
WL=${WORKLOADS:-primary,shadow,reflection,diffuse,random}
if [[ $SCENES != *,* && $SCENES != set:* && $WL != *,* ]]; then
    mkdir -p "$OUT/rays"
    SAVE=(--save-rays "$OUT/rays/${SCENES//[:\/]/_}__$WL.rays")
else
    SAVE=(--save-rays "$OUT/rays")
fi
for t in ${THREADS:-1 2}; do
    save=()
    [ "$t" = 1 ] && save=("${SAVE[@]}")
    $AB run --accels bvh,embree --threads "$t" "${save[@]}" "${COMMON[@]}"
    if grep -q 'split=.*sbvh' <<< "$bvh_params"; then
        $AB run --accels bvh,embree --param bvh.split=sbvh --param embree.quality=high --threads "$t" "${COMMON[@]}"
    fi
    if grep -q '^ *robust=' <<< "$bvh_params"; then
        # bvh (robust=on) against embree robust=on, bvh robust=off against Embree's default; each
        # row is paired with default Embree on the same rays, so champion_targets.py takes quotients.
        $AB run --accels 'bvh[robust=off],embree[robust=on],embree' --threads "$t" "${COMMON[@]}"
    fi
done
# Every scene traced (the CSV's scene column: sets expanded, views included) as NFF, for the outside tracer.
mkdir -p "$OUT/nff"
python3 -c 'import csv, sys; print("\n".join(dict.fromkeys(r["scene"] for r in csv.DictReader(open(sys.argv[1])))))' \
    "$OUT/matrix.csv" | while IFS= read -r scene; do
    nff="$OUT/nff/${scene//[:\/]/_}.nff"
    [ -s "$nff" ] || $AB scene export "$scene" --nff "$nff" </dev/null
done
scripts/champion_targets.py "$OUT/matrix.csv" --out "$OUT/summary.md" --plot "$OUT/ratios.png"
echo "bench_champion: results in $OUT (summary.md, ratios.png, matrix.csv; rays/ and nff/ for an outside tracer)"
