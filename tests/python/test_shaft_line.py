"""ShaftLine against its contract (docs/shaft-line-spec.md; chapter 3, section 3.5.3, Table 3.8, eq. 3.9),
on the book's own case (file Chap3_Submarine.mo of the authors' repository marcbudinger/
MultiphysicsModelingTechSys: the FMU's defaults) and on the chapter text's reading (`TEXT_READING`).

Where each reference comes from:
  * the defaults: the book file's values, written below as the file writes them (`BOOK_VALUES`);
  * steady state at U_max: the hand balance of the spec (k I = a w^2 + b w + T_c, U = R I + k w),
    solved by Newton's method in shaft_line_reference.steady_state;
  * the short-circuit transient: an independent solution of the spec's equations with scipy's Radau
    (rtol 1e-10), seal stick/slip by terminal events segment by segment (shaft_line_reference.simulate);
  * the reduced models: the same, for their equations (the book's ReducedModel: simulate with
    structure="book_reduced"; the activity-reduced one: shaft_line_reference.simulate_reduced);
  * the activity ranking: the FMU's own activity outputs (eq. 3.3), over the short-circuit window.
Parameter values are the FMU's own start values (modelDescription.xml) with the overrides a case sets;
nothing comes from a previous run of the FMU. The book ships no result file for this model.

The FMU is driven with fmpy's FMU2Slave (fmi_host.Slave): communication steps of 0.05 s, 1 ms over
the 10 s after the short circuit where the torque peaks, so the sampled peak is the peak (the
reference is evaluated on the same grid from its dense output).
"""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np
import pytest
from fmpy import read_model_description

import shaft_line_reference as ref
from conftest import DIST_DIR, require_fmu
from fmi_host import Slave

# The book file's values (Chap3_Submarine.mo, models FullModel / FullModel_AI / ReducedModel), as it
# writes them: (parameter, value, component). pi is written 3.14 in every speed of the file.
BOOK_SPEED = 120 * 2 * 3.14 / 60  # 120 rpm with pi = 3.14: 12.56 rad/s
BOOK_VALUES = [
    ("k_emf", 700 / (120 * 2 * 3.14 / 60), "emf: k = 700/(120*2*3.14/60)"),
    ("R_armature", 8e-3, "resistor: R = 8e-3"),
    ("L_armature", 20e-3, "inductor: L = 20e-3"),
    ("U_max", 700.0, "tableVoltage: [0,0; 50,700; 100,700; 100,0; 150,0]"),
    ("ramp_time", 50.0, "tableVoltage: 0 -> 700 V over 0-50 s"),
    ("plateau_time", 50.0, "tableVoltage: 700 V over 50-100 s, 0 V from 100 s"),
    ("J_motor", 3e3, "inertia_motor: J = 3e3"),
    ("b_motor_bearings", 10.0, "friction_motor: d = 10"),
    ("K_shaft", 6.5e6, "shaft_stiffness_loss: c = 6.5e6"),
    ("D_shaft", 25000.0, "shaft_stiffness_loss: d = 25000"),
    ("J_shaft", 0.0, "no shaft inertia in the file (Table 3.8 lists 20 kg m2)"),
    ("J_propeller", 150e3, "Propeler_Inertia: J = 150e3"),
    ("T_seal_coulomb", 9000.0, "Propeler_friction: tau_pos = [0, 9000]"),
    ("T_seal_static", 9000.0, "Propeler_friction: one value, sticking and sliding"),
    ("T_propeller_nominal", 1.75e5, "Propeler_quadratic_torque (FullModel_AI, ReducedModel): tau_nominal = -1.75e5"),
    ("speed_propeller_nominal", BOOK_SPEED, "Propeler_quadratic_torque: w_nominal = 120*2*3.14/60"),
    ("propeller_law", 1, "FullModel: TorqueDirection = false (ReducedModel: true, propeller_law = 2)"),
    ("emf_constant", 1, "k given directly (not derived from a rated point)"),
]
BOOK_STOP_TIME = 150.0  # the file's supply table ends at 150 s (it has no experiment annotation)

