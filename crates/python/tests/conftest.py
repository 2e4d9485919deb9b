"""Shared fixtures: the `rollstack` command line, to compare the module's results with
its `--json` output."""

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]


def _find_cli() -> str:
    """$ROLLSTACK_CLI, else the binary `cargo test --workspace` built (in
    $CARGO_TARGET_DIR or target/), else one built now. No `cargo metadata`: it waits for
    the package-cache lock while another cargo runs."""
    given = os.environ.get("ROLLSTACK_CLI")
    if given:
        return given
    target = Path(os.environ.get("CARGO_TARGET_DIR") or ROOT / "target")
    if not target.is_absolute():
        target = ROOT / target
    exe = target / "debug" / "rollstack"
    if not exe.exists():
        subprocess.run(["cargo", "build", "-q", "-p", "rollstack"], cwd=ROOT, check=True)
    return str(exe)


@pytest.fixture(scope="session")
def cli_exe() -> str:
    """The path of the `rollstack` binary, for the commands without `--json` (their
    files are compared instead)."""
    if shutil.which("cargo") is None and not os.environ.get("ROLLSTACK_CLI"):
        pytest.skip("no cargo and no ROLLSTACK_CLI: cannot compare with the command line")
    return _find_cli()


@pytest.fixture(scope="session")
def cli(cli_exe):
    """Runs `rollstack ARGS... --json` and returns the parsed JSON (the exit status is
    not checked: a run that stops early prints its JSON and exits with 1)."""
    exe = cli_exe

    def run(*args: str):
        out = subprocess.run([exe, *args, "--json"], capture_output=True, text=True)
        assert out.stdout, out.stderr
        return json.loads(out.stdout)

    return run
