"""CommonRailInjection against its contract, docs/common-rail-spec.md (chapter 3, section 3.4.3, Figure 3.20,
Table 3.7).

Where each reference comes from (never a previous run of the FMU):
  * the defaults: the spec's arguments, recomputed here from their sources' numbers (`DEFAULTS`);
  * the mean rail pressure: the flow balance by hand (common_rail_reference.hand_balance): the pump's mean
    delivery (displacement x pump revolutions per second) equals the mean injected flow (one shot per firing
    interval, the shot from the needle's trapezoid and the nozzle's two orifices at that pressure, by quad),
    the valve's flow in its static balance (k x = A p - preload - solenoid; Q = Cd pi d x sqrt(2 p / rho)) and
    the leakage p / R, solved for the pressure by brentq;
  * the ripple: the linearised accumulator (common_rail_reference.linear_ripple): per harmonic of the firing
    interval, p_k = (Q_pump,k - Q_inj,k) / (i w C + G_p + (G_x + i w A) A / (k - m w^2 + i w c)), C = V / B(p)
    at the mean pressure, G_p and G_x the valve's conductances (and the leakage's and the injectors' mean
    dQ/dp), the last term the valve's ball on its spring; the flows' harmonics from their own formulas;
  * the valve's opening pressure: preload over seat area, (F_spring_preload + F_solenoid) / (pi d^2 / 4),
    F_solenoid = A p_set - F_spring_preload (0 below the spring's own pressure);
  * the shot: Cd sqrt(2 dp / rho) times the integral of the nozzle's area over the needle's trapezoid, at the
    pressure the FMU reports during the shot (trapezoidal rule on a 1 us grid);
  * the firing order and the start-of-injection instants: 4 pi / n apart in crank angle, advance before each
    firing top dead centre, the run starting 1 degree after cylinder 1's start;
  * the whole trajectory: the spec's equations written out in common_rail_reference.Rail, integrated by
    scipy's DOP853 at rtol 1e-12 from kink to kink (every kink is known in time at a constant speed);
  * the energy balance: the runtime's power_balance_relative (sources - dE/dt of storage - dissipation).
Parameter values are the FMU's start values (modelDescription.xml) with a case's overrides.
"""

from __future__ import annotations

import functools
import math
import time

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu

import common_rail_reference as ref
from conftest import DIST_DIR, print_past_capture, require_fmu

REPORT: list[str] = []
TWO_PI = 2 * math.pi
RPM = TWO_PI / 60


@pytest.fixture(scope="module", autouse=True)
def _print_report(request):
    yield
    print_past_capture(request, "== CommonRailInjection: figures of the spec", REPORT)


def fmu():
    return require_fmu(DIST_DIR / "CommonRailInjection.fmu")


@functools.lru_cache(maxsize=None)
def model_description():
    return read_model_description(str(fmu()))


def start_values() -> dict:
    return {v.name: v.start for v in model_description().modelVariables if v.start is not None}


def params(**overrides) -> ref.Params:
    values = {**start_values(), **overrides}
    return ref.Params.from_values(values)


@functools.lru_cache(maxsize=None)
def run(start: tuple = (), stop_time: float = 0.12, interval: float = 2e-4, tolerance: float | None = 1e-10, outputs: tuple = ()):
    extra = {} if tolerance is None else {"relative_tolerance": tolerance}
    names = list(outputs) or ["rail_pressure", "pump_flow", "injection_flow", "relief_flow", "leakage_flow", "valve_lift",
                              "needle_lift", "injected_volume", "injected_volume_last_shot", "firing_cylinder",
                              "power_balance_relative", "valve_opening_pressure"]
    return simulate_fmu(str(fmu()), fmi_type="CoSimulation", stop_time=stop_time, output_interval=interval,
                        start_values=dict(start), output=names, **extra)


# ---- the defaults and their sources ---------------------------------------------------------------

