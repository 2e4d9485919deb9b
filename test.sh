#!/usr/bin/env bash
# Every test: the Rust workspace, then the Python module (scripts/python_test.sh:
# a virtual environment in .venv, `pip install ./crates/python`, pytest, the examples).
set -euo pipefail
cd "$(dirname "$0")"
cargo test --workspace
scripts/python_test.sh
