#!/bin/bash
# shellcheck source-path=SCRIPTDIR
# Submits a campaign to Slurm as a chain that finishes without a person:
#
#   scripts/slurm/submit.sh array CAMPAIGN_FILE [SBATCH_OPTION...] [-- JAM_RUN_OPTION...]
#   scripts/slurm/submit.sh mpi   CAMPAIGN_FILE [SBATCH_OPTION...] [-- JAM_RUN_OPTION...]
#
# e.g.  scripts/slurm/submit.sh array reference/campaigns/paper-2d.toml --array=0-31 --time=12:00:00
#       scripts/slurm/submit.sh mpi reference/campaigns/paper-2d.toml --ntasks=128 -- --log-every 600
#
# It submits, from the current directory (the jobs run there; a relative `output` of the
# campaign file is relative to it):
#   1. the work job: campaign-array.sbatch (one share per array task) or campaign-mpi.sbatch,
#      with the SBATCH_OPTIONs, which override its #SBATCH lines and are reused on every
#      resubmission (all but --array and --dependency);
#   2. campaign-finish.sbatch, --dependency=afterok on the work job: jam stats, check, report;
#   3. campaign-chain.sbatch, --dependency=afterany on the work job: when a task was interrupted
#      (time limit: the work jobs ask for SIGTERM 300 s before it and jam checkpoints) or lost,
#      it resubmits the unfinished tasks with 1-3 again, until `jam campaign status` says the
#      campaign is complete, a run failed, or JAM_SLURM_MAX_RESUBMIT resubmissions (default 10).
# JAM_RUN_OPTIONs go to every `jam campaign run` of the chain (not --shard, --until-decided).
#
# The campaign directory is the file's `output` as jam itself reads it (`jam campaign output
# FILE`; the scripts never parse the file), relative to the current directory; every job of the
# chain asks jam again and refuses to run on a different directory.
#
# Environment: JAM (jam executable; default build/jam of this checkout, else jam on PATH),
# JAM_SLURM_MAX_RESUBMIT, JAM_REPORT_DIR
# (report directory of the finishing job), and Slurm's own SBATCH_ACCOUNT, SBATCH_PARTITION, ...
# for every job. The chain's record:
# <campaign dir>/slurm/chain.log. Stop a chain with scancel on its jobs (squeue --me).
set -euo pipefail

jam_slurm_dir=$(cd -- "$(dirname -- "${BASH_SOURCE[0]}")" && pwd)
# shellcheck source=common.sh
source "$jam_slurm_dir/common.sh"

usage="usage: $0 array|mpi CAMPAIGN_FILE [SBATCH_OPTION...] [-- JAM_RUN_OPTION...]"
[[ $# -ge 2 ]] || jam_slurm_die "$usage"
mode=$1 file=$2
shift 2
[[ "$mode" == array || "$mode" == mpi ]] || jam_slurm_die "$usage"

sbatch_options=()
while [[ $# -gt 0 && "$1" != -- ]]; do
  sbatch_options+=("$1")
  shift
done
[[ $# -eq 0 ]] || shift # the --
jam_options=("$@")

# Absolute paths: the jobs, and the chain steps that resubmit them, may run anywhere.
[[ "$file" == /* ]] || file=$PWD/$file
if [[ -n "${JAM:-}" && "$JAM" == */* && "$JAM" != /* ]]; then JAM=$PWD/$JAM; fi
jam_slurm_setup "$file" "${jam_options[@]}"
[[ "$jam_bin" == /* ]] || jam_bin=$(cd -- "$(dirname -- "$jam_bin")" && pwd)/$(basename -- "$jam_bin")
[[ "$jam_dir" == /* ]] || jam_dir=$PWD/$jam_dir
[[ "$jam_state" == /* ]] || jam_state=$PWD/$jam_state
jam_slurm_whole JAM_SLURM_MAX_RESUBMIT "${JAM_SLURM_MAX_RESUBMIT:-10}"

# The options every resubmission reuses: all but the array's indices and the dependency.
kept=()
spec=""
unset JAM_SLURM_THROTTLE JAM_SLURM_SHARDS JAM_SLURM_FIRST JAM_SLURM_STEP
for ((i = 0; i < ${#sbatch_options[@]}; i++)); do
  o=${sbatch_options[i]}
  case "$o" in
    --array=* | -a?*)
      [[ "$mode" == array ]] || jam_slurm_die "$o: an MPI job is not an array"
      spec=${o#--array=}
      spec=${spec#-a}
      ;;
    --array | -a)
      [[ "$mode" == array ]] || jam_slurm_die "$o: an MPI job is not an array"
      i=$((i + 1))
      spec=${sbatch_options[i]:-}
      ;;
    --dependency | -d) i=$((i + 1)) ;;
    --dependency=* | -d?*) ;;
    *) kept+=("$o") ;;
  esac
done

if [[ "$spec" == *%* ]]; then
  export JAM_SLURM_THROTTLE="${spec##*%}"
  jam_slurm_whole "the array's %limit" "$JAM_SLURM_THROTTLE"
fi

# A new chain: the records of an earlier one would mislead its first chain step.
mkdir -p -- "$jam_state"
rm -f -- "$jam_state"/share-* "$jam_state/array" "$jam_state/mpi"
if ((${#kept[@]})); then
  printf '%s\0' "${kept[@]}" >"$jam_state/sbatch-options"
else
  : >"$jam_state/sbatch-options"
fi

jam_slurm_submit_round "$mode" 0 all "" "${sbatch_options[@]}"
cat <<EOF
Submitted the chain of $jam_file:
  work job       $jam_work_job ($mode)
  finishing job  $jam_finish_job (afterok: jam stats, check, report)
  chain step     $jam_chain_job (afterany: resubmits unfinished tasks, at most ${JAM_SLURM_MAX_RESUBMIT} times)
Follow it with: squeue --me; cat $(printf '%q' "$jam_state/chain.log"); $(printf '%q ' "$jam_bin" campaign status "$jam_dir")
EOF