# (parameter, value from its source's numbers, the source): docs/common-rail-spec.md, "Values".
DEFAULTS = [
    ("injection_advance", math.radians(4.0), "main injection 4 degrees before firing TDC at 2000 rpm, part load"),
    ("pump_ratio", 2.0 / 3.0, "3 plungers, one stroke per injection of 4 cylinders (OM647: 1.3 x camshaft speed)"),
    ("pump_phase", 0.0, ""),
    ("p_feed", 0.3e6, "boost pump, some 3 bar"),
    ("plunger_diameter", 6.5e-3, "CP1-class: 3 x 6.5 mm on a 3.5 mm eccentric = 0.697 cm3/rev"),
    ("eccentricity", 3.5e-3, ""),
    ("V_rail", 20e-6, "rail with its lines, 20 cm3"),
    ("B_fuel_0", 1.5e9, "diesel fuel near atmospheric pressure, 40 degrees C: 1.5 GPa"),
    ("dB_fuel_dp", 7.5, "B rising to ~2.85 GPa at 180 MPa"),
    ("R_leakage", 145e6 / 0.5e-6, "0.5 cm3/s at 145 MPa"),
    ("valve_seat_diameter", 0.6e-3, "pressure-control valve's ball seat"),
    ("Cd_valve", 0.7, "sharp seat"),
    ("m_valve", 3e-3, "ball, armature, a third of the spring"),
    ("k_valve", 7.5e4, "75 N/mm"),
    ("c_valve", 15.0, "damping ratio 0.5: 2 x 0.5 sqrt(k m) = 15.0 N s/m"),
    ("F_spring_preload", math.pi / 4 * 0.6e-3**2 * 10e6, "the spring alone holds 100 bar"),
    ("hole_diameter", 0.13e-3, "7 holes of 0.13 mm"),
    ("Cd_nozzle", 0.75, "hydro-eroded holes"),
    ("needle_seat_diameter", 1.5e-3, ""),
    ("needle_seat_half_angle", math.radians(30.0), "60 degree seat cone"),
    ("needle_lift_max", 0.2e-3, "0.2 mm"),
    ("needle_opening_speed", 1.0, "0.2 ms to full lift"),
    ("needle_closing_speed", 1.2, ""),
    ("opening_delay", 0.3e-3, ""),
    ("closing_delay", 0.3e-3, ""),
    ("p_cylinder", 6e6, "compression pressure near TDC"),
    ("engine_speed", 2000 * RPM, "2000 rpm"),
    ("rail_pressure_set_point", 145e6, "1450 bar"),
    ("energizing_time", 0.5e-3, "about 24 mm3 per shot"),
    ("p_rail", 149e6, "near the mean at the defaults"),
]


def test_defaults_are_the_specs_values():
    starts = start_values()
    wrong = [f"{name}: FMU {starts[name]}, spec {value} ({source})" for name, value, source in DEFAULTS
             if not math.isclose(float(starts[name]), value, rel_tol=1e-14)]
    assert not wrong, "\n".join(wrong)
    assert int(starts["cylinders"]) == 4 and int(starts["nozzle_holes"]) == 7
    # The damping ratio of the valve's ball on its spring, as argued.
    p = params()
    assert math.isclose(p.c_valve / (2 * math.sqrt(p.k_valve * p.m_valve)), 0.5, rel_tol=2e-3)
    md = model_description()
    cylinders = next(v for v in md.modelVariables if v.name == "cylinders")
    assert (cylinders.type, cylinders.variability, int(cylinders.min), int(cylinders.max)) == ("Integer", "fixed", 4, 6)
    de = md.defaultExperiment
    assert (float(de.startTime), float(de.stopTime), float(de.stepSize)) == (0.0, 0.12, 2e-4)


def test_the_default_experiment_is_cheap_in_fmpy():
    """Two engine cycles at 2000 rpm in fmpy's Co-Simulation, its default settings: well under 0.5 s."""
    t0 = time.perf_counter()
    res = simulate_fmu(str(fmu()), fmi_type="CoSimulation", output=["rail_pressure"])
    wall = time.perf_counter() - t0
    REPORT.append(f"DefaultExperiment (0.12 s, 2 engine cycles) in fmpy CS: {wall:.3f} s wall, {len(res)} rows")
    assert wall < 0.5


# ---- the parts' laws --------------------------------------------------------------------------------

def test_pump_flow_is_three_rectified_sines_and_its_mean_the_displacement():
    p = params()
    res = run(interval=1e-5, outputs=("pump_flow",))
    t = res["time"]
    expected = ref.pump_flow(p, t)
    err = np.max(np.abs(res["pump_flow"] - expected)) / np.max(expected)
    # Its mean over whole pump revolutions: 2 e A n times revolutions per second (0.697 cm3/rev, 1333 rpm).
    revolution = TWO_PI / (p.pump_ratio * p.engine_speed)
    inside = t <= 2 * revolution * (1 + 1e-12)
    k = np.count_nonzero(inside)
    mean = np.trapezoid(res["pump_flow"][:k], t[:k]) / t[k - 1]
    REPORT.append(f"pump flow: within {err:.1e} of the rectified sines; mean {mean * 1e6:.4f} cm3/s, displacement x speed "
                  f"{ref.pump_mean_flow(p) * 1e6:.4f} cm3/s ({p.displacement * 1e6:.4f} cm3/rev)")
    assert err < 1e-9
    assert abs(mean / ref.pump_mean_flow(p) - 1) < 1e-6


