#!/bin/sh
# Snakemake generic cluster submission (--cluster) that runs each job on this machine, in the
# background, as a batch scheduler would: it takes the job script, keeps a copy, starts it
# detached in its own session and prints the job id. local-status.sh and local-cancel.sh answer
# for these ids. Profile: pipelines/cluster/local (docs/pipelines.md).
#
#   local-submit.sh JOBSCRIPT     -> prints JOBID; the job's files are in $LODBAKE_LOCAL_CLUSTER_DIR/JOBID:
#                                    jobscript.sh, stdout, stderr, pid, rc (its exit code, written last)
#
# LODBAKE_LOCAL_CLUSTER_DIR defaults to .snakemake/local-cluster under the working directory.
set -eu
if [ $# -ne 1 ] || [ ! -f "$1" ]; then
  echo "local-submit.sh error: expected one existing job script, got: $*" >&2
  exit 1
fi
root=${LODBAKE_LOCAL_CLUSTER_DIR:-.snakemake/local-cluster}
mkdir -p "$root"
job=$(mktemp -d "$root/job.XXXXXX")
cp "$1" "$job/jobscript.sh"
# Every stream is redirected: Snakemake reads this script's stdout until it closes, so the
# detached job must not hold it. rc is renamed into place so the status script never reads half.
# shellcheck disable=SC2016 # $1 is the inner shell's argument, expanded there
setsid sh -c 'sh "$1/jobscript.sh" >"$1/stdout" 2>"$1/stderr"; echo $? >"$1/rc.tmp"; mv "$1/rc.tmp" "$1/rc"' \
  local-job "$job" </dev/null >/dev/null 2>&1 &
echo $! >"$job/pid"
echo "${job##*/}"
