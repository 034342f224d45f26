#!/bin/sh
# Snakemake --cluster-status for SLURM (profile pipelines/cluster/slurm): prints running, success
# or failed for a job id, from sacct, or from squeue while accounting has not seen the job yet.
set -u
state=$(sacct -j "$1" --format=State --noheader --parsable2 2>/dev/null | head -n 1 | cut -d ' ' -f 1)
if [ -z "$state" ]; then
  state=$(squeue -j "$1" --noheader --format=%T 2>/dev/null | head -n 1)
fi
case "$state" in
  COMPLETED) echo success ;;
  ""|PENDING|CONFIGURING|RUNNING|COMPLETING|SUSPENDED|REQUEUED|RESIZING|SIGNALING|STAGE_OUT|STOPPED) echo running ;;
  *) echo failed ;;
esac
