#!/usr/bin/env bash
# The thesis's algorithm beside rollstack's rules on Figure 4.5's setting
# (docs/exploration.md, "The thesis's algorithm"): `abundance` (the thesis's text, A = 1)
# and `abundance-author` (the author's scripts, A = 0.2), each at the scene's Δt, Δt/2
# and Δt/4, explored by
#   - `--preset thesis` (the author's algorithm and model: no floor, neighbour contacts,
#     every branch stopped at the onset of failure),
#   - rollstack's default rule (self-consistent candidates, scaled prox), and
#   - the converged rule with r = 0.3 (the thesis's count in rollstack's solver),
# each with every fork checked (--classify) to at most 200 branches and 180 s of wall
# time; then the thesis preset on `abundance-author` at Δt unchecked, to 3000 branches
# or 300 s, for the size of the tree. Prints one Markdown row per run: forks met and
# their labels, candidates over all forks and how many of them break a contact law (gap,
# normal, cone, complementarity), the branches that start with such a step, the leaves
# that ended on a failed step, the outcomes, the failure times over the leaves, and the
# deepest interpenetration. Needs `rollstack` on PATH (cargo build --release -p
# rollstack; export PATH=$PWD/target/release:$PATH). Takes about 10 minutes on 2 cores.
#
#   scripts/thesis_counts.sh                          # prints the table
#   scripts/thesis_counts.sh --write docs/exploration.md
#
# --write replaces the table between the markers <!-- thesis_counts: begin --> and
# <!-- thesis_counts: end --> of that file.
set -euo pipefail
write=""
if [ "${1:-}" = --write ]; then
  write=${2:?--write needs a file}
  grep -q '<!-- thesis_counts: begin -->' "$write" || { echo "$write has no thesis_counts markers" >&2; exit 2; }
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
row() { # scene factor mode max-branches max-wall [flags...]
  local scene=$1 factor=$2 mode=$3 branches=$4 wall=$5
  shift 5
  rollstack blocks explore "$tmp/$scene-$factor.toml" "$@" --max-branches "$branches" \
    --max-wall "$wall" --trajectories false --json |
    python3 -c "
import json, sys
d = json.load(sys.stdin)
cap = ' '.join(c for c, k in (('branches', 'branch_cap_reached'), ('wall', 'wall_cap_reached')) if d[k]) or '-'
times = [t for g in d['outcomes'] if g['failure_time'] for t in (g['failure_time'][0], g['failure_time'][2])]
fail = f'{min(times):.2f}–{max(times):.2f}' if times else '-'
l = d['labels']
labels = '-' if l['unchecked'] else f\"{l['real']} / {l['artefact']} / {l['undecided']}\"
print(f\"| $scene | Δt/$factor | $mode | {d['branches']} | {d['forks']} | {labels} | {d['candidates']} | {d['candidates_breaking_laws']} | {d['branches_breaking_laws']} | {d['failed_leaves']} | {d['distinct_outcomes']} | {fail} | {d['max_penetration']:.1e} | {cap} | {d['wall_time_s']:.1f} |\")"
}
table() {
echo "| scene | Δt | mode | branches | forks | real / artefact / undecided | candidates | breaking a law | branches breaking a law | failed leaves | outcomes | failure t | deepest overlap | cap | wall s |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for scene in abundance abundance-author; do
  for factor in 1 2 4; do
    rollstack blocks scenes "$scene" |
      python3 -c "
import re, sys
text = sys.stdin.read()
n = int(re.search(r'^steps_per_period = (\d+)', text, re.M).group(1))
print(re.sub(r'^steps_per_period = \d+', f'steps_per_period = {n * $factor}', text, flags=re.M), end='')" \
      > "$tmp/$scene-$factor.toml"
    row "$scene" "$factor" "thesis preset" 200 180 --preset thesis --classify
    row "$scene" "$factor" "self-consistent" 200 180 --branch-rule self-consistent --classify
    row "$scene" "$factor" "converged, r = 0.3" 200 180 --branch-rule converged --prox-constant 0.3 --classify
  done
done
row abundance-author 1 "thesis preset" 3000 300 --preset thesis
}
if [ -z "$write" ]; then
  table
else
  table > "$tmp/table.md"
  python3 "$(dirname "$0")/write_between_markers.py" thesis_counts "$write" "$tmp/table.md" \
    "$(rollstack --version), commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
fi
