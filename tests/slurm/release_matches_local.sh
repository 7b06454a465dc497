#!/usr/bin/env bash
# The demo through SLURM (`make release CLUSTER=slurm`, every job of the plan an srun step) gives a release
# tar byte-identical to the local run's, and SLURM's job completion log shows exactly one completed job per
# job of the plan. Needs a running cluster (make cluster-up); skips visibly without one.
#
#   tests/slurm/release_matches_local.sh [MANIFEST]     (default manifests/demo.toml; JOBS=2)
#
# The local release comes from outputs/ (`make release`, which runs whatever is not up to date there); the
# SLURM run starts from nothing in outputs/slurm-release/ (a tree sharing this one's sources, data and
# build, so that the files record the same relative paths). Both wall times are printed.
set -euo pipefail
cd "$(dirname "$0")/../.."
source tests/slurm/lib.sh
skip_unless_slurm

manifest=${1:-manifests/demo.toml}
jobs=${JOBS:-2}
name=$(sed -n 's/^name *= *"\(.*\)".*/\1/p' "$manifest" | head -n 1)
log=$(jobcomp_log)
tree=$(scratch_tree slurm-release)

start=$EPOCHREALTIME
make --no-print-directory release MANIFEST="$manifest" JOBS="$jobs" > /tmp/syn-slurm-local.$$.log 2>&1 ||
  { cat /tmp/syn-slurm-local.$$.log; fail "local make release failed"; }
local_seconds=$(awk "BEGIN{print $EPOCHREALTIME - $start}")
local_tar=$(ls outputs/"$name"/release/*.tar)

from=$(wc -l < "$log")
start=$EPOCHREALTIME
make --no-print-directory -C "$tree" release MANIFEST="$manifest" JOBS="$jobs" CLUSTER=slurm \
  > /tmp/syn-slurm-run.$$.log 2>&1 || { cat /tmp/syn-slurm-run.$$.log; fail "make release CLUSTER=slurm failed"; }
slurm_seconds=$(awk "BEGIN{print $EPOCHREALTIME - $start}")
slurm_tar=$(ls "$tree"/outputs/"$name"/release/*.tar)
rm -f /tmp/syn-slurm-local.$$.log /tmp/syn-slurm-run.$$.log

local_sha=$(sha256sum "$local_tar" | cut -d' ' -f1)
slurm_sha=$(sha256sum "$slurm_tar" | cut -d' ' -f1)
echo "local  $local_tar sha256 $local_sha ($local_seconds s, make -j$jobs; up-to-date jobs skipped)"
echo "slurm  $slurm_tar sha256 $slurm_sha ($slurm_seconds s, make -j$jobs CLUSTER=slurm, from nothing)"
[ "$local_sha" = "$slurm_sha" ] || {
  diff <(tar -xOf "$local_tar" --wildcards '*/SHA256SUMS') <(tar -xOf "$slurm_tar" --wildcards '*/SHA256SUMS') || true
  fail "the release through SLURM differs from the local one"
}

# One completed SLURM job (srun step) per job of the plan, nothing else, nothing twice.
wait_for_jobs_to_end "$tree"
expected=$(plan_job_names "$tree/outputs/$name/rules.mk")
finished=$(finished_jobs "$log" "$from" "$tree")
[ "$(awk '{print $1}' <<< "$finished")" = "$expected" ] ||
  fail "the job completion log does not list each job of the plan once:
$(diff <(echo "$expected") <(awk '{print $1}' <<< "$finished"))"
not_completed=$(awk '$2 != "COMPLETED"' <<< "$finished")
[ -z "$not_completed" ] || fail "jobs not COMPLETED: $not_completed"
echo "PASS: byte-identical release; $(wc -l <<< "$expected") plan jobs = $(wc -l <<< "$finished") completed SLURM jobs ($log)"
