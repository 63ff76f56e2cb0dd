"""TractionMotorThermal (chapter section 3.5.1): the V150 traction motor under its 1 MW overload.

Every reference here is derived by hand from the chapter's data (700 kW nominal, C_nom = 1400 N m
at 4800 rpm, P_J,nom = 5 kW, 140 K winding rise over a 40 C ambient, 1 MW overload at 4800 rpm),
from the book file's values (Chap3_TGV_Modelisation_Thermique.mo, the FMU's defaults, checked in
`test_defaults_are_the_book_files_values`) and from the parameters the FMU documents (read from its
modelDescription, so the test follows a user who changes them); nothing is taken from the FMU's own
outputs. The book's own result files (ModeleTGV_1.mat, ModeleTGV_2.mat, the authors' runs of that
file) give a second reference at five instants.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu

from conftest import DIST_DIR, require_fmu
from thermal_coupling import MOTOR_FAN_RATED_TORQUE, couple

# The chapter's figures (section 3.5.1).
NOMINAL_TORQUE = 1400.0  # N m
MAX_SPEED = 4800.0 * 2.0 * math.pi / 60.0  # rad/s
NOMINAL_LOSSES = 5000.0  # W
NOMINAL_RISE = 140.0  # K
AMBIENT = 40.0 + 273.15  # K
OVERLOAD_POWER = 1.0e6  # W

# Question 1: the overload torque at the same maximal speed; question 2: its Joule losses
# (torque proportional to current, losses to its square).
OVERLOAD_TORQUE = OVERLOAD_POWER / MAX_SPEED
OVERLOAD_LOSSES = NOMINAL_LOSSES * (OVERLOAD_TORQUE / NOMINAL_TORQUE) ** 2
INSULATION_LIMIT = AMBIENT + NOMINAL_RISE  # 180 C: the FMU's default limit

# The book file Chap3_TGV_Modelisation_Thermique.mo (marcbudinger/MultiphysicsModelingTechSys,
# files/): each value as the file writes it, with the component it is set in.
BOOK_FILE = "Chap3_TGV_Modelisation_Thermique.mo"
BOOK_VALUES = {
    "m_winding": (50.0, "ModeleTGV_2, heatCapacitor: C = 385 * 50"),
    "c_winding": (385.0, "ModeleTGV_2, heatCapacitor: C = 385 * 50"),
    "m_iron": (170.0, "ModeleTGV_2, heatCapacitor1: C = 444 * 170"),
    "c_iron": (444.0, "ModeleTGV_2, heatCapacitor1: C = 444 * 170"),
    "e_insulation": (0.6e-3, "ModeleTGV_2, RthCuivre: R = 0.6 * 1E-3 / (140E-3 * 0.54)"),
    "lambda_insulation": (140e-3, "ModeleTGV_2, RthCuivre"),
    "A_insulation": (0.54, "ModeleTGV_2, RthCuivre"),
    "h_cooling": (50.0, "ModeleTGV_2, RthFer: R = 1 / (1 * 50)"),
    "A_cooling": (1.0, "ModeleTGV_2, RthFer"),
    "R_one_node": (0.0279, "ModeleTGV_1, ResistanceThEq: R = 0.0279"),
    "P_joule_step": (10000.0, "ModeleTGV_1 PertesPuissance2, ModeleTGV_2 step1: height = 10000 (record)"),
    "T_ambient": (313.15, "TempAmbiante, TemperatureAmbient: 40 + 273.15"),
}
# ModeleTGV_1's one-node capacity, CapaThEq C = 94730 J/K: the two nodes' sum (checked below).
BOOK_ONE_NODE_CAPACITY = 94730.0
# The book file's experiment: StopTime = 10000, Interval = 20 (both models).
BOOK_STOP, BOOK_INTERVAL = 10000.0, 20.0
# The book's result files, read with scipy.io.loadmat (Dymola trajectory format): the sensors'
# temperatures, K, at t = 100, 1000, 2000, 5000, 10000 s, rounded to 0.1 mK. Their worst deviation
# from the closed forms below over all 502 rows is 0.75 mK (the authors' solver ran at rtol 1e-6).
BOOK_TIMES = (100.0, 1000.0, 2000.0, 5000.0, 10000.0)
BOOK_RESULTS = {
    # (nodes, losses W, node): ModeleTGV_1.mat temperatureSensor(2).T, ModeleTGV_2.mat temperatureCuivre(2)/Fer(2).T
    (1, 5000.0, "T_winding"): (318.3297, 357.0947, 387.1965, 431.6134, 449.4776),
    (1, 10000.0, "T_winding"): (323.5094, 401.0395, 461.2429, 550.0768, 585.8052),
    (2, 5000.0, "T_winding"): (332.5362, 383.8984, 411.8016, 444.1778, 452.1855),
    (2, 5000.0, "T_iron"): (314.7913, 349.6859, 375.3709, 405.1811, 412.5542),
    (2, 10000.0, "T_winding"): (351.9223, 454.6469, 510.4532, 575.2056, 591.2210),
    (2, 10000.0, "T_iron"): (316.4326, 386.2218, 437.5918, 497.2122, 511.9585),
}
BOOK_RESULT_TOLERANCE = 2e-3  # K: the book's own 0.75 mK from the exact solution, plus its rounding


def thermal_fmu():
    return require_fmu(DIST_DIR / "TractionMotorThermal.fmu")


@lru_cache(maxsize=None)
def parameter_starts() -> dict[str, float]:
    md = read_model_description(str(thermal_fmu()))
    return {v.name: float(v.start) for v in md.modelVariables if v.causality == "parameter" and v.type == "Real"}


def heat_capacity_total() -> float:
    """C = m_winding c_copper + m_iron c_steel, from the documented masses."""
    p = parameter_starts()
    return p["m_winding"] * p["c_winding"] + p["m_iron"] * p["c_iron"]


def conductances() -> tuple[float, float, float]:
    """(G winding-iron, G iron-air, G one node), W/K, from the documented book-file parameters:
    conduction lambda A / e through the slot insulation, convection h A, and 1 / R_one_node."""
    p = parameter_starts()
    return (p["lambda_insulation"] * p["A_insulation"] / p["e_insulation"], p["h_cooling"] * p["A_cooling"], 1.0 / p["R_one_node"])


def steady_rise(nodes: int, losses: float) -> float:
    g_wi, g_ia, g_one = conductances()
    return losses / g_one if nodes == 1 else losses * (1.0 / g_wi + 1.0 / g_ia)


def two_node_closed_form(losses: float):
    """The two-node model under a constant loss step from cold is linear with constant forcing,
    x' = A x + b (x: winding and iron rises over ambient), so x(t) = x_inf + e^{At}(x0 - x_inf)
    exactly (scipy's expm). Returns t -> (T_winding, T_iron)."""
    import scipy.linalg

    p = parameter_starts()
    c_w, c_i = p["m_winding"] * p["c_winding"], p["m_iron"] * p["c_iron"]
    g_wi, g_ia, _ = conductances()
    a = np.array([[-g_wi / c_w, g_wi / c_w], [g_wi / c_i, -(g_wi + g_ia) / c_i]])
    x_inf = -np.linalg.solve(a, np.array([losses / c_w, 0.0]))
    return lambda t: AMBIENT + (x_inf - scipy.linalg.expm(a * t) @ x_inf)


def one_node_closed_form(losses: float):
    tau = heat_capacity_total() / conductances()[2]
    return lambda t: AMBIENT + steady_rise(1, losses) * (1.0 - np.exp(-np.asarray(t) / tau))


@lru_cache(maxsize=None)
def run(nodes: int, stop_time: float, interval: float, heat_source: int = 4, losses: float = 0.0, initial_state: int = 1,
        extra: tuple = ()):
    """heat_source 3 takes `losses` as its input, 4 (the default) as its step P_joule_step (0: the
    FMU's default step)."""
    starts = {"nodes": nodes, "heat_source": heat_source, "initial_state": initial_state, **dict(extra)}
    if heat_source == 3:
        starts["P_joule_in"] = losses
    elif heat_source == 4 and losses:
        starts["P_joule_step"] = losses
    return simulate_fmu(
        str(thermal_fmu()),
        stop_time=stop_time,
        output_interval=interval,
        start_values=starts,
        output=["T_winding", "T_iron", "torque", "P_joule", "time_to_limit", "limit_reached", "margin_to_limit"],
        validate=False,
    )


def test_hand_figures_overload_torque_and_losses():
    # 1 MW / 502.65 rad/s = 1989.4 N m; 5 kW x (1989.4/1400)^2 = 10.10 kW.
    assert OVERLOAD_TORQUE == pytest.approx(1989.44, abs=0.01)
    assert OVERLOAD_LOSSES == pytest.approx(10096.6, abs=0.1)
    r = run(2, 100.0, 10.0, heat_source=1)
    assert r["torque"][-1] == pytest.approx(OVERLOAD_TORQUE, rel=1e-12)
    assert r["P_joule"][-1] == pytest.approx(OVERLOAD_LOSSES, rel=1e-12)
    rise = steady_rise(2, OVERLOAD_LOSSES)
    print(f"\noverload torque {OVERLOAD_TORQUE:.1f} N m, losses {OVERLOAD_LOSSES / 1e3:.3f} kW "
          f"(steady rise {rise:.1f} K, winding {rise + AMBIENT - 273.15:.1f} C if it lasted; the book file steps 10 kW)")


def test_defaults_are_the_book_files_values():
    p = parameter_starts()
    md = read_model_description(str(thermal_fmu()))
    ints = {v.name: int(v.start) for v in md.modelVariables if v.type in ("Integer", "Enumeration") and v.start is not None}
    inputs = {v.name: float(v.start) for v in md.modelVariables if v.causality == "input" and v.type == "Real"}
    print(f"\n| parameter | book value | FMU default | source ({BOOK_FILE}) |\n|---|---|---|---|")
    for name, (value, source) in BOOK_VALUES.items():
        default = p.get(name, inputs.get(name))
        print(f"| {name} | {value:g} | {default:g} | {source} |")
        assert default == pytest.approx(value, rel=1e-12), f"{name}: FMU default {default}, book file {value} ({source})"
    # The one-node capacity of ModeleTGV_1 is the sum of ModeleTGV_2's two (385*50 + 444*170).
    assert heat_capacity_total() == BOOK_ONE_NODE_CAPACITY
    # The defaults select the book's data and its experiment: a loss step at t = 0 from cold.
    assert ints["thermal_data"] == 1 and ints["heat_source"] == 4 and ints["initial_state"] == 1 and p["t_step"] == 0.0
    exp = md.defaultExperiment
    assert (float(exp.stopTime), float(exp.stepSize)) == (BOOK_STOP, BOOK_INTERVAL)


@pytest.mark.parametrize("nodes, losses", [(1, 5000.0), (1, 10000.0), (2, 5000.0), (2, 10000.0)],
                         ids=["one-node-rated", "one-node-record", "two-node-rated", "two-node-record"])
def test_the_book_files_experiment(nodes, losses):
    # The book file's four runs (normal service 5 kW, the record 10 kW; 10 000 s every 20 s):
    # every row against the closed form, and five instants against the book's result files.
    r = run(nodes, BOOK_STOP, BOOK_INTERVAL, losses=losses)
    t = np.asarray(r["time"])
    if nodes == 1:
        exact = {"T_winding": one_node_closed_form(losses)(t)}
    else:
        both = np.array([two_node_closed_form(losses)(ti) for ti in t])
        exact = {"T_winding": both[:, 0], "T_iron": both[:, 1]}
    for name, ref in exact.items():
        worst = float(np.max(np.abs(np.asarray(r[name]) - ref)))
        book = np.array(BOOK_RESULTS[(nodes, losses, name)])
        at = np.interp(BOOK_TIMES, t, np.asarray(r[name]))
        off = float(np.max(np.abs(at - book)))
        print(f"\n{nodes} node(s), {losses:.0f} W, {name}: at 10 000 s {r[name][-1] - 273.15:.4f} C; worst vs closed form "
              f"{worst:.1e} K, vs the book's result file {off:.1e} K")
        assert worst < 1e-4, f"{name}: {worst:.2e} K from the closed form"
        assert off < BOOK_RESULT_TOLERANCE, f"{name}: {off:.2e} K from the book's result file at {BOOK_TIMES}"


# 25 one-node time constants: the slowest mode has decayed to e^-25 of its start.
STEADY_HORIZON = 25.0 * 2643.0


@pytest.mark.parametrize("nodes", [1, 2])
@pytest.mark.parametrize("losses", [NOMINAL_LOSSES, OVERLOAD_LOSSES], ids=["nominal", "overload"])
def test_steady_winding_temperature(nodes, losses):
    r = run(nodes, STEADY_HORIZON, STEADY_HORIZON / 50, heat_source=3, losses=losses)
    expected = AMBIENT + steady_rise(nodes, losses)
    print(f"\n{nodes} node(s), {losses / 1e3:.2f} kW: steady winding {r['T_winding'][-1] - 273.15:.4f} C, "
          f"hand {expected - 273.15:.4f} C")
    assert r["T_winding"][-1] == pytest.approx(expected, abs=0.1)


@pytest.mark.parametrize("nodes", [1, 2])
def test_a_nominal_steady_start_stays_put(nodes):
    # initial_state = 2 starts at the nominal steady state; with the nominal losses it must not move.
    # The book's resistances put it at 179.5 C (one node) and 179.7 C (two), just below the 180 C limit.
    # "Must not move" within the solver's error: 10 x the FMU's declared tolerance of the
    # temperature (the accuracy rule of test_accuracy.py). Measured: 1.1e-5 K (2.4e-8 of 453 K) with
    # two nodes, where the explicit steps over the 1000 s rows sit at their stability limit on the
    # winding's 153 s mode; 0 with one node.
    tolerance = float(read_model_description(str(thermal_fmu())).defaultExperiment.tolerance)
    steady = AMBIENT + steady_rise(nodes, NOMINAL_LOSSES)
    bound = 10.0 * tolerance * steady
    r = run(nodes, 20_000.0, 1000.0, heat_source=3, losses=NOMINAL_LOSSES, initial_state=2)
    drift = float(np.max(np.abs(r["T_winding"] - steady)))
    print(f"\n{nodes} node(s), nominal steady start {steady - 273.15:.4f} C: drift {drift:.1e} K (bound {bound:.1e} K)")
    assert drift < bound
    assert steady < INSULATION_LIMIT and np.all(r["limit_reached"] == 0.0)
    # From the chapter's rise (thermal_data = 2: 5 kW over 140 K) it sits at the limit: reached at t = 0.
    r = run(nodes, 20_000.0, 1000.0, heat_source=3, losses=NOMINAL_LOSSES, initial_state=2, extra=(("thermal_data", 2),))
    assert np.max(np.abs(r["T_winding"] - INSULATION_LIMIT)) < bound
    assert r["limit_reached"][0] == 1.0 and r["time_to_limit"][-1] == 0.0


def test_one_node_time_constant_matches_the_exponential():
    # T(t) = T_amb + dT_inf (1 - e^{-t/tau}), tau = C/G: each sample gives tau = -t / ln(1 - theta).
    tau = heat_capacity_total() / conductances()[2]
    r = run(1, 3.0 * tau, tau / 100, heat_source=1)
    t, theta = r["time"][1:], (r["T_winding"][1:] - AMBIENT) / steady_rise(1, OVERLOAD_LOSSES)
    estimates = -t / np.log(1.0 - theta)
    worst = np.max(np.abs(estimates / tau - 1.0))
    print(f"\none-node time constant: C/G = {tau:.1f} s, from the trajectory {estimates.min():.2f}..{estimates.max():.2f} s "
          f"(worst {worst:.1e})")
    assert worst < 1e-3


def test_time_to_reach_the_insulation_limit_from_cold():
    # The default experiment: the book file's 10 kW record step.
    losses = BOOK_VALUES["P_joule_step"][0]
    tau = heat_capacity_total() / conductances()[2]
    # One node, closed form: T_amb + dT_inf (1 - e^{-t/tau}) = limit.
    closed_form = -tau * math.log(1.0 - NOMINAL_RISE / steady_rise(1, losses))
    one = run(1, BOOK_STOP, BOOK_INTERVAL)
    two = run(2, BOOK_STOP, BOOK_INTERVAL)
    t1, t2 = one["time_to_limit"][-1], two["time_to_limit"][-1]
    print(f"\ntime to {INSULATION_LIMIT - 273.15:.0f} C from cold under {losses / 1e3:.2f} kW: one node {t1:.1f} s "
          f"({t1 / 60:.1f} min; closed form {closed_form:.1f} s), two nodes {t2:.1f} s ({t2 / 60:.1f} min)")
    assert one["limit_reached"][-1] == 1.0 and two["limit_reached"][-1] == 1.0
    assert t1 == pytest.approx(closed_form, rel=1e-3)
    # The winding's own small heat capacity behind its insulation heats faster than the whole body.
    assert t2 < t1
    # Latched: the reported time is where the winding crossed the limit (sampled trajectory brackets it).
    for r, t_cross in ((one, t1), (two, t2)):
        before = r["time"] < t_cross
        assert np.all(r["T_winding"][before] < INSULATION_LIMIT) and np.all(r["T_winding"][~before] >= INSULATION_LIMIT)


def test_coupled_to_motor_fan_torque():
    # MotorFan's motor torque drives the thermal FMU (heat_source = 2) in a lockstep master.
    # Independent reference: with the input held over each communication step, the one-node model
    # has the exact per-step solution theta_{n+1} = theta_inf,n + (theta_n - theta_inf,n) e^{-h/tau},
    # theta_inf,n = P_n / G with P_n = P_J,nom (C_n / C_nom)^2 from the exchanged torque.
    step = 0.01
    r = couple(stop_time=30.0, step=step, nodes=1)
    losses = NOMINAL_LOSSES * (r["torque"] / MOTOR_FAN_RATED_TORQUE) ** 2
    assert np.allclose(r["P_joule"], losses, rtol=1e-12, atol=0.0)
    conductance = conductances()[2]
    tau = heat_capacity_total() / conductance
    theta = [0.0]
    decay = math.exp(-step / tau)
    for p in losses[:-1]:
        target = p / conductance
        theta.append(target + (theta[-1] - target) * decay)
    expected = AMBIENT + np.array(theta)
    worst = np.max(np.abs(r["T_winding"] - expected))
    print(f"\ncoupled to MotorFan: peak torque {r['torque'].max():.0f} N m, peak losses {losses.max() / 1e3:.1f} kW, "
          f"winding +{r['T_winding'][-1] - AMBIENT:.4f} K after 30 s; worst difference to the per-step exponential {worst:.1e} K")
    assert r["T_winding"][-1] > AMBIENT
    assert worst < 1e-6


@pytest.mark.parametrize("fmi_type", ["CoSimulation", "ModelExchange"])
def test_the_limit_is_a_state_event_in_both_interfaces(fmi_type):
    # Issue 19: the limit was latched by "an integral became positive" with no event indicator;
    # fmpy's CVode then latched it 2.2 K below the limit and put time_to_limit 3 s early. Now the
    # crossing is a state event: time_to_limit is the event time, in both interfaces.
    from scipy.optimize import brentq

    both = two_node_closed_form(BOOK_VALUES["P_joule_step"][0])
    crossing = brentq(lambda t: both(t)[0] - INSULATION_LIMIT, 100.0, 5000.0, xtol=1e-9)
    slope = (both(crossing + 0.5)[0] - both(crossing - 0.5)[0])
    tolerance = 1e-6
    r = simulate_fmu(
        str(thermal_fmu()), fmi_type=fmi_type, relative_tolerance=tolerance, stop_time=3000.0, output_interval=1.0,
        output=["T_winding", "time_to_limit", "limit_reached"], validate=False,
    )
    t, latched = r["time"], r["limit_reached"] > 0.5
    first = t[latched].min()
    print(f"\n{fmi_type} at rtol {tolerance:g}: time_to_limit {r['time_to_limit'][-1]:.4f} s, closed form {crossing:.4f} s, "
          f"first latched row at {first:.4f} s")
    # The bound the issue sets, 0.1 s: the winding rises `slope` K/s at the crossing (closed form,
    # 0.066 K/s with the book's values), so 0.1 s is 6.6e-3 K, 1.5e-5 of its 453 K: 15 x the
    # relative tolerance asked of the solver.
    print(f"\nwinding rises {slope:.4f} K/s at the crossing")
    assert abs(r["time_to_limit"][-1] - crossing) < 0.1
    assert np.all(r["time_to_limit"][t >= first] == r["time_to_limit"][-1]), "latched: time_to_limit holds after the event"
    # Never latched before the crossing: not before the closed form's (less the same 0.1 s), and
    # not while the FMU's own winding is below the limit (beyond the solver's error, 1e-6 x 440 K).
    assert np.all(~latched[t < crossing - 0.1])
    assert np.all(r["T_winding"][latched] >= INSULATION_LIMIT - 1e-6 * INSULATION_LIMIT)
    assert np.all(r["T_winding"][~latched] <= INSULATION_LIMIT + 1e-6 * INSULATION_LIMIT)
