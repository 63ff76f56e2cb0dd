"""A model of any size (issue 25): the torsional chain at N = 1000 inertias, built as a user builds it.

bench/torsional-chain (the size benchmark's model, a standalone crate: N inertias joined by N - 1
elastic damped shafts, 2N - 1 states named with FMI's structured names w[i] and theta[i]) is copied
outside the workspace with N = 1000 (src/size.rs) and its path dependencies made absolute, then
built with the CI build's `build-fmus build <dir>`, sharing its cargo target directory and the
workspace's Cargo.lock, so that the runtime's dependencies are not compiled again: the build takes
8 s when only the chain crate is compiled, 17 s when the runtime changed (fmu-runtime and
components are compiled once more, for a crate outside the workspace), and the whole module 22 s
and 31 s (2 cores). The FMUs
(FMI 2.0 and FMI 3.0) must pass fmpy's validation with zero findings, and their ModelStructure must
be exactly the band structure derived below from the chain's equations, written out here
independently of the model's code:

    J dw_1/dt = T_drive(t) - T_1
    J dw_i/dt = T_{i-1} - T_i                  (1 < i < N)
    J dw_N/dt = T_{N-1} - c_load w_N
    dtheta_i/dt = w_i - w_{i+1},   T_i = K theta_i + D (w_i - w_{i+1})
    T_drive(t) = drive_torque for t >= step_time, else 0;   w_first = w_1,  w_last = w_N
"""

from __future__ import annotations

import shutil
import time
from pathlib import Path

import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.validation import validate_fmu

from conftest import REPO_ROOT, assert_fmutool_clean, build_fmus

CHAIN = REPO_ROOT / "bench" / "torsional-chain"
N = 1000


@pytest.fixture(scope="module")
def chain_fmus(tmp_path_factory) -> dict[str, Path]:
    """The chain at N = 1000, built outside the workspace: {"2.0": FMU, "3.0": FMU}."""
    work = tmp_path_factory.mktemp("chain")
    assert not work.resolve().is_relative_to(REPO_ROOT), "the test must build outside the workspace"
    crate = work / "torsional-chain"
    shutil.copytree(CHAIN, crate, ignore=shutil.ignore_patterns("target", "Cargo.lock"))
    (crate / "src" / "size.rs").write_text(f"//! The chain's size, written by tests/python/test_chain.py.\n\npub const INERTIAS: usize = {N};\n")
    manifest = crate / "Cargo.toml"
    text = manifest.read_text()
    for dependency in ("fmu-runtime", "models/components"):
        relative = f'path = "../../{dependency}"'
        assert text.count(relative) == 1, text
        text = text.replace(relative, f'path = "{REPO_ROOT / dependency}"')
    manifest.write_text(text)
    # As `build-fmus new` does: the workspace's versions of every dependency, so that the shared
    # target directory's compiled dependencies are reused (and nothing is resolved afresh).
    shutil.copyfile(REPO_ROOT / "Cargo.lock", crate / "Cargo.lock")
    started = time.perf_counter()
    built = build_fmus("build", ".", cwd=crate)
    seconds = time.perf_counter() - started
    assert built.returncode == 0, f"build-fmus build failed:\n{built.stdout}\n{built.stderr}"
    compiled = [line.split()[1] for line in built.stderr.splitlines() if line.strip().startswith("Compiling ")]
    print(f"torsional chain, N = {N}: build-fmus build took {seconds:.1f} s, compiling {', '.join(compiled) or 'nothing'}\n{built.stdout}")
    fmus = {"2.0": crate / "dist" / "TorsionalChain.fmu", "3.0": crate / "dist" / "fmi3" / "TorsionalChain.fmu"}
    for fmu in fmus.values():
        assert fmu.is_file(), built.stdout
    return fmus


