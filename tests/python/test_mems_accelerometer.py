"""MemsAccelerometer against its contract, docs/mems-accelerometer-spec.md (chapter 3, section 3.4.1.1,
Figure 3.14, question 2).

Where each reference comes from (never a previous run of the FMU):
  * the defaults: the spec's arguments, recomputed here from their sources' numbers (`DEFAULTS`): the
    layout's dimensions, polysilicon's density, the ADXL50's 24 kHz and 19 mV/g;
  * the lumped parameters and the acceptance figures' closed forms: mems_reference.py, written out from
    the formulas the spec cites (folded flexure 2 E t w^3 / L^3, kinetic-theory mean free path, Veijola's
    effective viscosity, the Reynolds strip, Couette, parallel plates): static sensitivity m / k (carrier
    off) and m / (k - k_e) (carrier on), resonance sqrt(k / m), pull-in sqrt(8 k g^3 / (27 eps A)), the
    bandwidth of the linearised transfer function (numpy and brentq);
  * the transients: the same equations integrated by scipy's DOP853 at rtol 1e-12 (mems_reference.simulate);
  * the resonance: the FMU's own linearisation (Model Exchange, central differences of fmi2GetDerivatives)
    and a free oscillation simulated by the FMU, against sqrt(k / m);
  * the pull-in voltage: bisection on V_bias (ramped over 3 ms, held 2 ms) for the voltage at which the
    FMU's proof mass ends on its stop, against the parallel-plate formula;
  * the bandwidth: a sine at the closed form's bandwidth frequency, the steady amplitude of V_out against
    1/sqrt(2) of the static sensitivity.
Parameter values are the FMU's start values (modelDescription.xml) with a case's overrides.
"""

from __future__ import annotations

import functools
import math
import time

import numpy as np
import pytest
from fmi_host import state_jacobian
from fmpy import read_model_description, simulate_fmu

import mems_reference as ref
from conftest import DIST_DIR, print_past_capture, require_fmu

REPORT: list[str] = []
COMPARED = ("displacement", "velocity", "C_1", "C_2", "delta_C", "V_demodulated", "V_out", "F_electrostatic")
CARRIER_OFF = {"V_carrier": 0.0}


@pytest.fixture(scope="module", autouse=True)
def _print_report(request):
    yield
    print_past_capture(request, "== MemsAccelerometer: figures of the spec", REPORT)


def fmu():
    return require_fmu(DIST_DIR / "MemsAccelerometer.fmu")


@functools.lru_cache(maxsize=None)
def model_description():
    return read_model_description(str(fmu()))


def start_values() -> dict:
    return {v.name: v.start for v in model_description().modelVariables if v.start is not None}


def params(**overrides) -> ref.MemsParams:
    return ref.MemsParams.from_values({**start_values(), **overrides})


def run(start: dict, stop_time: float = 3e-3, interval: float = 1e-5, tolerance: float | None = 1e-10, outputs=COMPARED):
    extra = {} if tolerance is None else {"relative_tolerance": tolerance}
    return simulate_fmu(str(fmu()), fmi_type="CoSimulation", stop_time=stop_time, output_interval=interval,
                        start_values=start, output=list(outputs), **extra)


def grid(stop_time: float, interval: float) -> np.ndarray:
    return np.round(np.arange(int(round(stop_time / interval)) + 1) * interval, 12)


# ---- the defaults and their sources ---------------------------------------------------------------

PLATE = 448e-6 * 100e-6 * (1 - (4 / 18) ** 2) + 42 * 114e-6 * 4e-6  # m2: plate less its release holes, plus fingers
# (parameter, value from its source's numbers, the source): docs/mems-accelerometer-spec.md, "Values".
DEFAULTS = [
    ("m_proof", 2330.0 * 2e-6 * PLATE, "2 um polysilicon (2330 kg/m3) over the layout's plate and 42 fingers"),
    ("E_beam", 160e9, "polysilicon, 160 GPa"),
    ("L_beam", 92e-6, "chosen for the ADXL50's 24 kHz (AN-377)"),
    ("w_beam", 2e-6, "layout's spring width"),
    ("t_structure", 2e-6, "ADXL50's 2 um sensor layer"),
    ("A_electrode", 42 * 104e-6 * 2e-6, "42 fingers x 104 um overlap x 2 um"),
    ("gap", 1e-6, "layout's finger gap"),
    ("A_plate", PLATE, "the proof mass's footprint"),
    ("d_substrate", 1.6e-6, "sacrificial oxide"),
    ("p_gas", 101325.0, "1 atm"), ("T_gas", 298.15, "25 C"),
    ("x_stop", 0.5e-6, "half the gap"),
    ("V_carrier", 1.0, "chosen"), ("V_bias", 0.0, ""), ("t_bias_ramp", 0.0, ""),
    ("C_feedback", 100e-15, "chosen"), ("f_filter", 1000.0, "AN-377: dc to 1 kHz"), ("G_out", 28.0, "trim to 19 mV/g"),
    ("a_step", 10 * 9.80665, "10 g"), ("a_sine", 10 * 9.80665, "10 g"), ("f_sine", 1000.0, ""), ("t_start", 1e-4, ""),
]


