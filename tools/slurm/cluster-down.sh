#!/usr/bin/env bash
# `make cluster-down`: stops what `make cluster-up` started (slurmd, slurmctld, munged), each by the process
# id in its pid file. Idempotent: a daemon not running is skipped. Leaves packages, config and state in place.
#   --keep-munge   stop only the SLURM daemons (cluster-up uses it after rewriting slurm.conf)
set -euo pipefail

[ "$(id -u)" = 0 ] || { echo "cluster-down: needs root: sudo make cluster-down" >&2; exit 1; }

stop() {  # stop NAME PIDFILE: SIGTERM, then wait up to 10 s for the process to go
  local name=$1 pidfile=$2 pid
  [ -f "$pidfile" ] || return 0
  pid=$(cat "$pidfile")
  if kill -0 "$pid" 2>/dev/null; then
    kill -TERM "$pid"
    for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    if kill -0 "$pid" 2>/dev/null; then echo "cluster-down: $name ($pid) still running after 10 s" >&2; exit 1; fi
    echo "cluster-down: stopped $name ($pid)"
  fi
  rm -f "$pidfile"
}

stop slurmd /run/slurm/slurmd.pid
stop slurmctld /run/slurm/slurmctld.pid
if [ "${1:-}" != --keep-munge ]; then stop munged /run/munge/munged.pid; fi
