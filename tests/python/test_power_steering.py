"""PowerSteering against its physics (docs/power-steering-spec.md; issue 22, part 1).

References are independent of the FMU's results: a static balance by hand, the linear case written
out in power_steering_reference.py (scipy's DOP853 at rtol 1e-12), and the loop's stability limit,
found by simulating free responses and checked against the eigenvalues of the Jacobian that the
FMU's directional derivatives give (and against the reference's own matrix). Parameter values are
the FMU's declared defaults (read from its modelDescription.xml) unless a test overrides them.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi2 import FMU2Model
from scipy.integrate import solve_ivp

from conftest import DIST_DIR, require_fmu
from power_steering_reference import Steering

FMU = DIST_DIR / "PowerSteering.fmu"

# The linear case (power_steering_reference.py): an ideal worm without friction, treads that never
# slide (a friction 1e6 N m, far above any tire torque here), rigid tie rods (the default).
LINEAR = {"worm_efficiency_forward": 1.0, "worm_efficiency_backward": 1.0, "T_column_friction": 0.0, "T_tire_friction": 1e6}


@pytest.fixture(scope="module")
def fmu():
    return require_fmu(FMU)


@pytest.fixture(scope="module")
def start(fmu):
    return {v.name: v.start for v in read_model_description(str(fmu)).modelVariables if v.start is not None}


def simulate(fmu, stop, interval, start_values, outputs, tol=None):
    return simulate_fmu(str(fmu), fmi_type="CoSimulation", stop_time=stop, output_interval=interval, start_values=start_values,
                        output=outputs, relative_tolerance=tol)


def test_assistance_divides_the_static_torque_by_one_plus_the_gain(fmu, start):
    """At rest, the column's torques balance: T_bar + K_a T_bar = r F (an ideal worm: the assistance
    is K_a times the measured torque), so the rack force a driver's torque T_d holds is
    F = (1 + K_a) T_d / r: 2 N m and K_a = 4 hold 1000 N on the 10 mm pinion. And without
    assistance 2 N m hold 200 N."""
    t_driver = 2.0
    for gain in (4.0, 0.0):
        sv = dict(LINEAR, driver_input=2, torque_amplitude=0.0, torque_in=t_driver, assist_gain=gain)
        res = simulate(fmu, 6.0, 0.01, sv, ["rack_force", "torsion_bar_torque", "driver_torque", "motor_current"])
        force = (1.0 + gain) * t_driver / float(start["r_pinion"])
        print(f"K_a = {gain}: rack force {res['rack_force'][-1]:.9g} N (hand {force:.9g}), torsion bar {res['torsion_bar_torque'][-1]:.9g} N m")
        assert res["rack_force"][-1] == pytest.approx(force, rel=1e-6)
        assert res["torsion_bar_torque"][-1] == pytest.approx(t_driver, rel=1e-6)
        # The current that gives K_a T_d at the column through the worm: K_a T_d / (N k).
        current = gain * t_driver / (float(start["worm_ratio"]) * float(start["k_motor"]))
        assert res["motor_current"][-1] == pytest.approx(current, rel=1e-6, abs=1e-9)


def test_parking_effort_with_and_without_assistance(fmu):
    """The question a reader asks: how much does the assistance save the driver when parking? The
    book's mission (one turn each way at 1/16 Hz, the treads sliding on the ground) with the
    defaults, against the same without assistance. Reported; asserted: the assistance divides the
    peak effort by more than 3 (by 1 + K_a = 5 at best, less the damping and the worm's losses)."""
    outputs = ["driver_torque", "rack_force", "motor_current"]
    assisted = simulate(fmu, 16.0, 0.01, {}, outputs)
    manual = simulate(fmu, 16.0, 0.01, {"assist_gain": 0.0, "assist_damping": 0.0}, outputs)
    peak_a, peak_m = np.max(np.abs(assisted["driver_torque"])), np.max(np.abs(manual["driver_torque"]))
    print(f"parking: peak driver torque {peak_a:.3f} N m assisted, {peak_m:.3f} N m manual ({peak_m / peak_a:.2f} x); "
          f"peak rack force {np.max(np.abs(assisted['rack_force'])):.0f} / {np.max(np.abs(manual['rack_force'])):.0f} N; "
          f"peak motor current {np.max(np.abs(assisted['motor_current'])):.1f} A")
    assert peak_m / peak_a > 3.0


def test_linear_case_against_scipy(fmu, start):
    """The sine steer (0.5 rad at 1 Hz) in the linear case against the reference's ODE at rtol 1e-12:
    every compared output within 1e-6 of its range."""
    sv = dict(LINEAR, profile=2)
    ref_model = Steering.from_start_values(start)
    stop, h = 3.0, 0.002
    names = ["steering_wheel_angle", "driver_torque", "torsion_bar_torque", "rack_position", "wheel_angle", "motor_current", "current_command"]
    res = simulate(fmu, stop, h, sv, names + ["motor_voltage"], tol=1e-10)
    t = res["time"]
    sol = solve_ivp(ref_model.rhs(float(start["sine_amplitude"]), float(start["sine_frequency"])), (0.0, stop), np.zeros(8), method="DOP853",
                    rtol=1e-12, atol=1e-14, t_eval=t)
    assert sol.success
    expected = ref_model.outputs(sol.y)
    # The case is linear only if nothing saturates.
    assert np.max(np.abs(res["current_command"])) < float(start["I_max"])
    assert np.max(np.abs(res["motor_voltage"])) < float(start["U_battery"])
    worst = []
    for name in names:
        scale = np.ptp(expected[name])
        err = np.max(np.abs(res[name] - expected[name])) / scale
        worst.append((err, name))
        assert err < 1e-6, f"{name}: {err:.3g} of its range {scale:.4g}"
    print("linear sine steer, worst:", ", ".join(f"{n} {e:.2g}" for e, n in sorted(worst, reverse=True)[:3]))


# --- the loop's stability limit -----------------------------------------------------------------

# The assistance without its active damping, the driver's hands on the wheel holding it still (an
# angle profile of amplitude 0), an ideal worm, stuck treads: the column's mode against the
# torsion bar loses its damping as the gain rises, through the current loop's lag.
STABILITY = dict(LINEAR, driver_input=1, parking_amplitude=0.0, assist_damping=0.0)


class Linearized:
    """The FMU in Model Exchange at rest with the column just moving (w_column = 1e-3 rad/s, so the
    worm starts in a moving mode): the Jacobian of the physical states' derivatives from
    fmi2GetDirectionalDerivative, one column per state."""

    def __init__(self, fmu):
        self.md = read_model_description(str(fmu))
        self.dir = extract(str(fmu))
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.kind = {v.name: v.type for v in self.md.modelVariables}
        derivatives = [d.variable for d in self.md.derivatives]
        self.states = [(v.derivative.name, v.valueReference, v.derivative.valueReference) for v in derivatives if not v.derivative.name.startswith("A_")]

    def jacobian(self, start_values: dict) -> np.ndarray:
        m = FMU2Model(guid=self.md.guid, unzipDirectory=self.dir, modelIdentifier=self.md.modelExchange.modelIdentifier, instanceName="lin")
        m.instantiate()
        try:
            m.setupExperiment(startTime=0.0)
            m.enterInitializationMode()
            for name, value in dict(start_values, w_column=1e-3).items():
                if self.kind[name] in ("Integer", "Enumeration"):
                    m.setInteger([self.vr[name]], [int(value)])
                elif self.kind[name] == "Boolean":
                    m.setBoolean([self.vr[name]], [bool(value)])
                else:
                    m.setReal([self.vr[name]], [float(value)])
            m.exitInitializationMode()
            while m.newDiscreteStates()[0]:
                pass
            m.enterContinuousTimeMode()
            unknowns = [der for _, der, _ in self.states]
            columns = [m.getDirectionalDerivative(unknowns, [state], [1.0]) for _, _, state in self.states]
            return np.array(columns).T
        finally:
            m.terminate()
            m.freeInstance()


def max_real_eigenvalue(jacobian: np.ndarray) -> tuple[float, float]:
    """(largest real part, |imaginary part| there) among the eigenvalues that are not zero (the
    stuck treads' frozen states and the rigid tie rods' give exact zeros)."""
    ev = np.linalg.eigvals(jacobian)
    ev = ev[np.abs(ev) > 1e-9]
    i = int(np.argmax(ev.real))
    return float(ev[i].real), float(abs(ev[i].imag))


def bisect(f, lo: float, hi: float, rel: float) -> float:
    """The root of a function that is negative at lo and positive at hi."""
    assert f(lo) < 0.0 < f(hi), (f(lo), f(hi))
    while hi - lo > rel * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if f(mid) < 0.0 else (lo, mid)
    return 0.5 * (lo + hi)


def growth_rate(fmu, gain: float) -> float:
    """The free response's growth rate, 1/s, from a simulation: a 1e-3 rad/s column speed from rest,
    then the torsion bar torque's oscillation envelope over 1 s to 2 s against 0.5 s to 1 s."""
    res = simulate(fmu, 2.0, 2e-4, dict(STABILITY, assist_gain=gain, w_column=1e-3), ["torsion_bar_torque"], tol=1e-10)
    t, y = res["time"], np.abs(res["torsion_bar_torque"])
    early, late = y[(t >= 0.5) & (t < 1.0)].max(), y[(t >= 1.5) & (t <= 2.0)].max()
    return math.log(late / early) / 1.0


def test_the_jacobian_is_the_reference_matrix(fmu, start):
    """The FMU's directional derivatives against power_steering_reference.Steering.matrix() in the
    linear case at the default gain: the same eigenvalues (to 1e-6 relative)."""
    lin = Linearized(fmu)
    jac = lin.jacobian(STABILITY)
    ref = Steering.from_start_values(start, assist_damping=0.0).matrix()
    ev_fmu = np.sort_complex(np.round(np.linalg.eigvals(jac), 9))
    ev_fmu = ev_fmu[np.abs(ev_fmu) > 1e-6]
    ev_ref = np.sort_complex(np.linalg.eigvals(ref))
    ev_ref = ev_ref[np.abs(ev_ref) > 1e-6]
    print("eigenvalues (FMU):", ", ".join(f"{z.real:.4g}{z.imag:+.4g}j" for z in ev_fmu))
    assert len(ev_fmu) == len(ev_ref)
    for z in ev_ref:
        assert np.min(np.abs(ev_fmu - z)) < 1e-6 * max(1.0, abs(z)), f"reference eigenvalue {z} not among the FMU's"


def test_stability_limit_by_simulation_and_by_eigenvalues(fmu):
    """The assistance gain at which the loop becomes unstable (the known EPS limit: the torsion bar's
    stiffness against the gain): by bisection on the simulated free response's growth, and on the
    largest real part of the Jacobian's eigenvalues. Within 2 % of each other."""
    lin = Linearized(fmu)
    by_eigenvalues = bisect(lambda g: max_real_eigenvalue(lin.jacobian(dict(STABILITY, assist_gain=g)))[0], 1.0, 200.0, 1e-4)
    by_simulation = bisect(lambda g: growth_rate(fmu, g), 0.5 * by_eigenvalues, 1.5 * by_eigenvalues, 2e-3)
    re, im = max_real_eigenvalue(lin.jacobian(dict(STABILITY, assist_gain=by_eigenvalues)))
    print(f"stability limit: assist_gain {by_eigenvalues:.4g} (eigenvalues; the mode at {im / (2 * math.pi):.3g} Hz), "
          f"{by_simulation:.4g} (simulated growth); default gain 4")
    assert by_simulation == pytest.approx(by_eigenvalues, rel=0.02)
