#!/bin/bash
# submit.sh: an accelbench matrix on a Slurm cluster: a job array of N
# shards (scripts/slurm/matrix.sbatch, one task a shard, --cpus-per-task =
# --threads), then the merge (scripts/slurm/merge.sbatch) with
# --dependency=afterok on the array. Prints both job ids. See
# docs/cluster.md.
#
#   scripts/slurm/submit.sh --shards N --out DIR [options] -- RUN_ARGS...
#
#   --shards N          shards, one array task each (1..4096)
#   --out DIR           results folder on a shared file system: DIR/shard-K, DIR/merged, DIR/logs
#   --threads T         tracing threads per shard, = --cpus-per-task (default 1)
#   --partition P       sbatch --partition for both jobs
#   --time T            sbatch --time for each shard task (e.g. 04:00:00)
#   --merge-time T      sbatch --time for the merge (default: --time)
#   --mem M             sbatch --mem for each shard task (e.g. 8G)
#   --max-parallel P    at most P tasks at once (--array=...%P)
#   --tasks LIST        only these shards (K, comma-separated; default all): resubmits failed ones, which resume
#   --accelbench PATH   the binary (default: this checkout's build/harness/accelbench)
#   --no-plots          the merge writes no plots
#   --sbatch-opt OPT    any other sbatch option for both jobs (repeatable), e.g. --sbatch-opt=--account=proj
#   RUN_ARGS            accelbench run's matrix: --scenes, --accels, --workloads, --res, --repeat, --param ...
#                       (not --threads, --shard, --out: submit.sh sets them)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
src=$(cd "$here/../.." && pwd)
usage() { sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; }
die() { echo "submit.sh: $*" >&2; exit 2; }

shards="" out="" threads=1 partition="" time="" merge_time="" mem="" maxpar="" tasks="" no_plots=0
ab="$src/build/harness/accelbench"
extra=()
while [ $# -gt 0 ]; do
    case "$1" in
    --shards) shards=${2:?}; shift 2 ;;
    --out) out=${2:?}; shift 2 ;;
    --threads) threads=${2:?}; shift 2 ;;
    --partition) partition=${2:?}; shift 2 ;;
    --time) time=${2:?}; shift 2 ;;
    --merge-time) merge_time=${2:?}; shift 2 ;;
    --mem) mem=${2:?}; shift 2 ;;
    --max-parallel) maxpar=${2:?}; shift 2 ;;
    --tasks) tasks=${2:?}; shift 2 ;;
    --accelbench) ab=${2:?}; shift 2 ;;
    --no-plots) no_plots=1; shift ;;
    --sbatch-opt=*) extra+=("${1#--sbatch-opt=}"); shift ;;
    --sbatch-opt) extra+=("${2:?}"); shift 2 ;;
    -h|--help) usage; exit 0 ;;
    --) shift; break ;;
    *) die "unknown option '$1' (the matrix's run arguments go after --; see --help)" ;;
    esac
done
[[ "$shards" =~ ^[0-9]+$ ]] && [ "$shards" -ge 1 ] && [ "$shards" -le 4096 ] || die "--shards '$shards': expected 1..4096"
[ -n "$out" ] || die "no --out DIR given"
[[ "$threads" =~ ^[0-9]+$ ]] && [ "$threads" -ge 1 ] || die "--threads '$threads': expected a positive integer"
[ $# -gt 0 ] || die "no matrix given: the run arguments go after -- (e.g. -- --scenes set:medium --accels bvh,embree)"
for a in "$@"; do
    case "$a" in --threads|--threads=*|--shard|--shard=*|--out|--out=*) die "run argument '$a': submit.sh sets it" ;; esac
done
[ -x "$ab" ] || die "--accelbench $ab: not an executable (build first: meson setup build && ninja -C build)"
command -v sbatch > /dev/null || die "sbatch not found (not a Slurm login node?)"
ab=$(cd "$(dirname "$ab")" && pwd)/$(basename "$ab")
mkdir -p "$out/logs" || die "$out: cannot create"
out=$(cd "$out" && pwd)

# The matrix, once: every resubmission must run the same one (merge checks it too).
args_file="$out/matrix.args"
[ ! -e "$args_file" ] || [ -f "$args_file" ] || die "$args_file: exists and is not a regular file: not replaced"
printf '%s\n' "$@" > "$args_file.new"
if [ -f "$args_file" ] && ! cmp -s "$args_file" "$args_file.new"; then
    rm -f "$args_file.new"
    die "$args_file: $out holds another matrix (other run arguments); choose another --out"
fi
mv "$args_file.new" "$args_file"

array="0-$((shards - 1))"
if [ -n "$tasks" ]; then
    array=""
    IFS=, read -ra ks <<< "$tasks"
    for k in "${ks[@]}"; do
        [[ "$k" =~ ^[0-9]+$ ]] && [ "$k" -ge 1 ] && [ "$k" -le "$shards" ] || die "--tasks: '$k' is not a shard 1..$shards"
        array+="${array:+,}$((k - 1))"
    done
fi
[ -n "$maxpar" ] && array+="%$maxpar"

common=()
[ -n "$partition" ] && common+=(--partition="$partition")
common+=("${extra[@]}")
env="ALL,ACCELBENCH=$ab,MATRIX_OUT=$out,MATRIX_SHARDS=$shards,MATRIX_ARGS=$args_file,MATRIX_THREADS=$threads,MATRIX_NO_PLOTS=$no_plots"
shard_opts=(--array="$array" --cpus-per-task="$threads" --output="$out/logs/shard-%a.out")
[ -n "$time" ] && shard_opts+=(--time="$time")
[ -n "$mem" ] && shard_opts+=(--mem="$mem")
merge_opts=(--cpus-per-task=1 --output="$out/logs/merge.out")
[ -n "${merge_time:-$time}" ] && merge_opts+=(--time="${merge_time:-$time}")

jid=$(sbatch --parsable "${common[@]}" "${shard_opts[@]}" --export="$env" "$here/matrix.sbatch") || die "sbatch of the array failed"
jid=${jid%%;*}
mid=$(sbatch --parsable "${common[@]}" "${merge_opts[@]}" --dependency="afterok:$jid" --export="$env" "$here/merge.sbatch") \
    || die "sbatch of the merge failed (the array $jid is queued: scancel $jid, or merge by hand)"
mid=${mid%%;*}
echo "array job: $jid ($array of $shards shards, $threads threads each; logs $out/logs/shard-<K-1>.out)"
echo "merge job: $mid (after the array succeeds; $out/merged, log $out/logs/merge.out)"
