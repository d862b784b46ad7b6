# shellcheck shell=bash
# Resources of the chain's jobs, and whether a request can ever start (sourced by submit.sh and
# the chain step after common.sh, never run).
#
# A job that asks for more CPUs, memory or time than any node of its partition offers is
# accepted by sbatch and then pends for ever (reason PartitionConfig, PartitionTimeLimit, ...)
# with nothing to tell the user: submit.sh asks `sinfo` what the partition's nodes have and
# refuses such a request in one line naming the option and the value. Without sinfo (or when it
# cannot reach the controller) nothing is checked, and submit.sh says so.
#
# The finishing job's resources travel to every round in the environment (--export=ALL):
#   JAM_SLURM_FINISH_CPUS  --cpus-per-task (submit.sh --finish-cpus; default: the work job's
#                          -c/--cpus-per-task when given, else 1)
#   JAM_SLURM_FINISH_MEM   --mem (--finish-mem; default: the work job's --mem when given, else
#                          none: the partition's default)
#   JAM_SLURM_FINISH_TIME  --time (--finish-time; default 04:00:00, or the partition's limit
#                          when that is shorter)

jam_slurm_finish_default_time=04:00:00

# jam_slurm_option_value LONG SHORT OPTION...: the last value of --LONG=V, --LONG V, -SV or
# -S V among the options (nothing when absent; SHORT "": no short form).
jam_slurm_option_value() {
  local long=$1 short=$2 value="" i
  shift 2
  local -a opts=("$@")
  for ((i = 0; i < ${#opts[@]}; i++)); do
    case "${opts[i]}" in
      "--$long="*) value=${opts[i]#--"$long"=} ;;
      "--$long") value=${opts[i + 1]:-} i=$((i + 1)) ;;
      -?*)
        [[ -n "$short" ]] || continue
        if [[ "${opts[i]}" == "-$short" ]]; then
          value=${opts[i + 1]:-} i=$((i + 1))
        elif [[ "${opts[i]}" == "-$short"?* && "${opts[i]}" != --* ]]; then
          value=${opts[i]#-"$short"}
        fi
        ;;
    esac
  done
  printf '%s' "$value"
}

# jam_slurm_megabytes LABEL VALUE: an sbatch --mem value (suffix K, M, G or T; none: M) in MB.
jam_slurm_megabytes() {
  [[ "$2" =~ ^([0-9]{1,12})([KMGTkmgt]?)$ ]] ||
    jam_slurm_die "$1 '$2' must be a whole number with an optional K, M, G or T suffix"
  local n=$((10#${BASH_REMATCH[1]})) unit=${BASH_REMATCH[2]^^}
  case "$unit" in
    K) printf '%s\n' $(((n + 1023) / 1024)) ;;
    G) printf '%s\n' $((n * 1024)) ;;
    T) printf '%s\n' $((n * 1024 * 1024)) ;;
    *) printf '%s\n' "$n" ;;
  esac
}