def test_defaults_are_the_specs_values():
    starts = start_values()
    wrong = [f"{name}: FMU {starts[name]}, spec {value} ({source})" for name, value, source in DEFAULTS
             if not math.isclose(float(starts[name]), value, rel_tol=1e-12)]
    assert not wrong, "\n".join(wrong)
    md = model_description()
    profile = next(v for v in md.modelVariables if v.name == "profile")
    assert (profile.type, profile.variability, int(profile.min), int(profile.max), int(profile.start)) == ("Enumeration", "fixed", 1, 2, 1)
    assert [(i.name, int(i.value)) for i in profile.declaredType.items] == [("step", 1), ("sine", 2)]
    de = md.defaultExperiment
    assert (float(de.startTime), float(de.stopTime), float(de.stepSize)) == (0.0, 3e-3, 1e-5)
    units = {v.name: v.unit for v in md.modelVariables}
    for name, unit in [("a_frame", "m/s2"), ("displacement", "m"), ("delta_C", "F"), ("V_out", "V"), ("F_electrostatic", "N"),
                       ("E_beam", "Pa"), ("b_squeeze", "N.s/m"), ("k_suspension", "N/m"), ("bandwidth", "Hz"), ("x_proof", "m"),
                       ("v_proof", "m/s")]:
        assert units[name] == unit, name
    assert md.modelExchange is not None and md.coSimulation is not None
    # The ADXL50 class the values were chosen for: 24 kHz (AN-377), 19 mV/g (its data sheet).
    p = params()
    assert p.omega0 / (2 * math.pi) == pytest.approx(24e3, rel=0.01)
    assert p.sensitivity * ref.G_N == pytest.approx(19e-3, rel=0.01)


def test_derived_parameters_by_hand():
    p = params()
    names = ("k_suspension", "f_natural", "k_electrostatic", "f_natural_carrier", "b_squeeze", "b_slide", "Q_factor", "C_0", "V_pull_in",
             "V_pull_in_symmetric", "x_per_g", "delta_C_per_g", "V_out_per_g", "bandwidth", "Knudsen_gap", "squeeze_number")
    res = run({}, stop_time=1e-5, interval=1e-5, tolerance=None, outputs=names)
    expected = {
        "k_suspension": p.k, "f_natural": p.omega0 / (2 * math.pi), "k_electrostatic": p.k_e, "f_natural_carrier": p.omega_eff / (2 * math.pi),
        "b_squeeze": p.b_squeeze(), "b_slide": p.b_slide, "Q_factor": p.Q, "C_0": p.C0, "V_pull_in": p.V_pull_in,
        "V_pull_in_symmetric": p.V_pull_in_symmetric, "x_per_g": p.x_per_g, "delta_C_per_g": 2 * p.C0 / p.gap * p.x_per_g,
        "V_out_per_g": p.sensitivity * ref.G_N, "bandwidth": p.bandwidth(), "Knudsen_gap": p.mean_free_path / p.gap,
        "squeeze_number": 12 * p.mu_squeeze * p.omega_eff * p.t_structure**2 / (p.p_gas * p.gap**2),
    }
    for name, value in expected.items():
        assert res[name][-1] == pytest.approx(value, rel=1e-9), name
    REPORT.append(f"k = {p.k:.4f} N/m, m = {p.m_proof:.4e} kg, f0 = {p.omega0 / 2 / math.pi:.1f} Hz ({p.omega_eff / 2 / math.pi:.1f} Hz with the "
                  f"carrier's k_e = {p.k_e:.4f} N/m, {100 * p.k_e / p.k:.2f} %); b_squeeze {p.b_squeeze():.4e} + b_slide {p.b_slide:.4e} N s/m, "
                  f"Q = {p.Q:.2f}; C0 = {p.C0 * 1e15:.2f} fF; V_pi = {p.V_pull_in:.4f} V (symmetric {p.V_pull_in_symmetric:.4f} V); "
                  f"{p.x_per_g * 1e9:.4f} nm/g, {2 * p.C0 / p.gap * p.x_per_g * 1e18:.2f} aF/g, {p.sensitivity * ref.G_N * 1e3:.3f} mV/g; "
                  f"bandwidth {p.bandwidth():.2f} Hz; Kn {p.mean_free_path / p.gap:.4f}")


