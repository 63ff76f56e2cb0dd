#!/usr/bin/env bash
# Everything CI runs, in one command (README: "Run every test"):
#   1. builds every FMU once, in release, into dist/ (the tests load these very files), linked for
#      glibc 2.17 with cargo zigbuild (build-fmus installs the pinned toolchain into .build-tools/
#      on its first run),
#   2. runs the Rust tests (unit tests and the native FMI host tests against dist/*.fmu),
#   3. runs a subset of them under valgrind memcheck (tests/valgrind.sh) in the background while
#   4. it creates the Python virtual environment .venv from tests/requirements.txt (pinned) and
#      runs the independent checks with pytest (fmpy validate, fmutool -check, fmpy simulate).
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

# The system packages the next steps need, installed before anything runs beside anything else
# (two apt-get at once would wait on each other's lock): valgrind (tests/valgrind.sh) and, for the
# external co-simulation masters (tests/python/test_coupled_masters.py), ecospy's Debian libtbb12.
# (grep without -q: with pipefail, -q's early exit could fail ldconfig with SIGPIPE.)
missing=()
command -v valgrind >/dev/null || missing+=(valgrind)
ldconfig -p | grep 'libtbb\.so\.12' >/dev/null || missing+=(libtbb12)
if [ ${#missing[@]} -gt 0 ]; then
    if ! DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}"; then
        apt-get update
        DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}"
    fi
fi

# valgrind runs on one core, the Python tests on the other: both take minutes, and each on its
# own leaves a core idle. valgrind's output is shown when it is done.
echo "== valgrind memcheck (tests/valgrind.sh), beside the Python tests; its output follows them"
mkdir -p target
tests/valgrind.sh > target/valgrind.log 2>&1 &
valgrind_pid=$!
trap 'kill "$valgrind_pid" 2>/dev/null || true' EXIT

echo "== Python environment (.venv, tests/requirements.txt)"
if [ ! -x .venv/bin/python ]; then
    python3 -m venv .venv
fi
.venv/bin/python -m pip install --quiet --disable-pip-version-check -r tests/requirements.txt
# ecospy's wheel ships the `ecos` and `proxyfmu` executables without the executable bit.
ecospy_binaries="$(.venv/bin/python -c 'import importlib.util, pathlib; print(pathlib.Path(importlib.util.find_spec("ecospy").origin).parent / "binaries")')"
chmod +x "$ecospy_binaries/ecos" "$ecospy_binaries/proxyfmu"

echo "== Python tests (fmpy, fmutool)"
python_status=0
.venv/bin/python -m pytest -q tests/python || python_status=$?

valgrind_status=0
wait "$valgrind_pid" || valgrind_status=$?
trap - EXIT
echo "== valgrind memcheck output (tests/valgrind.sh, exit status $valgrind_status)"
cat target/valgrind.log
if [ "$python_status" -ne 0 ] || [ "$valgrind_status" -ne 0 ]; then
    echo "FAILED: Python tests exit status $python_status, valgrind exit status $valgrind_status"
    exit 1
fi
