"""The size benchmark of issue 25 ("Models of any size"): the torsional chain at N = 10, 100,
1 000 and 10 000 inertias (2N - 1 states), explicit and stiff (implicit), against scipy.

    bench/run.sh --chain [--sizes 10,100,1000] [--rev HEAD] [--repeats 5]
    .venv/bin/python bench/chain.py [same options]      (after cargo build --release -p build-fmus -p fmu-bench)

For each size N it
  1. writes a copy of bench/torsional-chain with `INERTIAS = N` (src/size.rs) into
     target/bench/chain/<source>/n<N>-explicit/, and a second copy whose info() declares
     `Solver::ImplicitRungeKutta` (n<N>-implicit/); each copy is its own crate
     (torsional-chain-n<N>-<variant>, path dependencies on the runtime's fmu-runtime and
     models/components), built with one shared CARGO_TARGET_DIR (target/bench/chain/cargo-target:
     the dependencies compile once, in a warm-up build of N = 2 that is not timed);
  2. times `build-fmus build <copy> --out <copy>/dist` (wall; the crate itself is recompiled at
     every run: its src/lib.rs is touched), and, in a fresh process, what build-fmus calls in the
     library to package it (`fmu-bench chain-describe`: the description and its dependency probe),
     so that build = description + probe, and the rest (compile, link, package);
  3. runs `fmu-bench chain` (bench/harness/src/chain.rs) on the FMI 2.0 FMU in a fresh process:
     first and second instantiation (fmi2Instantiate + setup + enter/exit initialization), heap and
     RSS per instance, the full Jacobian by directional derivatives (one column per state), the
     sparse Jacobian by colored directional derivatives (the states colored by the Derivatives'
     dependencies in the ModelStructure, one call per color, checked against the former), doStep
     cost over 1 s at 1 ms (CPU time of the thread, median), and one recorded run (the speeds of
     all inertias on the 1 ms grid);
       - explicit: the model's defaults (J = 1, K = 1e4, D = 1: non-stiff), default tolerance;
       - stiff: J = 1e-4, K = 1e5, D = 10 (STIFF below) with the implicit copy, at the default
         tolerance, else at the first of 1e-7, 1e-6, 1e-5 that steps through the second; if none
         does, the same with a third copy whose torque step is written `t > step_time` instead of
         the crate's `t >= step_time` (n<N>-implicit-gt/; issue 25: the implicit method fails at the
         declared time event); the choice made at the smallest size holds for the larger ones
         (`--stiff VARIANT:RTOL` sets it); our FMU steps the stiff chain up to --stiff-max (10000);
     a stepping run that would exceed --step-budget seconds of CPU is cut there and extrapolated
     from its mean per doStep (marked "extrapolated" with the number of doSteps measured); the
     Jacobian likewise (--jacobian-budget);
  4. solves the same equations (numpy, vectorized) with scipy's solve_ivp, restarted at step_time:
     RK45 for the explicit chain, BDF and Radau with `jac_sparsity` (the banded pattern, as a
     scipy.sparse matrix) for the stiff one, each at the loosest rtol in 1e-3 ... 1e-12 whose error
     is at or below ours (atol = 1e-3 rtol x nominal, our runtime's rule); CPU time of the whole
     second, per communication step; ours / scipy.
Accuracy: the speeds of all N inertias on the 1 ms grid against a reference (DOP853 at rtol 1e-12
for the explicit chain, Radau at rtol 1e-10 with the exact sparse Jacobian for the stiff one),
max |w - w_ref| in % of max |w_ref|; the reference is itself checked against the exact solution
(matrix exponential of the linear system, restarted at step_time) for N <= 100.
Also: the growth exponents (log-log slopes against N between consecutive sizes), and the
directional derivatives against the exact Jacobian (the model is linear).

The states are found from the modelDescription (its Derivatives and their `derivative`
attributes; speeds are the states in rad/s, in declaration order), never by name.

Writes target/bench/chain.md (the tables of BENCHMARKS.md's section on issue 25) and
target/bench/chain.json, and prints the tables.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import re
import resource
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import scipy
import scipy.sparse as sp
from scipy.integrate import solve_ivp

ROOT = Path(__file__).resolve().parent.parent
CHAIN = ROOT / "target" / "bench" / "chain"
SIZES = [10, 100, 1000, 10000]
#: The stiff chain: small inertias, stiff and strongly damped shafts (the other parameters at
#: the model's defaults: c_load 1, drive_torque 100, step_time 0.1).
STIFF = {"J": 1e-4, "K": 1e5, "D": 10.0}
PARAMETERS = ["J", "K", "D", "c_load", "drive_torque", "step_time"]
#: The FMUs' relative tolerance when none is given (fmu-runtime's DEFAULT_RELATIVE_TOLERANCE).
DEFAULT_RTOL = 1e-8
#: Tolerances tried in turn for the stiff chain when the default fails.
STIFF_FALLBACK = [1e-7, 1e-6, 1e-5]
ABSOLUTE_PER_RELATIVE = 1e-3
SCIPY_RTOLS = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12]
#: The torque step as the chain writes it, and the strict form the stiff chain falls back to when
#: the implicit method fails at the declared time event (issue 25: `t >= t_step` fails there
#: with "Step size is too small", `t > t_step` works).
STEP_AS_WRITTEN = "k.time() >= k[self.step_time]"
STEP_STRICT = "k.time() > k[self.step_time]"
#: The stiff chain's copies, tried in this order: as written, then with the strict step.
STIFF_VARIANTS = ["implicit", "implicit-gt"]
REF = {"explicit": ("DOP853", 1e-12), "stiff": ("Radau", 1e-10)}


def log(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def sh(cmd, **kw) -> str:
    return subprocess.run([str(c) for c in cmd], check=True, capture_output=True, text=True, **kw).stdout


# ---------------------------------------------------------------- the copies and their builds
def runtime_source(rev: str | None) -> tuple[Path, str]:
    """The tree whose fmu-runtime, models/components and bench/torsional-chain the copies use:
    the working tree, or `git archive <rev>` unpacked into target/bench/chain/src-<sha> (the
    repository itself is not touched)."""
    if rev is None:
        return ROOT, "worktree"
    sha = sh(["git", "-C", ROOT, "rev-parse", "--short", rev]).strip()
    src = CHAIN / f"src-{sha}"
    if not (src / "fmu-runtime" / "Cargo.toml").is_file():
        src.mkdir(parents=True, exist_ok=True)
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", sha], check=True, capture_output=True).stdout
        subprocess.run(["tar", "-x", "-C", str(src)], input=archive, check=True)
    return src, f"rev-{sha}"


def write_if_changed(path: Path, text: str) -> None:
    if not path.is_file() or path.read_text() != text:
        path.write_text(text)


def make_copy(src: Path, tag: str, n: int, variant: str) -> Path:
    """target/bench/chain/<tag>/n<N>-<variant>/: the chain crate with INERTIAS = n, its own
    package name, absolute path dependencies, and (implicit) the implicit solver."""
    template = src / "bench" / "torsional-chain"
    crate = CHAIN / tag / f"n{n}-{variant}"
    (crate / "src").mkdir(parents=True, exist_ok=True)
    name = f"torsional-chain-n{n}-{variant}"
    toml = (template / "Cargo.toml").read_text()
    toml = re.sub(r'(?m)^name = "torsional-chain"$', f'name = "{name}"', toml, count=1)
    toml = re.sub(r'(?m)^name = "torsional_chain"$', f'name = "{name.replace("-", "_")}"', toml, count=1)
    toml = toml.replace('path = "../../fmu-runtime"', f'path = "{src / "fmu-runtime"}"')
    toml = toml.replace('path = "../../models/components"', f'path = "{src / "models" / "components"}"')
    assert name in toml and str(src / "fmu-runtime") in toml, "bench/torsional-chain/Cargo.toml changed its layout"
    write_if_changed(crate / "Cargo.toml", toml)
    lock = ROOT / "bench" / "torsional-chain" / "Cargo.lock"
    if lock.is_file() and not (crate / "Cargo.lock").is_file():
        shutil.copy(lock, crate / "Cargo.lock")
    lib = (template / "src" / "lib.rs").read_text()
    if variant.startswith("implicit"):
        assert lib.count("Solver::ExplicitRungeKutta") == 1, "the chain's info() no longer declares Solver::ExplicitRungeKutta"
        lib = lib.replace("Solver::ExplicitRungeKutta", "Solver::ImplicitRungeKutta")
    if variant == "implicit-gt":
        assert lib.count(STEP_AS_WRITTEN) == 1, f"the chain's torque step is no longer written `{STEP_AS_WRITTEN}`"
        lib = lib.replace(STEP_AS_WRITTEN, STEP_STRICT)
    write_if_changed(crate / "src" / "lib.rs", lib)
    size = (template / "src" / "size.rs").read_text()
    size, count = re.subn(r"pub const INERTIAS: usize = \d+;", f"pub const INERTIAS: usize = {n};", size)
    assert count == 1, "bench/torsional-chain/src/size.rs no longer declares `pub const INERTIAS: usize`"
    write_if_changed(crate / "src" / "size.rs", size)
    return crate


def target_dir() -> Path:
    return CHAIN / "cargo-target"


def build(crate: Path, release: Path) -> dict:
    """`build-fmus build <crate>` (the crate recompiled: src/lib.rs touched); wall and CPU s."""
    (crate / "src" / "lib.rs").touch()
    env = dict(os.environ, CARGO_TARGET_DIR=str(target_dir()))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    began = time.perf_counter()
    proc = subprocess.run([str(release / "build-fmus"), "build", str(crate), "--out", str(crate / "dist")],
                          env=env, capture_output=True, text=True)
    wall = time.perf_counter() - began
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        raise RuntimeError(f"build-fmus build {crate} failed:\n{proc.stdout}\n{proc.stderr}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return {"wall_s": wall, "cpu_s": cpu, "output": proc.stdout.strip().splitlines()[-1:]}


def library(crate: Path) -> Path:
    name = "lib" + crate.name.replace("-", "_")
    toml = (crate / "Cargo.toml").read_text()
    lib_name = re.search(r'(?m)^name = "(torsional_chain[^"]*)"', toml).group(1)
    for triple_dir in ("x86_64-unknown-linux-gnu/release", "release"):
        path = target_dir() / triple_dir / f"lib{lib_name}.so"
        if path.is_file():
            return path
    raise FileNotFoundError(f"{name}: no library in {target_dir()}")


# ---------------------------------------------------------------- the FMU's side
class Layout:
    """The chain as the FMU declares it: states in the order of <Derivatives>, which of them
    are the speeds (rad/s, in declaration order) and the twists (rad), the nominals, and the
    parameters' start values."""

    def __init__(self, fmu: Path):
        from fmpy import read_model_description
        md = read_model_description(str(fmu))
        self.states = [d.variable.derivative for d in md.derivatives]
        self.nominal = np.array([float(s.nominal) if s.nominal is not None else 1.0 for s in self.states])
        order = {id(v): i for i, v in enumerate(md.modelVariables)}
        speeds = sorted((s for s in self.states if s.unit == "rad/s"), key=lambda s: order[id(s)])
        twists = sorted((s for s in self.states if s.unit == "rad"), key=lambda s: order[id(s)])
        self.n = len(speeds)
        assert len(twists) == self.n - 1 and len(self.states) == 2 * self.n - 1, \
            f"{fmu}: {len(speeds)} states in rad/s and {len(twists)} in rad of {len(self.states)}: not the chain"
        # The i in each name, where there is one, must follow the declaration order (a loose
        # check of the inertias' order, whatever the naming: w_3 or w[3]).
        for k, s in enumerate(speeds):
            digits = re.findall(r"\d+", s.name)
            assert not digits or int(digits[-1]) == k + 1, f"speed {s.name} is the {k + 1}-th declared"
        self.speed_vrs = [s.valueReference for s in speeds]
        # index of each FMU state in the numpy state vector [w_1..w_N, theta_1..theta_{N-1}]
        position = {id(s): k for k, s in enumerate(speeds)}
        position.update({id(s): self.n + k for k, s in enumerate(twists)})
        self.to_numpy = np.array([position[id(s)] for s in self.states])
        # the numpy state vector's nominals
        self.nominal_numpy = np.empty(2 * self.n - 1)
        self.nominal_numpy[self.to_numpy] = self.nominal
        de = md.defaultExperiment
        self.steps = int(round(float(de.stopTime) / float(de.stepSize)))
        self.step_size = float(de.stepSize)
        values = {v.name: v.start for v in md.modelVariables}
        self.defaults = {p: float(values[p]) for p in PARAMETERS}
        self.guid = md.guid