# The chapter text's reading (section 3.5.3 and Table 3.8): 200 s ramp, 200 s plateau, short circuit at
# 400 s, 600 s in all; the table's 20 kg m2 shaft inertia; k from the rated point; the propeller
# absorbing the rated torque at the rated 120 rpm = 4 pi rad/s. The FMU's defaults before the book file.
TEXT_READING = (("ramp_time", 200.0), ("plateau_time", 200.0), ("J_shaft", 20.0), ("emf_constant", 2),
                ("speed_propeller_nominal", 4.0 * math.pi))
TEXT_STOP_TIME = 600.0

PEAK_WINDOW_LENGTH = 10.0  # s after the short circuit, sampled at FINE
COARSE, FINE = 0.05, 1e-3
# The spec ("Model reduction"): model_reduction = 2 keeps exactly these elements.
ACTIVITY_REDUCED_KEEPS = {"armature_resistance", "armature_inductance", "propeller_inertia", "propeller_load"}
ACTIVITY_COVER = 0.95
OUTPUTS = ("shaft_torque", "motor_torque", "armature_current", "motor_speed", "propeller_speed", "supply_voltage", "seal_torque")
INTEGERS = {"model_reduction", "emf_constant", "propeller_law"}


def fmu():
    return require_fmu(DIST_DIR / "ShaftLine.fmu")


@functools.lru_cache(maxsize=None)
def model_description():
    return read_model_description(str(fmu()))


@functools.lru_cache(maxsize=None)
def elements() -> tuple[str, ...]:
    """The storage and dissipative elements whose activity the FMU reports: its outputs activity_<element>
    that have a share_<element> beside them (spec, "Variables"; the supply, a source, has no share)."""
    md = model_description()
    names = {v.name for v in md.modelVariables if v.causality == "output"}
    return tuple(n[len("activity_"):] for n in sorted(names, key=lambda n: [v.name for v in md.modelVariables].index(n))
                 if n.startswith("activity_") and f"share_{n[len('activity_'):]}" in names)


@functools.lru_cache(maxsize=None)
def params(overrides: tuple = ()) -> ref.ShaftLineParams:
    """The FMU's start values with a case's overrides."""
    values = {v.name: v.start for v in model_description().modelVariables if v.start is not None}
    values.update(dict(overrides))
    return ref.ShaftLineParams.from_values(values)


def stop_time(overrides: tuple = ()) -> float:
    return TEXT_STOP_TIME if overrides == TEXT_READING else BOOK_STOP_TIME


def grid(overrides: tuple = ()) -> np.ndarray:
    """The communication points: COARSE steps, FINE ones over the PEAK_WINDOW_LENGTH after the short circuit."""
    a = params(overrides).short_circuit_time
    b = a + PEAK_WINDOW_LENGTH
    return np.unique(np.round(np.concatenate([
        np.arange(0.0, a, COARSE),
        a + FINE * np.arange(int(round((b - a) / FINE))),
        np.arange(b, stop_time(overrides) + COARSE / 2, COARSE),
    ]), 9))


@functools.lru_cache(maxsize=None)
def run(model_reduction: int = 0, voltage_from_input: bool = False, overrides: tuple = ()) -> dict:
    """One Co-Simulation run over the grid; with voltage_from_input the master sets the supply
    profile of the spec as the input at each communication point (held over the step)."""
    p = params(overrides)
    times = grid(overrides)
    rows = {name: [] for name in OUTPUTS + tuple(f"activity_{e}" for e in elements())}
    with Slave(fmu(), instance_name="shaft") as s:
        s.instantiate()
        s.fmu.setupExperiment(startTime=0.0, stopTime=float(times[-1]))
        s.fmu.setInteger([s.vr["model_reduction"]], [model_reduction])
        s.fmu.setBoolean([s.vr["voltage_from_input"]], [voltage_from_input])
        for name, value in overrides:
            if name in INTEGERS:
                s.fmu.setInteger([s.vr[name]], [int(value)])
            else:
                s.fmu.setReal([s.vr[name]], [float(value)])
        s.fmu.enterInitializationMode()
        s.fmu.exitInitializationMode()
        s.initialized = True
        names = list(rows)
        vrs = [s.vr[n] for n in names]
        for k, t in enumerate(times):
            if voltage_from_input:
                s.set(U_supply_in=p.supply(t))
            for n, v in zip(names, s.fmu.getReal(vrs)):
                rows[n].append(v)
            if k + 1 < len(times):
                s.do_step(t, times[k + 1] - t)
        events, mode = s.fmu.getInteger([s.vr["state_events"], s.vr["seal_mode"]])
    out = {n: np.asarray(v) for n, v in rows.items()}
    out["time"] = times
    out["state_events"] = events
    out["seal_mode"] = mode
    return out


