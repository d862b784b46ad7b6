#!/usr/bin/env bash
# The reduced-scale reproduction of the paper, end to end, and its stored result:
#
#   scripts/reproduce.sh reduced-2d     # about 30 minutes on 2 cores
#   scripts/reproduce.sh reduced-3d     # about 15 minutes
#   scripts/reproduce.sh paper-2d       # the paper's 2D study: about 50 core-hours in all, its
#                                       # campaigns run in stretches first (docs/reproduction.md)
#
# 1. the phi_init check campaign (reference/campaigns/NAME-phi-init.toml), when there is one,
#    and the jamming-point campaign (NAME-jamming.toml: stats and report), when there is one,
# 2. the campaign (reference/campaigns/NAME.toml) in runs/NAME,
# 3. stats, cubic ln f, three times: the paper's q held (fit-q-fixed.json), both exponents held
#    (fit-held.json), and nothing held (stats.h5 and fit-free.json: the result),
# 4. all checks; with reference/campaigns/NAME-chain-control.toml its campaign and the chain
#    check (of NAME-chain-test.toml's chained samples when there is one); the reports (reports/NAME/: the free fit; reports/NAME-q-fixed/: q held),
# 5. the stored result reference/results/NAME/: stats.h5, fit-*.json, checks.json,
#    phi-init-checks.json or chain-checks.json, jamming-stats.h5 (the jamming-point
#    campaign's stats), campaign.toml, cost.json (each campaign's measured CPU seconds,
#    scripts/campaign_cost.py) and provenance.json (code
#    version, machine, date, wall time of every stage, core-seconds of every campaign),
#    written to a temporary directory and renamed into place.
#
# Runs that are already done are not redone (a campaign resumes), so running it again after an
# interruption finishes the work; the wall times then cover only this invocation.
# The stored result is what CI's regression test compares reruns with
# (tests/test_reduced_regression.cpp); rerunning this script regenerates it.
set -euo pipefail
cd "$(dirname "$0")/.."

name=${1:?usage: scripts/reproduce.sh reduced-2d|reduced-3d|paper-2d}
campaign=reference/campaigns/$name.toml
[ -f "$campaign" ] || { echo "reproduce: name: no campaign file $campaign" >&2; exit 2; }
jam=build/jam
[ -x "$jam" ] || { echo "reproduce: $jam missing: run scripts/setup.sh first" >&2; exit 2; }
# runs/NAME-q-fixed holds a copy of the result's stats and checks for the q-fixed report, made
# again on every invocation. Before any work: a directory of that name that holds anything else
# (or a file of that name) is not this script's, and is left alone.
qfixed=runs/$name-q-fixed
if [ -L "$qfixed" ] || { [ -e "$qfixed" ] && [ ! -d "$qfixed" ]; }; then
  echo "reproduce: $qfixed is not a directory this script made: move it away first" >&2
  exit 2
