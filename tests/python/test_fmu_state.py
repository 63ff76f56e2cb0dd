"""FMU state handling of RlcCircuit (canGetAndSetFMUstate, canSerializeFMUstate) through
fmpy.fmi2.FMU2Slave directly.

Reference: FMI 2.0 §2.1.8. An FMU state holds everything the FMU needs to continue ("continuous-time
states, discrete-time states, iteration variables, parameter values, input values, ... and FMU internal
status information"), so continuing from a restored state must reproduce the uninterrupted run of the
same FMU BIT FOR BIT (same binary, same arithmetic, same inputs). The reference of these tests is that
uninterrupted run; no physical values are involved.
"""

from __future__ import annotations

import shutil

import numpy as np
import pytest
from fmpy import extract
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import fmi2Error, fmi2FMUstate

from fmi_host import Slave

H = 1e-4  # communication step
N = 200  # steps: T = 0.02 s, inside the transient (which lasts ~10 ms), so the states are far from trivial
HALF = N // 2
U_IN_FIRST, U_IN_LATER, K_SWITCH = 1.5, 3.0, 3 * N // 4  # the input schedule: u_in changes at 3T/4


@pytest.fixture
def unzipdir(rlc_fmu):
    """One extraction shared by all instances of a test (as a master instantiating one FMU twice)."""
    d = extract(str(rlc_fmu))
    yield d
    shutil.rmtree(d, ignore_errors=True)


def real_names(s: Slave) -> list[str]:
    return [v.name for v in s.md.modelVariables if v.type == "Real"]


def snapshot(s: Slave) -> np.ndarray:
    """All Real variables (parameters, input, states, derivatives, outputs) at the current point."""
    return np.array(s.get(*real_names(s)), dtype=np.float64)


def run(s: Slave, k_from: int, k_to: int) -> np.ndarray:
    """Steps k_from..k_to-1 with the input schedule; returns the snapshots after each step."""
    rows = []
    for k in range(k_from, k_to):
        s.set(u_in=U_IN_FIRST if k < K_SWITCH else U_IN_LATER)
        s.do_step(k * H, H)
        rows.append(snapshot(s))
    return np.array(rows)


def assert_bit_identical(a: np.ndarray, b: np.ndarray, what: str, slave: Slave):
    """a and b: snapshots (1-D) or runs of snapshots (2-D, one row per step) of `slave`'s Real variables."""
    names = real_names(slave)
    assert a.shape == b.shape, what
    if a.tobytes() != b.tobytes():
        diff = np.argwhere(a.view(np.uint64) != b.view(np.uint64))
        lines = []
        for idx in diff[:6]:
            idx = tuple(idx)
            step = f"step {idx[0]}, " if a.ndim == 2 else ""
            lines.append(f"  {step}{names[idx[-1]]}: {float(a[idx])!r} != {float(b[idx])!r}")
        pytest.fail(f"{what}: not bit-identical ({len(diff)} values differ), first ones:\n" + "\n".join(lines))


def started(rlc_fmu, unzipdir, name, **start_values) -> Slave:
    s = Slave(rlc_fmu, instance_name=name, unzipdir=unzipdir)
    s.instantiate()
    s.initialize(start_time=0.0, start_values=start_values)
    return s


def test_get_set_state_replays_bit_identically(rlc_fmu, unzipdir):
    with started(rlc_fmu, unzipdir, "a") as s:
        run(s, 0, HALF)
        at_half = snapshot(s)
        state = s.fmu.getFMUstate()
        assert state.value, "fmi2GetFMUstate returned a NULL state"

        first = run(s, HALF, N)  # reference: the uninterrupted run from T/2 to T (u_in switches to 3.0)
        assert not np.array_equal(first[0], first[-1]), "the run is trivial"

        s.fmu.setFMUstate(state)
        # the restored state includes the input value (1.5), not the 3.0 set after the state was taken
        assert_bit_identical(snapshot(s), at_half, "all Real variables right after fmi2SetFMUstate", s)
        assert s.get("u_in")[0] == U_IN_FIRST

        second = run(s, HALF, N)
        assert_bit_identical(second, first, "replay from the restored state", s)

        # a state can be set more than once
        s.fmu.setFMUstate(state)
        assert_bit_identical(run(s, HALF, N), first, "second replay from the same state", s)

        s.fmu.freeFMUstate(state)
        assert state.value is None, "fmi2FreeFMUstate must return a NULL pointer in its argument"
        s.fmu.freeFMUstate(state)  # freeing a NULL state is ignored (FMI 2.0 §2.1.8)