@functools.lru_cache(maxsize=None)
def reference(overrides: tuple = (), structure: str = "full"):
    return ref.simulate(params(overrides), stop_time(overrides), t_eval=grid(overrides), structure=structure)


def peak(t, torque, short_circuit: float):
    """(largest |torque| after the short circuit, its signed value, its time)."""
    after = t >= short_circuit
    j = int(np.argmax(np.abs(torque[after])))
    return abs(torque[after][j]), torque[after][j], t[after][j]


def test_defaults_are_the_book_files_values():
    """The table of issue 20: parameter, book value, FMU default, source."""
    starts = {v.name: v.start for v in model_description().modelVariables}
    lines = [f"{'parameter':<24} {'book file':>14} {'FMU default':>14}  source (Chap3_Submarine.mo)"]
    wrong = []
    for name, book, source in BOOK_VALUES:
        default = int(starts[name]) if name in INTEGERS else float(starts[name])
        lines.append(f"{name:<24} {book:>14.8g} {default:>14.8g}  {source}")
        if not math.isclose(default, book, rel_tol=1e-15, abs_tol=0.0):
            wrong.append(name)
    print("\n" + "\n".join(lines))
    assert not wrong, "\n".join(lines)
    experiment = model_description().defaultExperiment
    assert float(experiment.stopTime) == BOOK_STOP_TIME


def test_eq_3_9_ratios_are_one_and_derived_parameters():
    """k_E = k_C from the power balance of the ideal machine (E I = C w). With the book's k given directly,
    k_machine is it and I_rated = T_rated / k; with emf_constant = 2 the FMU's machine constant
    reproduces the rated point both ways. a = T_propeller_nominal / speed_propeller_nominal^2."""
    p = params()
    with Slave(fmu()) as s:
        s.instantiate().initialize()
        k, a, i_rated = s.get("k_machine", "a_propeller", "I_rated")
    assert k == p.k_emf == pytest.approx(55.732484, rel=1e-7)  # 700 / 12.56
    assert i_rated == pytest.approx(p.T_rated / p.k_emf, rel=1e-14)
    assert a == pytest.approx(1.75e5 / BOOK_SPEED**2, rel=1e-14)

    q = params(TEXT_READING)
    with Slave(fmu()) as s:
        s.instantiate()
        s.fmu.setInteger([s.vr["emf_constant"]], [2])
        s.fmu.setReal([s.vr["speed_propeller_nominal"]], [4.0 * math.pi])
        s.initialize()
        k, a, i_rated = s.get("k_machine", "a_propeller", "I_rated")
    assert k == pytest.approx(q.k, rel=1e-12)
    assert a == pytest.approx(q.T_rated / q.speed_rated**2, rel=1e-12)
    # Rated point: U = R I + E with E = k w (k_E), T = k I (k_C); power E I = T w.
    assert q.U_rated == pytest.approx(q.R_armature * i_rated + k * q.speed_rated, rel=1e-12)
    assert q.T_rated == pytest.approx(k * i_rated, rel=1e-12)
    assert (k * q.speed_rated) * i_rated == pytest.approx(q.T_rated * q.speed_rated, rel=1e-12)


