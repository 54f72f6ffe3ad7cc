#!/bin/bash
# test_slurm.sh: the sharded matrix on a real Slurm: a single-node
# cluster brought up on this machine (munged on a socket of its own,
# slurmctld -D and slurmd -D with a minimal slurm.conf for the host, in a
# temporary folder; stopped by PID at the end), a 4-shard matrix (2 SPD
# scenes x 3 accelerators x 2 workloads at 16x16, repeat 1) submitted with
# scripts/slurm/submit.sh, the merge job waited for; the merged CSV is
# compared with a one-machine run column by column
# (scripts/compare_matrix.py); then a shard's folder loses its last row (a
# task killed before writing it) and only that task is resubmitted
# (--tasks K): it resumes, measures that one cell, and the merge again
# succeeds with every cell once. The Slurm packages (scripts/setup.sh's
# list) are installed when missing. If Slurm cannot start, the test fails
# with the daemons' logs. Prints "N passed, N failed"; exits 1 on a failure.
set -u
AB=${ACCELBENCH:?set ACCELBENCH to the accelbench binary}
SRCDIR=${SRCDIR:?set SRCDIR to the source folder}
. "$(dirname "$0")/cli_lib.sh"
PY=/usr/bin/python3
t0=$(date +%s.%N)
T=$(mktemp -d /tmp/accelbench-slurm.XXXXXX)
chmod 755 "$T"
pids=()
cleanup() {
    if [ -n "${SLURM_CONF:-}" ] && [ -f "$SLURM_CONF" ]; then
        for j in $(squeue -h -o %A 2> /dev/null); do scancel "$j" 2> /dev/null; done
    fi
    for p in "${pids[@]}"; do kill "$p" 2> /dev/null; done
    for p in "${pids[@]}"; do
        for _ in $(seq 1 50); do kill -0 "$p" 2> /dev/null || break; sleep 0.1; done
        kill -KILL "$p" 2> /dev/null
    done
    [ -f "$T/munged.pid" ] && kill "$(cat "$T/munged.pid")" 2> /dev/null
    rm -rf "$T"
}
trap cleanup EXIT
logs() {
    for f in "$T"/munged.log "$T"/slurmctld.log "$T"/slurmd.log "$T"/*.err; do
        [ -f "$f" ] && { echo "--- $f" >&2; tail -15 "$f" >&2; }
    done
}
give_up() { bad "$*"; logs; echo "$pass passed, $fail failed"; exit 1; }

# --- the packages, when missing (scripts/setup.sh lists them)
pkgs=$(sed -n 's/^ *\(slurmctld[^#]*\)#.*/\1/p' "$SRCDIR/scripts/setup.sh")
[ -n "$pkgs" ] || give_up "scripts/setup.sh lists no Slurm packages"
missing=()
for p in $pkgs; do dpkg-query -W -f='${Status}' "$p" 2> /dev/null | grep -q "install ok installed" || missing+=("$p"); done
if [ ${#missing[@]} -gt 0 ]; then
    echo "test_slurm: installing ${missing[*]}"
    [ "$(id -u)" = 0 ] || give_up "the Slurm packages ${missing[*]} are missing and this is not root"
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" > "$T/apt.err" 2>&1 \
        || give_up "apt-get install ${missing[*]} failed"
fi
for b in munged slurmctld slurmd sbatch squeue sinfo scontrol; do
    command -v "$b" > /dev/null || [ -x "/usr/sbin/$b" ] || give_up "$b not found after installing $pkgs"
done
export PATH="$PATH:/usr/sbin"
[ "$(id -u)" = 0 ] || give_up "the single-node Slurm runs as root (SlurmUser=root); run the test as root"

# --- munge: the system's key (made when there is none), a daemon of our own on a socket in $T
key=/etc/munge/munge.key
if [ ! -s "$key" ]; then
    mkdir -p /etc/munge
    if command -v mungekey > /dev/null || [ -x /usr/sbin/mungekey ]; then mungekey --create --keyfile="$key" --force 2> "$T/mungekey.err"
    else dd if=/dev/urandom of="$key" bs=1 count=1024 2> /dev/null; fi
    chown munge:munge "$key" && chmod 0400 "$key"
fi
mkdir -p "$T/munge" && chown munge:munge "$T/munge" && chmod 755 "$T/munge"
sock="$T/munge/munge.socket.2"
runuser -u munge -- munged --socket="$sock" --key-file="$key" --pid-file="$T/munge/munged.pid" \
    --log-file="$T/munge/munged.log" --seed-file="$T/munge/munged.seed" 2> "$T/munged.err" \
    || give_up "munged did not start"
cp "$T/munge/munged.pid" "$T/munged.pid" 2> /dev/null
for _ in $(seq 1 50); do [ -S "$sock" ] && break; sleep 0.1; done
[ -S "$sock" ] && ok || give_up "munged made no socket at $sock"

# --- slurm.conf for this host
host=$(hostname -s)
cpus=$(nproc)
mem=$(free -m | awk '/^Mem:/ { print int($2 * 0.9) }')
read -r cport dport < <("$PY" -c 'import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])')
mkdir -p "$T/state" "$T/spool"
export SLURM_CONF="$T/slurm.conf"
cat > "$SLURM_CONF" <<CONF
ClusterName=accelbench-ci
SlurmctldHost=$host
SlurmctldPort=$cport
SlurmdPort=$dport
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$sock
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/slurmctld.log
SlurmdLogFile=$T/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MpiDefault=none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/backfill
MinJobAge=300
NodeName=$host CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=ci Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF

# --- the daemons
slurmctld -D -f "$SLURM_CONF" > "$T/slurmctld.err" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" > "$T/slurmd.err" 2>&1 &
pids+=($!)
up=0
for _ in $(seq 1 300); do
    st=$(sinfo -h -N -o %T 2> /dev/null | head -1)
    [ "$st" = idle ] && { up=1; break; }
    for p in "${pids[@]}"; do kill -0 "$p" 2> /dev/null || give_up "a Slurm daemon exited (pid $p)"; done
    sleep 0.1
done
[ $up = 1 ] && ok || give_up "the node is not idle after 30 s (sinfo: '${st:-nothing}')"
t_up=$(date +%s.%N)

# job_states ID: the states of a job's tasks, sorted, one space after each
job_states() { scontrol show job "$1" 2> /dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p' | sort -u | tr '\n' ' '; }
# wait_job ID: until it has left the queue; prints its final state (scontrol keeps it MinJobAge seconds)
wait_job() {
    local st=""
    for _ in $(seq 1 1500); do
        if grep -q "DependencyNeverSatisfied" <(scontrol show job "$1" 2> /dev/null); then echo "NEVER"; return; fi
        if [ -z "$(squeue -h -j "$1" 2> /dev/null)" ]; then
            # Read the state after the job has left the queue, not before: a
            # state read first can be COMPLETING from just before it ended
            # (CI saw "merge job 2: COMPLETING" for a merge that had succeeded).
            st=$(job_states "$1")
            case " $st" in *" COMPLETING "*) ;; *) echo "${st% }"; return ;; esac
        fi
        sleep 0.2
    done
    st=$(job_states "$1")
    echo "TIMEOUT ${st% }"
}

# --- a 4-shard matrix through submit.sh
MATRIX=(--scenes spd:balls:1,spd:gears:1 --accels exhaustive,embree,grid --workloads primary,shadow --res 16x16 --repeat 1)
O="$T/out"
sub=$("$SRCDIR/scripts/slurm/submit.sh" --shards 4 --out "$O" --threads 1 --partition ci --time 00:10:00 \
      --accelbench "$AB" -- "${MATRIX[@]}" 2> "$T/submit.err") && ok || give_up "submit.sh failed: $(cat "$T/submit.err")"
jid=$(sed -n 's/^array job: \([0-9]*\).*/\1/p' <<<"$sub")
mid=$(sed -n 's/^merge job: \([0-9]*\).*/\1/p' <<<"$sub")
[ -n "$jid" ] && [ -n "$mid" ] && ok || give_up "submit.sh printed no job ids: $sub"
grep -q "Dependency=afterok:${jid}" <(scontrol show job "$mid") && ok || bad "the merge job does not depend on the array"
[ "$(scontrol show job "$jid" | grep -c 'ArrayTaskId=')" -ge 1 ] && ok || bad "job $jid is not an array"
st=$(wait_job "$mid")
[ "$st" = COMPLETED ] && ok || { bad "merge job $mid: $st"; for f in "$O"/logs/*.out; do echo "--- $f" >&2; tail -5 "$f" >&2; done; logs; }
for k in 0 1 2 3; do
    grep -q "accelbench shard $((k + 1))/4: job ${jid}_$k" "$O/logs/shard-$k.out" 2> /dev/null && ok || bad "no log of task $k"
done
grep -q "^merge: success: $O/merged/matrix.csv" "$O/logs/merge.out" 2> /dev/null && ok || bad "the merge job's log says no success"
[ -f "$O/merged/matrix.csv" ] && ok || give_up "no merged CSV"
ls "$O"/merged/*.png > /dev/null 2>&1 && ok || bad "the merge wrote no plots"
t_done=$(date +%s.%N)

# --- the same matrix on one machine, column by column
"$AB" run "${MATRIX[@]}" --threads 1 --no-plots --quiet --out "$T/one" 2> "$T/one.err" && ok || bad "one-machine run"
"$PY" "$SRCDIR/scripts/compare_matrix.py" "$T/one/matrix.csv" "$O/merged/matrix.csv" > "$T/cmp.out" && ok \
    || { bad "merged != one-machine run"; cat "$T/cmp.out" >&2; }
[ "$(($(wc -l < "$O/merged/matrix.csv") - 1))" = 12 ] && ok || bad "the merged CSV has not 12 rows"

# --- a task killed before its last row, resubmitted alone: it resumes, no row twice
k=0
for s in 1 2 3 4; do [ "$(wc -l < "$O/shard-$s/matrix.csv")" -gt 1 ] && k=$s && break; done
before=$(wc -l < "$O/shard-$k/matrix.csv")
head -n -1 "$O/shard-$k/matrix.csv" > "$T/cut" && cat "$T/cut" > "$O/shard-$k/matrix.csv"
rm -rf "$O/merged"
sub=$("$SRCDIR/scripts/slurm/submit.sh" --shards 4 --out "$O" --threads 1 --tasks "$k" --accelbench "$AB" -- "${MATRIX[@]}" 2> "$T/submit2.err") \
    && ok || bad "resubmission failed: $(cat "$T/submit2.err")"
mid=$(sed -n 's/^merge job: \([0-9]*\).*/\1/p' <<<"$sub")
st=$(wait_job "$mid")
[ "$st" = COMPLETED ] && ok || { bad "merge after resubmission: $st"; tail -5 "$O"/logs/*.out >&2; }
[ "$(wc -l < "$O/shard-$k/matrix.csv")" = "$before" ] && ok || bad "shard $k has $(wc -l < "$O/shard-$k/matrix.csv") lines, had $before"
grep -q "1 of this run's" "$O/logs/shard-$((k - 1)).out" 2> /dev/null || grep -q "^\[$((before - 1))/$((before - 1))\]" "$O/logs/shard-$((k - 1)).out" \
    && ok || { bad "the resubmitted task did not resume"; cat "$O/logs/shard-$((k - 1)).out" >&2; }
[ "$(grep -c '^\[' "$O/logs/shard-$((k - 1)).out")" = 1 ] && ok || bad "the resubmitted task measured other than its one missing cell"
"$PY" "$SRCDIR/scripts/compare_matrix.py" "$T/one/matrix.csv" "$O/merged/matrix.csv" > "$T/cmp2.out" && ok \
    || { bad "merged after resubmission != one-machine run"; cat "$T/cmp2.out" >&2; }
refused "submit.sh: .*another matrix" -- "$SRCDIR/scripts/slurm/submit.sh" --shards 4 --out "$O" --accelbench "$AB" -- --scenes spd:balls:2

t1=$(date +%s.%N)
printf 'test_slurm: Slurm up in %.1f s, the 4-shard matrix merged in %.1f s, whole test %.1f s\n' \
    "$(echo "$t_up - $t0" | bc)" "$(echo "$t_done - $t_up" | bc)" "$(echo "$t1 - $t0" | bc)"
echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