def test_get_state_into_existing_state(rlc_fmu, unzipdir):
    # FMI 2.0 §2.1.8: if *FMUstate is not NULL on entry, fmi2GetFMUstate copies into the existing state
    with started(rlc_fmu, unzipdir, "a") as s:
        run(s, 0, HALF)
        state = s.fmu.getFMUstate()
        pointer = state.value
        run(s, HALF, K_SWITCH)
        at_switch = snapshot(s)
        s.get_state_into(state)
        assert state.value == pointer, "the existing state was not reused"
        first = run(s, K_SWITCH, N)
        s.fmu.setFMUstate(state)
        assert_bit_identical(snapshot(s), at_switch, "restored state taken into an existing state", s)
        assert_bit_identical(run(s, K_SWITCH, N), first, "replay", s)
        s.fmu.freeFMUstate(state)


@pytest.mark.parametrize(
    "other_start",
    [{}, {"frequency": 500.0, "R_load": 20.0, "u_C": 1.0}],
    ids=["same-start", "other-parameters"],
)
def test_serialized_state_continues_in_fresh_instance(rlc_fmu, unzipdir, other_start):
    # reference: instance A's own continuation. B is a fresh instance (initialized with the defaults or
    # with other parameters and states: parameter values are part of the FMU state, FMI 2.0 §2.1.8).
    with started(rlc_fmu, unzipdir, "a") as a, started(rlc_fmu, unzipdir, "b", **other_start) as b:
        run(a, 0, HALF)
        at_half = snapshot(a)
        state_a = a.fmu.getFMUstate()
        data = a.fmu.serializeFMUstate(state_a)
        assert isinstance(data, bytes) and len(data) > 0

        state_b = b.fmu.deSerializeFMUstate(data)
        assert state_b.value, "fmi2DeSerializeFMUstate returned a NULL state"
        b.fmu.setFMUstate(state_b)
        assert_bit_identical(snapshot(b), at_half, "B right after setting A's deserialized state", b)

        assert_bit_identical(run(b, HALF, N), run(a, HALF, N), "A and B continued from the same state", b)

        a.fmu.freeFMUstate(state_a)
        b.fmu.freeFMUstate(state_b)
        assert state_a.value is None and state_b.value is None


def _flip(data: bytes, index: int, bit: int) -> bytes:
    b = bytearray(data)
    b[index] ^= 1 << bit
    return bytes(b)


CORRUPTIONS = {
    "flip-first-byte": lambda d: _flip(d, 0, 0),
    "flip-middle-byte": lambda d: _flip(d, len(d) // 2, 3),
    "flip-last-byte": lambda d: _flip(d, len(d) - 1, 7),
    "truncate-1": lambda d: d[:-1],
    "truncate-half": lambda d: d[: len(d) // 2],
    "empty": lambda d: b"",
}


@pytest.mark.parametrize("corruption", list(CORRUPTIONS))
def test_corrupted_serialized_state_is_rejected(rlc_fmu, unzipdir, corruption):
    # reference: a corrupted buffer is not a state this FMU produced, so fmi2DeSerializeFMUstate must
    # return fmi2Error (not fmi2Fatal: the instance stays usable), and a good state still works afterwards,
    # reproducing the uninterrupted continuation bit for bit.
    with started(rlc_fmu, unzipdir, "a") as s:
        run(s, 0, HALF)
        at_half = snapshot(s)
        good = s.fmu.getFMUstate()
        data = s.fmu.serializeFMUstate(good)
        first = run(s, HALF, N)

        bad = CORRUPTIONS[corruption](data)
        assert bad != data
        bad_state = fmi2FMUstate()
        with pytest.raises(FMICallException) as info:
            s.fmu.deSerializeFMUstate(bad, bad_state)
        assert info.value.status == fmi2Error, f"expected fmi2Error, got status {info.value.status}"

        s.fmu.setFMUstate(good)
        assert_bit_identical(snapshot(s), at_half, "after a rejected deserialization, setFMUstate(good)", s)
        assert_bit_identical(run(s, HALF, N), first, "continuation after the rejected deserialization", s)

        # the good bytes still deserialize in the same instance
        again = s.fmu.deSerializeFMUstate(data)
        s.fmu.setFMUstate(again)
        assert_bit_identical(run(s, HALF, N), first, "continuation from the good bytes", s)

        s.fmu.freeFMUstate(good)
        s.fmu.freeFMUstate(again)
        if bad_state.value:  # not expected, but do not leak it
            s.fmu.freeFMUstate(bad_state)
