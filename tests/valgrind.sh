#!/usr/bin/env bash
# Memory check of the native FMI host against every dist/*.fmu (FMI 2.0) and dist/fmi3/*.fmu
# (FMI 3.0, the same binaries through their fmi3 functions) under valgrind memcheck: zero
# errors (invalid reads/writes, uses of uninitialised values, bad frees) and zero bytes
# definitely or indirectly lost. Run by ./test.sh after the Rust tests (which build the
# binaries used here); installs valgrind with apt if it is missing.
#   1. 1000 instantiate/initialize/step/state/free cycles per FMU through FMI 2.0, 200 through
#      FMI 3.0 (tests/examples/lifecycle_cycles.rs)
#   2. the host tests every_fmu (default experiment, replay, serialization, reset) and
#      parameter_ranges through FMI 2.0; through FMI 3.0 every_fmu's serialization test and the
#      refused instantiations (wrong instantiationToken, Scheduled Execution: NULL, with a message);
#      a short run of the random call sequences (fuzz_calls: 180 sequences, half through each
#      version, with short communication steps: under valgrind only the memory handling matters,
#      not long integrations) and fuzz_calls' corrupted serialized states through FMI 2.0.
# (Under valgrind an instance costs ~50 ms: the FMI 3.0 additions are kept to ~1.5 min.)
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
echo "-- valgrind: lifecycle_cycles 1000 (FMI 2.0)"
FMI_VERSIONS=2 memcheck target/release/examples/lifecycle_cycles 1000
echo "-- valgrind: lifecycle_cycles 200 (FMI 3.0)"
FMI_VERSIONS=3 memcheck target/release/examples/lifecycle_cycles 200
for t in every_fmu parameter_ranges; do
    echo "-- valgrind: $t (FMI 2.0)"
    FMI_VERSIONS=2 memcheck "$(test_binary "$t")" --test-threads=1 -q
done
echo "-- valgrind: every_fmu (FMI 3.0: serialized state, refused instantiations)"
FMI_VERSIONS=3 memcheck "$(test_binary every_fmu)" --test-threads=1 -q \
    a_serialized_state_continues_bit_identically_in_a_fresh_instance fmi3_instantiation_refusals_return_null_with_a_message
echo "-- valgrind: fuzz_calls (180 sequences, 90 per FMI version, communication steps <= 1 ms)"
FUZZ_CASES=180 FUZZ_SHORT_STEPS=1 FUZZ_THREADS=1 memcheck "$(test_binary fuzz_calls)" --test-threads=1 -q \
    random_call_sequences_never_crash_hang_or_fail_silently
echo "-- valgrind: fuzz_calls' corrupted serialized states (FMI 2.0)"
FMI_VERSIONS=2 memcheck "$(test_binary fuzz_calls)" --test-threads=1 -q corrupted_serialized_states_are_refused
echo "valgrind: 0 errors, 0 bytes lost"