def run_harness(release: Path, fmu: Path, out: Path, params: dict, tolerance, args, record: Path | None,
                jacobian_out: Path | None, env: dict | None = None) -> dict:
    """`fmu-bench chain` in a process of its own (with `env` added to the environment); its JSON."""
    cmd = [release / "fmu-bench", "chain", "--fmu", fmu, "--out", out, "--repeats", args.repeats,
           "--step-budget", args.step_budget, "--jacobian-budget", args.jacobian_budget,
           "--memory-budget", args.memory_budget]
    for name, value in params.items():
        cmd += ["--real", f"{name}={value!r}"]
    if tolerance is not None:
        cmd += ["--tolerance", repr(tolerance)]
    if record is not None:
        cmd += ["--record", record.with_suffix(".vrs"), "--record-out", record]
    if jacobian_out is not None:
        cmd += ["--jacobian-out", jacobian_out]
    began = time.perf_counter()
    subprocess.run([str(c) for c in cmd], check=True, env=dict(os.environ, **(env or {})))
    result = json.loads(out.read_text())
    result["process_wall_s"] = time.perf_counter() - began
    return result


# ---------------------------------------------------------------- the same equations in numpy
class Chain:
    """dw_1 = (T_drive - T_1)/J, dw_i = (T_{i-1} - T_i)/J, dw_N = (T_{N-1} - c w_N)/J,
    dtheta_i = w_i - w_{i+1}, T_i = K theta_i + D (w_i - w_{i+1}); y = [w_1..w_N, theta_1..]."""

    def __init__(self, n: int, p: dict):
        self.n = n
        self.J, self.K, self.D, self.c = p["J"], p["K"], p["D"], p["c_load"]
        self.torque, self.step_time = p["drive_torque"], p["step_time"]

    def rhs(self, drive):
        n, J, K, D, c = self.n, self.J, self.K, self.D, self.c

        def f(t, y):
            w, th = y[:n], y[n:]
            rate = w[:-1] - w[1:]
            T = K * th + D * rate
            dy = np.empty_like(y)
            dw = dy[:n]
            dw[:] = 0.0
            dw[0] += drive
            dw[:-1] -= T
            dw[1:] += T
            dw[-1] -= c * w[-1]
            dw /= J
            dy[n:] = rate
            return dy
        return f

    def matrix(self) -> sp.csc_matrix:
        """The exact Jacobian A (dy/dt = A y + b)."""
        n, J, K, D, c = self.n, self.J, self.K, self.D, self.c
        rows, cols, vals = [], [], []

        def add(i, j, v):
            rows.append(i), cols.append(j), vals.append(v)
        for i in range(n - 1):
            # T_i = K th_i + D (w_i - w_{i+1}) leaves inertia i and enters inertia i + 1
            for (wi, sign) in ((i, -1.0), (i + 1, 1.0)):
                add(wi, n + i, sign * K / J)
                add(wi, i, sign * D / J)
                add(wi, i + 1, -sign * D / J)
            add(n + i, i, 1.0)
            add(n + i, i + 1, -1.0)
        add(n - 1, n - 1, -c / J)
        return sp.csc_matrix((vals, (rows, cols)), shape=(2 * n - 1, 2 * n - 1))

    def pattern(self) -> sp.csc_matrix:
        m = self.matrix().copy()
        m.data[:] = 1.0
        return m


