#!/usr/bin/env bash
# The reduced-scale reproduction of the paper, end to end, and its stored result:
#
#   scripts/reproduce.sh reduced-2d     # about 35 minutes on 2 cores
#   scripts/reproduce.sh reduced-3d     # about 40 minutes
#
# 1. the phi_init check campaign (reference/campaigns/NAME-phi-init.toml) that chose the start,
# 2. the campaign (reference/campaigns/NAME.toml) in runs/NAME,
# 3. stats with a free three-parameter scaling fit (kept as stats-free-fit.h5), then with the
#    paper's exponents q and 1/(z nu) held fixed (stats.h5, the result), cubic ln f,
# 4. all checks, the report (reports/NAME/, paper exponents; reports/NAME-free-fit/, fitted),
# 5. the stored result reference/results/NAME/: stats.h5, stats-free-fit.h5, checks.json,
#    phi-init-checks.json, campaign.toml and provenance.json (code version, machine, date, wall
#    time of every stage), written to a temporary directory and renamed into place.
#
# Runs that are already done are not redone (a campaign resumes), so running it again after an
# interruption finishes the work; the wall times then cover only this invocation.
# The stored result is what CI's regression test compares reruns with
# (tests/test_reduced_regression.cpp); rerunning this script regenerates it.
set -euo pipefail
cd "$(dirname "$0")/.."

name=${1:?usage: scripts/reproduce.sh reduced-2d|reduced-3d}
campaign=reference/campaigns/$name.toml
[ -f "$campaign" ] || { echo "reproduce: name: no campaign file $campaign" >&2; exit 2; }
jam=build/jam
[ -x "$jam" ] || { echo "reproduce: $jam missing: run scripts/setup.sh first" >&2; exit 2; }
quiet=""
[ -t 1 ] || quiet="--quiet"

declare -A wall
stage() {  # stage KEY command...: runs it and records its wall time in seconds
  local key=$1 start
  shift
  start=$(date +%s%N)
  "$@"
  wall[$key]=$(awk -v ns=$(($(date +%s%N) - start)) 'BEGIN { printf "%.1f", ns / 1e9 }')
}
# verdicts FILE command...: a check exits 1 both when a verdict fails (a finding, kept) and on
# an error (no verdict file written); only the second stops the script.
verdicts() {
  local file=$1
  shift
  rm -f "$file"
  "$@" >/dev/null || [ -f "$file" ] || { echo "reproduce: '$*' failed" >&2; exit 1; }
}

stage phi_init_campaign $jam campaign run "reference/campaigns/$name-phi-init.toml" $quiet
stage phi_init_stats $jam stats "runs/$name-phi-init" --no-fit >/dev/null
# The check fails where the start is remembered (fast rates): that is its finding.
stage phi_init_check verdicts "runs/$name-phi-init/checks-phi_init.json" \
  $jam check phi_init "runs/$name-phi-init"

stage campaign $jam campaign run "$campaign" $quiet
stage stats_free_fit $jam stats "runs/$name" --order 3 >/dev/null
cp "runs/$name/stats.h5" "runs/$name/stats-free-fit.h5"
stage stats $jam stats "runs/$name" --order 3 --fix-paper-exponents >/dev/null
stage checks verdicts "runs/$name/checks.json" $jam check all "runs/$name"

# The free-fit report reads a copy of the directory's stats and checks, not the runs.
free=runs/$name-free-fit
rm -rf "$free" && mkdir -p "$free"
cp "runs/$name"/{campaign.toml,manifest.toml,checks.json,checks.h5} "$free/"
cp "runs/$name/stats-free-fit.h5" "$free/stats.h5"
stage report $jam report "runs/$name" --out "reports/$name" --quiet
$jam report "$free" --out "reports/$name-free-fit" --quiet

out=reference/results/$name
tmp=$(mktemp -d "reference/results/.$name.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
cp "runs/$name/stats.h5" "runs/$name/stats-free-fit.h5" "runs/$name/checks.json" "$tmp/"
cp "runs/$name-phi-init/checks-phi_init.json" "$tmp/phi-init-checks.json"
cp "$campaign" "$tmp/campaign.toml"
core_seconds=$(/usr/bin/python3 -c '
import sys, tomllib
runs = tomllib.load(open(sys.argv[1], "rb")).get("runs", {})
print(sum(float(r.get("wall_seconds", 0)) for r in runs.values()))' "runs/$name/manifest.toml")
walls=""
for k in "${!wall[@]}"; do walls+="\"$k\": ${wall[$k]}, "; done
cat >"$tmp/provenance.json" <<EOF
{
  "name": "$name",
  "command": "scripts/reproduce.sh $name",
  "code_version": "$($jam --version)",
  "git_commit": "$(git rev-parse HEAD 2>/dev/null || echo unknown)",
  "date": "$(date -u +%Y-%m-%dT%H:%M:%SZ)",
  "machine": "$(lscpu | sed -n 's/^Model name: *//p' | head -1), $(nproc) cores, $(free -g | awk '/Mem:/ {print $2}') GiB",
  "os": "$(. /etc/os-release && echo "$PRETTY_NAME")",
  "wall_seconds": {${walls%, }},
  "campaign_run_core_seconds": $core_seconds,
  "regression": {"campaign": "reference/campaigns/$name-regression.toml", "tolerance": 0.0,
                 "test": "tests/test_reduced_regression.cpp"}
}
EOF
/usr/bin/python3 -m json.tool "$tmp/provenance.json" >/dev/null
mkdir -p reference/results
rm -rf "$out.old"
[ -d "$out" ] && mv "$out" "$out.old"
mv "$tmp" "$out"
rm -rf "$out.old"
trap - EXIT
echo "reproduce: $name stored in $out; report reports/$name/index.html"
