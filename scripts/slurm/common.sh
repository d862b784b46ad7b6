# shellcheck shell=bash
# Shared by the batch scripts of scripts/slurm/ and by submit.sh (sourced, never run).
#
# The chain keeps a little state beside the runs, in JAM_SLURM_STATE (default
# <campaign dir>/slurm/), which every job of a chain reads or writes on the shared file system:
#   array           "N FIRST STEP": the shares of the first array and its index numbering
#   share-K         "JOB RC": array job JOB ran share K (from 1) and `jam campaign run` exited RC
#   mpi             "JOB RC": the same for the MPI job
#   sbatch-options  the work job's sbatch options given to submit.sh, NUL-separated, reused by
#                   every resubmission
#   chain.log       one line per submission or decision of the chain
# No value read from there or from the environment is ever evaluated by a shell.

if ((BASH_VERSINFO[0] < 4 || (BASH_VERSINFO[0] == 4 && BASH_VERSINFO[1] < 4))); then
  echo "jam-slurm: error: bash 4.4 or newer is needed (this is $BASH_VERSION)" >&2
  exit 2
fi

jam_slurm_say() { printf 'jam-slurm: %s\n' "$*"; }
jam_slurm_die() {
  printf 'jam-slurm: error: %s\n' "$*" >&2
  exit 2
}

# A whole number (digits only), or die naming the variable.
jam_slurm_whole() {
  [[ "$2" =~ ^[0-9]+$ ]] || jam_slurm_die "$1 must be a whole number, not '$2'"
}

