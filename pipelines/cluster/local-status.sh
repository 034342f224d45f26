#!/bin/sh
# Snakemake --cluster-status for local-submit.sh: prints running, success or failed for a job id.
set -eu
root=${LODBAKE_LOCAL_CLUSTER_DIR:-.snakemake/local-cluster}
job="$root/$1"
if [ ! -d "$job" ]; then
  echo "local-status.sh error: $job: no such job" >&2
  exit 1
fi
if [ ! -f "$job/rc" ]; then
  echo running
elif [ "$(cat "$job/rc")" = 0 ]; then
  echo success
else
  echo failed
fi
