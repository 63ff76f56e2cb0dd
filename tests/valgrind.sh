#!/usr/bin/env bash
# Memory check of the native FMI host against every dist/*.fmu under valgrind memcheck: zero
# errors (invalid reads/writes, uses of uninitialised values, bad frees) and zero bytes
# definitely or indirectly lost. Run by ./test.sh after the Rust tests (which build the
# binaries used here); installs valgrind with apt if it is missing.
#   1. 1000 instantiate/initialize/step/state/free cycles per FMU (tests/examples/lifecycle_cycles.rs)
#   2. the host tests every_fmu (default experiment, replay, serialization, reset) and
#      parameter_ranges, and a short run of the random call sequences (fuzz_calls, with short
#      communication steps: under valgrind only the memory handling matters, not long integrations).
set -euo pipefail
cd "$(dirname "$0")/.."

if ! command -v valgrind >/dev/null; then
    if ! DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends valgrind; then
        apt-get update
        DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends valgrind
    fi
fi

memcheck() {
    valgrind --quiet --leak-check=full --show-leak-kinds=definite,indirect --errors-for-leak-kinds=definite,indirect --error-exitcode=1 "$@"
}

# The test executables cargo built for `cargo test --release` (the newest of each name).
test_binary() {
    cargo test --release -p fmi-host --test "$1" --no-run --message-format=json 2>/dev/null \
        | sed -n 's/.*"executable":"\([^"]*\)".*/\1/p' | tail -1
}

cargo build --release -p fmi-host --example lifecycle_cycles
echo "-- valgrind: lifecycle_cycles 1000"
memcheck target/release/examples/lifecycle_cycles 1000
for t in every_fmu parameter_ranges; do
    echo "-- valgrind: $t"
    memcheck "$(test_binary "$t")" --test-threads=1 -q
done
echo "-- valgrind: fuzz_calls (180 sequences, communication steps <= 1 ms)"
FUZZ_CASES=180 FUZZ_SHORT_STEPS=1 FUZZ_THREADS=1 memcheck "$(test_binary fuzz_calls)" --test-threads=1 -q
echo "valgrind: 0 errors, 0 bytes lost"