def expected_structure() -> dict[str, list[tuple[str, set[str]]]]:
    """The ModelStructure of the chain's equations (module docstring), each list in FMI's order
    (value references: the parameters, w[i] and der(w[i]) in turn, theta[i] and der(theta[i]), the
    outputs): (unknown, the knowns it depends on).

    While the model runs the knowns are the states (no inputs). At initialization they are also the
    parameters, each derivative taking those its equation multiplies or adds: J, and K and D through
    the shaft torques; c_load for the last inertia; drive_torque for the first, as the drive torque
    is on at the time the runtime probes the equations (0.2508 s, past step_time = 0.1 s). step_time
    itself is in no list: it moves T_drive only across the time event, which no perturbation of it
    at that time crosses (a switch in time, where the FMU stops its solver, not a dependency it
    probes)."""
    w = lambda i: f"w[{i}]"  # noqa: E731
    theta = lambda i: f"theta[{i}]"  # noqa: E731
    speed_rates, twist_rates = [], []
    for i in range(1, N + 1):
        states = {w(j) for j in (i - 1, i, i + 1) if 1 <= j <= N} | {theta(j) for j in (i - 1, i) if 1 <= j <= N - 1}
        speed_rates.append((f"der({w(i)})", states))
    for i in range(1, N):
        twist_rates.append((f"der({theta(i)})", {w(i), w(i + 1)}))
    outputs = [("w_first", {w(1)}), ("w_last", {w(N)})]

    def at_initialization(name: str, states: set[str]) -> set[str]:
        if not name.startswith("der(w["):
            return states
        i = int(name[len("der(w[") : -len("])")])
        return states | {"J", "K", "D"} | ({"drive_torque"} if i == 1 else set()) | ({"c_load"} if i == N else set())

    derivatives = speed_rates + twist_rates
    # The initial unknowns, in value-reference order: every derivative (each is calculated), then
    # the outputs (the states have start values, so they are no unknowns).
    initial = [(name, at_initialization(name, deps)) for name, deps in derivatives] + outputs
    return {"outputs": outputs, "derivatives": derivatives, "initialUnknowns": initial}


def structure_of(fmu: Path) -> dict[str, list[tuple[str, set[str] | None]]]:
    md = read_model_description(str(fmu))
    listed = lambda unknowns: [  # noqa: E731
        (u.variable.name, None if u.dependencies is None else {d.name for d in u.dependencies}) for u in unknowns
    ]
    return {"outputs": listed(md.outputs), "derivatives": listed(md.derivatives), "initialUnknowns": listed(md.initialUnknowns)}


@pytest.mark.parametrize("version", ["2.0", "3.0"])
def test_the_chain_validates_with_structured_names(chain_fmus, version):
    fmu = chain_fmus[version]
    problems = validate_fmu(str(fmu))
    assert problems == [], f"fmpy validate_fmu({fmu}) found {len(problems)} problem(s):\n" + "\n".join(f"  - {p}" for p in problems[:20])
    md = read_model_description(str(fmu))
    assert md.fmiVersion == version and md.variableNamingConvention == "structured"
    names = {v.name for v in md.modelVariables}
    assert {"w[1]", f"w[{N}]", "der(w[1])", "theta[1]", f"theta[{N - 1}]", f"der(theta[{N - 1}])"} <= names
    states = [v for v in md.modelVariables if v.name.startswith(("w[", "theta["))]
    assert len(states) == 2 * N - 1
    if version == "2.0":
        assert_fmutool_clean(fmu)


@pytest.mark.parametrize("version", ["2.0", "3.0"])
def test_the_chain_s_model_structure_is_its_band_structure(chain_fmus, version):
    found, expected = structure_of(chain_fmus[version]), expected_structure()
    for kind in ("outputs", "derivatives", "initialUnknowns"):
        got, want = found[kind], expected[kind]
        assert [name for name, _ in got] == [name for name, _ in want], f"{kind}: the unknowns or their order differ"
        wrong = [(name, deps, dict(want)[name]) for name, deps in got if deps != dict(want)[name]]
        assert not wrong, f"{kind}: {len(wrong)} unknown(s) with other dependencies, (unknown, found, expected): {wrong[:5]}"


@pytest.mark.parametrize("version", ["2.0", "3.0"])
def test_the_chain_instantiates_and_steps_past_its_torque_step(chain_fmus, version):
    """The packaged token is the one the binary accepts, and the drive torque moves the chain."""
    result = simulate_fmu(str(chain_fmus[version]), stop_time=0.12, output_interval=0.01, output=["w_first", "w_last"])
    assert result["w_first"][0] == 0.0 and result["w_first"][-1] > 0.0, result