# ---- acceptance: static sensitivity ----------------------------------------------------------------

@pytest.mark.parametrize("carrier", ["off", "on"])
def test_static_sensitivity(carrier):
    """A 1 g step, held 5.9 ms (the mode's envelope decays as exp(-t w0 / 2Q): by e^-16): x / a against
    -m / k with the carrier off (the closed form of the issue), -m / (k - k_e) with it on (its
    electrostatic softening); with the carrier on, delta_C and V_out against their linear closed forms."""
    start = {"a_step": ref.G_N, **(CARRIER_OFF if carrier == "off" else {})}
    p = params(**start)
    res = run(start, stop_time=6e-3)
    x_over_a = float(res["displacement"][-1]) / ref.G_N
    closed = -p.m_proof / (p.k if carrier == "off" else p.k_eff)
    error = x_over_a / closed - 1
    REPORT.append(f"static sensitivity, carrier {carrier}: x/a = {x_over_a:.6e} s2, closed form {closed:.6e} s2 "
                  f"({'m/k' if carrier == 'off' else 'm/(k - k_e)'}): {100 * error:+.5f} %")
    assert abs(error) < 0.01
    assert abs(error) < 1e-4  # the parallel plates' nonlinearity at 0.44 nm of a 1 um gap: (x/g)^2 ~ 2e-7
    if carrier == "on":
        d_c = float(res["delta_C"][-1])
        assert d_c == pytest.approx(-2 * p.C0 / p.gap * p.x_per_g, rel=1e-4)
        assert float(res["V_out"][-1]) == pytest.approx(p.sensitivity * ref.G_N, rel=1e-4)
        REPORT.append(f"  carrier on: delta_C = {d_c * 1e18:.3f} aF per g, V_out = {1e3 * float(res['V_out'][-1]):.4f} mV per g")


# ---- acceptance: resonance ---------------------------------------------------------------------------

def linearisation(overrides: dict, states=("x_proof", "v_proof")) -> np.ndarray:
    """The FMU's Jacobian d(der(x))/dx of the mechanical states at rest (Model Exchange, central
    differences of fmi2GetDerivatives, steps of 1e-6 of each state's nominal)."""
    return state_jacobian(fmu(), states, overrides)


@pytest.mark.parametrize("carrier", ["off", "on"])
def test_resonance_from_the_linearisation(carrier):
    """The eigenvalues of the FMU's mechanical Jacobian at rest: |lambda| = sqrt(k / m) (carrier off),
    sqrt((k - k_e) / m) (carrier on), and -Re / |lambda| = 1 / (2 Q)."""
    start = {"a_step": 0.0, **(CARRIER_OFF if carrier == "off" else {})}
    p = params(**start)
    lam = np.linalg.eigvals(linearisation(start))
    lam = lam[np.argmax(lam.imag)]
    closed = p.omega0 if carrier == "off" else p.omega_eff
    error = abs(lam) / closed - 1
    q = math.sqrt(p.m_proof * (p.k if carrier == "off" else p.k_eff)) / (p.b_squeeze() + p.b_slide)
    REPORT.append(f"resonance, carrier {carrier}, linearisation: {abs(lam) / 2 / math.pi:.3f} Hz against "
                  f"{'sqrt(k/m)' if carrier == 'off' else 'sqrt((k - k_e)/m)'} {closed / 2 / math.pi:.3f} Hz ({100 * error:+.2e} %); "
                  f"damping ratio {-lam.real / abs(lam):.5f} (1/2Q = {1 / (2 * q):.5f})")
    assert abs(error) < 0.01
    assert abs(error) < 1e-6
    assert -lam.real / abs(lam) == pytest.approx(1 / (2 * q), rel=1e-5)


