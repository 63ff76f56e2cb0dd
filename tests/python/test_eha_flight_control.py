"""EhaFlightControl against its contract, docs/eha-flight-control-spec.md (chapter 3, section 3.4.1.2,
Figure 3.16.a, Table 3.5).

Where each reference comes from (never a previous run of the FMU):
  * the defaults: the spec's arguments, recomputed here from their sources' numbers (`DEFAULTS`);
  * the steady state: by hand (eha_reference.steady_state): the surface at rest holds the hinge moment,
    dp = M_hinge / (r A), the pump's shaft torque D dp is the motor's k i, level 2's leakage dp / R is
    made up by the pump turning at w = Q / D, and the law's voltage is R i + k w;
  * the transients (the linear case without saturation, and the default saturated run): the spec's
    equations written out in eha_reference.py and integrated by scipy's DOP853 at rtol 1e-12, segment by
    segment (command steps and the voltage limit's corners located by terminal events);
  * the hydraulic mode: sqrt(k / m), k = 2 A^2 B / V (two chambers of V at mid stroke, Table 3.2's
    C = V / B each), m = J_surface / r^2, against the FMU's own linearisation (finite differences of its
    Model Exchange derivatives) and against a free oscillation simulated by the FMU;
  * the gain the mode allows: the analytic matrix of eha_reference.jacobian (bisection on its hydraulic
    eigenvalue's real part) against the FMU's linearisation on either side of it.
Parameter values are the FMU's start values (modelDescription.xml) with a case's overrides.
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest
from fmi_host import state_jacobian
from fmpy import read_model_description, simulate_fmu

import eha_reference as ref
from conftest import DIST_DIR, print_past_capture, require_fmu

REL_TOL = 1e-6  # of each output's range, FMU at rtol 1e-10 against the scipy reference
COMPARED = ("surface_angle", "surface_rate", "motor_voltage", "motor_current", "motor_speed", "motor_torque", "pump_pressure",
            "pump_flow", "piston_position", "piston_force", "hinge_moment", "leakage_flow", "bus_current")
# The magnitude each output has in the default run, the scale of an absolute tolerance near zero.
TYPICAL = {"surface_angle": 0.1, "hinge_moment": 1e3, "pump_pressure": 1e7, "piston_force": 1e4, "motor_current": 10.0,
           "motor_torque": 1.0, "motor_speed": 100.0, "motor_voltage": 10.0, "leakage_flow": 1e-5, "surface_rate": 1.0}
STATES = ("i_motor", "w_motor", "dp_load", "theta_surface", "w_surface")
REPORT: list[str] = []


@pytest.fixture(scope="module", autouse=True)
def _print_report(request):
    yield
    print_past_capture(request, "== EhaFlightControl: figures of the spec", REPORT)


def fmu():
    return require_fmu(DIST_DIR / "EhaFlightControl.fmu")


@functools.lru_cache(maxsize=None)
def model_description():
    return read_model_description(str(fmu()))


def start_values() -> dict:
    return {v.name: v.start for v in model_description().modelVariables if v.start is not None}


def params(**overrides) -> ref.EhaParams:
    return ref.EhaParams.from_values({**start_values(), **overrides})


def run(start: dict, stop_time: float = 1.0, interval: float = 1e-3, tolerance: float | None = 1e-10, outputs=COMPARED):
    extra = {} if tolerance is None else {"relative_tolerance": tolerance}
    return simulate_fmu(str(fmu()), fmi_type="CoSimulation", stop_time=stop_time, output_interval=interval,
                        start_values=start, output=list(outputs), **extra)


def grid(stop_time: float, interval: float) -> np.ndarray:
    return np.round(np.arange(int(round(stop_time / interval)) + 1) * interval, 12)


def worst(res, expected: dict, names=COMPARED) -> tuple[float, str, float]:
    """(largest |FMU - reference| over the reference's range, the output, its time)."""
    found = (0.0, "", 0.0)
    for name in names:
        exp = np.asarray(expected[name])
        span = float(np.max(exp) - np.min(exp))
        if span == 0.0:
            assert np.all(np.asarray(res[name]) == exp), name
            continue
        err = np.abs(np.asarray(res[name]) - exp) / span
        k = int(np.argmax(err))
        found = max(found, (float(err[k]), name, float(res["time"][k])))
    return found


# ---- the defaults and their sources ---------------------------------------------------------------

# (parameter, value from its source's numbers, the source): docs/eha-flight-control-spec.md, "Values".
DEFAULTS = [
    ("U_bus", 270.0, "MIL-STD-704 HVDC bus, 270 V"),
    ("D_pump", 1.5e-6 / (2 * math.pi), "1.5 cm3/rev, published EHA pumps 1-3 cm3/rev"),
    ("A_piston", math.pi / 4 * (0.050**2 - 0.028**2), "50 mm bore, 28 mm through rod"),
    ("r_horn", 0.1, "horn arm 100 mm"),
    ("J_surface", 5.0, "aileron about its hinge"),
    ("K_hinge", 1e4, "q S c |C_h,delta|: 20 kPa x 1.4 m2 x 0.6 m x 0.6 /rad"),
    ("V_chamber", 80e-6, "57 cm3 swept (half stroke) + 23 cm3 dead volume and passages"),
    ("B_oil", 1.5e9, "air-free aviation oil, 1.4-1.8 GPa"),
    ("R_leakage", 20.7e6 / (0.5e-3 / 60), "0.5 L/min at 20.7 MPa (3000 psi)"),
    ("R_motor", 1.0, "chosen motor"), ("L_motor", 2e-3, "chosen motor"), ("k_motor", 0.4, "chosen motor"),
    ("J_motor", 2e-4, "rotor and pump"), ("Kp", 3000.0, "about 40 % of the hydraulic mode's gain limit"),
    ("step_angle", math.radians(10.0), "10 degree step"), ("step_time", 0.1, ""), ("return_time", 0.6, ""),
]


def test_defaults_are_the_specs_values():
    starts = start_values()
    wrong = [f"{name}: FMU {starts[name]}, spec {value} ({source})" for name, value, source in DEFAULTS
             if not math.isclose(float(starts[name]), value, rel_tol=1e-14)]
    assert not wrong, "\n".join(wrong)
    assert int(starts["level"]) == 2
    md = model_description()
    level = next(v for v in md.modelVariables if v.name == "level")
    assert (level.type, level.variability, int(level.min), int(level.max)) == ("Enumeration", "fixed", 1, 2)
    assert [(i.name, int(i.value)) for i in level.declaredType.items] == [("ideal_transformers", 1), ("compressible_oil", 2)]
    de = md.defaultExperiment
    assert (float(de.startTime), float(de.stopTime), float(de.stepSize)) == (0.0, 1.0, 1e-3)
    units = {v.name: v.unit for v in md.modelVariables}
    for name, unit in [("surface_angle", "rad"), ("motor_current", "A"), ("motor_speed", "rad/s"), ("pump_pressure", "Pa"),
                       ("piston_force", "N"), ("hinge_moment", "N.m"), ("pump_flow", "m3/s"), ("D_pump", "m3/rad"),
                       ("V_chamber", "m3"), ("R_leakage", "Pa.s/m3"), ("Kp", "V/rad")]:
        assert units[name] == unit, name
    assert md.modelExchange is not None and md.coSimulation is not None


def test_derived_parameters():
    """gear ratio N = A r / D, J_s / N^2, the masses on the rod and f_hydraulic = sqrt(2 A^2 B / V / (J_s / r^2)) / 2 pi."""
    p = params()
    res = run({}, stop_time=1e-3, interval=1e-3, tolerance=None,
              outputs=("gear_ratio", "J_surface_referred", "m_surface_rod", "m_rotor_rod", "f_hydraulic"))
    expected = {
        "gear_ratio": p.A_piston * p.r_horn / p.D_pump,
        "J_surface_referred": p.J_surface * (p.D_pump / (p.A_piston * p.r_horn)) ** 2,
        "m_surface_rod": p.J_surface / p.r_horn**2,
        "m_rotor_rod": p.J_motor * (p.A_piston / p.D_pump) ** 2,
        "f_hydraulic": math.sqrt(2 * p.A_piston**2 * p.B_oil / p.V_chamber / (p.J_surface / p.r_horn**2)) / (2 * math.pi),  # written out
    }
    for name, value in expected.items():
        assert res[name][-1] == pytest.approx(value, rel=1e-12), name
    REPORT.append(f"N = {expected['gear_ratio']:.2f} motor rad per surface rad; J_s/N^2 = {expected['J_surface_referred']:.4g} kg m2 "
                  f"(rotor {p.J_motor:g}); on the rod: surface {expected['m_surface_rod']:.0f} kg, rotor {expected['m_rotor_rod']:.0f} kg; "
                  f"k_oil = {p.k_oil:.4g} N/m; f_hydraulic = {expected['f_hydraulic']:.3f} Hz")


# ---- the steady state by hand ------------------------------------------------------------------------

@pytest.mark.parametrize("level", [1, 2])
@pytest.mark.parametrize("m_external", [0.0, 800.0], ids=["no_external_moment", "M_external_800"])
def test_steady_state_by_hand(level, m_external):
    """The command held (return_time beyond the run), 3 s: the slowest pole (-13.7 /s) has decayed by
    e^-38. Every static output against the hand balance."""
    start = {"level": level, "return_time": 100.0, "M_external": m_external}
    res = run(start, stop_time=3.0, interval=0.01)
    p = params(level=level, return_time=100.0)
    hand = ref.steady_state(p, p.step_angle, m_external)
    worst_error = 0.0
    for name, value in hand.items():
        got = float(res[name][-1])
        worst_error = max(worst_error, abs(got - value) / max(abs(value), TYPICAL[name]))
        assert abs(got - value) <= 1e-8 * max(abs(value), TYPICAL[name]), f"level {level}, M_external {m_external}: {name} = {got!r}, by hand {value!r}"
    # The two statements of the issue: dp = M_hinge / (r A), and the current from T = D dp = k i.
    assert res["pump_pressure"][-1] == pytest.approx(res["hinge_moment"][-1] / (p.r_horn * p.A_piston), rel=1e-9)
    assert res["motor_current"][-1] == pytest.approx(p.D_pump * res["pump_pressure"][-1] / p.k_motor, rel=1e-9)
    error = p.step_angle - hand["surface_angle"]
    REPORT.append(f"steady state, level {level}, M_external {m_external:g} N m: theta {math.degrees(hand['surface_angle']):.4f} deg "
                  f"(error {math.degrees(error):.4f} deg, {100 * error / p.step_angle:.2f} % of the step), M {hand['hinge_moment']:.1f} N m, "
                  f"dp {hand['pump_pressure'] / 1e6:.3f} MPa, i {hand['motor_current']:.3f} A, w {hand['motor_speed']:.2f} rad/s, "
                  f"U {hand['motor_voltage']:.3f} V; FMU within {worst_error:.1e} (relative)")


# ---- transients against scipy -------------------------------------------------------------------------

@pytest.mark.parametrize("level", [1, 2])
def test_linear_case_against_scipy(level):
    """A 2 degree step (Kp e = 105 V < U_bus: the law never saturates), the equations linear."""
    start = {"level": level, "step_angle": math.radians(2.0)}
    p = params(**start)
    t = grid(1.0, 1e-3)
    expected = ref.simulate(p, t, rtol=1e-12)
    assert np.max(np.abs(expected["motor_voltage"])) < 0.5 * p.U_bus, "the linear case must stay clear of the limit"
    res = run(start)
    err, name, at = worst(res, expected)
    REPORT.append(f"linear case (2 deg), level {level}: worst |FMU - scipy| {err:.2e} of the range ({name} at {at:g} s)")
    assert err <= REL_TOL, f"{name}: {err:.3e} of its range at t = {at} s"


@pytest.mark.parametrize("level", [1, 2])
def test_default_run_against_scipy(level):
    """The default 10 degree step and return, the voltage saturated at U_bus: the corners of the limit
    are state events of the FMU and terminal events of the reference."""
    p = params(level=level)
    t = grid(1.0, 1e-3)
    expected = ref.simulate(p, t, rtol=1e-12)
    assert np.max(np.abs(expected["motor_voltage"])) == pytest.approx(p.U_bus, rel=1e-12), "the default run saturates"
    res = run({"level": level}, outputs=COMPARED + ("surface_angle_command",))
    err, name, at = worst(res, expected)
    REPORT.append(f"default run, level {level}: worst |FMU - scipy| {err:.2e} of the range ({name} at {at:g} s)")
    assert err <= REL_TOL, f"{name}: {err:.3e} of its range at t = {at} s"


# ---- the hydraulic mode ---------------------------------------------------------------------------------

def linearisation(overrides: dict) -> np.ndarray:
    """The FMU's Jacobian d(der(x))/dx of its physical states at rest (Model Exchange, central
    differences of fmi2GetDerivatives, steps of 1e-6 of each state's nominal)."""
    return state_jacobian(fmu(), STATES, overrides)


# The rotor made immovable: 1e3 kg m2 is 3.2e10 kg on the rod.
PUMP_HELD = {"level": 2, "J_motor": 1e3}


def against_sqrt_k_over_m(f: float, what: str, hinge_rel: float):
    """f against sqrt(k / m) (bound 2 %) and against the same with the hinge's stiffness beside the oil's."""
    p = params(**PUMP_HELD)
    f_oil, f_hinge = p.f_hydraulic_hz, p.f_hydraulic_with_hinge_hz
    REPORT.append(f"hydraulic mode, {what}: {f:.4f} Hz; sqrt(k/m) {f_oil:.4f} Hz ({100 * (f / f_oil - 1):+.2f} %), "
                  f"with the hinge stiffness {f_hinge:.4f} Hz ({100 * (f / f_hinge - 1):+.3f} %)")
    assert f == pytest.approx(f_oil, rel=0.02)
    assert f == pytest.approx(f_hinge, rel=hinge_rel)


def test_hydraulic_mode_with_the_pump_held():
    """The pump held: the surface rides on the two oil columns, at sqrt(k / m) with k = 2 A^2 B / V and
    m = J_s / r^2 (the hinge's K_h / r^2 adds 1.5 % to k). The FMU's linearisation."""
    p = params(**PUMP_HELD)
    lam = ref.hydraulic_mode(np.linalg.eigvals(linearisation(PUMP_HELD)), 2 * math.pi * p.f_hydraulic_hz)
    against_sqrt_k_over_m(abs(lam) / (2 * math.pi), f"pump held, linearisation (damping {-lam.real / abs(lam):.4f})", 1e-3)


def test_hydraulic_mode_as_a_free_oscillation():
    """The same, simulated: the pump held, the surface released from an initial pressure difference of
    1 MPa with no command; the surface rate's zero crossings over 0.2 s give the damped period, and
    sqrt(w_d^2 + sigma^2) (sigma from the decay of its peaks) the natural frequency."""
    res = run({**PUMP_HELD, "step_angle": 0.0, "dp_load": 1e6}, stop_time=0.2, interval=2e-5, tolerance=1e-10, outputs=("surface_rate",))
    t, y = np.asarray(res["time"]), np.asarray(res["surface_rate"])
    s = np.nonzero(np.diff(np.sign(y)) != 0)[0]
    crossings = t[s] - y[s] * (t[s + 1] - t[s]) / (y[s + 1] - y[s])
    period = 2 * float(np.mean(np.diff(crossings)))
    peaks = [float(np.max(np.abs(y[(t >= a) & (t < b)]))) for a, b in zip(crossings[:-1], crossings[1:])]
    sigma = -np.polyfit(0.5 * (crossings[:-1] + crossings[1:]), np.log(peaks), 1)[0]
    f = math.sqrt((2 * math.pi / period) ** 2 + sigma**2) / (2 * math.pi)
    against_sqrt_k_over_m(f, f"pump held, free oscillation over {len(crossings)} crossings", 2e-3)


def test_hydraulic_mode_of_the_default_actuator():
    """With the default rotor (6374 kg on the rod, 12.7 x the surface's 500 kg) held by the loop and its
    armature, the mode stays within 2 % of sqrt(k / m_surface); the FMU's eigenvalues are the
    reference's matrix's."""
    p = params()
    jac = linearisation({})
    near = math.sqrt(p.k_oil / p.m_surface)
    lam = ref.hydraulic_mode(np.linalg.eigvals(jac), near)
    lam_ref = ref.hydraulic_mode(np.linalg.eigvals(ref.jacobian(p)), near)
    assert abs(lam - lam_ref) <= 1e-5 * abs(lam_ref)
    np.testing.assert_allclose(np.sort_complex(np.linalg.eigvals(jac)), np.sort_complex(np.linalg.eigvals(ref.jacobian(p))), rtol=1e-5)
    f, f_oil = abs(lam) / (2 * math.pi), p.f_hydraulic_hz
    REPORT.append(f"hydraulic mode, default actuator: {f:.4f} Hz, damping {-lam.real / abs(lam):.4f} ({100 * (f / f_oil - 1):+.2f} % from "
                  f"sqrt(k/m) {f_oil:.4f} Hz); eigenvalues {np.round(np.linalg.eigvals(jac), 2)}")
    assert f == pytest.approx(f_oil, rel=0.02)


def test_the_mode_sets_the_loop_gain_limit():
    """Level 1 (rigid oil) stays stable far beyond the gain at which level 2's hydraulic mode goes
    unstable; the FMU's linearisation agrees with the reference's limit on either side of it."""
    p = params()
    kp_limit = ref.stability_limit_kp(p, p.Kp, 30 * p.Kp)
    near = math.sqrt(p.k_oil / p.m_surface)
    below = ref.hydraulic_mode(np.linalg.eigvals(linearisation({"Kp": 0.98 * kp_limit})), near)
    above = ref.hydraulic_mode(np.linalg.eigvals(linearisation({"Kp": 1.02 * kp_limit})), near)
    assert below.real < 0 < above.real, (below, above)
    # It is the hydraulic mode that goes unstable: at the limit every other eigenvalue is damped.
    at_limit = np.linalg.eigvals(ref.jacobian(p.with_(Kp=kp_limit)))
    others = [lam for lam in at_limit if abs(lam - ref.hydraulic_mode(at_limit, near)) > 1e-6 * near and abs(lam.imag + ref.hydraulic_mode(at_limit, near).imag) > 1e-6 * near]
    assert max(lam.real for lam in others) < -1.0, at_limit
    rigid = np.linalg.eigvals(linearisation({"level": 1, "Kp": 3 * kp_limit})[np.ix_([0, 1, 3], [0, 1, 3])])
    assert np.all(rigid.real < 0), rigid
    level1_limit = ref.stability_limit_kp(p.with_(level=1), 3 * kp_limit, 1e3 * kp_limit)
    REPORT.append(f"gain limit: level 2 (hydraulic mode) Kp = {kp_limit:.1f} V/rad ({kp_limit / p.Kp:.2f} x the default {p.Kp:g}); "
                  f"level 1 (electromechanical mode) Kp = {level1_limit:.0f} V/rad ({level1_limit / p.Kp:.1f} x)")


# ---- what the mode does to the response ----------------------------------------------------------------

def response_figures(res, p: ref.EhaParams) -> dict:
    t = np.asarray(res["time"])
    theta = np.asarray(res["surface_angle"])
    hold = (t >= p.step_time) & (t < p.return_time)
    final = float(theta[hold][-1])
    overshoot = (float(np.max(theta[hold])) - final) / p.step_angle
    outside = np.nonzero(np.abs(theta[hold] - final) > 0.02 * p.step_angle)[0]
    settling = float(t[hold][outside[-1] + 1] - p.step_time) if len(outside) else 0.0
    dp = np.asarray(res["pump_pressure"])
    return {"final": final, "overshoot": overshoot, "settling": settling, "dp_max": float(np.max(dp)), "dp_min": float(np.min(dp)),
            "i_max": float(np.max(np.abs(res["motor_current"])))}


def test_what_the_mode_does_to_the_response():
    """Level 1 against level 2 over the default run (the FMU at its default tolerance, 0.1 ms rows):
    the surface's response is the same to a fraction of a percent of the step (the loop's 14 /s pole
    is 27 x below the mode), the pressure is not: level 2 rings at the mode's frequency after each
    corner of the motor's torque and peaks far above level 1."""
    p = params()
    runs = {level: run({"level": level}, interval=1e-4, tolerance=None) for level in (1, 2)}
    figures = {level: response_figures(runs[level], params(level=level)) for level in (1, 2)}
    for level, fig in figures.items():
        REPORT.append(f"response, level {level}: final {math.degrees(fig['final']):.3f} deg, overshoot {100 * fig['overshoot']:.3f} % "
                      f"of the step, 2 % settling {1e3 * fig['settling']:.1f} ms, pump pressure {fig['dp_min'] / 1e6:.2f} .. "
                      f"{fig['dp_max'] / 1e6:.2f} MPa, |i| <= {fig['i_max']:.1f} A")
    # The angle: same settling within 5 ms, overshoot below 0.5 % of the step at both levels.
    assert abs(figures[1]["settling"] - figures[2]["settling"]) < 5e-3
    assert max(figures[1]["overshoot"], figures[2]["overshoot"]) < 5e-3
    # The angles differ by the steady error the leakage adds (hand figures), not by the mode.
    error_gap = ref.steady_state(p.with_(level=1), p.step_angle)["surface_angle"] - ref.steady_state(p, p.step_angle)["surface_angle"]
    assert figures[1]["final"] - figures[2]["final"] == pytest.approx(error_gap, rel=1e-3)
    t = np.asarray(runs[2]["time"])
    gap = np.degrees(np.asarray(runs[2]["surface_angle"]) - np.asarray(runs[1]["surface_angle"]))
    for a, b in ((p.step_time, p.return_time), (p.return_time, 1.0)):
        sel = (t >= a) & (t < b)
        REPORT.append(f"surface angle, level 2 - level 1 over {a:g}-{b:g} s: {gap[sel].min():+.3f} .. {gap[sel].max():+.3f} deg "
                      f"(at the end {gap[sel][-1]:+.4f} deg)")
    # The pressure rings at the mode: over 0.15-0.35 s (after the saturated slew), the dominant frequency
    # of level 2's pressure less level 1's is the damped hydraulic mode's.
    window = (t >= 0.15) & (t < 0.35)
    ripple = np.asarray(runs[2]["pump_pressure"])[window] - np.asarray(runs[1]["pump_pressure"])[window]
    spectrum = np.abs(np.fft.rfft((ripple - ripple.mean()) * np.hanning(len(ripple)), n=64 * len(ripple)))
    freqs = np.fft.rfftfreq(64 * len(ripple), d=1e-4)
    f_ring = float(freqs[int(np.argmax(spectrum))])
    lam = ref.hydraulic_mode(np.linalg.eigvals(ref.jacobian(p)), math.sqrt(p.k_oil / p.m_surface))
    REPORT.append(f"pressure ringing (level 2 - level 1, 0.15-0.35 s): {f_ring:.2f} Hz; damped hydraulic mode {lam.imag / (2 * math.pi):.2f} Hz")
    assert f_ring == pytest.approx(lam.imag / (2 * math.pi), rel=0.02)
    assert figures[2]["dp_max"] > 1.5 * figures[1]["dp_max"]
