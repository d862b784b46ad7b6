#!/bin/bash
# shellcheck source-path=SCRIPTDIR
# Submits a campaign to Slurm as a chain that finishes without a person:
#
#   scripts/slurm/submit.sh array CAMPAIGN_FILE [SBATCH_OPTION...] [-- JAM_RUN_OPTION...]
#   scripts/slurm/submit.sh mpi   CAMPAIGN_FILE [SBATCH_OPTION...] [-- JAM_RUN_OPTION...]
#
# Among the SBATCH_OPTIONs, the finishing job's own (never given to the work job):
#   --finish-cpus N   its --cpus-per-task (default: the work job's -c/--cpus-per-task, else 1)
#   --finish-mem M    its --mem, e.g. 8G (default: the work job's --mem, else the partition's)
#   --finish-time T   its --time (default 04:00:00, or the partition's limit when shorter)
# Where `sinfo` answers, every CPU, memory and time request of the work and finishing jobs is
# checked against the nodes of the partition (--partition/-p, else SBATCH_PARTITION, else the
# default): one that no node can meet is refused in one line naming it, before anything is
# submitted (Slurm would accept it and leave it pending for ever, reason PartitionConfig).
# Defaults of the batch scripts' headers the partition cannot meet are cut to what it offers,
# and Slurm itself then judges each job (sbatch --test-only), a refusal naming the option.
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
# shellcheck source=resources.sh
source "$jam_slurm_dir/resources.sh"

