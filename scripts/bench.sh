#!/bin/bash
# bench.sh: the default benchmark matrix. Installs and builds (setup.sh),
# then runs every accelerator on the default scenes and all five workloads,
# writing results/<date-time>/matrix.csv, run.txt and PNG plots.
# Extra arguments go to `accelbench run` (e.g. --threads 1, --out DIR).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
SCENES=${SCENES:-spd:balls:3,spd:balls:2:t,dragon,bunny}
exec build/harness/accelbench run --scenes "$SCENES" --res 96x96 --repeat 5 "$@"
