#!/bin/sh
# Snakemake --cluster-cancel for local-submit.sh: ends the given jobs (each runs in its own
# session, so its process group holds the job script and everything it started).
set -u
root=${LODBAKE_LOCAL_CLUSTER_DIR:-.snakemake/local-cluster}
for id in "$@"; do
  if [ -f "$root/$id/pid" ] && [ ! -f "$root/$id/rc" ]; then
    kill -TERM -- "-$(cat "$root/$id/pid")" 2>/dev/null || true
  fi
done