def test_firing_order_and_starts_of_injection():
    """Cylinders 1-3-4-2 (4-5-6 cylinders: their inline orders), a start every 4 pi / n of crank angle,
    each `injection_advance` before its cylinder's firing TDC; the shot volume restarts at each."""
    for n in (4, 5, 6):
        p = params(cylinders=n)
        res = run(start=(("cylinders", n),), interval=1e-5, outputs=("firing_cylinder", "injected_volume"))
        t, cyl = res["time"], res["firing_cylinder"]
        changes = np.flatnonzero(np.diff(cyl) != 0) + 1
        order = [int(cyl[0])] + [int(cyl[i]) for i in changes]
        expected = [ref.FIRING_ORDERS[n][j % n] for j in range(len(order))]
        assert order == expected, (n, order)
        starts = p.start_times(0.12)
        assert len(changes) == len(starts)
        # Each change falls in the output interval that holds the hand-computed start.
        assert np.all((t[changes - 1] < starts) & (starts <= t[changes])), (t[changes], starts)
        # The shot volume falls back to 0 there.
        assert np.all(res["injected_volume"][changes] < res["injected_volume"][changes - 1])


def test_shot_volume_is_the_nozzle_law_over_the_needles_trapezoid():
    """Each latched shot against Cd sqrt(2 (p - p_cyl) / rho) A(h(s)) integrated over the needle's
    trapezoid (quad, piece by piece) at the FMU's own rail pressure during the shot (a cubic spline
    through its 1 us output grid)."""
    from scipy.integrate import quad
    from scipy.interpolate import CubicSpline

    p = params()
    res = run(interval=1e-6, stop_time=0.05, outputs=("rail_pressure", "injected_volume_last_shot", "injection_flow"))
    t, pr = res["time"], res["rail_pressure"]
    starts = p.start_times(0.05)
    pieces = ref.needle_phases(p, p.energizing_time)
    worst = 0.0
    for a, b in zip(starts[:-1], starts[1:]):
        inside = (t >= a - 5e-6) & (t <= a + ref.shot_end(p, p.energizing_time) + 5e-6)
        pressure = CubicSpline(t[inside], pr[inside])
        expected = sum(quad(lambda s: ref.nozzle_flow(p, ref.lift(p, s - a, p.energizing_time), float(pressure(s))), a + lo, a + hi,
                            epsabs=0.0, epsrel=1e-12, limit=200)[0] for lo, hi, _ in pieces)
        latched = res["injected_volume_last_shot"][np.searchsorted(t, b) + 1]
        worst = max(worst, abs(latched / expected - 1))
    hand = ref.shot_volume(p, ref.hand_balance(p)["p"])
    REPORT.append(f"shot: {latched * 1e9:.4f} mm3 latched, within {worst:.1e} of the nozzle law over the FMU's pressure; "
                  f"{hand * 1e9:.4f} mm3 at the mean pressure")
    assert worst < 1e-7
    # At the mean pressure: the shot starts above the mean and ends below it (the ripple), within 0.5 %.
    assert abs(latched / hand - 1) < 5e-3


# ---- the chapter's question: the rail pressure's mean and ripple ----------------------------------------

@functools.lru_cache(maxsize=None)
def settled_period(samples: int = 3000):
    """The rail pressure over one firing interval in the third engine cycle (the valve and the rail
    settle in about 3 ms), sampled uniformly from a start of injection (cubic interpolation of a fine
    output grid); the run's outputs, and the engine cycle (four firing intervals) that ends there."""
    from scipy.interpolate import CubicSpline

    p = params()
    T = p.period
    starts = p.start_times(0.2)
    res = run(stop_time=0.2, interval=T / samples, outputs=("rail_pressure", "pump_flow", "injection_flow", "relief_flow", "leakage_flow"))
    spline = CubicSpline(res["time"], res["rail_pressure"])
    grid = starts[-2] + np.arange(samples) * (T / samples)
    return grid, spline(grid), res, (starts[-6], starts[-2])


