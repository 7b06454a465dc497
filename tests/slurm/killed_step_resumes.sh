#!/usr/bin/env bash
# A step killed by SLURM (scancel mid-retarget, as preemption or a time limit would) fails its make rule and
# leaves no finished-looking file; rerunning `make run CLUSTER=slurm` runs only what is missing (the
# finished outputs keep their times) and ends with a release byte-identical to the local one. Over both runs
# every job of the plan completed exactly once. Needs a running cluster (make cluster-up); skips visibly
# without one.
#
#   tests/slurm/killed_step_resumes.sh [MANIFEST]     (default manifests/demo.toml; JOBS=2)
set -euo pipefail
cd "$(dirname "$0")/../.."
source tests/slurm/lib.sh
skip_unless_slurm

manifest=${1:-manifests/demo.toml}
jobs=${JOBS:-2}
name=$(sed -n 's/^name *= *"\(.*\)".*/\1/p' "$manifest" | head -n 1)
log=$(jobcomp_log)
# A tree sharing this one's sources, data and build, with its own outputs/ (so the release can be compared).
tree=$(scratch_tree slurm-resume)
out=$tree/outputs
rules=$out/$name/rules.mk
run_log=/tmp/syn-slurm-resume.$$.log
trap 'rm -f $run_log' EXIT

# Each plan output and the srun job name that writes it: "OUTPUT syn-STAGE-TRIAL".
outputs_and_jobs() {
  awk -v tree="$tree/" '$1 ~ /:$/ && $0 !~ /^(all|\.)/ {target = $1; sub(/:$/, "", target); target = tree target}
       /call syn_launch,/ {match($0, /call syn_launch,[^)]*/); job = substr($0, RSTART + 16, RLENGTH - 16);
                           sub(/,/, "-", job); print target, "syn-" job}' "$rules"
}

# The plan first (make run writes the same rules again, unchanged), to choose the victim before anything runs:
# the retarget step of the trial with the largest capture. A fast machine retargets a demo trial in under a
# second, so the victim is held by the writers' test hook (SYN_TEST_PAUSE_BEFORE_RENAME, common/file_bytes.h):
# it pauses with its complete temporary file on disk, the worst moment for a kill. srun passes the environment
# to the step; only the victim's output path matches, every other job runs as usual.
(cd "$tree" && "${BUILD_DIR:-build}"/bin/syn-plan "$manifest" -o "outputs/$name/rules.mk" --outputs outputs > /dev/null) ||
  fail "syn-plan $manifest failed"