def test_steady_state_at_u_max_is_the_hand_balance():
    p = params()
    hand = ref.steady_state(p)
    r = run()
    t = r["time"]
    k = int(np.argmin(np.abs(t - (p.short_circuit_time - 1.0))))  # 1 s before the short circuit
    got = {
        "speed": r["motor_speed"][k],
        "current": r["armature_current"][k],
        "motor_torque": r["motor_torque"][k],
        "shaft_torque": r["shaft_torque"][k],
    }
    lines = [f"steady state at U_max = {p.U_max:g} V, t = {t[k]:g} s (FMU vs hand balance):"]
    for name, value in got.items():
        err = value / hand[name] - 1.0
        lines.append(f"  {name:<13} {value:14.8g} {hand[name]:14.8g}  {err:+.2e}")
    print("\n".join(lines))
    assert r["propeller_speed"][k] == pytest.approx(hand["speed"], rel=1e-3)
    for name, value in got.items():
        assert value == pytest.approx(hand[name], rel=1e-3), "\n".join(lines)


@pytest.mark.parametrize("case", ["book file", "chapter text"])
def test_peak_short_circuit_torque_matches_radau(case):
    overrides = () if case == "book file" else TEXT_READING
    p = params(overrides)
    r = run(overrides=overrides)
    res, switches = reference(overrides)
    mag, signed, when = peak(r["time"], r["shaft_torque"], p.short_circuit_time)
    ref_mag, ref_signed, ref_when = peak(res["t"], res["shaft_torque"], p.short_circuit_time)
    ratio = signed / p.T_rated
    diff = mag / ref_mag - 1.0
    print(
        f"\n{case}: maximal transient shaft torque after the short circuit at {p.short_circuit_time:g} s: {signed:.6g} N m "
        f"at t = {when:.3f} s, {ratio:+.3f} x rated ({p.T_rated:g} N m); Radau (rtol 1e-10): {ref_signed:.6g} N m at "
        f"{ref_when:.3f} s; difference {diff:+.2e}; seal switches {len(switches)}, stuck for good at {switches[-1][0]:.2f} s"
    )
    assert abs(diff) < 0.01
    assert np.sign(signed) == np.sign(ref_signed)
    # The whole torque history, not just its peak: within 1 % of the peak everywhere.
    assert np.array_equal(res["t"], r["time"])
    worst = np.max(np.abs(r["shaft_torque"] - res["shaft_torque"])) / ref_mag
    assert worst < 0.01, f"largest shaft-torque difference {worst:.2e} of the peak"
    # The seal switches as often as in the reference and ends stuck like it.
    assert r["state_events"] == len(switches), f"FMU {r['state_events']} events, Radau {len(switches)} switches: {switches}"
    assert r["seal_mode"] == int(res["mode"][-1]) == 0


def test_no_chattering_and_the_propeller_sticks_after_the_transient():
    p = params()
    r = run()
    res, switches = reference()
    print(f"\nstate events over {BOOK_STOP_TIME:g} s: {r['state_events']}")
    assert 0 < r["state_events"] < 100
    after = r["time"] > switches[-1][0] + 1.0  # a second after the reference's last stick
    assert r["seal_mode"] == 0
    assert np.all(r["propeller_speed"][after] == 0.0), "stuck: exactly still"
    # Held by the seal: the torque it must take stays within the static friction.
    assert np.all(np.abs(r["shaft_torque"][after]) <= p.T_seal_static)
    # And it is the torque the independent solution holds (the shaft's ringing after the stick):
    # within 10 x the default tolerance (1e-8) of the shaft torque's range, the accuracy rule.
    stuck = r["time"] > switches[-1][0]
    scale = np.ptp(res["shaft_torque"])
    worst = np.max(np.abs(r["seal_torque"][stuck] + res["shaft_torque"][stuck]))
    print(f"held seal torque after {switches[-1][0]:.3f} s against Radau: {worst:.3g} N m ({worst / scale:.2e} of the shaft torque's range)")
    assert worst <= 10 * 1e-8 * scale
    # The speed reverses during the transient (the seal slips both ways).
    assert np.min(r["propeller_speed"]) < 0.0


