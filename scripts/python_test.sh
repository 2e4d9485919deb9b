#!/usr/bin/env bash
# The Python part of the tests: creates a virtual environment (default .venv, or
# $ROLLSTACK_VENV), installs the module into it as the README says
# (`pip install ./crates/python`, built by maturin), runs the pytest suite of
# crates/python/tests, then the three examples of examples/python without a display.
# Runs from a fresh clone; `./test.sh` runs it after `cargo test --workspace`.
set -euo pipefail
cd "$(dirname "$0")/.."
venv="${ROLLSTACK_VENV:-.venv}"
if [ ! -x "$venv/bin/python" ]; then
    if ! python3 -m venv "$venv" 2>/dev/null; then
        # Debian and Ubuntu ship venv separately.
        echo "python3 -m venv failed: installing python3-venv" >&2
        rm -rf "$venv"
        apt-get install -y -q python3-venv >/dev/null
        python3 -m venv "$venv"
    fi
fi
py="$venv/bin/python"
echo "== pip install ./crates/python"
start=$(date +%s)
"$py" -m pip install -q --upgrade pip
"$py" -m pip install -q ./crates/python pytest matplotlib pandas
echo "installed in $(( $(date +%s) - start )) s"
echo "== pytest crates/python/tests"
"$py" -m pytest -q crates/python/tests
echo "== examples/python"
out="$(mktemp -d)"
for example in examples/python/*.py; do
    MPLBACKEND=Agg "$py" "$example" "$out"
done
rm -rf "$out"