def grid(steps: int, h: float) -> np.ndarray:
    return np.arange(1, steps + 1) * h


def solve(chain: Chain, method: str, rtol: float, atol, t_grid: np.ndarray, **kw):
    """solve_ivp from rest over [0, step_time] (no torque), then restarted at step_time with the
    torque, output on the grid; (speeds on the grid [steps x N], f-evals)."""
    y0 = np.zeros(2 * chain.n - 1)
    pieces, nfev = [], 0
    stop = float(t_grid[-1])
    for (t0, t1, drive) in ((0.0, chain.step_time, 0.0), (chain.step_time, stop, chain.torque)):
        inside = t_grid[(t_grid > t0) & (t_grid <= t1)]
        t_eval = inside if len(inside) and inside[-1] == t1 else np.append(inside, t1)
        sol = solve_ivp(chain.rhs(drive), (t0, t1), y0, method=method, t_eval=t_eval, rtol=rtol, atol=atol, **kw)
        if not sol.success:
            raise RuntimeError(f"solve_ivp {method} rtol {rtol}: {sol.message}")
        nfev += sol.nfev
        pieces.append(sol.y[:chain.n, :len(inside)].T)
        y0 = sol.y[:, -1]  # where the next stretch starts
    return np.concatenate(pieces), nfev


def exact(chain: Chain, t_grid: np.ndarray) -> np.ndarray:
    """The exact solution on the grid (a linear system with a piecewise-constant input): the
    augmented matrix exponential over one step h, applied step after step (step_time on the
    grid)."""
    from scipy.linalg import expm
    A = chain.matrix().toarray()
    m = A.shape[0]
    h = float(t_grid[1] - t_grid[0])
    b = np.zeros(m)
    b[0] = chain.torque / chain.J
    aug = np.zeros((m + 1, m + 1))
    aug[:m, :m] = A
    aug[:m, m] = b
    E = expm(aug * h)
    Phi, gamma = E[:m, :m], E[:m, m]
    y = np.zeros(m)
    out = np.empty((len(t_grid), chain.n))
    for k, t in enumerate(t_grid):
        t_prev = t - h
        y = Phi @ y + (gamma if t_prev >= chain.step_time - 1e-12 else 0.0)
        out[k] = y[:chain.n]
    return out


def reference(r: dict, case: str, chain: Chain, lay: Layout, t_grid: np.ndarray, n: int) -> np.ndarray:
    """The reference speeds on the grid (REF[case]; Radau with the exact sparse Jacobian),
    checked against the exact solution for N <= 100."""
    method, rtol = REF[case]
    kw = {"jac": chain.matrix()} if method == "Radau" else {}
    began = time.thread_time()
    ref, _ = solve(chain, method, rtol, ABSOLUTE_PER_RELATIVE * rtol * lay.nominal_numpy, t_grid, **kw)
    r[f"ref_{case}"] = {"method": method, "rtol": rtol, "cpu_s": time.thread_time() - began}
    if n <= 100:
        r[f"ref_{case}"]["error_vs_exact_pct"] = error(ref, exact(chain, t_grid))
        log(f"   reference {method} rtol {rtol:.0e} vs the exact solution: {r[f'ref_{case}']['error_vs_exact_pct']:.1e} %")
    return ref


def error(speeds: np.ndarray, ref: np.ndarray | None) -> float | None:
    """max |w - w_ref| over the grid and the inertias, in % of max |w_ref|."""
    if ref is None:
        return None
    return 100.0 * float(np.max(np.abs(speeds - ref))) / float(np.max(np.abs(ref)))


def timed_solve(chain, method, rtol, atol, t_grid, repeats, **kw):
    times = []
    for _ in range(repeats):
        began = time.thread_time()
        speeds, nfev = solve(chain, method, rtol, atol, t_grid, **kw)
        times.append(time.thread_time() - began)
        if times[-1] > 20.0:
            break
    return statistics.median(times), speeds, nfev, len(times)


