#!/usr/bin/env bash
# A split render on a real, one-node Slurm cluster (make test-slurm; not part of make test).
#
# Installs munge and Slurm if missing (Debian 12: slurm-wlm 22.05), starts munged, slurmctld and
# slurmd on this host with a configuration in a temporary directory, and runs the README's recipe:
#   1. an 8-task array job, task i rendering `prism render SCENE --part i/8` to a .film with
#      --checkpoint-every 1s;
#   2. one task is cancelled (scancel) once its checkpoint exists, requeued (scontrol requeue)
#      and must resume from the checkpoint (its log says "resuming at sample s", s > its first);
#   3. a merge job, dependent on the array (afterany), runs `prism merge` on the parts.
# Then it checks against renders on this machine alone:
#   - the resumed part's .film equals an uninterrupted render of that part byte for byte (a
#     resumed render adds the same samples to the same sums in the same order);
#   - the merged EXR equals a single `prism render` of the scene byte for byte. The merged film's
#     f64 sums group the samples by part, so they may differ from the single render's in the last
#     bits; the image (f32 or half) does not, unless a value lies within that rounding of an f32
#     rounding boundary.
# Everything it starts is stopped on exit; the temporary directory is removed unless KEEP=1.
# Must run as root (it installs packages and runs the daemons as root).
#
# Environment: SCENE (default scenes/materials.pbrt), SPP (384), RESOLUTION (320x160),
# CANCEL_TASK (2), SLURM_PORT (6817; slurmd uses the next one), CARGO (cargo), KEEP (0).
set -euo pipefail
cd "$(dirname "$0")/.."

SCENE=$(realpath "${SCENE:-scenes/materials.pbrt}")
SPP=${SPP:-384}
RESOLUTION=${RESOLUTION:-320x160}
PARTS=8
CANCEL_TASK=${CANCEL_TASK:-2}
SLURM_PORT=${SLURM_PORT:-6817}
CARGO=${CARGO:-cargo}
PRISM=$PWD/target/release/prism
# The settings every render shares (parts, the uninterrupted part, the single render).
RENDER_ARGS="--spp $SPP --resolution $RESOLUTION --seed 7"

say() { echo "test-slurm: $*"; }
fail() {
  echo "test-slurm: FAILED: $*" >&2
  exit 1
}
# Runs "$@" until it succeeds, every 0.2 s, for at most $1 seconds; returns 1 on timeout.
wait_for() {
  local limit=$1 t0=$SECONDS
  shift
  until "$@"; do
    [ $((SECONDS - t0)) -lt "$limit" ] || return 1
    sleep 0.2
  done
}

[ "$(id -u)" -eq 0 ] || fail "run as root: it installs munge and Slurm and runs munged, slurmctld and slurmd"
[ -f "$SCENE" ] || fail "no scene $SCENE"

# --- packages --------------------------------------------------------------------------------
packages=(munge slurmctld slurmd slurm-client)
need=()
for p in "${packages[@]}"; do
  [ "$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)" = "install ok installed" ] || need+=("$p")