fi
for entry in "$qfixed"/* "$qfixed"/.[!.]*; do
  [ -e "$entry" ] || [ -L "$entry" ] || continue
  case $(basename "$entry") in
    campaign.toml | manifest.toml | stats.h5 | checks.json | checks.h5)
      [ -f "$entry" ] && [ ! -L "$entry" ] && continue ;;
  esac
  echo "reproduce: $qfixed holds $(basename "$entry"), which this script did not write:" \
    "move it away first" >&2
  exit 2
done
quiet=""
[ -t 1 ] || quiet="--quiet"
commit=$(git rev-parse HEAD 2>/dev/null || echo unknown)
mkdir -p reference/results

declare -A wall
stage() {  # stage KEY command...: runs it and records its wall time in seconds
  local key=$1 start
  shift
  start=$(date +%s%N)
  "$@"
  wall[$key]=$(awk -v ns=$(($(date +%s%N) - start)) 'BEGIN { printf "%.1f", ns / 1e9 }')
}
# verdicts FILE command...: a check exits 1 when a verdict fails and 3 when one is
# inconclusive (findings, kept), 2 on an error (no verdict file written); only the last stops
# the script.
verdicts() {
  local file=$1 status=0
  shift
  rm -f "$file"
  "$@" >/dev/null || status=$?
  if [ "$status" -eq 2 ] || [ ! -f "$file" ]; then
    echo "reproduce: '$*' failed (exit status $status)" >&2
    exit 1
  fi
}

# measure KEY DIR: the measured CPU seconds of the campaign in DIR into cores[KEY], its account
# (scripts/campaign_cost.py: the runs' records, a run's wall seconds where its record has
# none; the chained starts left again, from the campaign's log when the stored result keeps
# it in logs/; an estimate for records short of their run) into cost.json under KEY. Wall
# time would also count a machine's other load and any stretch in which the campaign was
# stopped.
costs=$(mktemp -d)
trap 'rm -rf "$costs"' EXIT
measure() {
  local key=$1 dir=$2 log
  log=reference/results/$name/logs/$(basename "$dir").log
  local logs=()
  [ -f "$log" ] && logs=(--log "$log")
  /usr/bin/python3 scripts/campaign_cost.py "$dir" "${logs[@]}" --json >"$costs/$key.json"
  cores[$key]=$(/usr/bin/python3 -c 'import json, sys
print(json.load(open(sys.argv[1]))["cpu_seconds_total"])' "$costs/$key.json")
}
declare -A cores

# A separate phi_init campaign, for campaigns whose own phi_init values do not compare starts.
if [ -f "reference/campaigns/$name-phi-init.toml" ]; then
  stage phi_init_campaign $jam campaign run "reference/campaigns/$name-phi-init.toml" $quiet
  measure phi_init_campaign "runs/$name-phi-init"
  stage phi_init_stats $jam stats "runs/$name-phi-init" --no-fit >/dev/null
  # Judged below, over the campaign's fit window.
fi

# A separate jamming-point campaign, for campaigns that look for none themselves (the search
# would cost more than they do): its stats (every run's phi_Ji) and its report.
if [ -f "reference/campaigns/$name-jamming.toml" ]; then
  stage jamming_campaign $jam campaign run "reference/campaigns/$name-jamming.toml" $quiet
  measure jamming_campaign "runs/$name-jamming"
  stage jamming_stats $jam stats "runs/$name-jamming" --no-fit >/dev/null
  verdicts "runs/$name-jamming/checks.json" $jam check all "runs/$name-jamming" --with-lammps
  $jam report "runs/$name-jamming" --out "reports/$name-jamming" --quiet
fi

stage campaign $jam campaign run "$campaign" $quiet
measure campaign "runs/$name"
fits=$(mktemp -d)
# The fits that hold the paper's values, kept beside the result for comparison ...
stage stats_q_fixed $jam stats "runs/$name" --order 3 --fix-paper-q >/dev/null
scripts/fit_to_json.py "runs/$name/stats.h5" "$fits/fit-q-fixed.json" \
  "jam stats --order 3 --fix-paper-q"
# The q-fixed report reads a copy of the directory's stats and checks, not the runs
# (checked at the start that an earlier one is this script's).
rm -rf "$qfixed" && mkdir -p "$qfixed"
cp "runs/$name"/{campaign.toml,manifest.toml,stats.h5} "$qfixed/"
stage stats_held $jam stats "runs/$name" --order 3 --fix-paper-exponents >/dev/null
scripts/fit_to_json.py "runs/$name/stats.h5" "$fits/fit-held.json" \
  "jam stats --order 3 --fix-paper-exponents"
# ... and the result: the free fit, nothing held (the checks use its phi_J).
stage stats $jam stats "runs/$name" --order 3 >/dev/null
scripts/fit_to_json.py "runs/$name/stats.h5" "$fits/fit-free.json" "jam stats --order 3"
# --with-lammps: the stored results carry the LAMMPS self-checks (`check all` judges them only
# when asked).
stage checks verdicts "runs/$name/checks.json" $jam check all "runs/$name" --with-lammps
cp "runs/$name"/{checks.json,checks.h5} "$qfixed/"

# fit_window STATS: the representative scaling fit's "phi_min phi_max"; nothing when the fit
# failed (the checks then say that no window was given).
fit_window() {
  /usr/bin/python3 -c 'import h5py, sys
f = h5py.File(sys.argv[1], "r")
if "fit/representative" in f:
    a = f["fit/representative"].attrs
    print(a["phi_min"], a["phi_max"])' "$1"
}
# The separate phi_init campaign is judged over the window the campaign's free fit uses, the
# range whose phi_init independence the fit needs: its own stats hold no fit, and without a
# window every pressure verdict would be inconclusive by construction. The check fails where
# the start is remembered (fast rates): that is its finding.
if [ -f "reference/campaigns/$name-phi-init.toml" ]; then
  window=()
  bounds=$(fit_window "runs/$name/stats.h5")
  [ -n "$bounds" ] && window=(--phi-min "${bounds% *}" --phi-max "${bounds#* }")
  stage phi_init_check verdicts "runs/$name-phi-init/checks-phi_init.json" \
    $jam check phi_init "runs/$name-phi-init" "${window[@]}"
fi

chain_json=""
# Chained starts justified: each chained rate against the same samples unchained. With
# NAME-chain-test.toml (the campaign's chains on more samples of its smallest size) that set is
# judged, over the campaign's own scaling window; else the campaign's own chained samples.
if [ -f "reference/campaigns/$name-chain-control.toml" ]; then
  stage chain_control_campaign $jam campaign run "reference/campaigns/$name-chain-control.toml" \
    $quiet
  measure chain_control_campaign "runs/$name-chain-control"
  $jam stats "runs/$name-chain-control" --no-fit >/dev/null
  chained="runs/$name"
  window=()
  if [ -f "reference/campaigns/$name-chain-test.toml" ]; then
    stage chain_test_campaign $jam campaign run "reference/campaigns/$name-chain-test.toml" $quiet
    measure chain_test_campaign "runs/$name-chain-test"
    $jam stats "runs/$name-chain-test" --no-fit >/dev/null
    chained="runs/$name-chain-test"
    bounds=$(fit_window "runs/$name/stats.h5")
    [ -n "$bounds" ] && window=(--phi-min "${bounds% *}")
  fi
  stage chain_check verdicts "$chained/checks-chain.json" \
    $jam check chain "$chained" --against "runs/$name-chain-control" "${window[@]}"
  chain_json="$chained/checks-chain.json"
fi
stage report $jam report "runs/$name" --out "reports/$name" --quiet
$jam report "$qfixed" --out "reports/$name-q-fixed" --quiet

out=reference/results/$name
tmp=$(mktemp -d "reference/results/.$name.XXXXXX")
# mktemp makes it private (0700); the stored result is as readable as any directory made here.
chmod "$(umask -S)" "$tmp"
trap 'rm -rf "$tmp" "$costs"' EXIT
cp "runs/$name/stats.h5" "runs/$name/checks.json" "$fits"/fit-*.json "$tmp/"
rm -rf "$fits"
[ -f "runs/$name-phi-init/checks-phi_init.json" ] &&
  cp "runs/$name-phi-init/checks-phi_init.json" "$tmp/phi-init-checks.json"
[ -n "$chain_json" ] && cp "$chain_json" "$tmp/chain-checks.json"
[ -f "reference/campaigns/$name-jamming.toml" ] &&
  cp "runs/$name-jamming/stats.h5" "$tmp/jamming-stats.h5"
cp "$campaign" "$tmp/campaign.toml"
/usr/bin/python3 -c 'import json, os, sys
d = sys.argv[1]
json.dump({f[:-5]: json.load(open(os.path.join(d, f))) for f in sorted(os.listdir(d))},
          open(sys.argv[2], "w"), indent=1)' "$costs" "$tmp/cost.json"
rm -rf "$costs"
total_cores=0
core_fields=""
for k in "${!cores[@]}"; do
  core_fields+="\"${k}_core_seconds\": ${cores[$k]}, "
  total_cores=$(awk -v a="$total_cores" -v b="${cores[$k]}" 'BEGIN { print a + b }')
done
walls=""
for k in "${!wall[@]}"; do walls+="\"$k\": ${wall[$k]}, "; done
regression=""
if [ -f "reference/campaigns/$name-regression.toml" ]; then
  regression=',
  "regression": {"campaign": "reference/campaigns/'"$name"'-regression.toml", "tolerance": 0.0,
                 "test": "tests/test_reduced_regression.cpp"}'
fi
cat >"$tmp/provenance.json" <<EOF
{
  "name": "$name",
  "command": "scripts/reproduce.sh $name",
  "code_version": "$($jam --version | head -n 1)",
  "git_commit": "$commit",
  "date": "$(date -u +%Y-%m-%dT%H:%M:%SZ)",
  "machine": "$(lscpu | sed -n 's/^Model name: *//p' | head -1), $(nproc) cores, $(free -g | awk '/Mem:/ {print $2}') GiB",
  "os": "$(. /etc/os-release && echo "$PRETTY_NAME")",
  "wall_seconds": {${walls%, }},
  "wall_seconds_note": "wall times of this invocation's stages; runs an earlier invocation (or a separate jam campaign run) already did take none here and count only in the *_core_seconds (each campaign's measured CPU seconds, scripts/campaign_cost.py: its runs' own CPU seconds, their wall seconds where a record has none, with the chained starts left again and the short records' estimated rest; cost.json holds each account)",
  "campaign_run_core_seconds": ${cores[campaign]},
  ${core_fields}"total_core_seconds": $total_cores${regression}
}
EOF
/usr/bin/python3 -m json.tool "$tmp/provenance.json" >/dev/null
# What the stored result holds beside the files this script writes (results of other commands
# such as until-decided/, a campaign's committed partial products) is carried over, never
# deleted; a file of its own that this invocation did not write again is not (it would be stale).
if [ -d "$out" ]; then
  for entry in "$out"/* "$out"/.[!.]*; do
    [ -e "$entry" ] || continue
    case $(basename "$entry") in
      stats.h5 | checks.json | fit-*.json | phi-init-checks.json | chain-checks.json | \
        jamming-stats.h5 | campaign.toml | provenance.json | cost.json) ;;
      *) cp -a "$entry" "$tmp/" ;;
    esac
  done
fi
rm -rf "$out.old"
[ -d "$out" ] && mv "$out" "$out.old"
mv "$tmp" "$out"
rm -rf "$out.old"
trap - EXIT
echo "reproduce: $name stored in $out; report reports/$name/index.html"
