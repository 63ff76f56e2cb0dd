#!/usr/bin/env bash
# The benchmark of issue 11 in one command (see BENCHMARKS.md):
#   bench/run.sh [--repeats N]
# 1. builds every FMU into dist/ and the benchmark crates (bench/harness, bench/empty-step,
#    bench/null-fmu) in release, and zips the two floor FMUs into target/bench/;
# 2. makes .venv (tests/requirements.txt + bench/requirements.txt, pinned) unless it is there;
# 3. runs bench/run.py: builds the pythonfmu FMU, runs the native host (fmu-bench), fmpy, scipy
#    and the allocation count, and writes target/bench/results.md (the tables of BENCHMARKS.md).
#
#   bench/run.sh --chain [--sizes 10,100,1000] [--rev HEAD] [--repeats N]
# runs the size benchmark of issue 25 instead (bench/chain.py: the torsional chain at N = 10,
# 100, 1000 and 10000 inertias, explicit and stiff, against scipy; writes target/bench/chain.md).
# It builds build-fmus and fmu-bench only (the chain's copies are built by bench/chain.py).
# Not part of ./test.sh: speed is never asserted by a test.
set -euo pipefail
cd "$(dirname "$0")/.."

if [ "${1:-}" = "--chain" ]; then
    shift
    echo "== build (release): build-fmus, fmu-bench"
    cargo build --release -p build-fmus -p fmu-bench
    if [ ! -x .venv/bin/python ]; then
        python3 -m venv .venv
    fi
    .venv/bin/python -m pip install --quiet --disable-pip-version-check -r tests/requirements.txt -r bench/requirements.txt
    echo "== torsional chain (bench/chain.py)"
    exec .venv/bin/python bench/chain.py "$@"
fi

echo "== build (release)"
cargo run --release -p build-fmus
cargo build --release -p fmu-bench -p empty-step -p null-fmu
target_dir="${CARGO_TARGET_DIR:-target}"
mkdir -p target/bench
"$target_dir/release/fmu-bench" package-floors --empty-step "$target_dir/release/libempty_step.so" \
    --null-step "$target_dir/release/libNullStep.so" --out target/bench

echo "== Python environment (.venv)"
if [ ! -x .venv/bin/python ]; then
    python3 -m venv .venv
fi
.venv/bin/python -m pip install --quiet --disable-pip-version-check -r tests/requirements.txt -r bench/requirements.txt

echo "== benchmark"
.venv/bin/python bench/run.py "$@"