done
if [ ${#need[@]} -gt 0 ]; then
  say "installing ${need[*]}"
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need[@]}" >/dev/null
fi

say "building prism (release)"
$CARGO build --release --quiet

# --- temporary cluster -----------------------------------------------------------------------
T=$(mktemp -d /tmp/prism-slurm.XXXXXX)
# munged refuses a socket whose directories others cannot search.
chmod 755 "$T"
mkdir -p "$T"/{munge,state,spool,log,parts,ref}
chmod 755 "$T/munge"
export SLURM_CONF=$T/slurm.conf
jobid=""

# Stops the process in pid file $1: SIGTERM, then up to 10 s for it to exit.
stop_pidfile() {
  [ -f "$1" ] || return 0
  local pid
  pid=$(cat "$1")
  kill -0 "$pid" 2>/dev/null || return 0
  kill "$pid" 2>/dev/null || true
  wait_for 10 eval "! kill -0 $pid 2>/dev/null" || kill -9 "$pid" 2>/dev/null || true
}
cleanup() {
  local rc=$?
  set +e
  if [ -n "$jobid" ]; then scancel "$jobid" "${merge_jobid:-}" 2>/dev/null; fi
  if [ -f "$T/slurmctld.pid" ]; then scontrol shutdown >/dev/null 2>&1; fi
  stop_pidfile "$T/slurmd.pid"
  stop_pidfile "$T/slurmctld.pid"
  stop_pidfile "$T/munge/munged.pid"
  if [ $rc -ne 0 ]; then
    for f in "$T"/log/*.log; do
      [ -s "$f" ] && { echo "--- last lines of $f"; tail -n 15 "$f"; }
    done >&2
  fi
  if [ "${KEEP:-0}" = 1 ]; then say "kept $T"; else rm -rf "$T"; fi
}
trap cleanup EXIT

# munge, with its own key and socket: the host's munge (if any) is left alone.
dd if=/dev/urandom of="$T/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$T/munge/munge.key"
sock=$T/munge/munge.socket
munged --socket="$sock" --key-file="$T/munge/munge.key" --pid-file="$T/munge/munged.pid" \
  --log-file="$T/log/munged.log" --seed-file="$T/munge/munged.seed" ||
  fail "munged did not start (see $T/log/munged.log)"
munge -n --socket="$sock" | unmunge --socket="$sock" >/dev/null || fail "munge cannot decode its own credential"

# This host as the only node, described by slurmd itself (CPUs, sockets, cores, RealMemory).
# NodeAddr and the controller's address are 127.0.0.1: the host name need not resolve.
node=$(slurmd -C | head -n 1)
host=$(hostname -s)
case "$node" in NodeName=*) ;; *) fail "slurmd -C printed no node description: $node" ;; esac
cat >"$SLURM_CONF" <<EOF
ClusterName=prismtest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$SLURM_PORT
SlurmdPort=$((SLURM_PORT + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$sock
CredType=cred/munge
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/log/slurmctld.log
SlurmdLogFile=$T/log/slurmd.log
# No cgroups: a container rarely has a cgroup tree of its own to delegate.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
MpiDefault=none
SwitchType=switch/none
MailProg=/bin/true
ReturnToService=2
$node NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=render Nodes=$host Default=YES MaxTime=60 State=UP
EOF
slurmctld -f "$SLURM_CONF" || fail "slurmctld did not start (port $SLURM_PORT in use? set SLURM_PORT)"
slurmd -f "$SLURM_CONF" || fail "slurmd did not start"
node_idle() { [ "$(sinfo -h -n "$host" -o %T 2>/dev/null)" = idle ]; }
wait_for 60 node_idle || fail "node $host did not become idle: $(sinfo -h -o '%T %E' 2>&1)"
say "cluster up: $node (munged, slurmctld, slurmd; config in $T)"

# --- the array job ---------------------------------------------------------------------------
cat >"$T/part.sbatch" <<EOF
#!/bin/bash
#SBATCH --job-name=prism-part
#SBATCH --array=1-$PARTS
#SBATCH --cpus-per-task=1
#SBATCH --time=15
#SBATCH --requeue
#SBATCH --open-mode=append
#SBATCH --output=$T/log/part-%a.log
set -eu
i=\$SLURM_ARRAY_TASK_ID
out=$T/parts/part\$i.film
resume=()
if [ -f "\$out.ckpt" ]; then resume=(--resume); fi
echo "part \$i/$PARTS: run \$((\${SLURM_RESTART_COUNT:-0} + 1))\${resume:+, from \$out.ckpt}"
exec $PRISM render $SCENE $RENDER_ARGS --threads \$SLURM_CPUS_PER_TASK \\
  --part \$i/$PARTS --checkpoint-every 1s "\${resume[@]}" -o "\$out"
EOF
jobid=$(sbatch --parsable "$T/part.sbatch" | cut -d';' -f1)
say "submitted array job $jobid (tasks 1-$PARTS): $(basename "$SCENE") $RENDER_ARGS --part i/$PARTS"

task=${jobid}_$CANCEL_TASK
state() { scontrol -o show job "$1" 2>/dev/null | grep -o 'JobState=[A-Z_]*' | head -n 1 | cut -d= -f2; }
ckpt=$T/parts/part$CANCEL_TASK.film.ckpt
ckpt_or_done() { [ -f "$ckpt" ] || [ "$(state "$task")" = COMPLETED ]; }
wait_for 300 ckpt_or_done || fail "task $task wrote no checkpoint within 300 s (state $(state "$task"))"
[ -f "$ckpt" ] || fail "task $task completed before its first checkpoint: raise SPP"
scancel "$task"
cancelled() { case "$(state "$task")" in CANCELLED | COMPLETED | FAILED) true ;; *) false ;; esac }
wait_for 30 cancelled || fail "task $task not cancelled after 30 s (state $(state "$task"))"
[ "$(state "$task")" = CANCELLED ] || fail "task $task ended $(state "$task") before scancel reached it: raise SPP"
[ -f "$ckpt" ] || fail "the checkpoint of task $task is gone after its cancellation"
held=$(head -c 4096 "$ckpt" | tr -d '\0' | grep -ao '"samples":{[^}]*}' | head -n 1)
say "cancelled $task with a checkpoint on disk: $held"

scontrol requeue "$task" || fail "scontrol requeue $task failed"
# A requeued batch job becomes eligible only after Slurm's requeue delay (about 2 min).
scontrol update JobId="$task" StartTime=now || fail "could not make $task eligible now"
say "requeued $task"

# afterany, not afterok: Slurm 22.05 holds an afterok on an array whose task was cancelled as
# never satisfied, even once the task is requeued and completes. Merge names a missing part.
parts=$(printf "$T/parts/part%d.film " $(seq 1 $PARTS))
merge_jobid=$(sbatch --parsable --job-name=prism-merge --dependency=afterany:"$jobid" --time=5 \
  --output="$T/log/merge.log" --wrap="$PRISM merge $parts -o $T/merged.exr" | cut -d';' -f1)
say "submitted merge job $merge_jobid (afterany:$jobid)"

merge_ended() {
  case "$(state "$merge_jobid")" in
    COMPLETED | FAILED | CANCELLED | TIMEOUT) true ;;
    *) scontrol -o show job "$merge_jobid" | grep -q 'Reason=DependencyNeverSatisfied' ;;
  esac
}
wait_for 900 merge_ended || fail "merge job not finished after 900 s: $(squeue -h -o '%i %T %r' 2>&1 | tr '\n' ';')"
for i in $(seq 1 $PARTS); do
  s=$(state "${jobid}_$i")
  [ "$s" = COMPLETED ] || fail "task ${jobid}_$i ended $s (log: $(tail -n 1 "$T/log/part-$i.log" 2>/dev/null))"
done
[ "$(state "$merge_jobid")" = COMPLETED ] ||
  fail "merge job $(state "$merge_jobid") ($(squeue -h -j "$merge_jobid" -o %r 2>/dev/null)): $(tail -n 1 "$T/log/merge.log" 2>/dev/null)"
say "all $PARTS tasks and the merge completed: $(tail -n 1 "$T/log/merge.log")"
say "the log of task $task:"
sed 's/^/    /' "$T/log/part-$CANCEL_TASK.log"
resumed=$(grep -o 'resuming at sample [0-9]*' "$T/log/part-$CANCEL_TASK.log" | grep -o '[0-9]*$') ||
  fail "task $task did not resume from its checkpoint (no 'resuming at sample' in its log)"
first=$((SPP * (CANCEL_TASK - 1) / PARTS))
[ "$resumed" -gt "$first" ] || fail "task $task resumed at sample $resumed, its first: it started over"
[ "$(grep -c '^part ' "$T/log/part-$CANCEL_TASK.log")" -eq 2 ] || fail "task $task did not run exactly twice"
[ ! -e "$ckpt" ] || fail "the checkpoint $ckpt was left behind by the finished part"

# --- the same render on this machine alone ---------------------------------------------------
say "rendering part $CANCEL_TASK/$PARTS uninterrupted and the whole image in one process"
"$PRISM" render "$SCENE" $RENDER_ARGS --part "$CANCEL_TASK/$PARTS" -o "$T/ref/part$CANCEL_TASK.film" 2>/dev/null ||
  fail "the uninterrupted render of part $CANCEL_TASK failed"
"$PRISM" render "$SCENE" $RENDER_ARGS -o "$T/ref/single.exr" 2>&1 | tail -n 1 | sed 's/^/    /'
[ -f "$T/ref/single.exr" ] || fail "the single render failed"
cmp -s "$T/parts/part$CANCEL_TASK.film" "$T/ref/part$CANCEL_TASK.film" ||
  fail "part $CANCEL_TASK resumed from its checkpoint differs from the uninterrupted render of that part"
say "part $CANCEL_TASK, resumed at sample $resumed: identical to the uninterrupted part (cmp)"
# The pixels, not the bytes: the headers differ (a single render records its time and camera,
# which the parts' merge does not know).
max_abs=$("$PRISM" compare --json "$T/merged.exr" "$T/ref/single.exr" | grep -o '"max_abs": *[^,}]*' | grep -o '[^ :]*$') ||
  fail "prism compare could not compare the merged image with the single render"
if [ "$max_abs" != "0.0" ]; then
  "$PRISM" compare "$T/merged.exr" "$T/ref/single.exr" 2>&1 | sed 's/^/    /' >&2 || true
  fail "the merged image's pixels differ from the single render's (max |difference| $max_abs)"
fi
say "merged.exr: every pixel identical to the single render's (prism compare: max |difference| 0)"
say "PASSED"