def sweep(chain, method, ref, ours_err, nominal, t_grid, repeats, rtols, **kw):
    """The loosest rtol whose error is at or below ours (ours_err None: the given rtols' first,
    the caller passes the one matched at a smaller size); its timing and the sweep."""
    entries = []
    for rtol in rtols:
        atol = ABSOLUTE_PER_RELATIVE * rtol * nominal
        began = time.thread_time()
        try:
            speeds, nfev = solve(chain, method, rtol, atol, t_grid, **kw)
        except RuntimeError as e:
            entries.append({"rtol": rtol, "failed": str(e)})
            log(f"   {method} rtol {rtol:.0e}: {e}")
            continue
        seconds = time.thread_time() - began
        e = error(speeds, ref)
        entries.append({"rtol": rtol, "cpu_s": seconds, "error_pct": e, "nfev": nfev})
        log(f"   {method} rtol {rtol:.0e}: {seconds:.3f} s, error {'-' if e is None else f'{e:.2e} %'}, {nfev} f-evals")
        if ours_err is None or e <= ours_err:
            extra = max(0, repeats - 1) if seconds < 20.0 else 0
            times = [seconds] + [timed_solve(chain, method, rtol, atol, t_grid, 1, **kw)[0] for _ in range(extra)]
            return {"method": method, "rtol": rtol, "cpu_s": statistics.median(times), "runs": len(times),
                    "error_pct": e, "nfev": nfev, "matched": ours_err is not None, "sweep": entries}
    return {"method": method, "rtol": None, "cpu_s": entries[-1].get("cpu_s"), "error_pct": entries[-1].get("error_pct"),
            "matched": False, "sweep": entries}


def profile(h: dict, results: dict, n: int) -> None:
    """For a stiff run cut after k doSteps: how the first k doSteps' mean compared with the
    whole run's at the largest smaller size measured in full (the cost per doStep is not flat:
    the first doSteps, at rest, cost the most); h["profile_estimate_us"] is the extrapolation
    scaled by that ratio."""
    k = int(h["steps_done"])
    for m in sorted((m for m in results if m < n), reverse=True):
        full = results[m].get("stiff", {})
        if full.get("step_extrapolated") != "no":
            continue
        c = full["step_checkpoints_steps_cpu_s"]
        steps, cum = np.array(c[::2]), np.array(c[1::2])
        first_run = full["step_cpu_s_all"][0]
        steps, cum = np.append(steps, full["steps"]), np.append(cum, first_run)
        ratio = (np.interp(k, steps, cum) / k) / (first_run / full["steps"])
        h["profile_size"], h["profile_ratio"] = m, float(ratio)
        h["profile_estimate_us"] = h["us_per_step"] / ratio
        log(f"   at N = {m} the first {k} doSteps cost {ratio:.2f}x the run's mean: about {fmt_us(h['profile_estimate_us'])} per doStep")
        return


def scipy_only(r, case, chain, lay, matched_rtol, args, t_grid):
    """scipy at the rtol matched at a smaller size, where our FMU was not run (no reference)."""
    for m_ in ["BDF", "Radau"]:
        rtol = matched_rtol.get((case, m_), 1e-6)
        log(f"   scipy {m_} at rtol {rtol:.0e} (matched at a smaller size)")
        s = sweep(chain, m_, None, None, lay.nominal_numpy, t_grid, min(args.repeats, 3), [rtol], jac_sparsity=chain.pattern())
        s["us_per_step"] = s["cpu_s"] / len(t_grid) * 1e6
        r[f"scipy_{case}_{m_}"] = s


# ---------------------------------------------------------------- report
def slope(sizes, values):
    out = []
    for (n0, v0), (n1, v1) in zip(zip(sizes, values), list(zip(sizes, values))[1:]):
        if v0 and v1 and v0 > 0 and v1 > 0:
            out.append((n0, n1, float(np.log(v1 / v0) / np.log(n1 / n0))))
        else:
            out.append((n0, n1, None))
    return out


def fmt_time(seconds) -> str:
    if seconds is None:
        return "-"
    if seconds >= 1.0:
        return f"{seconds:.3g} s"
    if seconds >= 1e-3:
        return f"{seconds * 1e3:.3g} ms"
    if seconds >= 1e-6:
        return f"{seconds * 1e6:.3g} us"
    return f"{seconds * 1e9:.3g} ns"


def fmt_us(us) -> str:
    return "-" if us is None else fmt_time(us * 1e-6)


def fmt_ratio(ratio) -> str:
    """ours / scipy, and how many times faster or slower that is."""
    if ratio is None:
        return "-"
    times = lambda x: f"{x:.0f}" if x >= 100 else f"{x:.3g}"  # noqa: E731
    return f"{ratio:.3g} ({times(1 / ratio)}x faster)" if ratio < 1 else f"{times(ratio)} ({times(ratio)}x slower)"


def fmt_kb(kb) -> str:
    return "-" if kb is None else (f"{kb / 1024:.3g} MB" if kb >= 1000 else f"{kb:.3g} kB")


def machine() -> str:
    cpu = next((l.split(":", 1)[1].strip() for l in sh(["lscpu"]).splitlines() if l.startswith("Model name")), "?")
    mem_kb = next(int(l.split()[1]) for l in open("/proc/meminfo") if l.startswith("MemTotal"))
    import fmpy
    return (f"{cpu}, {os.cpu_count()} cores, {mem_kb / 1048576:.0f} GiB; {sh(['rustc', '-V']).strip()}; "
            f"Python {platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}, fmpy {fmpy.__version__}")


KINDS = ("dense", "band", "sparse")  # FMU_RUNTIME_JACOBIAN's values