# jam_slurm_minutes LABEL VALUE: a Slurm time (M, M:S, H:M:S, D-H, D-H:M, D-H:M:S, or
# infinite/unlimited) in whole minutes, rounded up.
jam_slurm_minutes() {
  local v=${2,,} d=0 h=0 m=0 s=0 n='([0-9]{1,7})'
  if [[ "$v" == infinite || "$v" == unlimited ]]; then
    printf '%s\n' 999999999
    return
  fi
  if [[ "$v" =~ ^$n-$n(:$n(:$n)?)?$ ]]; then
    d=${BASH_REMATCH[1]} h=${BASH_REMATCH[2]} m=${BASH_REMATCH[4]:-0} s=${BASH_REMATCH[6]:-0}
  elif [[ "$v" =~ ^$n:$n:$n$ ]]; then
    h=${BASH_REMATCH[1]} m=${BASH_REMATCH[2]} s=${BASH_REMATCH[3]}
  elif [[ "$v" =~ ^$n(:$n)?$ ]]; then
    m=${BASH_REMATCH[1]} s=${BASH_REMATCH[3]:-0}
  else
    jam_slurm_die "$1 '$2' is not a Slurm time (minutes, H:M:S or D-H:M:S)"
  fi
  printf '%s\n' $((10#$d * 1440 + 10#$h * 60 + 10#$m + (10#$s + 59) / 60))
}

# The finishing job's sbatch options from JAM_SLURM_FINISH_*, checked (they come from the
# environment): sets the array jam_slurm_finish_options.
jam_slurm_finish_resources() {
  jam_slurm_finish_options=()
  local cpus=${JAM_SLURM_FINISH_CPUS:-1} mem=${JAM_SLURM_FINISH_MEM:-}
  local time=${JAM_SLURM_FINISH_TIME:-$jam_slurm_finish_default_time}
  [[ "$cpus" =~ ^[1-9][0-9]{0,5}$ ]] || jam_slurm_die "JAM_SLURM_FINISH_CPUS must be a whole number >= 1, not '$cpus'"
  jam_slurm_minutes JAM_SLURM_FINISH_TIME "$time" >/dev/null
  jam_slurm_finish_options=("--cpus-per-task=$cpus" "--time=$time")
  if [[ -n "$mem" ]]; then
    jam_slurm_megabytes JAM_SLURM_FINISH_MEM "$mem" >/dev/null
    jam_slurm_finish_options+=("--mem=$mem")
  fi
}

# jam_slurm_partition_nodes PARTITION: reads `sinfo -N` into jam_slurm_nodes ("CPUS MB MINUTES"
# per node of PARTITION: a comma list, or "" for the default one) and jam_slurm_partition (the
# name). Returns 1, with jam_slurm_nodes empty, when sinfo is absent, fails or lists no node.
jam_slurm_partition_nodes() {
  local wanted=$1 out part cpus mem limit name
  jam_slurm_nodes=()
  jam_slurm_partition=${wanted:-default}
  command -v sinfo >/dev/null 2>&1 || return 1
  out=$(sinfo -h -N -o '%P %c %m %l' 2>/dev/null) || return 1
  while read -r part cpus mem limit; do
    [[ -n "$part" ]] || continue
    name=${part%\*}
    if [[ -z "$wanted" ]]; then
      [[ "$part" == *\* ]] || continue
      jam_slurm_partition=$name
    elif [[ ",$wanted," != *",$name,"* ]]; then
      continue
    fi
    cpus=${cpus%+} mem=${mem%+}
    [[ "$cpus" =~ ^[0-9]{1,7}$ && "$mem" =~ ^[0-9]{1,12}$ ]] || continue
    # a limit sinfo prints otherwise (n/a) limits nothing here
    (jam_slurm_minutes "" "$limit" >/dev/null 2>&1) || limit=infinite
    jam_slurm_nodes+=("$cpus $mem $(jam_slurm_minutes "" "$limit")")
  done <<<"$out"
  ((${#jam_slurm_nodes[@]} > 0))
}

# jam_slurm_check_fits CPUS_LABEL CPUS MEM_LABEL MEM TIME_LABEL TIME: dies naming the first
# value that no node of the partition read by jam_slurm_partition_nodes can meet (MEM and TIME
# may be empty: not asked).
jam_slurm_check_fits() {
  local cpus=$2 mb=0 minutes=0 most_cpus=0 most_mb=0 longest=0 both=0 c m t node
  [[ -z "$4" || "$4" == 0 ]] || mb=$(jam_slurm_megabytes "$3" "$4")
  [[ -z "$6" ]] || minutes=$(jam_slurm_minutes "$5" "$6")
  for node in "${jam_slurm_nodes[@]}"; do
    read -r c m t <<<"$node"
    if ((c > most_cpus)); then most_cpus=$c; fi
    if ((m > most_mb)); then most_mb=$m; fi
    if ((t > longest)); then longest=$t; fi
    if ((c >= cpus && m >= mb)); then both=1; fi
  done
  local where="partition $jam_slurm_partition (sinfo)" never="the job could never start"
  ((cpus <= most_cpus)) ||
    jam_slurm_die "$1 $cpus: no node of $where has more than $most_cpus CPUs: $never"
  ((mb <= most_mb)) ||
    jam_slurm_die "$3 $4: no node of $where has more than $most_mb MB of memory: $never"
  ((both)) ||
    jam_slurm_die "$1 $cpus with $3 $4: no node of $where has both: $never"
  ((minutes <= longest)) ||
    jam_slurm_die "$5 $6: the time limit of $where is $longest minutes: $never"
}

# jam_slurm_header_value SCRIPT OPTION: the value of "#SBATCH --OPTION=VALUE" in SCRIPT (the
# batch script's own default; nothing when it has none). The headers are the one place the
# defaults are written, so submit.sh reads them rather than repeating them.
jam_slurm_header_value() {
  sed -n "s/^#SBATCH --$2=\([^[:space:]]*\).*/\1/p" "$1" | tail -n 1
}

# jam_slurm_partition_defaults MODE CPUS NTASKS TIME: the work job's header defaults that the
# partition read by jam_slurm_partition_nodes cannot meet, cut to what it offers (a request it
# can never meet pends for ever): prints one option per line, e.g. --time=60 when the header's
# 24:00:00 exceeds a one-hour limit. CPUS, NTASKS, TIME: what the user gave ("": nothing, so
# the header's applies). MODE array: --cpus-per-task and --time; mpi: --ntasks and --time.
jam_slurm_partition_defaults() {
  local mode=$1 cpus=$2 ntasks=$3 time=$4 script="${jam_slurm_dir:?}/campaign-$1.sbatch"
  local most_cpus=0 total_cpus=0 longest=0 c t node header
  for node in "${jam_slurm_nodes[@]}"; do
    read -r c _ t <<<"$node"
    total_cpus=$((total_cpus + c))
    if ((c > most_cpus)); then most_cpus=$c; fi
    if ((t > longest)); then longest=$t; fi
  done
  if [[ -z "$time" ]]; then
    header=$(jam_slurm_header_value "$script" time)
    if [[ -n "$header" ]] && ((longest < $(jam_slurm_minutes "$script --time" "$header"))); then
      printf '%s\n' "--time=$longest"
    fi
  fi
  [[ -n "$cpus" ]] || cpus=$(jam_slurm_header_value "$script" cpus-per-task)
  [[ "$cpus" =~ ^[1-9][0-9]{0,5}$ ]] || cpus=1
  if [[ "$mode" == array && -z "$2" ]] && ((cpus > most_cpus && most_cpus > 0)); then
    printf '%s\n' "--cpus-per-task=$most_cpus"
  fi
  if [[ "$mode" == mpi && -z "$ntasks" ]]; then
    header=$(jam_slurm_header_value "$script" ntasks)
    if [[ "$header" =~ ^[0-9]+$ ]] && ((header * cpus > total_cpus && total_cpus >= cpus)); then
      printf '%s\n' "--ntasks=$((total_cpus / cpus))"
    fi
  fi
}

# jam_slurm_can_start WHAT SCRIPT OPTION... -- ARGUMENT...: asks Slurm itself whether the job
# SCRIPT with OPTIONs (its header's for the rest) could ever start (`sbatch --test-only`, which
# submits nothing). When not, dies in one line naming WHAT, the option to blame (the first
# whose removal lets the job start) and Slurm's reason. sinfo cannot see everything Slurm
# judges (core counts per socket, --ntasks against a node's cores, partitions, accounts, QOS).
jam_slurm_can_start() {
  local what=$1 script=$2 out reason i j
  shift 2
  local -a opts=() args=() rest=()
  while (($#)) && [[ "$1" != -- ]]; do
    opts+=("$1")
    shift
  done
  (($# == 0)) || shift
  args=("$@")
  out=$(sbatch --test-only "${opts[@]}" "$script" "${args[@]}" 2>&1) && return 0
  # Slurm's last line, without its prefixes ("allocation failure: ...", "sbatch: error: ...")
  reason=$(printf '%s\n' "$out" | sed -e '/^[[:space:]]*$/d' | tail -n 1)
  reason=${reason#allocation failure: }
  reason=${reason#sbatch: error: }
  # One option with its values (the words after it that do not start with -) at a time: left
  # out (the header's value applies), or, when its value is a number, asking for 1 instead
  # (the header's value may be too much as well).
  local -a least
  local try
  for ((i = 0; i < ${#opts[@]}; i = j)); do
    for ((j = i + 1; j < ${#opts[@]}; j++)); do
      [[ "${opts[j]}" != -* ]] || break
    done
    least=()
    if ((j == i + 2)) && [[ "${opts[i + 1]}" =~ ^[0-9] ]]; then
      least=("${opts[i]}" 1)
    elif [[ "${opts[i]}" =~ ^(--[a-z-]+=)[0-9] ]]; then
      least=("${BASH_REMATCH[1]}1")
    fi
    for try in without least; do
      if [[ "$try" == without ]]; then
        rest=("${opts[@]:0:i}" "${opts[@]:j}")
      elif ((${#least[@]})); then
        rest=("${opts[@]:0:i}" "${least[@]}" "${opts[@]:j}")
      else
        continue
      fi
      if sbatch --test-only "${rest[@]}" "$script" "${args[@]}" >/dev/null 2>&1; then
        jam_slurm_die "$what: ${opts[*]:i:j-i}: Slurm says '$reason' (sbatch --test-only): the job could never start"
      fi
    done
  done
  jam_slurm_die "$what: Slurm says '$reason' (sbatch --test-only ${opts[*]} $(basename -- "$script")): the job could never start"
}