[ -f "$rules" ] || fail "syn-plan wrote no $rules"
trial=$(awk '$1 ~ /\/markers\.h5:$/ {print $2, $1}' "$rules" | while read -r capture target; do
  case $capture in /*) ;; *) capture=$tree/$capture ;; esac
  echo "$(stat -c %s "$capture") $target"
done | sort -n | tail -n 1 | sed 's|.*/trials/\([^/]*\)/markers\.h5:$|\1|')
victim_job=syn-retarget-$trial

from=$(wc -l < "$log")
SYN_TEST_PAUSE_BEFORE_RENAME="trials/$trial/motion.h5" \
  make --no-print-directory -C "$tree" run MANIFEST="$manifest" JOBS="$jobs" CLUSTER=slurm > "$run_log" 2>&1 &
make_pid=$!

# Cancelled once its temporary file is complete and it waits in the hook.
victim_log=$out/$name/trials/$trial/motion.h5.log
victim_id=
for _ in $(seq 3000); do
  if grep -qs 'test hook: paused before renaming' "$victim_log"; then
    victim_id=$(squeue -h -t R -o '%i %j %Z' | awk -v job="$victim_job" -v dir="$tree" '$2 == job && $3 == dir {print $1; exit}')
    [ -n "$victim_id" ] && break
  fi
  kill -0 $make_pid 2>/dev/null || { cat "$run_log"; fail "make finished before $victim_job reached its rename"; }
  sleep 0.1
done
[ -n "$victim_id" ] || { cat "$run_log"; fail "$victim_job not paused before its rename after 300 s"; }
scancel "$victim_id"
echo "scancel $victim_id ($victim_job) after $(squeue -h -j "$victim_id" -o %M 2>/dev/null || echo '?') running"

if wait $make_pid; then cat "$run_log"; fail "make run succeeded although step $victim_job was cancelled"; fi
grep -q "make: retarget $trial failed" "$run_log" || { cat "$run_log"; fail "no 'retarget $trial failed' message"; }
wait_for_jobs_to_end "$tree"

# No finished-looking file: neither the killed job's output nor anything downstream of it exists; what
# remains in the trial's folder is logs, inputs made before, and at most a temporary file.
motion=$out/$name/trials/$trial/motion.h5
[ ! -e "$motion" ] || fail "$motion exists after its step was cancelled"
for downstream in segments.h5 synergies.h5 metrics.json; do
  [ ! -e "$out/$name/trials/$trial/$downstream" ] || fail "$trial/$downstream exists although its motion was cancelled"
done
leftovers=$(find "$out/$name/trials/$trial" -name 'motion.h5.tmp-*' -printf '%f ')
echo "the cancelled step's log: $(tr '\n' ' ' < "$motion.log")"
echo "after the kill, $trial/ holds: $(find "$out/$name/trials/$trial" -mindepth 1 -printf "%f ")"

# The rerun: exactly the missing jobs run, the finished outputs are untouched.
declare -A done_before
while read -r output job; do
  [ -f "$output" ] && done_before[$job]=$(stat -c %.9Y "$output")
done < <(outputs_and_jobs)
from_rerun=$(wc -l < "$log")
make --no-print-directory -C "$tree" run MANIFEST="$manifest" JOBS="$jobs" CLUSTER=slurm > "$run_log" 2>&1 ||
  { cat "$run_log"; fail "the rerun failed"; }
wait_for_jobs_to_end "$tree"
while read -r output job; do
  if [ -n "${done_before[$job]:-}" ]; then
    [ "$(stat -c %.9Y "$output")" = "${done_before[$job]}" ] || fail "$output was rewritten by the rerun"
  fi
done < <(outputs_and_jobs)
missing=$(outputs_and_jobs | while read -r output job; do [ -n "${done_before[$job]:-}" ] || echo "$job"; done | LC_ALL=C sort)
rerun=$(finished_jobs "$log" "$from_rerun" "$tree")
[ "$(awk '{print $1}' <<< "$rerun")" = "$missing" ] ||
  fail "the rerun ran other jobs than the missing ones:
$(diff <(echo "$missing") <(awk '{print $1}' <<< "$rerun"))"
echo "rerun: ${#done_before[@]} finished jobs kept, $(wc -l <<< "$missing") missing jobs run"

# Over both runs: each job of the plan completed exactly once; the victim's first attempt was cancelled.
all=$(finished_jobs "$log" "$from" "$tree")
[ "$(awk '$2 == "COMPLETED" {print $1}' <<< "$all")" = "$(plan_job_names "$rules")" ] ||
  fail "not every plan job completed exactly once:
$(diff <(plan_job_names "$rules") <(awk '$2 == "COMPLETED" {print $1}' <<< "$all"))"
grep -q "^$victim_job CANCELLED" <<< "$all" || fail "the completion log has no CANCELLED $victim_job"

# And the result is the local one, byte for byte.
make --no-print-directory -C "$tree" release MANIFEST="$manifest" JOBS="$jobs" CLUSTER=slurm > "$run_log" 2>&1 ||
  { cat "$run_log"; fail "make release CLUSTER=slurm failed"; }
make --no-print-directory release MANIFEST="$manifest" JOBS="$jobs" > "$run_log" 2>&1 ||
  { cat "$run_log"; fail "local make release failed"; }
resumed_sha=$(sha256sum "$out/$name"/release/*.tar | cut -d' ' -f1)
local_sha=$(sha256sum outputs/"$name"/release/*.tar | cut -d' ' -f1)
[ "$resumed_sha" = "$local_sha" ] || fail "the resumed release ($resumed_sha) differs from the local one ($local_sha)"
echo "PASS: cancelled $victim_job left ${leftovers:-no temporary file}; the rerun completed only the" \
  "$(wc -l <<< "$missing") missing jobs; release sha256 $resumed_sha = local"