def dense_or_sparse(args) -> None:
    """The stiff chain's us per doStep (1 s at 1 ms, default tolerance, median of --repeats) with
    the Newton matrix dense, as a band (the band LU, what the runtime picks for the chain from
    DENSE_BELOW on) and sparse (faer's sparse LU), at each N of --dense-or-sparse: the measurement
    behind fmu-runtime's `stepper::jacobian::DENSE_BELOW`. Prints a table and writes
    <out>/dense_or_sparse.md."""
    release = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target")) / "release"
    src, tag = runtime_source(args.rev)
    out = Path(args.out)
    (out / "chain").mkdir(parents=True, exist_ok=True)
    head = sh(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"]).strip()
    rows = []
    for n in sorted(int(s) for s in args.dense_or_sparse.split(",") if s.strip()):
        crate = make_copy(src, tag, n, "implicit")
        if not args.no_build:
            build(crate, release)
        fmu = crate / "dist" / "TorsionalChain.fmu"
        us = {}
        for kind in KINDS:
            h = run_harness(release, fmu, out / "chain" / f"dense_or_sparse_n{n}_{kind}.json", dict(STIFF), None, args,
                            None, None, env={"FMU_RUNTIME_JACOBIAN": kind})
            if "error" in h:
                sys.exit(f"N = {n}, {kind}: {h['error'][:300]}")
            us[kind] = h["us_per_step"]
        rows.append((n, 2 * n - 1, us))
        log(f"   N = {n} ({2 * n - 1} states): " + ", ".join(f"{k} {us[k]:.1f} us" for k in KINDS) + " per doStep")
    text = "\n".join([
        f"Stiff torsional chain (J = {STIFF['J']:g}, K = {STIFF['K']:g}, D = {STIFF['D']:g}), implicit method, default "
        f"tolerance, 1 ms doSteps over 1 s, median of {args.repeats}; commit {head}; {machine()}",
        "",
        "| N | states | dense: us per doStep | band: us per doStep | sparse: us per doStep | band / dense | sparse / dense |",
        "| --- | --- | --- | --- | --- | --- | --- |",
        *[f"| {n} | {m} | {u['dense']:.1f} | {u['band']:.1f} | {u['sparse']:.1f} | {u['band'] / u['dense']:.2f} | {u['sparse'] / u['dense']:.2f} |"
          for n, m, u in rows],
        "",
    ])
    (out / "dense_or_sparse.md").write_text(text)
    print(text)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", default=",".join(map(str, SIZES)),
                    help="inertias N, comma-separated (default: 10,100,1000,10000; about 12 min in all at bb1291d, N = 10000 most of it)")
    ap.add_argument("--repeats", type=int, default=5, help="timed doStep runs (median) and scipy repeats (up to 3)")
    ap.add_argument("--rev", default=None,
                    help="build against the runtime of this git revision (git archive into target/bench/chain/src-<sha>) "
                         "instead of the working tree")
    ap.add_argument("--step-budget", type=float, default=60.0, help="CPU s of doSteps per run before extrapolating")
    ap.add_argument("--jacobian-budget", type=float, default=30.0, help="CPU s of Jacobian columns before extrapolating")
    ap.add_argument("--memory-budget", type=float, default=10.0, help="s of instantiation for the memory figure")
    ap.add_argument("--stiff-max", type=int, default=10000,
                    help="largest N whose stiff chain our FMU steps (default 10000; the dense implicit method before "
                         "issue 25 needed 1000: above, hours per doStep; scipy runs at every size)")
    ap.add_argument("--stiff", default=None, metavar="VARIANT:RTOL",
                    help="the stiff chain's copy and tolerance, e.g. implicit-gt:1e-5 (default: the first of "
                         f"{', '.join(STIFF_VARIANTS)} x default, {', '.join(f'{t:.0e}' for t in STIFF_FALLBACK)} that "
                         "steps through the second at the smallest size)")
    ap.add_argument("--no-build", action="store_true", help="reuse the FMUs of an earlier run (no build figures)")
    ap.add_argument("--no-describe", action="store_true", help="skip the description/probe split of the build")
    ap.add_argument("--out", default=str(ROOT / "target" / "bench"))
    ap.add_argument("--report-only", action="store_true", help="render chain.md again from an earlier run's chain.json")
    ap.add_argument("--dense-or-sparse", default=None, metavar="SIZES",
                    help="instead of the benchmark: the stiff chain's doStep at these N with the implicit method's Newton "
                         "matrix dense, band and sparse (FMU_RUNTIME_JACOBIAN), for fmu-runtime's DENSE_BELOW, e.g. 3,5,8,10,15,25")
    args = ap.parse_args()
    if args.dense_or_sparse:
        dense_or_sparse(args)
        return
    if args.report_only:
        saved = json.loads((Path(args.out) / "chain.json").read_text())
        results = {int(k): v for k, v in saved["results"].items()}
        text = report(results, saved["meta"])
        (Path(args.out) / "chain.md").write_text(text)
        print(text)
        return
    sizes = sorted(int(s) for s in args.sizes.split(",") if s.strip())
    for n in SIZES:
        if n not in sizes:
            log(f"note: N = {n} skipped (not in --sizes {args.sizes}); `--sizes {','.join(map(str, sorted(set(sizes) | {n})))}` runs it")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    release = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target")) / "release"
    for tool in ("build-fmus", "fmu-bench"):
        if not (release / tool).is_file():
            sys.exit(f"{release / tool} is missing: cargo build --release -p build-fmus -p fmu-bench")
    src, tag = runtime_source(args.rev)
    head = sh(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"]).strip()
    dirty = bool(sh(["git", "-C", ROOT, "status", "--porcelain", "--untracked-files=no"]).strip())
    started = time.time()
    load_start = os.getloadavg()
    log(f"== torsional chain, sizes {sizes}, runtime from {'the working tree' if tag == 'worktree' else src} "
        f"(HEAD {head}{', dirty' if dirty else ''}); load average {load_start[0]:.1f}")

    results = {}
    if not args.no_build:
        log("== warm-up build (N = 2: the dependencies, not timed)")
        warm = build(make_copy(src, tag, 2, "warmup"), release)
        log(f"   {warm['wall_s']:.1f} s")
    stiff_choice = None  # the stiff chain's (variant, tolerance) that worked, carried to the next size
    if args.stiff:
        variant, _, tol = args.stiff.partition(":")
        assert variant in STIFF_VARIANTS, f"--stiff {args.stiff}: the variant is one of {STIFF_VARIANTS}"
        stiff_choice = (variant, float(tol) if tol and tol != "default" else None)
    matched_rtol = {}  # method -> the rtol matched at the last size where our error was measured
    for n in sizes:
        log(f"== N = {n} ({2 * n - 1} states)")
        r = results[n] = {"n": n, "states": 2 * n - 1, "load_before": os.getloadavg()[0]}
        crates, fmus = {}, {}

        def ensure_built(variant):
            """The FMU of a variant of this size (built on first use; `--no-build`: the earlier one)."""
            if variant not in fmus:
                crates[variant] = make_copy(src, tag, n, variant)
                fmus[variant] = crates[variant] / "dist" / "TorsionalChain.fmu"
                if not args.no_build:
                    b = r[f"build_{variant}"] = build(crates[variant], release)
                    log(f"   build-fmus build ({variant}): {b['wall_s']:.1f} s wall; {b['output']}")
                elif not fmus[variant].is_file():
                    sys.exit(f"--no-build: {fmus[variant]} is missing")
            return fmus[variant]

        ensure_built("explicit")
        if not args.no_build and not args.no_describe:
            d = out / "chain" / f"describe_n{n}.json"
            d.parent.mkdir(parents=True, exist_ok=True)
            sh([release / "fmu-bench", "chain-describe", "--lib", library(crates["explicit"]), "--out", d])
            r["describe"] = json.loads(d.read_text())
            log(f"   description + probe (fresh process): {r['describe']['total_wall_s']:.3f} s wall")
        lay = Layout(fmus["explicit"])
        assert lay.n == n, f"the FMU has {lay.n} inertias, not {n}"
        t_grid = grid(lay.steps, lay.step_size)
        for case in ("explicit", "stiff"):
            params = {} if case == "explicit" else dict(STIFF)
            p = dict(lay.defaults, **params)
            chain = Chain(n, p)
            rec = out / "chain" / f"traj_n{n}_{case}.bin"
            rec.parent.mkdir(parents=True, exist_ok=True)
            rec.with_suffix(".vrs").write_text("\n".join(map(str, lay.speed_vrs)) + "\n")
            jac_file = out / "chain" / f"jacobian_n{n}_{case}.txt" if n <= 1000 else None
            if case == "stiff" and n > args.stiff_max:
                log(f"   note: our stiff chain skipped at N = {n} (--stiff-max {args.stiff_max}); scipy only")
                choices = []
                h = r["stiff"] = {"skipped": True}
            elif case == "explicit":
                choices = [("explicit", None)]
            elif stiff_choice is not None:
                choices = [stiff_choice]
            else:
                choices = [(v, t) for v in STIFF_VARIANTS for t in [None] + STIFF_FALLBACK]
            for variant, tol in choices:
                fmu = ensure_built(variant)
                if variant != "explicit":
                    assert Layout(fmu).speed_vrs == lay.speed_vrs, f"{variant}: not the explicit copy's variables"
                log(f"   fmu-bench chain ({case}, {variant}, rtol {tol or DEFAULT_RTOL:.0e}{'' if tol else ' (default)'})")
                h = run_harness(release, fmu, out / "chain" / f"rust_n{n}_{case}.json", params, tol, args,
                                rec, jac_file)
                h["tolerance"] = tol or DEFAULT_RTOL
                h["tolerance_default"] = tol is None
                h["variant"] = variant
                if "error" not in h:
                    break
                log(f"   failed in {h.get('error_phase')}: {h['error'][:300]}")
                r.setdefault(f"failures_{case}", []).append({"variant": variant, "tolerance": tol or DEFAULT_RTOL,
                                                              "phase": h.get("error_phase"), "error": h["error"][:500]})
            r[case] = h
            if "error" in h:
                log(f"   {case}: every tolerance failed")
                continue
            if h.get("skipped"):
                scipy_only(r, case, chain, lay, matched_rtol, args, t_grid)
                continue
            if case == "stiff":
                if h["step_extrapolated"] == "no":
                    stiff_choice = (variant, tol)
                elif stiff_choice is None:
                    h["unverified"] = True  # cut before step_time: whether it steps through is not known
                else:
                    profile(h, results, n)
            steps = int(h["steps"])
            t_grid = grid(steps, h["step_size"])
            # Jacobian against the exact one.
            if jac_file is not None and jac_file.is_file() and h["jacobian_columns_done"] == h["states"]:
                rows, cols, vals = np.loadtxt(jac_file, ndmin=2).T if jac_file.stat().st_size else (np.array([]),) * 3
                m = 2 * n - 1
                J = sp.csc_matrix((vals, (lay.to_numpy[rows.astype(int)], lay.to_numpy[cols.astype(int)])), shape=(m, m)).toarray()
                A = chain.matrix().toarray()
                h["jacobian_max_rel_error"] = float(np.max(np.abs(J - A)) / np.max(np.abs(A)))
                h["jacobian_nonzeros"] = int(len(vals))
                log(f"   directional derivatives vs the exact Jacobian: max |J - A| / max |A| = {h['jacobian_max_rel_error']:.1e}")
            # Reference and our error (for a stiff run cut short above N = 1000 the reference would
            # only give scipy's error, at minutes of Radau: left out).
            if case == "stiff" and not h.get("recorded") and n > 1000:
                log("   no reference (our error unmeasured at this size)")
                ref = None
            else:
                ref = reference(r, case, chain, lay, t_grid, n)
            nominal = lay.nominal_numpy
            ours_err = None
            if h.get("recorded"):
                speeds = np.fromfile(rec, dtype="<f8").reshape(steps, n)
                ours_err = error(speeds, ref)
                h["error_pct"] = ours_err
                log(f"   our error: {ours_err:.2e} % of the peak speed")
            # scipy.
            methods = ["RK45"] if case == "explicit" else ["BDF", "Radau"]
            for m_ in methods:
                kw = {} if m_ == "RK45" else {"jac_sparsity": chain.pattern()}
                rtols = SCIPY_RTOLS
                if ours_err is None:
                    rtols = [matched_rtol.get((case, m_), 1e-6)]
                log(f"   scipy {m_}" + ("" if ours_err is not None else f" at rtol {rtols[0]:.0e} (our error unmeasured at this size)"))
                s = sweep(chain, m_, ref, ours_err, nominal, t_grid, min(args.repeats, 3), rtols, **kw)
                s["us_per_step"] = s["cpu_s"] / steps * 1e6 if s.get("cpu_s") else None
                if s["matched"]:
                    matched_rtol[(case, m_)] = s["rtol"]
                r[f"scipy_{case}_{m_}"] = s
        r["load_after"] = os.getloadavg()[0]
        meta = {"head": head, "dirty": dirty, "tag": tag, "started": started, "ended": time.time(),
                "load_start": load_start[0], "load_end": os.getloadavg()[0], "sizes": sizes, "repeats": args.repeats,
                "step_budget": args.step_budget, "stiff_max": args.stiff_max, "machine": machine()}
        (out / "chain.json").write_text(json.dumps({"meta": meta, "results": {str(k): v for k, v in results.items()}},
                                                   indent=1, default=str))

    text = report(results, meta)
    (out / "chain.md").write_text(text)
    print(text)
    log(f"wrote {out / 'chain.md'} and {out / 'chain.json'}")


def report(results: dict, meta: dict) -> str:
    sizes, head, dirty, tag = meta["sizes"], meta["head"], meta["dirty"], meta["tag"]
    loads = [meta["load_start"], meta["load_end"]] + [v for r in results.values() for k, v in r.items() if k.startswith("load_")]
    def get(n, *keys):
        v = results[n]
        for k in keys:
            if not isinstance(v, dict) or k not in v:
                return None
            v = v[k]
        return v

    lines = [
        f"Measured {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime(meta['started']))} to "
        f"{time.strftime('%H:%M UTC', time.gmtime(meta['ended']))}, commit {head}"
        f"{' (working tree dirty with other work)' if dirty else ''}, the chain built against "
        f"{'the working tree' if tag == 'worktree' else tag.replace('rev-', 'the runtime of ')}; load average (1 min) "
        f"{min(loads):.1f} to {max(loads):.1f} during the run ({meta['load_start']:.1f} at the start), on {os.cpu_count()} cores.",
        "",
        f"- {meta['machine']}",
        f"- explicit: the model's defaults (J = 1 kg m2, K = 1e4 N m/rad, D = 1 N m s/rad, c_load = 1, drive_torque = 100 N m at "
        f"step_time = 0.1 s), Solver::ExplicitRungeKutta (tsit45), default tolerance 1e-8; stiff: J = {STIFF['J']:g}, "
        f"K = {STIFF['K']:g}, D = {STIFF['D']:g} (the rest as above), the copy with Solver::ImplicitRungeKutta (ESDIRK5(4)7L[2]SA_2)",
        "- 1 s at 1 ms (1000 doSteps + fmi2GetReal of the two outputs), CPU time of the thread, median of up to "
        f"{meta['repeats']} runs; a run whose doSteps would pass {meta['step_budget']:g} s of CPU is cut and extrapolated (marked *)",
        "",
    ]
    # Stiffness.
    stiff_lines = []
    for n in [m for m in sizes if m <= 100]:
        lay_defaults = {"J": 1.0, "K": 1e4, "D": 1.0, "c_load": 1.0, "drive_torque": 100.0, "step_time": 0.1}
        for case, p in (("explicit", {}), ("stiff", STIFF)):
            lam = np.linalg.eigvals(Chain(n, dict(lay_defaults, **p)).matrix().toarray())
            re_ = np.abs(lam.real)
            stiff_lines.append(f"N = {n} {case}: eigenvalues' real parts from -{re_.max():.3g} to -{re_.min():.3g} 1/s "
                               f"(stiffness ratio {re_.max() / re_.min():.3g}), largest |lambda| {np.abs(lam).max():.3g} 1/s")
    lines += ["Stiffness (numpy eigenvalues of the chain's matrix):", ""] + [f"- {l}" for l in stiff_lines] + [""]

    # Main table.
    lines += [
        "| N (states) | build-fmus build, s (description + probe / the rest) | first instantiate | second instantiate | "
        "doStep explicit (per state) | doStep stiff, implicit (per state) | full Jacobian by directional derivatives (per column) | "
        "sparse Jacobian by colored directional derivatives (colors) | "
        "heap per instance (RSS) | peak RSS after the first instantiate |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for n in sizes:
        if n not in results:
            continue
        b = get(n, "build_explicit", "wall_s")
        d = get(n, "describe", "total_wall_s")
        build_cell = "-" if b is None else (f"{b:.1f} ({d:.3g} / {b - d:.1f})" if d is not None else f"{b:.1f}")
        for v in STIFF_VARIANTS:
            bi = get(n, f"build_{v}", "wall_s")
            if bi is not None:
                build_cell += f"; {v} copy {bi:.1f}"
        e, s = results[n].get("explicit", {}), results[n].get("stiff", {})

        def step_cell(h):
            if not h or "us_per_step" not in h:
                return "failed" if h and "error" in h else "-"
            mark = f"* ({int(h['steps_done'])} doSteps" if h.get("step_extrapolated") == "yes" else ""
            if mark and "profile_estimate_us" in h:
                mark += f"; about {fmt_us(h['profile_estimate_us'])} by N = {h['profile_size']}'s profile"
            if mark and h.get("unverified"):
                mark += "; cut before step_time: not known whether it steps through"
            mark += ")" if mark else ""
            tol = "" if h.get("tolerance_default") else f", rtol {h['tolerance']:.0e}"
            if h.get("variant") == "implicit-gt":
                tol += ", step as t > step_time"
            return f"{fmt_us(h['us_per_step'])}{mark} ({fmt_us(h['us_per_step'] / h['states'])}{tol})"

        def jac_cell(h):
            if not h or "jacobian_cpu_s_full" not in h:
                return "-"
            mark = "" if h["jacobian_columns_done"] == h["states"] else f"* ({int(h['jacobian_columns_done'])} columns)"
            return f"{fmt_time(h['jacobian_cpu_s_full'])}{mark} ({fmt_time(h['jacobian_cpu_s_per_column'])})"

        def sparse_cell(h):
            if not h or "sparse_jacobian_s" not in h:
                return "-"
            mark = f"* ({int(h['sparse_jacobian_colors_done'])} colors)" if h.get("sparse_jacobian_extrapolated") == "yes" else ""
            extra = "" if h.get("sparse_jacobian_structure") == "sparse" else "; dense: no dependencies listed"
            if h.get("sparse_jacobian_mismatches"):
                extra += f"; {int(h['sparse_jacobian_mismatches'])} entries differ from the per-column Jacobian"
            return f"{fmt_time(h['sparse_jacobian_s'])}{mark} ({int(h['sparse_jacobian_colors'])}{extra})"

        lines.append(
            f"| {n} ({2 * n - 1}) | {build_cell} | {fmt_time(e.get('first_total_wall_s'))} | {fmt_time(e.get('second_total_wall_s'))} | "
            f"{step_cell(e)} | {step_cell(s)} | {jac_cell(e)} | {sparse_cell(e)} | "
            f"{fmt_kb(e.get('heap_kb_per_instance'))} ({fmt_kb(e.get('rss_kb_per_instance'))}, "
            f"{int(e.get('memory_instances', 0))} instances) | {fmt_kb(e.get('peak_rss_kb_after_first'))} |"
        )
    lines += ["",
              "Instantiation times are wall times of fmi2Instantiate + fmi2SetReal + fmi2SetupExperiment + enter/exit "
              "initialization in a fresh `fmu-bench chain` process (the first) and right after (the second); "
              "the description + probe is what build-fmus calls in the library, timed in a fresh process "
              "(`fmu-bench chain-describe`); the Jacobian is CPU time after initialization of the explicit chain; memory: "
              "growth of the malloc heap in use (and of RSS) with the instances alive, per instance; peak RSS: of the "
              "`fmu-bench chain` process of the explicit chain after its first instantiation (library loaded, description "
              "made, one instance).",
              ""]

    # Against scipy.
    lines += [
        "| N | chain | ours, per doStep | our error, % of peak speed | scipy | rtol | scipy, per step of 1 ms (CPU s per 1 s) | error, % | ours / scipy |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for n in sizes:
        if n not in results:
            continue
        for case, methods in (("explicit", ["RK45"]), ("stiff", ["BDF", "Radau"])):
            h = results[n].get(case, {})
            for m_ in methods:
                s = results[n].get(f"scipy_{case}_{m_}")
                if not s:
                    continue
                ours_us = h.get("us_per_step")
                mark = "*" if h.get("step_extrapolated") == "yes" else ""
                err = h.get("error_pct")
                if s["rtol"] is None:
                    setting = f"none down to {SCIPY_RTOLS[-1]:.0e}"
                else:
                    setting = f"{s['rtol']:.0e}" + (" (matched)" if s["matched"] else " (ours unmeasured: rtol matched at a smaller size)")
                ratio = ours_us / s["us_per_step"] if s.get("us_per_step") and ours_us else None
                s_err = "-" if s.get("error_pct") is None else f"{s['error_pct']:.1e}"
                lines.append(
                    f"| {n} | {case} | {fmt_us(ours_us) if ours_us else ('skipped' if h.get('skipped') else 'failed')}{mark} | {'-' if err is None else f'{err:.1e}'} | {m_} | {setting} | "
                    f"{fmt_us(s.get('us_per_step'))} ({s.get('cpu_s', float('nan')):.3g} s) | "
                    f"{s_err} | "
                    f"{fmt_ratio(ratio)} |")
    refs = []
    for n in sizes:
        for case in ("explicit", "stiff"):
            ref = results.get(n, {}).get(f"ref_{case}")
            if ref:
                check = f", {ref['error_vs_exact_pct']:.1e} % from the exact solution" if "error_vs_exact_pct" in ref else ""
                refs.append(f"N = {n} {case}: {ref['method']} rtol {ref['rtol']:.0e}{' with the exact sparse Jacobian' if ref['method'] == 'Radau' else ''}{check}")
    lines += ["", "ours / scipy below 1: we are faster. scipy: solve_ivp on the same equations (numpy, vectorized), "
              "restarted at step_time, t_eval on the 1 ms grid, atol = 1e-3 rtol x nominal; BDF and Radau with "
              "jac_sparsity (the band as a scipy.sparse matrix); CPU time of the whole second / 1000; errors: max over the "
              "grid and all inertias of |w - w_ref|, in % of max |w_ref|. References: " + "; ".join(refs) + ".", ""]

    # Jacobian accuracy and failures.
    notes = []
    for n in sizes:
        for case in ("explicit", "stiff"):
            h = results.get(n, {}).get(case, {})
            failures = results.get(n, {}).get(f"failures_{case}", [])
            for v in dict.fromkeys(f["variant"] for f in failures):
                mine = [f for f in failures if f["variant"] == v]
                what = {"implicit": "t >= step_time as written", "implicit-gt": "t > step_time"}.get(v, v)
                tols = ", ".join(f"{f['tolerance']:.0e}" for f in mine)
                notes.append(f"N = {n} {case}: the {v} copy ({what}) failed at rtol {tols}, each in {mine[0]['phase']}; "
                             f"the first: {mine[0]['error'][:300]}")
            if h.get("sparse_jacobian_mismatches"):
                notes.append(f"N = {n} {case}: the sparse Jacobian by colored directional derivatives differs from the per-column "
                             f"one in {int(h['sparse_jacobian_mismatches'])} of {int(h['sparse_jacobian_compared_entries'])} entries "
                             f"({int(h['sparse_jacobian_outside_structure'])} outside the declared structure)")
            if h.get("skipped"):
                notes.append(f"N = {n} {case}: our FMU not run (--stiff-max {meta['stiff_max']}): the dense implicit method "
                             "would need hours per doStep; scipy at the rtol matched at a smaller size")
    jac = [(n, case, results[n][case]["jacobian_max_rel_error"]) for n in sizes for case in ("explicit", "stiff")
           if "jacobian_max_rel_error" in results.get(n, {}).get(case, {})]
    if jac:
        worst = max(jac, key=lambda x: x[2])
        notes.insert(0, f"directional derivatives against the exact Jacobian (the model is linear), max |J - A| / max |A|: "
                        f"at most {worst[2]:.1e} (N = {', '.join(str(n) for n in dict.fromkeys(n for n, _, _ in jac))}, both chains)")
    if notes:
        lines += ["Notes:", ""] + [f"- {x}" for x in notes] + [""]

    # Growth exponents.
    ns = [n for n in sizes if n in results]
    def extrapolated(n, case, what):
        h = results[n].get(case, {})
        if what == "sparse":
            return h.get("sparse_jacobian_extrapolated") == "yes"
        return h.get("step_extrapolated") == "yes" if what == "step" else h.get("jacobian_columns_done", 0) < h.get("states", 0)

    marks = {"doStep explicit": [extrapolated(n, "explicit", "step") for n in ns],
             "doStep stiff (implicit)": [extrapolated(n, "stiff", "step") for n in ns],
             "full Jacobian": [extrapolated(n, "explicit", "jacobian") for n in ns],
             "sparse Jacobian (colored)": [extrapolated(n, "explicit", "sparse") for n in ns]}
    series = {
        "doStep explicit": [get(n, "explicit", "us_per_step") for n in ns],
        "doStep stiff (implicit)": [get(n, "stiff", "us_per_step") for n in ns],
        "build-fmus build": [get(n, "build_explicit", "wall_s") for n in ns],
        "description + probe": [get(n, "describe", "total_wall_s") for n in ns],
        "first instantiate": [get(n, "explicit", "first_total_wall_s") for n in ns],
        "second instantiate": [get(n, "explicit", "second_total_wall_s") for n in ns],
        "full Jacobian": [get(n, "explicit", "jacobian_cpu_s_full") for n in ns],
        "sparse Jacobian (colored)": [get(n, "explicit", "sparse_jacobian_s") for n in ns],
        "heap per instance": [get(n, "explicit", "heap_kb_per_instance") for n in ns],
    }
    for m_ in ("RK45",):
        series[f"scipy {m_} (explicit, matched)"] = [get(n, "scipy_explicit_RK45", "cpu_s") for n in ns]
    for m_ in ("BDF", "Radau"):
        series[f"scipy {m_} (stiff)"] = [get(n, f"scipy_stiff_{m_}", "cpu_s") for n in ns]
    pairs = list(zip(ns, ns[1:]))
    lines += ["Growth exponents (log-log slope against N between consecutive sizes):", "",
              "| figure | " + " | ".join(f"N {a} -> {b}" for a, b in pairs) + " |",
              "|---|" + "---|" * len(pairs)]
    for name, values in series.items():
        m = marks.get(name, [False] * len(ns))
        cells = ["-" if s is None else f"{s:.2f}" + ("*" if m[i] or m[i + 1] else "") for i, (_, _, s) in enumerate(slope(ns, values))]
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    lines += ["", "*: from an extrapolated figure.", ""]
    return "\n".join(lines)


if __name__ == "__main__":
    main()
