# shellcheck shell=bash
# Shared by tests/slurm/*.sh (sourced): skipping, the plan's job names, and SLURM's job completion log.

fail() { echo "FAIL: $*" >&2; exit 1; }

# A visible skip (exit 0) when no SLURM controller answers; CI runs `make cluster-up` first, so it never skips.
skip_unless_slurm() {
  if ! sinfo -h >/dev/null 2>&1; then
    echo "SKIPPED $(basename "$0"): no SLURM controller answers (start one with: sudo make cluster-up)"
    exit 0
  fi
}

# The job completion log (jobcomp/filetxt: one line per finished job, as `make cluster-up` configures it).
jobcomp_log() {
  local type
  type=$(scontrol show config | sed -n 's/^JobCompType *= *//p')
  [ "$type" = jobcomp/filetxt ] || fail "these tests read SLURM's job completion log; the cluster has JobCompType=$type (make cluster-up sets jobcomp/filetxt)"
  scontrol show config | sed -n 's/^JobCompLoc *= *//p'
}

# Every srun job name the plan RULES (outputs/NAME/rules.mk) can start, one per job: syn-STAGE-TRIAL.
plan_job_names() {
  grep -o 'call syn_launch,[^)]*' "$1" | sed 's/^call syn_launch,/syn-/; s/,/-/' | LC_ALL=C sort
}

# The jobs of the completion log after line FROM that ran in directory DIR: "NAME STATE", sorted by name.
finished_jobs() {
  local log=$1 from=$2 dir=$3
  tail -n +"$((from + 1))" "$log" | awk -v dir="$dir" '{
      name = ""; state = ""; workdir = "";
      for (i = 1; i <= NF; i++) {
        if ($i ~ /^Name=/) name = substr($i, 6);
        if ($i ~ /^JobState=/) state = substr($i, 10);
        if ($i ~ /^WorkDir=/) workdir = substr($i, 9);
      }
      if (workdir == dir && name ~ /^syn-/) print name, state }' | LC_ALL=C sort
}

# Waits until no job named syn-* from directory DIR is queued or running (slurmctld writes the completion
# log when a job ends, which can be a moment after srun returned).
wait_for_jobs_to_end() {
  local dir=$1
  for _ in $(seq 100); do
    squeue -h -o '%j %Z' | awk -v dir="$dir" '$1 ~ /^syn-/ && $2 == dir' | grep -q . || return 0
    sleep 0.1
  done
  fail "syn-* jobs still in squeue after 10 s: $(squeue -h -o '%i %j %T %Z')"
}

# A tree at outputs/NAME that shares this one's sources, data and build (symlinks) but has its own
# outputs/. Intermediate files record their inputs' paths as given (outputs/demo/trials/...), so a run
# compared byte for byte with the local one must use the same relative paths, only in another directory.
scratch_tree() {
  local dir=$PWD/outputs/$1 entry
  rm -rf "$dir"
  mkdir -p "$dir"
  for entry in Makefile CMakeLists.txt manifests datasets tools "${BUILD_DIR:-build}"; do
    ln -s "$PWD/$entry" "$dir/$entry"
  done
  echo "$dir"
}