def window_activities(r) -> dict:
    t = r["time"]
    i0 = int(np.argmin(np.abs(t - params().short_circuit_time)))
    return {e: r[f"activity_{e}"][-1] - r[f"activity_{e}"][i0] for e in elements()}


def test_activity_ranking_and_the_activity_reduced_model_reproduce_the_peak():
    p = params()
    full = run(0)
    reduced = run(2)
    assert len(elements()) == 9, elements()  # R, L, J_m, bearings, K, D, J_p, seal, propeller (spec)
    activities = window_activities(full)
    total = sum(activities.values())
    ranked = sorted(activities.items(), key=lambda kv: -kv[1])
    whole = {e: full[f"activity_{e}"][-1] for e in elements()}
    whole_total = sum(whole.values())
    lines = [f"activity (eq. 3.3), short-circuit window {p.short_circuit_time:g}-{BOOK_STOP_TIME:g} s, and 0-{BOOK_STOP_TIME:g} s:",
             f"  {'element':<22} {'A (J)':>12} {'share':>8} {'cumul.':>8}   {'A whole run':>12} {'share':>8}"]
    keep, cumulative = set(), 0.0
    for name, a in ranked:
        if cumulative < ACTIVITY_COVER * total:
            keep.add(name)
        cumulative += a
        lines.append(f"  {name:<22} {a:12.4g} {100 * a / total:7.2f}% {100 * cumulative / total:7.2f}%   "
                     f"{whole[name]:12.4g} {100 * whole[name] / whole_total:7.2f}%")
    mag, _, _ = peak(full["time"], full["shaft_torque"], p.short_circuit_time)
    red_mag, red_signed, red_when = peak(reduced["time"], reduced["shaft_torque"], p.short_circuit_time)
    diff = red_mag / mag - 1.0
    lines.append(f"kept (>= {100 * ACTIVITY_COVER:g} %): {sorted(keep)}")
    lines.append(f"peak shaft torque: full {mag:.6g} N m, activity-reduced {red_mag:.6g} N m at {red_when:.3f} s ({diff:+.2%})")
    print("\n" + "\n".join(lines))
    assert keep == ACTIVITY_REDUCED_KEEPS, "\n".join(lines)
    assert abs(diff) < 0.05, "\n".join(lines)
    # The reduced model's dropped elements are really gone.
    for e in set(elements()) - ACTIVITY_REDUCED_KEEPS:
        assert reduced[f"activity_{e}"][-1] == 0.0, e
    # And it is the reduced equations: an independent Radau solution of them.
    t_ref, torque_ref = ref.simulate_reduced(p, BOOK_STOP_TIME, t_eval=grid())
    ref_mag, _, _ = peak(t_ref, torque_ref, p.short_circuit_time)
    assert red_mag == pytest.approx(ref_mag, rel=1e-3)


@pytest.mark.parametrize("propeller_law", [1, 2])
def test_the_books_reduced_model(propeller_law):
    """model_reduction = 1 is the book file's ReducedModel: no motor inertia and a rigid shaft, the
    motor bearings and the seal kept. The file writes its propeller with TorqueDirection = true
    (propeller_law = 2: a w^2 drives the propeller once it turns backwards); the two laws differ
    only after the speed reverses, so the peak is the same and the backwards swing is not."""
    overrides = (("propeller_law", propeller_law),)
    p = params(overrides)
    full = run(0)
    reduced = run(1, overrides=overrides)
    res, switches = reference(overrides, structure="book_reduced")
    assert np.array_equal(res["t"], reduced["time"])
    mag, _, _ = peak(full["time"], full["shaft_torque"], p.short_circuit_time)
    red_mag, red_signed, red_when = peak(reduced["time"], reduced["shaft_torque"], p.short_circuit_time)
    ref_mag, _, ref_when = peak(res["t"], res["shaft_torque"], p.short_circuit_time)
    lowest, ref_lowest = np.min(reduced["propeller_speed"]), np.min(res["propeller_speed"])
    print(f"\nbook's reduced model, propeller_law {propeller_law}: peak {red_signed:.6g} N m at {red_when:.3f} s "
          f"({red_mag / mag - 1:+.2%} against the full model), Radau {ref_mag:.6g} N m at {ref_when:.3f} s; "
          f"lowest propeller speed {lowest:.4f} rad/s (Radau {ref_lowest:.4f}); seal events {reduced['state_events']} "
          f"(Radau {len(switches)})")
    assert red_mag == pytest.approx(ref_mag, rel=1e-3)
    worst = np.max(np.abs(reduced["shaft_torque"] - res["shaft_torque"])) / ref_mag
    assert worst < 0.01, f"largest torque difference {worst:.2e} of the peak"
    assert lowest == pytest.approx(ref_lowest, rel=1e-3)
    assert reduced["state_events"] == len(switches)
    assert abs(red_mag / mag - 1.0) < 0.05
    for e in ("motor_inertia", "shaft_stiffness", "shaft_damping"):
        assert reduced[f"activity_{e}"][-1] == 0.0, e
    for e in ("motor_bearings", "seal_friction"):
        assert reduced[f"activity_{e}"][-1] > 0.0, e