def test_mean_rail_pressure_is_the_flow_balance_by_hand():
    """Pump mean = injected mean + relief + leakage at the mean pressure: the valve's flow is linear in its
    lift and the lift's mean is the static one (the spring and damper average to the mean force), so only
    the ripple's second-order terms separate the FMU's mean from the hand balance, each a flow over the
    valve's conductance dQ_relief/dp = G_x A / k + Q / 2p = 3.0e-12 m3/(s Pa): the relief flow's mean of
    x sqrt(p) exceeds x(p) sqrt(p) at the mean by var(p) / (2 p (p - p_open)), ~7e-4 of 13.3 cm3/s with
    a 10 bar rms ripple (~3 kPa), and each shot sprays into its own dip, 0.4 % less than at the mean
    pressure (6e-9 m3/s, ~2 kPa, the other way). Bound 4e-5 of the pressure (6 kPa, their sum)."""
    p = params()
    mean = ref.hand_balance(p)
    grid, pr, res, (c0, c1) = settled_period()
    fmu_mean = float(np.mean(pr))
    # The FMU's own flows over a whole engine cycle balance too (the pressure returns to itself).
    t = res["time"]
    cycle = (t >= c0 - 1e-12) & (t <= c1 + 1e-12)
    span = t[cycle][-1] - t[cycle][0]
    flows = {k: np.trapezoid(res[k][cycle], t[cycle]) / span for k in ("pump_flow", "injection_flow", "relief_flow", "leakage_flow")}
    net = flows["pump_flow"] - flows["injection_flow"] - flows["relief_flow"] - flows["leakage_flow"]
    REPORT.append(
        f"mean rail pressure: FMU {fmu_mean / 1e5:.4f} bar, flow balance by hand {mean['p'] / 1e5:.4f} bar "
        f"({fmu_mean / mean['p'] - 1:+.1e}); pump {mean['q_pump'] * 1e6:.4f} = injected {mean['q_injection'] * 1e6:.4f} + relief "
        f"{mean['q_relief'] * 1e6:.4f} + leakage {mean['q_leakage'] * 1e6:.4f} cm3/s; FMU's flows over a cycle: pump "
        f"{flows['pump_flow'] * 1e6:.4f}, injected {flows['injection_flow'] * 1e6:.4f}, relief {flows['relief_flow'] * 1e6:.4f}, "
        f"leakage {flows['leakage_flow'] * 1e6:.4f} cm3/s, net {net * 1e6:.1e}")
    assert abs(fmu_mean / mean["p"] - 1) < 4e-5
    # (trapezoidal rule on the 5 us output grid: the rectified sines' kinks cost some 1e-6)
    assert abs(flows["pump_flow"] / mean["q_pump"] - 1) < 5e-5
    assert abs(flows["relief_flow"] / mean["q_relief"] - 1) < 2e-3
    assert abs(flows["injection_flow"] / mean["q_injection"] - 1) < 5e-3
    assert abs(net) < 1e-3 * flows["pump_flow"]


def test_ripple_is_the_linearised_accumulators():
    """The rail pressure's harmonics of the injection frequency (66.7 Hz at 2000 rpm) against the closed
    form of the linearised rail and valve. What the linearisation leaves out is of the order of the ripple
    over the pressure, p_ripple / 2 (p - p_cyl) ~ 0.6 %, times the share of the flows it touches: the
    injectors' flow falls ~1 % from the start of a shot to its end as the pressure dips, the valve's flow
    holds x sqrt(p) (a product of two ripples), B(p) changes by 0.2 % over the ripple. Bounds: the first
    harmonic within 0.3 % in amplitude and 0.01 rad in phase, the next two within 1.5 %, the
    peak-to-peak ripple within 1 %."""
    p = params()
    mean = ref.hand_balance(p)
    lin = ref.linear_ripple(p, mean, count=60)
    grid, pr, _, _ = settled_period()
    fk = ref.harmonics(pr, 3)
    rows = []
    for k in range(3):
        a, b = fk[k], lin["harmonics"][k]
        rows.append(f"  harmonic {k + 1} ({(k + 1) / p.period:.1f} Hz): FMU {abs(a) / 1e5:.4f} bar, linear {abs(b) / 1e5:.4f} bar "
                    f"({abs(a) / abs(b) - 1:+.2e}), phase difference {np.angle(a / b):+.1e} rad")
    ptp, ptp_lin = float(np.ptp(pr)), float(np.ptp(lin["wave"]))
    REPORT.append("ripple against the linearised accumulator (C = V / B(p_mean) = "
                  f"{lin['C']:.4e} m3/Pa, G_p = {lin['g_p']:.3e} m3/(s Pa), G_x = {lin['g_x']:.4f} m2/s):\n" + "\n".join(rows)
                  + f"\n  peak-to-peak: FMU {ptp / 1e5:.3f} bar, linear (60 harmonics) {ptp_lin / 1e5:.3f} bar ({ptp / ptp_lin - 1:+.1e})")
    assert abs(abs(fk[0]) / abs(lin["harmonics"][0]) - 1) < 3e-3
    assert abs(np.angle(fk[0] / lin["harmonics"][0])) < 0.01
    for k in (1, 2):
        assert abs(abs(fk[k]) / abs(lin["harmonics"][k]) - 1) < 1.5e-2
    assert abs(ptp / ptp_lin - 1) < 1e-2


