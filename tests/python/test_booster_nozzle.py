"""BoosterNozzle against its contract, docs/booster-nozzle-spec.md (chapter 3, section 3.4.1.1,
Figure 3.15, question 2: the dominant effect of each part).

Where each reference comes from (never a previous run of the FMU):
  * the defaults: the spec's arguments, recomputed here from their sources' numbers (`DEFAULTS`);
  * the actuator-nozzle resonance: the undamped two-degree-of-freedom chain written in this test's
    reference (booster_nozzle_reference.two_dof_matrices: M = diag(J, m_a), K = [[K_b + k r^2, -k r],
    [-k r, k + K_a]], k = 2 A^2 B / V, Table 3.2's C = V / B per chamber), solved by scipy's eigh,
    against (a) the eigenvalues of the FMU's Jacobian built from its directional derivatives
    (fmi2GetDirectionalDerivative, Model Exchange) and (b) a free oscillation simulated by the FMU
    from the chain's own low mode shape;
  * the static deflection under a constant load: by hand (booster_nozzle_reference.static_deflection);
  * the transients: the spec's linear equations written out in booster_nozzle_reference.py in the
    physical coordinates and solved in closed form (particular solution plus matrix exponential);
  * the dominant effects (question 2): the activities (eq. 3.3) of the reference's powers,
    integrated on a 5 us grid, against the FMU's activities and shares, and the claims of the table.
Parameter values are the FMU's start values (modelDescription.xml) with a case's overrides.
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.fmi2 import FMU2Model

import booster_nozzle_reference as ref
from conftest import DIST_DIR, fmu_key, print_past_capture, require_fmu, unzipdir

REL_TOL = 1e-6  # of each output's range, FMU at rtol 1e-10 against the closed-form reference
AXIS_OUTPUTS = ("nozzle_angle", "nozzle_rate", "nozzle_command", "actuator_force", "pressure_difference", "hinge_moment",
                "actuator_stroke", "anchoring_deflection", "valve_flow")
AXIS_STATES = ("theta", "w", "dp", "phi_body", "w_body")
REPORT: list[str] = []


def outputs_of(axis: str) -> tuple[str, ...]:
    return tuple(f"{name}_{axis}" for name in AXIS_OUTPUTS)


@pytest.fixture(scope="module", autouse=True)
def _print_report(request):
    yield
    print_past_capture(request, "== BoosterNozzle: figures of the spec", REPORT)


def fmu():
    return require_fmu(DIST_DIR / "BoosterNozzle.fmu")


@functools.lru_cache(maxsize=None)
def model_description():
    return read_model_description(str(fmu()))


def start_values() -> dict:
    return {v.name: v.start for v in model_description().modelVariables if v.start is not None}


def params(**overrides) -> ref.NozzleParams:
    return ref.NozzleParams.from_values({**start_values(), **overrides})


def run(start: dict, stop_time: float = 1.0, interval: float = 1e-3, tolerance: float | None = 1e-10, outputs=outputs_of("pitch"), inputs=None):
    extra = {} if tolerance is None else {"relative_tolerance": tolerance}
    if inputs is not None:
        table = np.zeros(2, dtype=[("time", float)] + [(name, float) for name in inputs])
        table["time"] = [0.0, stop_time]
        for name, value in inputs.items():
            table[name] = value
        extra["input"] = table
    return simulate_fmu(str(fmu()), fmi_type="CoSimulation", stop_time=stop_time, output_interval=interval,
                        start_values=start, output=list(outputs), **extra)


def grid(stop_time: float, interval: float) -> np.ndarray:
    return np.round(np.arange(int(round(stop_time / interval)) + 1) * interval, 12)


def worst(res, expected: dict, names) -> tuple[float, str, float]:
    """(largest |FMU - reference| over the reference's range, the output, its time)."""
    found = (0.0, "", 0.0)
    for name in names:
        exp = np.asarray(expected[name])
        span = float(np.max(exp) - np.min(exp))
        if span == 0.0:  # a constant (a held command): against its own magnitude
            span = max(float(np.max(np.abs(exp))), 1e-300)
        err = np.abs(np.asarray(res[name]) - exp) / span
        k = int(np.argmax(err))
        found = max(found, (float(err[k]), name, float(res["time"][k])))
    return found


# ---- the defaults and their sources ---------------------------------------------------------------

DEG = math.pi / 180.0
# (parameter, value from its source's numbers, the source): docs/booster-nozzle-spec.md, "Values".
DEFAULTS = [
    ("J_nozzle", 1.40e3, "Vega P80 nozzle inertia, Budinger's Vega TVC course (SizingLab/sizing_course, Lab-vega)"),
    ("K_bearing", 15_200.0 / DEG, "15 200 N m/deg, same source"),
    ("D_bearing", 174.0 / DEG, "174 N m s/deg, same source"),
    ("r_arm", 1.35, "1.35 m lever arm, same source"),
    ("A_piston", math.pi / 4 * (0.100**2 - 0.050**2), "100 mm bore, 50 mm through rod"),
    ("V_chamber", 1.0e-3, "half stroke 58.9 cm2 x 145 mm = 854 cm3 + 146 cm3 dead volume"),
    ("B_oil", 1.5e9, "air-free hydraulic oil, 1.4-1.8 GPa"),
    ("R_leakage", 3.0e10, "1/K_c = 2 Ps / Q0 = 2 x 20.7 MPa / (A r 10 deg/s) = 2.98e10"),
    ("m_actuator", 30.0, "actuator body"),
    ("K_anchor", 1e8, "100 kN/mm anchoring"),
    ("D_anchor", 2 * 0.05 * math.sqrt(1e8 * 30.0), "5 % of critical for the body alone on its anchoring"),
    ("K_v", 3.0 / 0.072, "rigid loop's 5 % response time = the P80's 72 ms"),
    ("M_offset", 2.26e6 * 5e-3, "2.26 MN thrust passing 5 mm from the pivot"),
    ("offset_azimuth", 0.0, ""), ("command_amplitude", 0.5 * DEG, "the P80's 0.5 deg dynamic step"),
    ("command_azimuth", 0.0, ""), ("step_time", 0.1, ""), ("sine_frequency", 2.0, "an endurance cycle"),
]


def test_defaults_are_the_specs_values():
    starts = start_values()
    wrong = [f"{name}: FMU {starts[name]}, spec {value} ({source})" for name, value, source in DEFAULTS
             if not math.isclose(float(starts[name]), value, rel_tol=1e-14, abs_tol=0.0 if value else 1e-300)]
    assert not wrong, "\n".join(wrong)
    # R_leakage is the rounded valve coefficient 2 Ps / Q0, Q0 the flow of a 10 deg/s nozzle rate.
    q0 = float(starts["A_piston"]) * 1.35 * 10 * DEG
    assert 2 * 20.7e6 / q0 == pytest.approx(3.0e10, rel=0.01)
    md = model_description()
    profile = next(v for v in md.modelVariables if v.name == "profile")
    assert (profile.type, profile.variability, int(profile.min), int(profile.max), int(profile.start)) == ("Enumeration", "fixed", 0, 2, 1)
    assert [(i.name, int(i.value)) for i in profile.declaredType.items] == [("none", 0), ("step", 1), ("sine", 2)]
    de = md.defaultExperiment
    assert (float(de.startTime), float(de.stopTime), float(de.stepSize)) == (0.0, 1.0, 1e-3)
    units = {v.name: v.unit for v in md.modelVariables}
    for name, unit in [("nozzle_angle_pitch", "rad"), ("actuator_force_yaw", "N"), ("pressure_difference_pitch", "Pa"),
                       ("hinge_moment_yaw", "N.m"), ("valve_flow_pitch", "m3/s"), ("K_bearing", "N.m/rad"), ("D_bearing", "N.m.s/rad"),
                       ("J_nozzle", "kg.m2"), ("K_v", "1/s"), ("R_leakage", "Pa.s/m3"), ("f_actuator_nozzle", "Hz")]:
        assert units[name] == unit, name
    assert md.modelExchange is not None and md.coSimulation is not None
    assert md.modelExchange.providesDirectionalDerivative


def test_derived_parameters():
    """k_oil = 2 A^2 B / V, the chain's two natural frequencies (scipy's eigh on the test's M and K),
    sqrt(K_b / J), the servo's static stiffness r^2 / (1/K_a + 1/(A^2 R K_v)), J / r^2."""
    p = params()
    res = run({}, stop_time=1e-3, interval=1e-3, tolerance=None,
              outputs=("k_oil", "f_actuator_nozzle", "f_actuator_body", "f_bearing", "K_servo_static", "m_nozzle_rod"))
    w, _ = ref.two_dof_modes(p)
    expected = {
        "k_oil": 2 * p.A_piston**2 * p.B_oil / p.V_chamber,
        "f_actuator_nozzle": w[0] / (2 * math.pi),
        "f_actuator_body": w[1] / (2 * math.pi),
        "f_bearing": math.sqrt(p.K_bearing / p.J_nozzle) / (2 * math.pi),
        "K_servo_static": p.r_arm**2 / (1 / p.K_anchor + 1 / (p.A_piston**2 * p.R_leakage * p.K_v)),
        "m_nozzle_rod": p.J_nozzle / p.r_arm**2,
    }
    for name, value in expected.items():
        assert res[name][-1] == pytest.approx(value, rel=1e-12), name
    k_series = 1 / (1 / p.k_oil + 1 / p.K_anchor)
    f_massless = math.sqrt((p.K_bearing + p.r_arm**2 * k_series) / p.J_nozzle) / (2 * math.pi)
    REPORT.append(f"k_oil = {expected['k_oil']:.4g} N/m, K_anchor = {p.K_anchor:.3g} N/m, in series {k_series:.4g} N/m; J/r^2 = "
                  f"{expected['m_nozzle_rod']:.1f} kg on the rod; f_bearing = {expected['f_bearing']:.4f} Hz; two-DOF chain: "
                  f"f_actuator_nozzle = {expected['f_actuator_nozzle']:.4f} Hz (massless body: {f_massless:.4f} Hz), "
                  f"f_actuator_body = {expected['f_actuator_body']:.3f} Hz; K_servo_static = {expected['K_servo_static']:.4g} N m/rad")


# ---- the actuator-nozzle resonance ------------------------------------------------------------------

def fmu_jacobian(overrides: dict, axis: str = "pitch") -> np.ndarray:
    """d(der(x))/dx of one axis's five states at rest, column by column from the FMU's
    fmi2GetDirectionalDerivative (Model Exchange, continuous-time mode)."""
    md = model_description()
    m = FMU2Model(guid=md.guid, unzipDirectory=unzipdir(fmu_key(fmu())), modelIdentifier=md.modelExchange.modelIdentifier, instanceName="jac")
    variables = {v.name: v for v in md.modelVariables}
    m.instantiate()
    try:
        m.setupExperiment(startTime=0.0)
        for name, value in overrides.items():
            v = variables[name]
            if v.type in ("Integer", "Enumeration"):
                m.setInteger([v.valueReference], [int(value)])
            else:
                m.setReal([v.valueReference], [float(value)])
        m.enterInitializationMode()
        m.exitInitializationMode()
        while m.newDiscreteStates()[0]:
            pass
        m.enterContinuousTimeMode()
        by_state = {d.variable.derivative.name: d.variable.valueReference for d in md.derivatives}
        states = [f"{s}_{axis}" for s in AXIS_STATES]
        unknowns = [by_state[s] for s in states]
        jac = np.zeros((5, 5))
        for j, s in enumerate(states):
            jac[:, j] = m.getDirectionalDerivative(unknowns, [variables[s].valueReference], [1.0])
        return jac
    finally:
        m.terminate()
        m.freeInstance()


def resonance(eigenvalues: np.ndarray, near: float) -> complex:
    """The eigenvalue (positive imaginary part) whose modulus is nearest `near` rad/s."""
    return min((lam for lam in eigenvalues if lam.imag > 0), key=lambda lam: abs(abs(lam) - near))


# The valve closed (no loop flow), sealed (no leak), the bearing and the anchoring without damping: the
# FMU's axis is then the undamped chain plus the conserved oil volume (an eigenvalue 0).
CHAIN = {"K_v": 0.0, "R_leakage": 1e30, "D_bearing": 0.0, "D_anchor": 0.0, "profile": 0, "M_offset": 0.0}


@pytest.mark.parametrize("axis", ["pitch", "yaw"])
def test_resonance_against_the_two_dof_eigenvalues(axis):
    """The chain's conditions: the FMU's Jacobian (directional derivatives) has the two-DOF chain's
    natural frequencies as +-i w; the default actuator (loop closed, leakage, bearing damping) keeps
    its resonance within 1 % of the chain's. Both axes."""
    p = params(**CHAIN)
    w, _ = ref.two_dof_modes(p)
    eig = np.linalg.eigvals(fmu_jacobian(CHAIN, axis))
    for k, wk in enumerate(w):
        lam = resonance(eig, wk)
        assert abs(lam.real) <= 1e-6 * wk, lam
        assert lam.imag == pytest.approx(wk, rel=1e-6), (k, lam, wk)
    assert min(abs(eig)) <= 1e-6 * w[0]
    low = resonance(eig, w[0])
    # The default actuator: the FMU's Jacobian against the reference's matrix (referred coordinates:
    # the FMU keeps the body's x / r, a similarity transform that leaves the eigenvalues alone) ...
    d = params()
    jac = fmu_jacobian({}, axis)
    F, _ = ref.system_matrix(d)
    T = np.diag([1.0, 1.0, 1.0, 1.0 / d.r_arm, 1.0 / d.r_arm])
    np.testing.assert_allclose(jac, T @ F @ np.linalg.inv(T), rtol=1e-6, atol=1e-9 * np.max(np.abs(F)))
    eig_d = np.linalg.eigvals(jac)
    w_d, _ = ref.two_dof_modes(d)
    lam = resonance(eig_d, w_d[0])
    body = resonance(eig_d, w_d[1])
    f_chain, f_default = w_d[0] / (2 * math.pi), abs(lam) / (2 * math.pi)
    REPORT.append(f"resonance ({axis}): chain {f_chain:.4f} Hz and {w_d[1] / (2 * math.pi):.3f} Hz; FMU Jacobian, chain conditions "
                  f"{low.imag / (2 * math.pi):.6f} Hz ({low.imag / w[0] - 1:+.1e}); default actuator {f_default:.4f} Hz "
                  f"({100 * (f_default / f_chain - 1):+.2f} %), damping {-lam.real / abs(lam):.4f}, damped {lam.imag / (2 * math.pi):.3f} Hz; "
                  f"body mode {abs(body) / (2 * math.pi):.2f} Hz, damping {-body.real / abs(body):.4f}; "
                  f"loop pole {min((l.real for l in eig_d if abs(l.imag) < 1e-9 and l.real < -1.0), key=abs):.2f} /s")
    assert f_default == pytest.approx(f_chain, rel=0.01)
    assert np.all(eig_d.real < 0), eig_d


def test_resonance_as_a_free_oscillation():
    """The FMU released from the chain's low mode shape (0.5 deg of nozzle, the body's share, the oil's
    dp = -(k/A)(r theta - x_b), at rest), valve closed and sealed, the bearing's and the anchoring's
    damping kept: the
    zero crossings of the nozzle rate give the damped period, the decay of its peaks sigma, and
    sqrt(w_d^2 + sigma^2) the natural frequency, against the chain's within 1 %."""
    case = {**CHAIN, "D_bearing": float(params().D_bearing), "D_anchor": float(params().D_anchor)}
    p = params(**case)
    w, phi = ref.two_dof_modes(p)
    theta0 = 0.5 * DEG
    x_b0 = theta0 * phi[1, 0] / phi[0, 0]
    dp0 = -(p.k_oil / p.A_piston) * (p.r_arm * theta0 - x_b0)
    start = {**case, "theta_pitch": theta0, "phi_body_pitch": x_b0 / p.r_arm, "dp_pitch": dp0}
    res = run(start, stop_time=0.2, interval=2e-5, outputs=("nozzle_rate_pitch", "nozzle_angle_pitch"))
    t, y = np.asarray(res["time"]), np.asarray(res["nozzle_rate_pitch"])
    s = np.nonzero(np.diff(np.sign(y)) != 0)[0]
    s = s[s > 0]
    crossings = t[s] - y[s] * (t[s + 1] - t[s]) / (y[s + 1] - y[s])
    period = 2 * float(np.mean(np.diff(crossings)))
    peaks = [float(np.max(np.abs(y[(t >= a) & (t < b)]))) for a, b in zip(crossings[:-1], crossings[1:])]
    sigma = -np.polyfit(0.5 * (crossings[:-1] + crossings[1:]), np.log(peaks), 1)[0]
    f = math.sqrt((2 * math.pi / period) ** 2 + sigma**2) / (2 * math.pi)
    f_chain = w[0] / (2 * math.pi)
    REPORT.append(f"free oscillation (valve closed, dampings kept): {f:.4f} Hz over {len(crossings)} crossings "
                  f"({100 * (f / f_chain - 1):+.3f} % from the chain's {f_chain:.4f} Hz), damping {sigma / (2 * math.pi * f):.4f}")
    assert f == pytest.approx(f_chain, rel=0.01)


def gain_limit(p: ref.NozzleParams) -> float:
    """The K_v at which the reference's matrix gets an eigenvalue with a positive real part (bisection)."""

    def growth(kv):
        return float(np.max(np.linalg.eigvals(ref.system_matrix(p.with_(K_v=kv))[0]).real))

    lo, hi = p.K_v, 10 * p.K_v
    assert growth(lo) < 0 < growth(hi)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if growth(mid) < 0 else (lo, mid)
    return 0.5 * (lo + hi)


def test_the_loop_gain_limit():
    """How far the position loop's gain can go. Without structural damping the reference's matrix
    meets Merritt's bound for a valve-controlled actuator damped by the valve's flow-pressure
    coefficient, K_v < 2 zeta_h w_h = K_c / C = 1 / (R_leakage C) (mass and stiffness cancel out of
    it), within 1 %; the anchoring's damping raises it. The FMU's Jacobian is stable at 0.98 x the
    default's limit and unstable at 1.02 x."""
    p = params()
    undamped = gain_limit(p.with_(D_anchor=0.0))
    merritt = 1.0 / (p.R_leakage * p.C)
    assert undamped == pytest.approx(merritt, rel=0.01)
    limit = gain_limit(p)
    assert np.max(np.linalg.eigvals(fmu_jacobian({"K_v": 0.98 * limit})).real) < 0
    above = np.linalg.eigvals(fmu_jacobian({"K_v": 1.02 * limit}))
    unstable = max(above, key=lambda lam: lam.real)
    assert unstable.real > 0
    REPORT.append(f"loop gain limit: K_v = {limit:.2f} /s ({limit / p.K_v:.2f} x the default {p.K_v:.2f}), past it the mode at "
                  f"{abs(unstable) / (2 * math.pi):.1f} Hz goes unstable; without the anchoring's damping {undamped:.3f} /s, "
                  f"Merritt's 1/(R C) = {merritt:.3f} /s ({100 * (undamped / merritt - 1):+.2f} %)")


# ---- the static deflection by hand ---------------------------------------------------------------

# The magnitude of each static output in these cases, the scale of an absolute tolerance near 0.
TYPICAL = {"nozzle_angle": 1e-3, "actuator_force": 1e3, "pressure_difference": 1e5, "hinge_moment": 1e3, "anchoring_deflection": 1e-5,
           "actuator_stroke": 1e-3, "valve_flow": 1e-6}
STATIC_CASES = {
    "loop_closed_50kNm": ({"profile": 0, "M_offset": 0.0}, {"M_aero_pitch": 5e4, "M_aero_yaw": 5e4}, 0.0, 5e4),
    "command_3deg_with_offset": ({"command_amplitude": 3 * DEG, "step_time": 0.0}, None, 3 * DEG, None),
    "loop_open_50kNm": ({"profile": 0, "M_offset": 0.0, "K_v": 0.0, "R_leakage": 1e9}, {"M_aero_pitch": 5e4, "M_aero_yaw": 5e4}, 0.0, 5e4),
}


@pytest.mark.parametrize("case", list(STATIC_CASES))
def test_static_deflection_by_hand(case):
    """A constant torque (and a held command): after 1.5 s every static output against the hand balance,
    theta = (K_s theta_cmd + M) / (K_s + K_b). The slowest pole has decayed by e^-27 or more: the loop's
    -42.6 /s; loop open, the nozzle on its bearing damped by D_bearing and by the oil pushed through
    R_leakage = 1e9 (R A^2 r^2 = 6.3e4 N m s/rad, overdamped: -18 /s). Both axes when both are loaded alike."""
    start, inputs, theta_cmd, m_aero = STATIC_CASES[case]
    p = params(**start)
    moment = p.M_offset + (m_aero or 0.0)
    hand = ref.static_deflection(p, moment, theta_cmd)
    axes = ["pitch", "yaw"] if inputs else ["pitch"]
    res = run(start, stop_time=1.5, interval=0.01, outputs=sum((outputs_of(a) for a in axes), ()), inputs=inputs)
    worst_error = 0.0
    for axis in axes:
        for name, value in hand.items():
            got = float(res[f"{name}_{axis}"][-1])
            scale = max(abs(value), TYPICAL[name])
            worst_error = max(worst_error, abs(got - value) / scale)
            assert abs(got - value) <= 1e-8 * scale, f"{case} {axis}: {name} = {got!r}, by hand {value!r}"
    REPORT.append(f"static, {case}: M {moment:.4g} N m, command {theta_cmd / DEG:g} deg: theta {hand['nozzle_angle'] / DEG:.5f} deg "
                  f"(K_s {p.servo_static_stiffness:.4g} N m/rad against K_b {p.K_bearing:.4g}), F {hand['actuator_force']:.1f} N, "
                  f"dp {hand['pressure_difference'] / 1e6:.4f} MPa, anchoring {1e3 * hand['anchoring_deflection']:.4f} mm; FMU within {worst_error:.1e}")


# ---- pitch and yaw ------------------------------------------------------------------------------------

def test_a_pitch_command_leaves_yaw_at_rest():
    """Pitch and yaw are identical and uncoupled: the default run (the step and the offset torque
    all in pitch) leaves every yaw output exactly 0; turned by 90 degrees (both azimuths pi/2) the yaw
    axis repeats the pitch axis's default run."""
    both = outputs_of("pitch") + outputs_of("yaw")
    default = run({}, outputs=both)
    for name in outputs_of("yaw"):
        assert np.all(np.asarray(default[name]) == 0.0), name
    assert np.max(np.abs(default["nozzle_angle_pitch"])) > 0.4 * DEG
    turned = run({"command_azimuth": math.pi / 2, "offset_azimuth": math.pi / 2}, outputs=both)
    err = max(float(np.max(np.abs(np.asarray(turned[f"{n}_yaw"]) - np.asarray(default[f"{n}_pitch"])))
                    / np.ptp(np.asarray(default[f"{n}_pitch"]))) for n in AXIS_OUTPUTS)
    # The pitch share of the turned run is cos(pi/2) = 6e-17 of the default's.
    pitch_left = float(np.max(np.abs(turned["nozzle_angle_pitch"])) / np.max(np.abs(default["nozzle_angle_pitch"])))
    REPORT.append(f"pitch/yaw: default run, yaw outputs all exactly 0; turned 90 deg, yaw repeats pitch within {err:.1e} of the ranges "
                  f"(pitch left at {pitch_left:.1e})")
    assert err <= 1e-9
    assert pitch_left <= 1e-15


# ---- transients against the closed form -----------------------------------------------------------

@pytest.mark.parametrize("case", ["step", "sine", "inputs"])
def test_transients_against_the_closed_form(case):
    """The default step, the 2 Hz sine (profile 2), and the inputs alone (profile 0: a 0.25 deg yaw
    command and a 20 kN m aerodynamic torque from t = 0): every output of the driven axis against the
    reference's closed form."""
    start = {"step": {}, "sine": {"profile": 2}, "inputs": {"profile": 0, "M_offset": 0.0}}[case]
    axis = "yaw" if case == "inputs" else "pitch"
    inputs = {"theta_command_yaw": 0.25 * DEG, "M_aero_yaw": 2e4} if case == "inputs" else None
    p = params(**start)
    t = grid(1.0, 1e-3)
    expected = ref.simulate(p, axis, t, command_in=(inputs or {}).get("theta_command_yaw", 0.0), m_aero=(inputs or {}).get("M_aero_yaw", 0.0))
    res = run(start, outputs=outputs_of(axis), inputs=inputs)
    err, name, at = worst(res, expected, outputs_of(axis))
    dp = np.asarray(res[f"pressure_difference_{axis}"])
    rate = np.asarray(res[f"nozzle_rate_{axis}"])
    REPORT.append(f"transient ({case}, {axis}): worst |FMU - closed form| {err:.2e} of the range ({name} at {at:g} s); dp {dp.min() / 1e6:.2f} .. "
                  f"{dp.max() / 1e6:.2f} MPa, nozzle rate up to {np.max(np.abs(rate)) / DEG:.1f} deg/s")
    assert err <= REL_TOL, f"{name}: {err:.3e} of its range at t = {at} s"


def test_step_response_figures():
    """The default step (0.5 deg at 0.1 s): 5 % response time and overshoot, against the rigid loop's
    3 / K_v = 72 ms; the final angle is the static one by hand (command plus the offset's deflection)."""
    p = params()
    res = run({}, stop_time=1.0, interval=1e-4, tolerance=None, outputs=("nozzle_angle_pitch", "pressure_difference_pitch"))
    t, theta = np.asarray(res["time"]), np.asarray(res["nozzle_angle_pitch"])
    before = float(theta[np.searchsorted(t, p.step_time) - 1])
    final = ref.static_deflection(p, p.M_offset, p.command_amplitude)["nozzle_angle"]
    assert float(theta[-1]) == pytest.approx(final, rel=1e-6)
    after = t >= p.step_time
    travel = final - before
    outside = np.nonzero(np.abs(theta[after] - final) > 0.05 * abs(travel))[0]
    t5 = float(t[after][outside[-1] + 1] - p.step_time)
    overshoot = (float(np.max(theta[after])) - final) / travel
    REPORT.append(f"step response: 5 % response time {1e3 * t5:.1f} ms (rigid loop 3/K_v = {3e3 / p.K_v:.1f} ms), overshoot "
                  f"{100 * overshoot:.1f} %, final {final / DEG:.5f} deg (command {p.command_amplitude / DEG:g} deg + offset's "
                  f"{(final - p.command_amplitude * p.servo_static_stiffness / (p.servo_static_stiffness + p.K_bearing)) / DEG:.5f} deg)")
    assert t5 < 0.1


# ---- question 2: the dominant effect of each part ------------------------------------------------------

SCENARIOS = {
    # name: (start values, stop time)
    "step": ({}, 1.0),
    "sine_2Hz": ({"profile": 2}, 1.0),
    "endurance_0.3Hz_5.7deg": ({"profile": 2, "sine_frequency": 0.3, "command_amplitude": 5.7 * DEG, "step_time": 0.0}, 10 / 3),
}


@functools.lru_cache(maxsize=None)
def shares(scenario: str) -> tuple[dict, dict]:
    """(the FMU's activities and shares of the pitch elements, the reference's activities)."""
    start, stop = SCENARIOS[scenario]
    names = [f"activity_{n}_pitch" for n in ref.STORAGE + ref.DISSIPATION] + [f"share_{n}_pitch" for n in ref.STORAGE + ref.DISSIPATION]
    res = run(start, stop_time=stop, interval=stop / 100, tolerance=1e-10, outputs=names)
    fmu_values = {n: float(res[n][-1]) for n in names}
    return fmu_values, ref.activities(params(**start), "pitch", stop)


@pytest.mark.parametrize("scenario", list(SCENARIOS))
def test_activities_against_the_reference(scenario):
    """Each element's activity (eq. 3.3) and share: the FMU's against the reference's powers
    integrated on a 5 us grid (within 2e-4 relative: the grid's error on the body's 417 Hz ringing)."""
    fmu_values, reference = shares(scenario)
    for group in (ref.STORAGE, ref.DISSIPATION):
        total = sum(reference[n] for n in group)
        for n in group:
            got = fmu_values[f"activity_{n}_pitch"]
            assert got == pytest.approx(reference[n], rel=2e-4, abs=2e-5 * total), (scenario, n)
            assert fmu_values[f"share_{n}_pitch"] == pytest.approx(100 * reference[n] / total, abs=2e-3), (scenario, n)
    REPORT.append(f"shares, {scenario}: storage " + ", ".join(f"{n} {fmu_values[f'share_{n}_pitch']:.2f} %" for n in ref.STORAGE)
                  + "; dissipation " + ", ".join(f"{n} {fmu_values[f'share_{n}_pitch']:.2f} %" for n in ref.DISSIPATION))


def test_the_dominant_effects_table():
    """The claims of the spec's question-2 table, on the FMU's shares (Table 3.3's ranking):
    * the nozzle: its inertia is the largest storage in the fast step;
    * the flexible bearing: its stiffness is the storage in a slow, large motion (the endurance cycle);
    * the actuator: its oil and the anchoring share the step's storage about equally (the series
      spring of the resonance), the body's mass stays small;
    * the servo-valve's K_c (the leakage element) is the main dissipation, the bearing's damping second."""
    step, _ = shares("step")
    slow, _ = shares("endurance_0.3Hz_5.7deg")
    sine, _ = shares("sine_2Hz")
    s = lambda d, n: d[f"share_{n}_pitch"]  # noqa: E731
    assert max(ref.STORAGE, key=lambda n: s(step, n)) == "nozzle_inertia"
    assert s(slow, "bearing_stiffness") > 90.0
    assert max(ref.STORAGE, key=lambda n: s(sine, n)) == "bearing_stiffness"
    assert s(step, "oil") > 15.0 and s(step, "anchoring") > 15.0
    assert abs(s(step, "oil") - s(step, "anchoring")) < 5.0
    assert max(s(d, "actuator_body") for d in (step, slow, sine)) < 10.0
    for d in (step, slow, sine):
        assert s(d, "leakage") > s(d, "bearing_damping")