# The campaign's output directory as jam itself reads it from FILE (`jam campaign output`: the
# file is never parsed here, so a string that looks like a key cannot mislead), made absolute
# against the current directory (a relative `output` is relative to where the jobs run).
# Sets jam_dir; dies with jam's error when jam cannot read the file.
jam_slurm_read_output() {
  local out
  out=$("$jam_bin" campaign output "$jam_file") ||
    jam_slurm_die "jam cannot read the campaign file '$jam_file' (its error above)"
  # jam refuses control characters in campaign strings: the one line it prints is the path
  [[ -n "$out" ]] || jam_slurm_die "jam campaign output printed nothing for '$jam_file'"
  [[ "$out" == /* ]] || out=$PWD/$out
  jam_dir=$out
}

# jam_slurm_setup FILE [jam campaign run options...]  (jam_slurm_dir: this directory)
# Sets jam_file, jam_bin, jam_dir (campaign directory), jam_state, jam_run_args (array) and
# jam_jobs_given (1 when the options name --jobs).
# shellcheck disable=SC2034 # jam_jobs_given is read by the work job scripts
jam_slurm_setup() {
  [[ $# -ge 1 && -n "$1" ]] || jam_slurm_die "usage: $(basename -- "$0") CAMPAIGN_FILE [jam campaign run options...]"
  jam_file=$1
  shift
  [[ -f "$jam_file" && -r "$jam_file" ]] || jam_slurm_die "campaign file '$jam_file' cannot be read"
  [[ "$jam_file" == /* ]] || jam_file=$PWD/$jam_file # never read as an option
  jam_run_args=("$@")
  jam_jobs_given=0
  local a
  for a in "${jam_run_args[@]}"; do
    case "$a" in
      --shard | --shard=*) jam_slurm_die "--shard is set by these scripts (one share per array task)" ;;
      --until-decided) jam_slurm_die "--until-decided adds runs as it goes; run it in one job, not in this chain" ;;
      --jobs | --jobs=*) jam_jobs_given=1 ;;
    esac
  done

  jam_bin=${JAM:-}
  if [[ -n "$jam_bin" && "$jam_bin" != */* ]]; then
    jam_bin=$(command -v -- "$jam_bin" || true)
  elif [[ -z "$jam_bin" ]]; then
    if [[ -x "${jam_slurm_dir:?}/../../build/jam" ]]; then
      jam_bin=$jam_slurm_dir/../../build/jam
    else
      jam_bin=$(command -v jam || true)
    fi
  fi
  [[ -n "$jam_bin" && -x "$jam_bin" ]] || jam_slurm_die "no jam executable: set JAM=/path/to/jam"

  jam_slurm_read_output
  # JAM_CAMPAIGN_DIR (submit.sh passes its answer on to the jobs) must name the same directory:
  # else the finishing job and the chain step would judge one directory while the work jobs
  # fill another (a job started elsewhere, a value of the user's).
  if [[ -n "${JAM_CAMPAIGN_DIR:-}" ]]; then
    local given=$JAM_CAMPAIGN_DIR
    [[ "$given" == /* ]] || given=$PWD/$given
    if [[ "$given" != "$jam_dir" ]] && ! [[ -e "$given" && "$given" -ef "$jam_dir" ]]; then
      jam_slurm_die "JAM_CAMPAIGN_DIR '$given' is not the output of $jam_file, '$jam_dir' (jam campaign output): unset it, or run the jobs where the chain was submitted"
    fi
  fi
  jam_state=${JAM_SLURM_STATE:-$jam_dir/slurm}
}

jam_slurm_log() {
  mkdir -p -- "$jam_state"
  printf '%s %s\n' "$(date -u +%Y-%m-%dT%H:%M:%SZ)" "$*" >>"$jam_state/chain.log"
  jam_slurm_say "$*"
}

# Writes "JOB RC" to the state file NAME (atomically: a reader sees the old or the new line).
jam_slurm_record() {
  mkdir -p -- "$jam_state"
  printf '%s %s\n' "$2" "$3" >"$jam_state/$1.$$"
  mv -f -- "$jam_state/$1.$$" "$jam_state/$1"
}

# The RC that state file NAME records for job JOB, or nothing (no such file, or another job's).
jam_slurm_recorded_rc() {
  local job rc
  [[ -r "$jam_state/$1" ]] || return 0
  read -r job rc <"$jam_state/$1" || true
  if [[ "$job" == "$2" && "$rc" =~ ^[0-9]+$ ]]; then printf '%s\n' "$rc"; fi
}

# jam_slurm_run COMMAND...: runs it in the background and waits. With jam_slurm_pass_on=1 (the
# default) the first SIGTERM or SIGINT this shell gets (Slurm's --signal=B:TERM@..., an scancel)
# is passed on to it once: jam writes its checkpoints and exits 130 (a second signal would end it
# at once, without checkpoints). With 0 the shell only waits on (srun: Slurm signals the ranks
# itself, and srun would turn a SIGTERM into a SIGKILL of every rank).
# Sets jam_slurm_rc to its exit status.
jam_slurm_pass_on=1
jam_slurm_signals=0
jam_slurm_child=""
jam_slurm_forwarded=0
jam_slurm_forward() {
  if [[ -n "$jam_slurm_child" && "$jam_slurm_forwarded" == 0 ]]; then
    jam_slurm_forwarded=1
    if ((jam_slurm_pass_on)); then
      jam_slurm_say "signal received: asking jam (pid $jam_slurm_child) to checkpoint and stop"
      kill -TERM "$jam_slurm_child" 2>/dev/null || true
    else
      jam_slurm_say "signal received: waiting for the job step (Slurm signals its tasks)"
    fi
  fi
}
jam_slurm_on_signal() {
  jam_slurm_signals=$((jam_slurm_signals + 1))
  jam_slurm_forward
}
jam_slurm_run() {
  local seen next
  trap jam_slurm_on_signal TERM INT
  "$@" &
  jam_slurm_child=$!
  ((jam_slurm_signals == 0)) || jam_slurm_forward # a signal before the child existed
  jam_slurm_rc=0
  while :; do
    seen=$jam_slurm_signals
    next=0
    wait "$jam_slurm_child" || next=$?
    # 127: the wait before already had the status (the child ended as the signal came)
    if ((next == 127 && jam_slurm_rc != 0)); then break; fi
    jam_slurm_rc=$next
    # > 128 with a signal meanwhile: the wait was cut short, the child may still be running
    ((jam_slurm_rc > 128 && jam_slurm_signals != seen)) || break
  done
  trap - TERM INT
}

# The job id sbatch --parsable printed ("ID" or "ID;CLUSTER").
jam_slurm_job_id() {
  local id=${1%%;*}
  [[ "$id" =~ ^[0-9]+$ ]] || jam_slurm_die "sbatch printed '$1', not a job id"
  printf '%s\n' "$id"
}

# jam_slurm_submit_round MODE ROUND SHARES DEPENDENCY [work job sbatch options...]
# Submits one round of the chain: the work job (MODE array: the array tasks of SHARES, "all"
# or share numbers from 1; MODE mpi: one MPI job), after DEPENDENCY (a job id, or "" for none);
# the finishing job (afterok on the work job: it runs only if every task of it succeeded); the
# chain step (afterany on the work job: it decides what comes next). Needs jam_slurm_setup and
# resources.sh (the finishing job's resources from JAM_SLURM_FINISH_*).
# Sets jam_work_job, jam_finish_job and jam_chain_job.
jam_slurm_submit_round() {
  local mode=$1 round=$2 shares=$3 dependency=$4
  shift 4
  local -a work_job=(--parsable --export=ALL)
  local indices="" k
  local -a list
  if [[ "$mode" == array ]]; then
    if [[ "$shares" != all ]]; then
      read -r -a list <<<"$shares"
      for k in "${list[@]}"; do
        indices+="${indices:+,}$((JAM_SLURM_FIRST + (k - 1) * JAM_SLURM_STEP))"
      done
      work_job+=("--array=$indices${JAM_SLURM_THROTTLE:+%$JAM_SLURM_THROTTLE}")
    fi
  elif [[ "$mode" != mpi ]]; then
    jam_slurm_die "unknown mode '$mode' (array or mpi)"
  fi
  [[ -z "$dependency" ]] || work_job+=("--dependency=afterany:$dependency")
  work_job+=("$@" "$jam_slurm_dir/campaign-$mode.sbatch" "$jam_file" "${jam_run_args[@]}")

  export JAM="$jam_bin" JAM_SLURM_DIR="$jam_slurm_dir" JAM_CAMPAIGN_DIR="$jam_dir"
  export JAM_SLURM_STATE="$jam_state" JAM_SLURM_MODE="$mode" JAM_SLURM_ROUND="$round"
  export JAM_SLURM_SHARES="$shares" JAM_SLURM_MAX_RESUBMIT="${JAM_SLURM_MAX_RESUBMIT:-10}"
  jam_work_job=$(jam_slurm_job_id "$(sbatch "${work_job[@]}")")
  jam_slurm_finish_resources
  # shellcheck disable=SC2154 # jam_slurm_finish_options: set by jam_slurm_finish_resources
  jam_finish_job=$(jam_slurm_job_id "$(sbatch --parsable --export=ALL \
    "--dependency=afterok:$jam_work_job" "${jam_slurm_finish_options[@]}" \
    "$jam_slurm_dir/campaign-finish.sbatch" "$jam_file")")
  jam_chain_job=$(jam_slurm_job_id "$(JAM_SLURM_WORK_JOB="$jam_work_job" \
    JAM_SLURM_FINISH_JOB="$jam_finish_job" sbatch --parsable --export=ALL \
    "--dependency=afterany:$jam_work_job" "$jam_slurm_dir/campaign-chain.sbatch" \
    "$jam_file" "${jam_run_args[@]}")")
  local what="$mode job $jam_work_job${indices:+ (array $indices)}${dependency:+ after $dependency}"
  jam_slurm_log "round $round: $what, finishing job $jam_finish_job (afterok;" \
    "${jam_slurm_finish_options[*]}), chain step $jam_chain_job (afterany)"
}
