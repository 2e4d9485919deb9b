#!/usr/bin/env bash
# The real-versus-artefact counts of docs/method.md §8.4: Figure 4.5's setting
# (`abundance`) and the Lire collapse (`lire-collapse`), each rule and prox choice, at the
# scene's Δt, Δt/2 and Δt/4, explored to at most 200 branches and 120 s of wall time
# (the thesis's rule puts bodies into each other, and every later step of such a branch
# is split to keep them apart, which is slow), with every fork checked. Prints one
# Markdown row per run ("cap": a cap ended the exploration; "deepest overlap": the deepest
# interpenetration over every branch). Needs `rollstack` on PATH (cargo build --release -p
# rollstack; export PATH=$PWD/target/release:$PATH). Takes 5-15 minutes on 2 cores.
#
#   scripts/abundance_counts.sh                          # prints the table
#   scripts/abundance_counts.sh --write docs/exploration.md
#
# --write replaces the table between the markers <!-- abundance_counts: begin --> and
# <!-- abundance_counts: end --> of that file, so the counts the docs show are this
# script's output, not a copy.
set -euo pipefail
write=""
if [ "${1:-}" = --write ]; then
  write=${2:?--write needs a file}
  grep -q '<!-- abundance_counts: begin -->' "$write" || { echo "$write has no abundance_counts markers" >&2; exit 2; }
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
table() {
echo "| scene | Δt | rule | prox | branches | forks | real | artefact | undecided | outcomes | deepest overlap | cap | wall s |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for scene in abundance lire-collapse; do
  for factor in 1 2 4; do
    file="$tmp/$scene-$factor.toml"
    if [ "$scene" = abundance ]; then
      rollstack blocks scenes "$scene" | sed "s/^steps_per_period = 60/steps_per_period = $((60 * factor))/" > "$file"
    else
      dt=$(python3 -c "print(0.01 / $factor)")
      rollstack blocks scenes "$scene" | sed "s/^dt = 0.01/dt = $dt/" > "$file"
    fi
    for rule in self-consistent converged; do
      for prox in scaled 0.3; do
        extra=()
        [ "$prox" = scaled ] || extra=(--prox-constant "$prox")
        rollstack blocks explore "$file" --branch-rule "$rule" "${extra[@]}" --classify \
          --max-branches 200 --max-wall 120 --trajectories false --json |
          python3 -c "
import json, sys
d = json.load(sys.stdin)
l = d['labels']
cap = ' '.join(c for c, k in (('branches', 'branch_cap_reached'), ('wall', 'wall_cap_reached')) if d[k]) or '-'
print(f\"| $scene | Δt/$factor | $rule | $prox | {d['branches']} | {d['forks']} | {l['real']} | {l['artefact']} | {l['undecided']} | {d['distinct_outcomes']} | {d['max_penetration']:.1e} | {cap} | {d['wall_time_s']:.1f} |\")"
      done
    done
  done
done
}
if [ -z "$write" ]; then
  table
else
  table > "$tmp/table.md"
  python3 "$(dirname "$0")/write_between_markers.py" abundance_counts "$write" "$tmp/table.md" \
    "$(rollstack --version), commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
fi