@pytest.mark.parametrize("set_point,start,label", [(0.0, 9.5e6, "spring alone"), (150e6, 149.5e6, "spring and solenoid")])
def test_valve_opens_at_preload_over_seat_area(set_point, start, label):
    """No injection, the engine at 200 rpm: the pump raises the rail pressure by ~1 bar per ms (at 100 bar)
    and the valve's ball leaves its seat exactly where A p reaches the spring's preload plus the solenoid's
    force: the output samples (1 us apart) bracket that pressure."""
    p = params(rail_pressure_set_point=set_point)
    opening = (p.F_spring_preload + p.solenoid_force) / (math.pi / 4 * p.valve_seat_diameter**2)
    res = run(start=(("rail_pressure_set_point", set_point), ("p_rail", start), ("engine_speed", 200 * RPM), ("energizing_time", 0.0)),
              stop_time=0.01, interval=1e-6, outputs=("rail_pressure", "valve_lift", "valve_opening_pressure"))
    lifted = np.flatnonzero(res["valve_lift"] > 0.0)
    assert lifted.size and lifted[0] > 0, f"{label}: the valve never opened"
    i = lifted[0]
    before, after = res["rail_pressure"][i - 1], res["rail_pressure"][i]
    REPORT.append(f"valve opening ({label}): preload / area {opening / 1e5:.4f} bar; the ball lifts between {before / 1e5:.4f} and "
                  f"{after / 1e5:.4f} bar (t = {res['time'][i] * 1e3:.3f} ms); FMU's valve_opening_pressure {res['valve_opening_pressure'][0] / 1e5:.4f} bar")
    assert before <= opening <= after
    assert after - before < 1e-4 * opening
    assert math.isclose(res["valve_opening_pressure"][0], opening, rel_tol=1e-12)
    assert np.all(res["valve_lift"][:i] == 0.0)


# ---- the whole trajectory and the energy balance -----------------------------------------------------

def test_trajectory_matches_the_equations_integrated_by_scipy():
    """The default run (valve, pump, injections, shots) against DOP853 at rtol 1e-12 from kink to kink on
    the spec's equations: each output within 1e-7 of its range (FMU at rtol 1e-10)."""
    p = params()
    res = run(interval=2e-5)
    sim = ref.Rail(p).simulate(res["time"], rtol=1e-12)
    pairs = [("rail_pressure", "p"), ("valve_lift", "x"), ("injected_volume", "shot"), ("injection_flow", "q_inj"),
             ("pump_flow", "q_pump"), ("relief_flow", "q_relief"), ("leakage_flow", "q_leak")]
    worst = []
    for name, key in pairs:
        err = np.abs(res[name] - sim[key]) / np.ptp(sim[key])
        k = int(np.argmax(err))
        worst.append((float(err[k]), name, float(res["time"][k])))
    REPORT.append("trajectory against scipy (DOP853, rtol 1e-12, kink to kink): " + ", ".join(f"{n} {e:.1e}" for e, n, _ in worst))
    bad = [w for w in worst if w[0] > 1e-7]
    assert not bad, bad


def test_energy_balance_holds_to_rounding():
    res = run(interval=2e-5, tolerance=None)
    worst = float(np.max(np.abs(res["power_balance_relative"])))
    REPORT.append(f"energy balance: |power_balance_relative| <= {worst:.1e} over the default run")
    assert worst < 1e-13