def test_resonance_from_a_free_response():
    """The mass released 10 nm from rest, carrier off, no acceleration: the zero crossings of its
    displacement over 1 ms (24 periods) give the damped frequency w0 sqrt(1 - 1/(4 Q^2)); within 1 % of
    sqrt(k / m), and within 1e-4 of the damped closed form."""
    start = {"a_step": 0.0, "x_proof": 10e-9, **CARRIER_OFF}
    p = params(**start)
    res = run(start, stop_time=1e-3, interval=2e-7, outputs=("displacement",))
    t, y = np.asarray(res["time"]), np.asarray(res["displacement"])
    s = np.nonzero(np.diff(np.sign(y)) != 0)[0]
    crossings = t[s] - y[s] * (t[s + 1] - t[s]) / (y[s + 1] - y[s])
    omega_d = math.pi / float(np.mean(np.diff(crossings)))
    q = math.sqrt(p.m_proof * p.k) / (p.b_squeeze() + p.b_slide)
    damped = p.omega0 * math.sqrt(1 - 1 / (4 * q * q))
    REPORT.append(f"resonance, free response (carrier off, {len(crossings)} crossings): {omega_d / 2 / math.pi:.3f} Hz; sqrt(k/m) "
                  f"{p.omega0 / 2 / math.pi:.3f} Hz ({100 * (omega_d / p.omega0 - 1):+.4f} %), damped {damped / 2 / math.pi:.3f} Hz "
                  f"({100 * (omega_d / damped - 1):+.5f} %)")
    assert omega_d == pytest.approx(p.omega0, rel=0.01)
    assert omega_d == pytest.approx(damped, rel=1e-4)


# ---- acceptance: pull-in -----------------------------------------------------------------------------

PULL_IN_RAMP = 3e-3  # s: V_bias ramps up over 72 periods of the mode ...
PULL_IN_HOLD = 2e-3  # s: ... then holds


def pulls_in(v_bias: float, hold: float = PULL_IN_HOLD, tolerance: float | None = None) -> tuple[bool, dict]:
    start = {**CARRIER_OFF, "a_step": 0.0, "V_bias": v_bias, "t_bias_ramp": PULL_IN_RAMP}
    res = run(start, stop_time=PULL_IN_RAMP + hold, interval=1e-5, tolerance=tolerance,
              outputs=("at_stop", "displacement", "F_stop", "F_electrostatic", "power_balance_relative", "V_bias_applied"))
    return bool(res["at_stop"][-1] == 1.0), res


def test_pull_in_voltage_by_bisection():
    """Carrier off, V_bias on electrode 1 alone: the voltage at which the mass snaps onto the stop, by
    bisection (14 halvings of [0.9, 1.1] V_pi), within 1 % of sqrt(8 k g^3 / (27 eps0 A)). The ramp's
    finite speed lets the mass overshoot its equilibrium a little, so the snap comes a little below V_pi
    (-0.31 % with a 1 ms ramp, -0.12 % with 3 ms, -0.07 % with 6 ms: it tends to V_pi)."""
    p = params(**CARRIER_OFF)
    lo, hi = 0.9 * p.V_pull_in, 1.1 * p.V_pull_in
    assert not pulls_in(lo)[0] and pulls_in(hi)[0]
    for _ in range(14):
        mid = 0.5 * (lo + hi)
        if pulls_in(mid)[0]:
            hi = mid
        else:
            lo = mid
    v_snap = 0.5 * (lo + hi)
    error = v_snap / p.V_pull_in - 1
    REPORT.append(f"pull-in: the mass snaps at V_bias = {v_snap:.5f} V (bisection, {1e3 * PULL_IN_RAMP:g} ms ramp); "
                  f"sqrt(8 k g^3 / (27 eps A)) = {p.V_pull_in:.5f} V ({100 * error:+.3f} %)")
    assert abs(error) < 0.01
    # Pulled in, it rests on the stop: x = x_stop, the stop holds the electrode's pull less the spring's.
    snapped, res = pulls_in(1.02 * p.V_pull_in)
    assert snapped and float(res["displacement"][-1]) == p.x_stop
    v = 1.02 * p.V_pull_in
    pull = ref.EPS0 * p.A_electrode * v**2 / (2 * (p.gap - p.x_stop) ** 2)
    assert float(res["F_stop"][-1]) == pytest.approx(-(pull - p.k * p.x_stop), rel=1e-12)
    assert np.max(np.abs(res["power_balance_relative"])) < 1e-12


