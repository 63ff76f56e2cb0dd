#!/usr/bin/env bash
# Everything CI runs, in one command (README: "Run every test"):
#   1. builds every FMU once, in release, into dist/ (the tests load these very files),
#   2. runs the Rust tests (unit tests and the native FMI host tests against dist/*.fmu),
#   3. creates the Python virtual environment .venv from tests/requirements.txt (pinned),
#   4. runs the independent checks with pytest (fmpy validate, fmutool -check, fmpy simulate).
set -euo pipefail
cd "$(dirname "$0")"

echo "== build every FMU (release)"
cargo run --release -p build-fmus

echo "== Rust tests"
cargo test --release --workspace

echo "== Python environment (.venv, tests/requirements.txt)"
if [ ! -x .venv/bin/python ]; then
    python3 -m venv .venv
fi
.venv/bin/python -m pip install --quiet --disable-pip-version-check -r tests/requirements.txt

echo "== Python tests (fmpy, fmutool)"
.venv/bin/python -m pytest -q tests/python
