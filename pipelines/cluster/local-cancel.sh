#!/bin/sh
# Snakemake --cluster-cancel for local-submit.sh: ends the given jobs. Each runs in its own
# session, so its process group holds the job script and everything it started; the group's
# wrapper dies with it, so rc is written here (143, SIGTERM's code) for local-status.sh.
set -u
root=${LODBAKE_LOCAL_CLUSTER_DIR:-.snakemake/local-cluster}
for id in "$@"; do
  job="$root/$id"
  if [ -f "$job/pid" ] && [ ! -f "$job/rc" ]; then
    # env: the kill program; dash's builtin takes no process group.
    env kill -s TERM -- "-$(cat "$job/pid")" 2>/dev/null || true
    [ -f "$job/rc" ] || echo 143 >"$job/rc"
  fi
done