@pytest.mark.parametrize("fraction", [0.5, 0.9, 0.98])
def test_below_pull_in_the_mass_rests_at_the_static_balance(fraction):
    """Below V_pi the mass settles where k x = eps0 A V^2 / (2 (g - x)^2) has its stable root (brentq).
    Held 7 ms: the ringing the ramp's end leaves decays as exp(-b t / 2m), b / 2m = 2700 /s."""
    p = params(**CARRIER_OFF)
    v = fraction * p.V_pull_in
    snapped, res = pulls_in(v, hold=7e-3, tolerance=1e-10)
    x_eq = p.static_equilibrium(v)
    assert not snapped
    assert float(res["displacement"][-1]) == pytest.approx(x_eq, rel=1e-6)
    REPORT.append(f"below pull-in, V_bias = {fraction:g} V_pi: x = {1e9 * float(res['displacement'][-1]):.3f} nm, static balance "
                  f"{1e9 * x_eq:.3f} nm ({x_eq / p.gap:.4f} of the gap; g/3 at pull-in)")


def test_the_stops_take_a_shock_and_let_go():
    """A 2000 g sine at 200 Hz (a shock the ADXL50 survives): the mass hits each stop (at_stop -1, then 1),
    rests on it while the acceleration presses it there, leaves when it no longer does; every output stays
    finite and the energy balance holds through the contacts."""
    start = {"profile": 2, "a_sine": 2000 * ref.G_N, "f_sine": 200.0, "t_start": 0.0}
    p = params(**start)
    res = run(start, stop_time=10e-3, interval=2e-6, tolerance=None,
              outputs=("at_stop", "displacement", "F_stop", "V_out", "power_balance_relative", "acceleration_frame"))
    at = np.asarray(res["at_stop"])
    x = np.asarray(res["displacement"])
    for name in ("displacement", "F_stop", "V_out", "power_balance_relative"):
        assert np.all(np.isfinite(res[name])), name
    assert set(np.unique(at)) == {-1.0, 0.0, 1.0}
    assert np.all(np.abs(x) <= p.x_stop * (1 + 1e-12))
    assert np.all(x[at == 1.0] == p.x_stop) and np.all(x[at == -1.0] == -p.x_stop)
    # On a stop the stop holds what the acceleration, the spring and the electrodes press on it, and
    # pushes back: F_stop = -(-m a - k x + F_e(x)), of the opposite sign to the side.
    a = np.asarray(res["acceleration_frame"])
    on = at != 0.0
    pressing = -p.m_proof * a[on] - p.k * x[on] + np.array([p.electrostatic_force(xi, 0.0) for xi in x[on]])
    np.testing.assert_allclose(np.asarray(res["F_stop"])[on], -pressing, rtol=1e-9, atol=1e-12 * p.k * p.x_stop)
    assert np.all(at[on] * pressing >= -1e-12 * p.k * p.x_stop)
    assert np.all(np.asarray(res["F_stop"])[~on] == 0.0)
    contacts = int(np.count_nonzero(np.diff(np.abs(at)) > 0))
    REPORT.append(f"stops: a 2000 g, 200 Hz sine lands the mass on a stop {contacts} times in 10 ms (it rests there "
                  f"{100 * np.mean(at != 0):.1f} % of the time); worst |power_balance_relative| {np.max(np.abs(res['power_balance_relative'])):.1e}")
    assert contacts >= 3
    assert np.max(np.abs(res["power_balance_relative"])) < 1e-12


# ---- bandwidth -----------------------------------------------------------------------------------------

