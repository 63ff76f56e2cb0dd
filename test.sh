#!/usr/bin/env bash
# Everything CI runs, in one command (README: "Run every test"):
#   1. builds every FMU once, in release, into dist/ (the tests load these very files), linked for
#      glibc 2.17 with cargo zigbuild (build-fmus installs the pinned toolchain into .build-tools/
#      on its first run),
#   2. runs the Rust tests (unit tests and the native FMI host tests against dist/*.fmu), then
#      a subset of them under valgrind memcheck (tests/valgrind.sh),
#   3. creates the Python virtual environment .venv from tests/requirements.txt (pinned),
#   4. runs the independent checks with pytest (fmpy validate, fmutool -check, fmpy simulate).
set -euo pipefail
cd "$(dirname "$0")"

# One source date for every build below (build-fmus takes the same from git when it is unset):
# export_fmu! bakes it into each model at compile time, so with one value cargo does not rebuild
# the model crates between `build-fmus` and `cargo test`.
if [ -z "${SOURCE_DATE_EPOCH:-}" ] && source_date="$(git log -1 --format=%ct 2>/dev/null)"; then
    export SOURCE_DATE_EPOCH="$source_date"
fi

echo "== build every FMU (release)"
cargo run --release -p build-fmus

echo "== Rust tests"
cargo test --release --workspace

echo "== valgrind memcheck (tests/valgrind.sh)"
tests/valgrind.sh

echo "== Python environment (.venv, tests/requirements.txt)"
if [ ! -x .venv/bin/python ]; then
    python3 -m venv .venv
fi
.venv/bin/python -m pip install --quiet --disable-pip-version-check -r tests/requirements.txt
# The external co-simulation masters (tests/python/test_coupled_masters.py): ecospy's native
# library needs Debian's libtbb12, and its wheel ships the `ecos` and `proxyfmu` executables
# without the executable bit. Both steps do nothing when already done.
# (grep without -q: with pipefail, -q's early exit could fail ldconfig with SIGPIPE.)
if ! ldconfig -p | grep 'libtbb\.so\.12' >/dev/null; then
    if ! DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends libtbb12; then
        apt-get update
        DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends libtbb12
    fi
fi
ecospy_binaries="$(.venv/bin/python -c 'import importlib.util, pathlib; print(pathlib.Path(importlib.util.find_spec("ecospy").origin).parent / "binaries")')"
chmod +x "$ecospy_binaries/ecos" "$ecospy_binaries/proxyfmu"

echo "== Python tests (fmpy, fmutool)"
.venv/bin/python -m pytest -q tests/python