def test_the_supply_as_an_input_gives_the_same_short_circuit():
    """voltage_from_input: the master sets the profile at each communication point (held over the
    0.05 s steps of the ramp: the ramp lags by half a step, 0.05 % of U_max over 50 s, and settles).
    Settled, the two runs differ by their integration errors, which follow the FMU's relative tolerance
    (1e-8, fmu-runtime's default): 10 x the tolerance."""
    p = params()
    built_in = run(0, False)
    from_input = run(0, True)
    mag, _, _ = peak(built_in["time"], built_in["shaft_torque"], p.short_circuit_time)
    mag_in, _, _ = peak(from_input["time"], from_input["shaft_torque"], p.short_circuit_time)
    assert from_input["supply_voltage"][-1] == 0.0
    k = int(np.argmin(np.abs(built_in["time"] - (p.short_circuit_time - 1.0))))
    assert from_input["motor_speed"][k] == pytest.approx(built_in["motor_speed"][k], rel=10 * 1e-8)
    assert mag_in == pytest.approx(mag, rel=1e-3)
    assert math.isclose(float(np.max(from_input["supply_voltage"])), p.U_max, rel_tol=1e-12)


def test_model_exchange_under_cvode_finds_the_same_events_and_peak():
    """The ME interface: fmpy's CVode (rtol 1e-8) integrates, finds the seal's zero crossings with its own root
    finder (fmi2GetEventIndicators) and lets the FMU switch the modes (fmi2NewDiscreteStates)."""
    from fmpy import simulate_fmu

    p = params()
    res, switches = reference()
    ref_mag, _, _ = peak(res["t"], res["shaft_torque"], p.short_circuit_time)
    me = simulate_fmu(str(fmu()), fmi_type="ModelExchange", solver="CVode", relative_tolerance=1e-8, record_events=False,
                      stop_time=BOOK_STOP_TIME, output_interval=COARSE,
                      output=["shaft_torque", "propeller_speed", "state_events", "seal_mode"])
    t = np.asarray(me["time"])
    # The peak on the coarse grid is within the torque's change over one 0.05 s sample of the true one:
    # compare with the reference on the same coarse grid.
    on_grid = np.isin(np.round(res["t"], 9), np.round(t, 9))
    ref_coarse, _, _ = peak(res["t"][on_grid], res["shaft_torque"][on_grid], p.short_circuit_time)
    mag, _, _ = peak(t, np.asarray(me["shaft_torque"]), p.short_circuit_time)
    print(f"\nModel Exchange (CVode): peak {mag:.6g} N m on the 0.05 s grid (Radau {ref_coarse:.6g}); "
          f"state events {me['state_events'][-1]}, Radau switches {len(switches)}")
    assert mag == pytest.approx(ref_coarse, rel=1e-3)
    assert ref_mag == pytest.approx(ref_coarse, rel=1e-2), "the 0.05 s grid nearly catches the peak"
    assert me["state_events"][-1] == len(switches)
    assert me["seal_mode"][-1] == 0
