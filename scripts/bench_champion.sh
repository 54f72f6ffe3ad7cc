#!/bin/bash
# bench_champion.sh: the target matrix of the champion accelerator
# `bvh` against Embree: the medium meshes (set:medium), Sponza's interior
# (`sponza`, whose default view is inside the atrium) and spd:balls:4:t;
# primary, shadow, reflection, diffuse and random rays; 1 and 2 threads.
# `bvh` runs with its defaults (isa=auto: the CSV's params column says which
# kernels ran) beside `embree` (its row gives Embree's build time and bytes
# per primitive at the same thread count); when bvh has a split=sbvh
# parameter, bvh split=sbvh also runs beside Embree quality=high (spatial
# splits on both sides). Every cell is verified and paired with Embree
# (accelbench run) in one matrix.csv; an interrupted run resumes when started
# again with the same OUT. scripts/champion_targets.py then writes
# summary.md (each target met or missed, the ISA, the machine) and
# ratios.png (the trace time ratios per scene and workload), every number
# read from the CSV.
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
for t in ${THREADS:-1 2}; do
    $AB run --accels bvh,embree --threads "$t" "${COMMON[@]}"
    if grep -q 'split=.*sbvh' <<< "$bvh_params"; then
        $AB run --accels bvh,embree --param bvh.split=sbvh --param embree.quality=high --threads "$t" "${COMMON[@]}"
    fi
done
scripts/champion_targets.py "$OUT/matrix.csv" --out "$OUT/summary.md" --plot "$OUT/ratios.png"
echo "bench_champion: results in $OUT (summary.md, ratios.png, matrix.csv)"