usage="usage: $0 array|mpi CAMPAIGN_FILE [SBATCH_OPTION...] [-- JAM_RUN_OPTION...]"
[[ $# -ge 2 ]] || jam_slurm_die "$usage"
mode=$1 file=$2
shift 2
[[ "$mode" == array || "$mode" == mpi ]] || jam_slurm_die "$usage"

sbatch_options=()
finish_cpus="" finish_mem="" finish_time=""
while [[ $# -gt 0 && "$1" != -- ]]; do
  case "$1" in
    --finish-cpus | --finish-mem | --finish-time)
      [[ $# -ge 2 ]] || jam_slurm_die "$1 needs a value"
      printf -v "finish_${1#--finish-}" '%s' "$2"
      shift
      ;;
    --finish-cpus=* | --finish-mem=* | --finish-time=*)
      name=${1%%=*}
      printf -v "finish_${name#--finish-}" '%s' "${1#*=}"
      ;;
    --finish-*) jam_slurm_die "$1: unknown (--finish-cpus, --finish-mem, --finish-time)" ;;
    *) sbatch_options+=("$1") ;;
  esac
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

# The finishing job's resources, and both jobs' requests against what their partition offers
# (the work job's: its --partition, else SBATCH_PARTITION, else the default; the finishing
# job's: SBATCH_PARTITION, else the default).
work_cpus=$(jam_slurm_option_value cpus-per-task c "${kept[@]}")
work_mem=$(jam_slurm_option_value mem "" "${kept[@]}")
work_time=$(jam_slurm_option_value time t "${kept[@]}")
[[ -z "$work_cpus" ]] || [[ "$work_cpus" =~ ^[1-9][0-9]{0,5}$ ]] ||
  jam_slurm_die "--cpus-per-task '$work_cpus' must be a whole number >= 1"
cpus_label=--finish-cpus mem_label=--finish-mem
[[ -n "$finish_cpus" ]] || cpus_label="--finish-cpus (by default the work job's -c)"
[[ -n "$finish_mem" ]] || mem_label="--finish-mem (by default the work job's --mem)"
[[ -n "$finish_cpus" ]] || finish_cpus=${work_cpus:-1}
[[ "$finish_cpus" =~ ^[1-9][0-9]{0,5}$ ]] ||
  jam_slurm_die "--finish-cpus '$finish_cpus' must be a whole number >= 1"
[[ -n "$finish_mem" ]] || finish_mem=$work_mem
[[ -z "$finish_mem" ]] || jam_slurm_megabytes --finish-mem "$finish_mem" >/dev/null
[[ -z "$finish_time" ]] || jam_slurm_minutes --finish-time "$finish_time" >/dev/null
partition=$(jam_slurm_option_value partition p "${kept[@]}")
checked="not checked against the partition (no answer from sinfo)"
answered=0 # sinfo answered: Slurm's controller is there to ask
if command -v sinfo >/dev/null 2>&1 && sinfo -h -o %P >/dev/null 2>&1; then answered=1; fi
defaults=()
if jam_slurm_partition_nodes "${partition:-${SBATCH_PARTITION:-}}"; then
  # The header's defaults the partition cannot meet (24:00:00 in a one-hour partition, 64
  # ranks on 16 cores) are cut to what it offers and kept for every round, as if given.
  work_ntasks=$(jam_slurm_option_value ntasks n "${kept[@]}")
  cut=$(jam_slurm_partition_defaults "$mode" "$work_cpus" "$work_ntasks" "$work_time")
  [[ -z "$cut" ]] || mapfile -t defaults <<<"$cut"
  kept+=("${defaults[@]}")
  sbatch_options+=("${defaults[@]}")
  jam_slurm_check_fits --cpus-per-task "${work_cpus:-1}" --mem "$work_mem" --time "$work_time"
  checked="checked against partition $jam_slurm_partition (sinfo)"
elif ((answered)); then
  label=--partition
  [[ -n "$partition" ]] || label=SBATCH_PARTITION
  [[ -n "$partition${SBATCH_PARTITION:-}" ]] || label="the default partition"
  jam_slurm_die "$label '${partition:-${SBATCH_PARTITION:-}}': sinfo lists no node of it (sinfo -s lists the partitions): the job could never start"
fi
if jam_slurm_partition_nodes "${SBATCH_PARTITION:-}"; then
  if [[ -z "$finish_time" ]]; then
    # the default, or the partition's limit when that is shorter
    finish_time=$jam_slurm_finish_default_time
    longest=0
    for node in "${jam_slurm_nodes[@]}"; do
      read -r _ _ t <<<"$node"
      if ((t > longest)); then longest=$t; fi
    done
    if ((longest < $(jam_slurm_minutes "" "$finish_time"))); then finish_time=$longest; fi
  fi
  jam_slurm_check_fits "$cpus_label" "$finish_cpus" "$mem_label" "$finish_mem" \
    --finish-time "$finish_time"
  checked="checked against partition $jam_slurm_partition (sinfo)"
fi
export JAM_SLURM_FINISH_CPUS="$finish_cpus" JAM_SLURM_FINISH_MEM="$finish_mem"
export JAM_SLURM_FINISH_TIME="${finish_time:-$jam_slurm_finish_default_time}"

# srun starts the MPI job's ranks: where this cluster's MpiDefault is none and SLURM_MPI_TYPE
# (srun --mpi) is not set, OpenMPI's ranks cannot find each other; each would be a jam of its
# own, all but one refused by the directory's lock.
if [[ "$mode" == mpi ]] && ((answered)); then
  mpi_type=${SLURM_MPI_TYPE:-}
  if [[ -z "$mpi_type" ]]; then
    mpi_type=$(scontrol show config 2>/dev/null | sed -n 's/^MpiDefault *= *//p' || true)
  fi
  [[ "$mpi_type" != none ]] ||
    jam_slurm_die "srun would start separate jam processes, not MPI ranks: srun's MPI plugin is none (SLURM_MPI_TYPE, else the cluster's MpiDefault); set SLURM_MPI_TYPE to a plugin before submit.sh (srun --mpi=list shows them; pmix for Debian's OpenMPI)"
fi

# Slurm itself judges each job of the chain as it will be submitted (sbatch --test-only, which
# submits nothing): what sinfo cannot see (cores per socket, a partition or account that does
# not exist, ...) is refused here, naming the option, rather than left pending for ever.
if ((answered)); then
  test_options=("${kept[@]}")
  [[ -z "$spec" ]] || test_options+=("--array=$spec")
  jam_slurm_can_start "the work job" "$jam_slurm_dir/campaign-$mode.sbatch" \
    "${test_options[@]}" -- "$jam_file" "${jam_options[@]}"
  jam_slurm_finish_resources
  jam_slurm_can_start "the finishing job (--finish-cpus, --finish-mem, --finish-time)" \
    "$jam_slurm_dir/campaign-finish.sbatch" "${jam_slurm_finish_options[@]}" -- "$jam_file"
  jam_slurm_can_start "the chain step" "$jam_slurm_dir/campaign-chain.sbatch" -- "$jam_file"
  checked="$checked, and by Slurm (sbatch --test-only)"
  ((${#defaults[@]} == 0)) || checked="$checked; cut to the partition: ${defaults[*]}"
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
  finishing job  $jam_finish_job (afterok: jam stats, check, report; ${jam_slurm_finish_options[*]})
  resources      $checked
  chain step     $jam_chain_job (afterany: resubmits unfinished tasks, at most ${JAM_SLURM_MAX_RESUBMIT} times)
Follow it with: squeue --me; cat $(printf '%q' "$jam_state/chain.log"); $(printf '%q ' "$jam_bin" campaign status "$jam_dir")
EOF