def test_bandwidth():
    """The bandwidth is the lowest frequency at which the output per unit acceleration leaves +-3 dB of
    its static value. The FMU's `bandwidth` is the reference's; a 1 g sine at that frequency, simulated,
    gives a steady V_out amplitude of 1/sqrt(2) of the static sensitivity (within 1 %)."""
    p = params()
    f_bw = p.bandwidth()
    start = {"profile": 2, "a_sine": ref.G_N, "f_sine": f_bw, "t_start": 0.0}
    res = run(start, stop_time=8e-3, interval=2e-6, outputs=("V_out", "bandwidth"))
    assert float(res["bandwidth"][-1]) == pytest.approx(f_bw, rel=1e-9)
    t, y = np.asarray(res["time"]), np.asarray(res["V_out"])
    sel = t >= 4e-3
    w = 2 * math.pi * f_bw
    basis = np.column_stack([np.sin(w * t[sel]), np.cos(w * t[sel]), np.ones(np.count_nonzero(sel))])
    (a, b, _), *_ = np.linalg.lstsq(basis, y[sel], rcond=None)
    ratio = math.hypot(a, b) / (p.sensitivity * ref.G_N)
    REPORT.append(f"bandwidth: {f_bw:.2f} Hz (the filter's 1 kHz corner, the mechanics adding {100 * (f_bw / p.f_filter - 1):.3f} %); "
                  f"simulated amplitude ratio there {ratio:.5f} (1/sqrt 2 = 0.70711); mechanical resonance alone would "
                  f"leave the band at {ref.MemsParams.bandwidth(p.with_(f_filter=1e9)):.0f} Hz (its +3 dB rise)")
    assert ratio == pytest.approx(1 / math.sqrt(2), rel=0.01)
    assert ratio == pytest.approx(1 / math.sqrt(2), rel=2e-3)


# ---- transients against scipy ---------------------------------------------------------------------------

CASES = {
    "default 10 g step": {},
    "1 kHz 10 g sine": {"profile": 2},
    "self-test 2.5 V on electrode 1, 0.5 ms ramp": {"a_step": 0.0, "V_bias": 2.5, "t_bias_ramp": 0.5e-3},
}


@pytest.mark.parametrize("case", list(CASES))
def test_against_scipy(case):
    start = CASES[case]
    p = params(**start)
    t = grid(3e-3, 1e-5)
    expected = ref.simulate(p, t)
    res = run(start)
    worst = (0.0, "", 0.0)
    for name in COMPARED:
        exp = np.asarray(expected[name])
        span = float(np.ptp(exp))
        err = np.abs(np.asarray(res[name]) - exp) / span
        k = int(np.argmax(err))
        worst = max(worst, (float(err[k]), name, float(t[k])))
    REPORT.append(f"{case}: worst |FMU - scipy| {worst[0]:.2e} of the range ({worst[1]} at {worst[2]:g} s)")
    assert worst[0] <= 1e-7, worst


# ---- question 2: the dominant effect of each part ----------------------------------------------------------

def test_dominant_effects_question_2():
    """In the measurement band (a 1 kHz sine) the suspension's stiffness holds nearly all the storage
    activity, the proof mass's kinetic share is of the order of (f / f0)^2, the capacitors' share is the
    carrier's softening k_e / k; the squeeze film dissipates more than the slide film, in the ratio of
    their coefficients. In the step's ringing at the resonance the mass takes its share."""
    p = params()
    names = [f"share_{e}" for e in ("proof_mass", "folded_beams", "sense_capacitors", "squeeze_film", "slide_film")]
    band = run({"profile": 2}, tolerance=None, outputs=names)
    step = run({}, tolerance=None, outputs=names)
    s = {n.removeprefix("share_"): float(band[n][-1]) for n in names}
    r = {n.removeprefix("share_"): float(step[n][-1]) for n in names}
    REPORT.append("question 2 (shares of activity, 1 kHz sine | 10 g step): " + ", ".join(f"{n} {s[n]:.2f} % | {r[n]:.2f} %" for n in s))
    assert s["folded_beams"] > 90.0
    assert s["proof_mass"] < 2.0 and r["proof_mass"] > 10.0
    assert s["sense_capacitors"] == pytest.approx(100 * p.k_e / p.k, rel=0.05)
    b = p.b_squeeze() + p.b_slide
    assert s["squeeze_film"] == pytest.approx(100 * p.b_squeeze() / b, rel=1e-3)
    assert s["squeeze_film"] > s["slide_film"]


def test_default_experiment_is_cheap():
    """The DefaultExperiment (3 ms, 300 communication points) in fmpy Co-Simulation, as the generic
    suites run it: well under 0.3 s."""
    md = model_description()
    simulate_fmu(str(fmu()), fmi_type="CoSimulation")  # warm up (extraction, loading)
    t0 = time.perf_counter()
    simulate_fmu(str(fmu()), fmi_type="CoSimulation", output=["V_out"])
    wall = time.perf_counter() - t0
    REPORT.append(f"DefaultExperiment ({float(md.defaultExperiment.stopTime) * 1e3:g} ms) in fmpy CS: {wall:.3f} s")
    assert wall < 0.3
