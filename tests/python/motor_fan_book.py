"""Independent reference computation of the cooling-tower motor-fan with the book authors' values.

Chapter 3, sections 3.1-3.3 (../shared/seed/chapter3.txt) and the book's Modelica package
``Chap3_CoolingTowerFan`` (BOOK_FILE) with its Dymola result files. Nothing here is generated from,
or copied out of, the Modelica file: the values carry over (each one with the component it comes
from), the physics is written out again in plain numpy/scipy (solve_ivp, brentq); the
steady-state T-equivalent circuit is motor_fan_reference.t_equivalent, shared with the hand formulas.

Models of the book file reproduced (Figure 3.5 levels and Figures 3.7-3.10, Table 3.3):
  level 1 = a  Steady_State: motor torque table TorqueSpeed, LossyGear, QuadraticSpeedDependentTorque;
               the equilibrium table torque = fan torque / (N eta).
  level 2 = b  Transient_Dynamic: + inertia_motor 1.72, inertia_fan 3000, rigid shaft.
  level 3 = c  Transient_Resonance: + SpringDamper `spring` between the motor inertia and the gear,
               table smoothness ContinuousDerivative (Akima).
  level 4 = d  the induction machine (Modelica.Electrical.Machines AIM_SquirrelCage `aimc`) of the
               result files Transient_InductionMachine_graphic.mat / Test_InductionMachine2.mat (the
               model itself is not in the .mo file; its parameters are the .mat's parameter data).
  start 'pi'       Transient_SpeedControler (upper half): timeTable ramp -> secondOrder1 filter ->
                   feedback -> PI -> secondOrder actuator -> torque on the motor inertia.
  start 'inverse'  Transient_SpeedControler (lower half): InverseBlockConstraints make the motor
                   speed equal to the filtered set point; the motor torque is what that takes.
  Activity_Index_direct / Activity_Index_controller: activities (eq. 3.3) of the fan inertia, the
  spring-damper and the motor inertia (table33()).

Sign conventions (those of the project's MotorFan spec): every torque positive in the motor's driving
direction; shaft_torque = the torque the coupling transmits from the motor to the gear input
(= -spring.tau of the Modelica SpringDamper, whose flange_b is on the gear side); fan torque
opposes the rotation (TorqueDirection=false; for w >= 0 identical to the default true).

Gear (Modelica LossyGear, lossTable=[0,0.94,0.94,0,0], no bearing friction): with T_high the torque
into the gear input and w_high its speed, T_low = eta N T_high if T_high w_high >= 0 (power towards
the fan), T_low = N T_high / eta otherwise (power back from the fan). Elastic shaft: T_high is the
spring-damper torque (a state function, explicit). Rigid shaft: both hypotheses give T_high of the
same sign (numerator T_m J_fan + J_m N T_fan), so the consistent branch is unique; w_high = 0
counts as forward rolling (the book's gear is "Stuck" only at the first instant, with zero torque).

Solvers: scipy.integrate.solve_ivp, rtol 1e-10, per-state atol (_ATOL), max_step 0.05 s (level 4:
0.2 supply periods, for the dense output of the 50 Hz electrical transient); DOP853 for
the non-stiff cases (direct starts, machine, inverse simulation), LSODA for the PI start (the 800 Hz
actuator: double eigenvalue -5024 1/s; Radau agrees to 2e-7 relative but is ~4x slower and stalls
on the rigid PI case). The integration is split at the time kinks (end of the ramp, last timeTable
point, switch-on of the machine). Activities are integrated as extra ODE states.

Findings (script output, numpy 2.4.6 / scipy 1.17.1; numpy 1.26.4 / scipy 1.11.4 agree to ~1e-8):
  * The book's SpringDamper_AI sensor (ActivityIndex_MechaRSensor with Rigid=false) multiplies the
    spring-damper torque (spring + damper) by the relative speed; the inertia sensors (Rigid=true)
    multiply (torque out - torque in) = -J dw/dt by the absolute speed. activity_shaft_stiffness
    follows the book; activity_shaft_spring_only is |K theta dtheta/dt| (2e-5 to 5e-5 relative below the book measure here).
  * Table 3.3's digits are reproduced with the 10 s ramp of Transient_SpeedControler, not with the
    20 s ramp of the file's Activity_Index_controller (see table33).
  * Level c vs Transient_Resonance.mat: worst 0.15 % of range (spring.tau, 11 N.m at 5.44 s).
  * The dq machine vs the two machine result files: worst 0.05 % of range.

"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from motor_fan_reference import t_equivalent

BOOK_FILE = (
    "files/Chap3_CoolingTowerFan.mo of github.com/marcbudinger/MultiphysicsModelingTechSys "
    "(package Chap3_CoolingTowerFan, uses Modelica 3.2.2); result files files/Transient_Resonance.mat, "
    "files/Transient_InductionMachine_graphic.mat, files/Test_InductionMachine2.mat"
)
_MO = "book file Chap3_CoolingTowerFan.mo"
_MAT_IM = "Transient_InductionMachine_graphic.mat and Test_InductionMachine2.mat, data_1"

# book file Chap3_CoolingTowerFan.mo, component TorqueSpeed (CombiTable1D, every model using it):
# table=[0,454; 80,579; 160,784; 220,997; 240,1057; 250,1071; 260,1060; 280,919; 300,500; 314,0]
# (motor speed rad/s -> motor torque N.m).
BOOK_TABLE_SPEED = (0.0, 80.0, 160.0, 220.0, 240.0, 250.0, 260.0, 280.0, 300.0, 314.0)
BOOK_TABLE_TORQUE = (454.0, 579.0, 784.0, 997.0, 1057.0, 1071.0, 1060.0, 919.0, 500.0, 0.0)

# FMU parameter name -> (value, source): the book's values as the MotorFan FMU takes them (its
# parameter names and codes, docs/motor-fan-spec.md "Parameters"). Integer/Boolean switches are
# given by the FMU's codes: they select the book's model structure.
_TRANSIENT_SC = f"{_MO}, model Transient_SpeedControler"
BOOK_VALUES = {
    "level": (3, f"{_MO}, model Transient_Resonance (Figure 3.5 c, the level the chapter retains) and "
              "Activity_Index_direct: inertias + SpringDamper; the model of the result file Transient_Resonance.mat"),
    "start_mode": (1, f"{_MO}, model Transient_Resonance: TorqueSpeed drives the motor from t = 0 "
                   "(direct on line; 2 = PI and 3 = inverse are Transient_SpeedControler's two halves)"),
    "keep_shaft_stiffness": (True, f"{_MO}, component spring (SpringDamper) between inertia_motor and lossyGear"),
    "motor_model": (1, f"{_MO}, component TorqueSpeed (CombiTable1D): the motor is its torque-speed table"),
    "motor_table_interpolation": (0, f"{_MO}: TorqueSpeed read as each model's file does: linear "
                                  "(Steady_State, Transient_Dynamic: CombiTable1D default), Akima "
                                  "(Transient_Resonance, Activity_Index_direct: smoothness ContinuousDerivative)"),
    **{f"motor_table_speed_{i + 1}": (w, f"{_MO}, component TorqueSpeed: table[{i + 1},1] (rad/s)")
       for i, w in enumerate(BOOK_TABLE_SPEED)},
    **{f"motor_table_torque_{i + 1}": (T, f"{_MO}, component TorqueSpeed: table[{i + 1},2] (N.m)")
       for i, T in enumerate(BOOK_TABLE_TORQUE)},
    "J_motor": (1.72, f"{_MO}, component inertia_motor (Transient_Dynamic and later): J=1.72 kg.m2. "
                "NB the machine result files add the machine's own rotor inertia aimc.Jr = 1.72 to "
                "inertia_motor.J = 1.72 (3.44 kg.m2 on the motor side at level d)"),
    "J_fan": (3000.0, f"{_MO}, component inertia_fan: J=3000 kg.m2 (low-speed side; "
              "Steady_State has a 1e-3 placeholder inertia)"),
    "gear_ratio": (16.0, f"{_MO}, component lossyGear: ratio=16"),
    "gear_efficiency": (0.94, f"{_MO}, component lossyGear: lossTable=[0,0.94,0.94,0,0] "
                        "(0.94 both directions of power flow, no bearing friction)"),
    "K_shaft": (866.0, f"{_MO}, component spring (SpringDamper, Transient_Resonance etc.): c=866 N.m/rad "
                "(Transient_SpeedControler2: c=866e3)"),
    "D_shaft": (866.0 / 100.0 / math.sqrt(886.0 / 1.7),
                f"{_MO}, component spring: d=866/100/sqrt(886/1.7) = 0.3793373 N.m.s/rad "
                "(written with 886 and 1.7, not 866 and 1.72; Transient_Resonance.mat spring.d = 0.37933725)"),
    "T_fan_nominal": (7742.6, f"{_MO}, component quadraticSpeedDependentTorque: tau_nominal=-7742.6 N.m "
                      "(negative = load; TorqueDirection=false from Transient_Resonance on: opposes the rotation)"),
    "speed_fan_nominal": (19.373154697137, f"{_MO}, component quadraticSpeedDependentTorque: "
                          "w_nominal=19.373154697137 rad/s (= 185 rpm; Steady_State writes 19.37)"),
    "R_s": (0.038, f"{_MAT_IM}: aimc.Rs = 0.038 Ohm (alpha20s = 0)"),
    "R_r": (0.038, f"{_MAT_IM}: aimc.Rr = 0.038 Ohm (alpha20r = 0)"),
    "L_s_sigma": (2e-4, f"{_MAT_IM}: aimc.Lssigma = 2e-4 H (aimc.Lszero = 2e-4 H, inactive)"),
    "L_r_sigma": (4e-4, f"{_MAT_IM}: aimc.Lrsigma = 4e-4 H"),
    "L_m": (0.012, f"{_MAT_IM}: aimc.Lm = 0.012 H (airGapS.Lm)"),
    "pole_pairs": (1.0, f"{_MAT_IM}: aimc.p = 1"),
    "winding_connection": (2, f"{_MAT_IM}: terminalBox with delta plugs (terminalBox.delta.*): the FMU's "
                           "code 2 = delta (each winding across U_supply; 1 = star)"),
    "U_supply": (230.0, f"{_MAT_IM}: sineVoltage.V = 187.794 V peak per phase of a star source (star, "
                 "ground) = 230 V rms line to line (VNominal = 230); the machine is DELTA connected, so "
                 "each winding sees 230 V rms (aimc.vs peak 325.27 V = 230 sqrt 2). With "
                 "winding_connection = 2 (delta) the FMU takes this line-to-line 230 V as it is (a star "
                 "model would need 230 sqrt 3 = 398.37 V for the same winding voltage)"),
    "f_supply": (50.0, f"{_MAT_IM}: fNominal = 50, sineVoltage.freqHz = 50 Hz"),
    "speed_setpoint": (300.0, f"{_TRANSIENT_SC}, component timeTable: table=[0,0; 10,300; 20,300] -> 300 rad/s"),
    "ramp_time": (10.0, f"{_TRANSIENT_SC}, component timeTable: 0 -> 300 rad/s in 10 s (the chapter's "
                  "Figure 3.8 'within 10 s'; Activity_Index_controller: table=[0,0; 20,300; 30,300], 20 s)"),
    "setpoint_filter": (1, f"{_TRANSIENT_SC}, component secondOrder1 between timeTable and the feedback "
                        "(the FMU's code 1 = the filter at filter_frequency_below)"),
    "filter_frequency_below": (0.5 * 3.14 / math.pi,
                               f"{_TRANSIENT_SC}, component secondOrder1 (SecondOrder): w=2*3.14*0.5 rad/s "
                               "-> 0.49975 Hz (3.14 for pi)"),
    "filter_damping": (1.0, f"{_TRANSIENT_SC}, component secondOrder1: D=1"),
    "Kp_speed": (10000.0, f"{_TRANSIENT_SC}, component PI (Blocks.Continuous.PI): k=10000 -> Kp = k N.m.s/rad"),
    "Ki_speed": (100000.0, f"{_TRANSIENT_SC}, component PI: k=10000, T=0.1 -> Ki = k/T = 1e5 N.m/rad"),
    "T_limit": (0.0, f"{_TRANSIENT_SC}, component PI: Blocks.Continuous.PI has no output limit (the "
                "FMU's 0 = none)"),
    "actuator_angular_frequency": (2.0 * 3.14 * 800.0, f"{_TRANSIENT_SC}, component secondOrder: w=2*3.14*800 "
                                   "= 5024 rad/s (torque actuator, unit gain)"),
    "actuator_damping": (1.0, f"{_TRANSIENT_SC}, component secondOrder: D=1"),
}
# FMU parameters the book has no counterpart for (name -> reason): they act only outside the book's
# configurations, so no book value applies.
NOT_IN_BOOK = {
    "T_tracking": "anti-windup tracking time of a limited PI; the book's PI has no limit (T_limit 0), so it never acts",
    "filter_frequency_above": "Figure 3.13's second filter (above 1.4 Hz); the book file has only secondOrder1 "
                              "(setpoint_filter 1 selects filter_frequency_below)",
}

# Extra facts of the book files that are not FMU parameters (value, source).
BOOK_EXTRA = {
    "U_winding_rms": (230.0, f"{_MAT_IM}: VNominal = 230 V; aimc.vs peak 325.27 V = 230 sqrt(2)"),
    "U_line_rms": (230.0, f"{_MAT_IM}: sineVoltage.V = 187.794 V = 230 sqrt(2/3) peak, star source"),
    "J_rotor_machine": (1.72, f"{_MAT_IM}: aimc.Jr = 1.72 kg.m2 (in series with inertia_motor.J = 1.72)"),
    "J_stator_machine": (1.72, f"{_MAT_IM}: aimc.Js = 1.72 (useSupport=false: housing fixed, no effect)"),
    "machine_switch_time": (1.0, "Transient_InductionMachine_graphic.mat: booleanStep[k].startTime = 1.0 s "
                            "(idealCloser closes at 1 s); Test_InductionMachine2.mat: 0.0 s"),
    "machine_losses": (0.0, f"{_MAT_IM}: friction, core, stray-load PRef = 0; Ron = Goff = 1e-5 switch"),
    "machine_fan_TorqueDirection": (True, f"{_MAT_IM}: quadraticSpeedDependentTorque.TorqueDirection = 1"),
    "resonance_result_stop_time": (20.0, "Transient_Resonance.mat: Time 0 .. 20 s, output step 0.004 s"),
}


@dataclass(frozen=True)
class BookParameters:
    """The book's values (BOOK_VALUES) as a frozen dataclass: override with dataclasses.replace or
    .with_(name=value). Units SI; U_supply is line-to-line rms; with winding_connection 'delta' (the
    book's, the default) each winding sees U_supply, with 'star' U_supply/sqrt(3).

    Extra fields (not FMU parameters, except winding_connection):
      machine_rotor_inertia: added to J_motor at level 4 only (0 = the FMU's level d, whose J_motor is the whole motor-side inertia;
        the book's machine result files have aimc.Jr = 1.72 in addition to inertia_motor 1.72).
      machine_switch_time: the supply is connected at this time at level 4 (book graphic file: 1 s).
      winding_connection (an FMU parameter, here by name): 'star' (the FMU's code 1, U_supply/sqrt(3)
        per winding) or 'delta' (code 2, U_supply per winding; the book's).
      ramp_hold: only documents the timeTable's third point (ramp_time + 10 s, same value): the
        set point is constant after ramp_time either way.
    """

    J_motor: float = BOOK_VALUES["J_motor"][0]
    J_fan: float = BOOK_VALUES["J_fan"][0]
    gear_ratio: float = BOOK_VALUES["gear_ratio"][0]
    gear_efficiency: float = BOOK_VALUES["gear_efficiency"][0]
    K_shaft: float = BOOK_VALUES["K_shaft"][0]
    D_shaft: float = BOOK_VALUES["D_shaft"][0]
    T_fan_nominal: float = BOOK_VALUES["T_fan_nominal"][0]
    speed_fan_nominal: float = BOOK_VALUES["speed_fan_nominal"][0]
    R_s: float = BOOK_VALUES["R_s"][0]
    R_r: float = BOOK_VALUES["R_r"][0]
    L_s_sigma: float = BOOK_VALUES["L_s_sigma"][0]
    L_r_sigma: float = BOOK_VALUES["L_r_sigma"][0]
    L_m: float = BOOK_VALUES["L_m"][0]
    pole_pairs: float = BOOK_VALUES["pole_pairs"][0]
    U_supply: float = BOOK_VALUES["U_supply"][0]
    f_supply: float = BOOK_VALUES["f_supply"][0]
    speed_setpoint: float = BOOK_VALUES["speed_setpoint"][0]
    ramp_time: float = BOOK_VALUES["ramp_time"][0]
    Kp_speed: float = BOOK_VALUES["Kp_speed"][0]
    Ki_speed: float = BOOK_VALUES["Ki_speed"][0]
    filter_frequency_below: float = BOOK_VALUES["filter_frequency_below"][0]
    filter_damping: float = BOOK_VALUES["filter_damping"][0]
    actuator_angular_frequency: float = BOOK_VALUES["actuator_angular_frequency"][0]
    actuator_damping: float = BOOK_VALUES["actuator_damping"][0]
    machine_rotor_inertia: float = 0.0
    machine_switch_time: float = 0.0
    winding_connection: str = {1: "star", 2: "delta"}[BOOK_VALUES["winding_connection"][0]]

    def with_(self, **changes) -> "BookParameters":
        return replace(self, **changes)

    @classmethod
    def book_machine_files(cls, **changes) -> "BookParameters":
        """The configuration of the book's machine result files: delta windings on 230 V line to
        line, machine rotor inertia 1.72 in addition to inertia_motor 1.72, switch-on at
        machine_switch_time (1.0 s in Transient_InductionMachine_graphic.mat; pass 0.0 for
        Test_InductionMachine2.mat)."""
        base = dict(U_supply=230.0, winding_connection="delta", machine_rotor_inertia=1.72,
                    machine_switch_time=1.0)
        base.update(changes)
        return cls(**base)

    @property
    def winding_voltage_rms(self) -> float:
        if self.winding_connection == "delta":
            return self.U_supply
        if self.winding_connection == "star":
            return self.U_supply / math.sqrt(3.0)
        raise ValueError("winding_connection must be 'star' or 'delta'")


# --------------------------------------------------------------------------------------------
# Components
# --------------------------------------------------------------------------------------------

def akima_slopes(x, y) -> np.ndarray:
    """Node slopes of Akima's 1970 spline (the Modelica CombiTable1D smoothness ContinuousDerivative).

    End condition (Akima 1970, also scipy.interpolate.Akima1DInterpolator's default 'akima'): two
    extra segment slopes at each end, m_-1 = 2 m_0 - m_1, m_-2 = 2 m_-1 - m_0 (and mirrored at the
    right end). Node slope t_i = (|m_i+1 - m_i| m_i-1 + |m_i-1 - m_i-2| m_i) / (sum of weights),
    with the mean of m_i-1 and m_i when both weights vanish (does not happen for this table).
    Checked against Transient_Resonance.mat (TorqueSpeed.u -> TorqueSpeed.y, 5114 rows incl. the
    negative speeds): max |difference| 5.1e-4 N.m (float32 storage).
    """
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    m = np.diff(y) / np.diff(x)
    mm = np.concatenate([[3 * m[0] - 2 * m[1], 2 * m[0] - m[1]], m,
                         [2 * m[-1] - m[-2], 3 * m[-1] - 2 * m[-2]]])
    t = np.empty(len(x))
    for i in range(len(x)):
        w1 = abs(mm[i + 3] - mm[i + 2])
        w2 = abs(mm[i + 1] - mm[i])
        t[i] = (w1 * mm[i + 1] + w2 * mm[i + 2]) / (w1 + w2) if w1 + w2 > 0 else 0.5 * (mm[i + 1] + mm[i + 2])
    return t


class TorqueTable:
    """The motor torque table TorqueSpeed (book file, component TorqueSpeed).

    interpolation 'linear' (CombiTable1D default, smoothness LinearSegments) or 'akima'
    (smoothness ContinuousDerivative). Outside [0, 314] rad/s the CombiTable1D default
    extrapolation (LastTwoPoints) is reproduced: linear through the two end points for 'linear';
    for 'akima' a straight line with the spline's end slope (the spline's C1 continuation: 1.0625
    N.m.s/rad at 0 rad/s, which Transient_Resonance.mat confirms: TorqueSpeed.y = 450.11 at
    u = -3.66 rad/s). The speed does leave the table there: motor speed down to -3.66 rad/s at
    t = 0.19 s in the book's level-c result.
    """

    def __init__(self, interpolation: str = "linear", speed=BOOK_TABLE_SPEED, torque=BOOK_TABLE_TORQUE):
        if interpolation not in ("linear", "akima"):
            raise ValueError("interpolation must be 'linear' or 'akima'")
        self.interpolation = interpolation
        self.x = [float(v) for v in speed]
        self.y = [float(v) for v in torque]
        n = len(self.x)
        if interpolation == "akima":
            self.t = [float(v) for v in akima_slopes(self.x, self.y)]
        else:
            s = [(self.y[i + 1] - self.y[i]) / (self.x[i + 1] - self.x[i]) for i in range(n - 1)]
            self.t = [s[0]] + [0.0] * (n - 2) + [s[-1]]  # only the end slopes are used (extrapolation)
            self.seg = s

    def __call__(self, u: float) -> float:
        x, y, t = self.x, self.y, self.t
        if u <= x[0]:
            return y[0] + t[0] * (u - x[0])
        if u >= x[-1]:
            return y[-1] + t[-1] * (u - x[-1])
        k = bisect.bisect_right(x, u) - 1
        if self.interpolation == "linear":
            return y[k] + self.seg[k] * (u - x[k])
        h = x[k + 1] - x[k]
        s = (u - x[k]) / h
        s2 = s * s
        s3 = s2 * s
        return ((2 * s3 - 3 * s2 + 1) * y[k] + (s3 - 2 * s2 + s) * h * t[k]
                + (-2 * s3 + 3 * s2) * y[k + 1] + (s3 - s2) * h * t[k + 1])

    def vec(self, u) -> np.ndarray:
        return np.array([self(float(v)) for v in np.atleast_1d(u)])


def fan_torque(p: BookParameters, w_fan):
    """Load torque of the fan (magnitude positive against positive rotation), book file component
    quadraticSpeedDependentTorque: tau = tau_nominal (w/w_nominal)^2 with TorqueDirection=false
    (sign(w) (w/w_nominal)^2, i.e. always braking). Returns T_fan_nominal (w/wn)|w/wn|."""
    r = np.asarray(w_fan, dtype=float) / p.speed_fan_nominal
    return p.T_fan_nominal * r * np.abs(r)


def gear_low_torque(p: BookParameters, T_high: float, w_high: float) -> float:
    """Low-speed torque of the LossyGear given the torque into its input and the input speed."""
    if T_high * w_high >= 0.0:
        return p.gear_efficiency * p.gear_ratio * T_high
    return p.gear_ratio * T_high / p.gear_efficiency


def ramp(p: BookParameters, t: float) -> tuple[float, float]:
    """Set point of the book's timeTable [0,0; ramp_time,W; ramp_time+10,W] (W = speed_setpoint):
    (value, slope). ramp_time = 0: a step at t = 0 (slope 0)."""
    W, T = p.speed_setpoint, p.ramp_time
    if T <= 0.0:
        return W, 0.0
    if t < T:
        return W * t / T, W / T
    return W, 0.0


def machine_steady_torque(p: BookParameters, w_m):
    """Steady-state torque of the induction machine (T-equivalent circuit per winding, rms
    winding voltage p.winding_voltage_rms): Z = Rs + j ws Lss + (j ws Lm || (Rr/s + j ws Lrs)),
    T = 3 |I_r|^2 (Rr/s) p / ws. Exactly the steady state of the dq model below."""
    w_m = np.asarray(w_m, dtype=float)
    ws = 2.0 * math.pi * p.f_supply
    s = 1.0 - p.pole_pairs * w_m / ws
    s = np.where(np.abs(s) < 1e-15, 1e-15, s)
    return t_equivalent(p, p.winding_voltage_rms, ws, s)[0]


# --------------------------------------------------------------------------------------------
# Level a: quasi-static equilibrium
# --------------------------------------------------------------------------------------------

def steady_state(params: BookParameters = BookParameters(), interpolation: str = "linear") -> tuple[float, float]:
    """Level a (book file model Steady_State): motor speed where the table torque equals the fan
    torque referred to the high-speed side with power flowing to the fan, T_fan(w/N)/(N eta).
    Returns (motor speed rad/s, motor = shaft torque N.m). brentq on [0, 314]."""
    p = params
    tab = TorqueTable(interpolation)
    f = lambda w: tab(w) - float(fan_torque(p, w / p.gear_ratio)) / (p.gear_ratio * p.gear_efficiency)  # noqa: E731
    w = brentq(f, 0.0, BOOK_TABLE_SPEED[-1], xtol=1e-13, rtol=1e-15, maxiter=200)
    return w, tab(w)


def machine_steady_state(params: BookParameters = BookParameters()) -> tuple[float, float]:
    """Direct-on-line steady state of the machine (equivalent circuit) with the fan load through
    the gear: (speed rad/s, torque N.m), brentq between the breakdown speed and synchronism."""
    p = params
    ws = 2 * math.pi * p.f_supply / p.pole_pairs
    grid = np.linspace(0.0, ws * (1 - 1e-9), 20001)
    wb = grid[int(np.argmax(machine_steady_torque(p, grid)))]
    f = lambda w: float(machine_steady_torque(p, w)) - float(fan_torque(p, w / p.gear_ratio)) / (p.gear_ratio * p.gear_efficiency)  # noqa: E731
    w = brentq(f, wb, ws * (1 - 1e-12), xtol=1e-13, rtol=1e-15)
    return w, float(machine_steady_torque(p, w))


# --------------------------------------------------------------------------------------------
# Dynamic levels
# --------------------------------------------------------------------------------------------

# state layout
_WM, _TH, _WF, _PSD, _PSQ, _PRD, _PRQ, _XPI, _F1, _F2, _A1, _A2, _EM, _ES, _EF, _ESP = range(16)
_N = 16
_ATOL = np.array([1e-8, 1e-11, 1e-9, 1e-9, 1e-9, 1e-9, 1e-9, 1e-10, 1e-9, 1e-9, 1e-7, 1e-4,
                  1e-6, 1e-6, 1e-6, 1e-6])


def _build(p: BookParameters, level: int, start: str, interpolation: str, rigid: bool, setpoint_filter: bool):
    """Returns (rhs(t, y) -> dy, outputs(t, y) -> dict of scalars)."""
    N, eta = p.gear_ratio, p.gear_efficiency
    Jf = p.J_fan
    Jm = p.J_motor + (p.machine_rotor_inertia if level == 4 else 0.0)
    K, D = p.K_shaft, p.D_shaft
    Tn, wn = p.T_fan_nominal, p.speed_fan_nominal
    Kp, Ki = p.Kp_speed, p.Ki_speed
    wfil = 2.0 * math.pi * p.filter_frequency_below
    Dfil = p.filter_damping
    wa, Da = p.actuator_angular_frequency, p.actuator_damping
    elastic = (level >= 3) and not rigid
    tab = TorqueTable(interpolation) if level in (2, 3) else None
    # machine
    ws = 2.0 * math.pi * p.f_supply
    pp = p.pole_pairs
    Ls, Lr, Lm = p.L_s_sigma + p.L_m, p.L_r_sigma + p.L_m, p.L_m
    det = Ls * Lr - Lm * Lm
    Rs, Rr = p.R_s, p.R_r
    Vhat = math.sqrt(2.0) * p.winding_voltage_rms if level == 4 else 0.0
    t_on = p.machine_switch_time

    def tfan(w):
        r = w / wn
        return Tn * r * abs(r)

    def setpoint(t, y):
        """(w_ref, dw_ref/dt, d2w_ref/dt2 or None) after the optional filter."""
        r, rd = ramp(p, t)
        if setpoint_filter:
            f1, f2 = y[_F1], y[_F2]
            return f1, f2, wfil * (wfil * (r - f1) - 2.0 * Dfil * f2)
        return r, rd, 0.0

    def machine(t, y, wm):
        psd, psq, prd, prq = y[_PSD], y[_PSQ], y[_PRD], y[_PRQ]
        isd = (Lr * psd - Lm * prd) / det
        isq = (Lr * psq - Lm * prq) / det
        ird = (Ls * prd - Lm * psd) / det
        irq = (Ls * prq - Lm * psq) / det
        v = Vhat if t >= t_on else 0.0
        wslip = ws - pp * wm
        d = (v - Rs * isd + ws * psq, -Rs * isq - ws * psd, -Rr * ird + wslip * prq, -Rr * irq - wslip * prd)
        Te = 1.5 * pp * (psd * isq - psq * isd)
        return Te, d, (isd, isq, v)

    def evaluate(t, y, want):
        dy = [0.0] * _N
        out = {} if want else None
        # ---- set point (filter states always integrated when used) ----
        if start in ("pi", "inverse"):
            wref, wref_d, wref_dd = setpoint(t, y)
            if setpoint_filter:
                dy[_F1] = y[_F2]
                dy[_F2] = wref_dd
            if want:
                out["speed_reference"] = wref
        else:
            wref = wref_d = wref_dd = 0.0
        # ---- motor side kinematics ----
        if start == "inverse":
            wm, am_imposed = wref, wref_d
        else:
            wm, am_imposed = y[_WM], None
        if elastic:
            wf = y[_WF]
            wg = N * wf
            th = y[_TH]
            thd = wm - wg
            Ts = K * th + D * thd
            Tlow = eta * N * Ts if Ts * wg >= 0.0 else N * Ts / eta
            af = (Tlow - tfan(wf)) / Jf
            dy[_TH] = thd
            dy[_WF] = af
        else:
            wf = wm / N
            wg = wm
            th = thd = 0.0
        # ---- motor torque ----
        if start == "direct":
            if level == 4:
                Tm, dpsi, el = machine(t, y, wm)
                dy[_PSD], dy[_PSQ], dy[_PRD], dy[_PRQ] = dpsi
                if want:
                    out["stator_current_rms"] = math.hypot(el[0], el[1]) / math.sqrt(2.0)
                    out["electrical_power"] = 1.5 * el[2] * el[0]
            else:
                Tm = tab(wm)
        elif start == "pi":
            e = wref - wm
            dy[_XPI] = e
            Tcmd = Kp * e + Ki * y[_XPI]
            Tm = y[_A1]
            dy[_A1] = y[_A2]
            dy[_A2] = wa * (wa * (Tcmd - Tm) - 2.0 * Da * y[_A2])
        else:  # inverse: torque follows from the imposed motion
            Tm = None
        # ---- dynamics ----
        if elastic:
            if start == "inverse":
                am = am_imposed
                Tm = Jm * am + Ts
            else:
                am = (Tm - Ts) / Jm
                dy[_WM] = am
        else:
            Tf = tfan(wf)
            if start == "inverse":
                am = am_imposed
                af = am / N
                Tlow = Jf * af + Tf
                Ts = Tlow / (eta * N) if Tlow * wg >= 0.0 else eta * Tlow / N
                Tm = Jm * am + Ts
            else:
                af = (eta * N * Tm - Tf) / (Jf + eta * N * N * Jm)
                Ts = Tm - Jm * N * af
                if Ts * wg < 0.0:
                    af = (N * Tm / eta - Tf) / (Jf + N * N * Jm / eta)
                    Ts = Tm - Jm * N * af
                am = N * af
                dy[_WM] = am
        # ---- activities (eq. 3.3) ----
        dy[_EM] = abs(Jm * am * wm)
        dy[_EF] = abs(Jf * af * wf)
        dy[_ES] = abs(Ts * thd) if elastic else 0.0          # book's sensor: whole spring-damper
        dy[_ESP] = abs(K * th * thd) if elastic else 0.0     # spring only
        if want:
            out.update(motor_speed=wm, fan_speed=wf, shaft_torque=Ts, motor_torque=Tm,
                       gear_speed=wg, shaft_twist=th, motor_acceleration=am, fan_acceleration=af)
            return out
        return dy

    # the states this configuration uses (the others stay 0 and are not handed to the solver)
    active = [_EM, _EF]
    if start != "inverse":
        active.append(_WM)
    if elastic:
        active += [_TH, _WF, _ES, _ESP]
    if level == 4:
        active += [_PSD, _PSQ, _PRD, _PRQ]
    if start == "pi":
        active += [_XPI, _A1, _A2]
    if start in ("pi", "inverse") and setpoint_filter:
        active += [_F1, _F2]
    active = sorted(active)
    full = np.zeros(_N)

    def rhs(t, z):
        y = full.copy()
        y[active] = z
        dy = evaluate(t, y, False)
        return [dy[i] for i in active]

    def outputs(t, y):
        return evaluate(t, y, True)

    return rhs, outputs, active


def _breakpoints(p: BookParameters, level: int, start: str, stop: float) -> list[float]:
    pts = [0.0]
    if start in ("pi", "inverse") and p.ramp_time > 0:
        pts += [p.ramp_time, p.ramp_time + 10.0]
    if level == 4 and start == "direct" and p.machine_switch_time > 0:
        pts.append(p.machine_switch_time)
    pts = sorted(set(v for v in pts if 0.0 <= v < stop))
    return pts + [stop]


def simulate(level: int, start: str = "direct", params: BookParameters = BookParameters(), stop: float = 30.0,
             t_eval=None, interpolation: str | None = None, rigid: bool = False, setpoint_filter: bool = True,
             rtol: float = 1e-10, method: str | None = None, max_step: float | None = None) -> dict:
    """Simulate the book's drive from rest (all states zero) to `stop` s.

    level 1..4 = Figure 3.5 a..d; start 'direct' (direct on line: table torque at levels 2-3,
    machine dq model at level 4), 'pi' (Transient_SpeedControler's PI start) or 'inverse' (its
    inverse simulation: motor speed imposed = filtered set point). Level 1 'direct' is the
    quasi-static equilibrium (constant arrays); level 1 'pi'/'inverse' is quasi-static tracking
    (motor speed = set point, torque = fan torque / (N eta)). Level 4 is 'direct' only.

    interpolation: None = the book's choice for the level (linear at levels 1-2 as in Steady_State
    and Transient_Dynamic, 'akima' at level 3 as in Transient_Resonance / Activity_Index_direct);
    'linear' or 'akima' to force. Unused at level 4 and in the controlled starts.
    rigid: rigid shaft at levels 3-4 (level 2 is always rigid): Transient_SpeedControlerRigid,
    Test_InductionMachine2. setpoint_filter: False bypasses secondOrder1.
    t_eval: output times (default: 1 ms grid from 0 to stop).

    Returns numpy arrays: t, motor_speed, fan_speed, shaft_torque (coupling torque on the high-speed
    side, = gear input torque), motor_torque, gear_speed, shaft_twist, speed_reference (controlled
    starts), stator_current_rms and electrical_power (level 4; winding current, 1.5 v_d i_d), and
    the activities in J: activity_motor_inertia (|J_m dw_m/dt w_m|), activity_shaft_stiffness (the
    book's sensor in SpringDamper_AI: |T_springdamper (w_b - w_a)|, spring AND damper),
    activity_shaft_spring_only (|K theta dtheta/dt|), activity_fan_inertia (|J_fan dw_fan/dt w_fan|),
    plus nfev and the solver statistics under 'info'.
    """
    p = params
    if level not in (1, 2, 3, 4):
        raise ValueError("level must be 1..4")
    if start not in ("direct", "pi", "inverse"):
        raise ValueError("start must be 'direct', 'pi' or 'inverse'")
    if interpolation is None:
        interpolation = "akima" if level == 3 else "linear"
    if t_eval is None:
        t_eval = np.linspace(0.0, stop, int(round(stop / 1e-3)) + 1)
    t_eval = np.asarray(t_eval, dtype=float)
    n = len(t_eval)

    if level == 1:
        if start == "direct":
            w, T = steady_state(p, interpolation)
            const = lambda v: np.full(n, v)  # noqa: E731
            return dict(t=t_eval, motor_speed=const(w), fan_speed=const(w / p.gear_ratio), shaft_torque=const(T),
                        motor_torque=const(T), gear_speed=const(w), shaft_twist=const(0.0),
                        activity_motor_inertia=const(0.0), activity_shaft_stiffness=const(0.0),
                        activity_shaft_spring_only=const(0.0), activity_fan_inertia=const(0.0), info={})
        # quasi-static tracking of the (filtered) set point
        wref = _setpoint_only(p, t_eval, setpoint_filter)
        T = fan_torque(p, wref / p.gear_ratio) / (p.gear_ratio * p.gear_efficiency)
        z = np.zeros(n)
        return dict(t=t_eval, motor_speed=wref, fan_speed=wref / p.gear_ratio, shaft_torque=T, motor_torque=T,
                    gear_speed=wref, shaft_twist=z, speed_reference=wref, activity_motor_inertia=z,
                    activity_shaft_stiffness=z, activity_shaft_spring_only=z, activity_fan_inertia=z, info={})
    if level == 4 and start != "direct":
        raise ValueError("level 4 (machine dq model) is simulated for the direct start only")
    if start == "inverse" and not setpoint_filter and p.ramp_time <= 0:
        raise ValueError("inverse simulation of an unfiltered step needs an infinite acceleration")

    rhs, outputs, active = _build(p, level, start, interpolation, rigid or level == 2, setpoint_filter)
    if max_step is None:
        # level 4: at most 0.2 supply periods per step (4 ms at 50 Hz). The outputs on t_eval come from
        # the solver's dense output, and with 50 ms steps DOP853's interpolant misses the 50 Hz
        # electrical transient of the first seconds by up to 7e-6 of the range (electrical power;
        # 3e-6 for the current, 1.6e-6 for the torque) even at rtol 1e-12; with 4 ms, 1e-8 (against
        # rtol 1e-13, max_step 1 ms).
        max_step = 0.2 / p.f_supply if level == 4 else 0.05
    if method is None:
        # the PI start carries the 800 Hz actuator (double eigenvalue -5024 1/s): stiff -> LSODA
        # (Radau agrees to 2e-7 relative on the elastic PI start but is 4x slower and stalls on the
        # rigid one); everything else is non-stiff (shaft mode ~4 Hz, machine 50 Hz) -> DOP853
        method = "LSODA" if start == "pi" else "DOP853"
    z = np.zeros(len(active))
    atol = _ATOL[active]
    pts = _breakpoints(p, level, start, stop)
    Y = np.zeros((_N, n))
    nfev = 0
    nsteps = 0
    for a, b in zip(pts[:-1], pts[1:]):
        last = b == pts[-1]
        mask = (t_eval >= a) & ((t_eval <= b) if last else (t_eval < b))
        sol = solve_ivp(rhs, (a, b), z, method=method, rtol=rtol, atol=atol, max_step=max_step,
                        dense_output=True)
        if not sol.success:
            raise RuntimeError(sol.message)
        nfev += sol.nfev
        nsteps += len(sol.t) - 1
        if mask.any():
            Y[np.ix_(active, np.nonzero(mask)[0])] = sol.sol(t_eval[mask])
        z = sol.y[:, -1].copy()
    y = np.zeros(_N)
    y[active] = z
    # outputs
    keys = None
    cols = {}
    for j in range(n):
        o = outputs(t_eval[j], Y[:, j])
        if keys is None:
            keys = list(o)
            cols = {k: np.empty(n) for k in keys}
        for k in keys:
            cols[k][j] = o[k]
    res = dict(t=t_eval)
    res.update(cols)
    res.update(activity_motor_inertia=Y[_EM].copy(), activity_shaft_stiffness=Y[_ES].copy(),
               activity_shaft_spring_only=Y[_ESP].copy(), activity_fan_inertia=Y[_EF].copy())
    res["info"] = dict(nfev=nfev, steps=nsteps, method=method, rtol=rtol, interpolation=interpolation,
                       final_state=y)
    return res


def _setpoint_only(p: BookParameters, t_eval, setpoint_filter: bool) -> np.ndarray:
    """The (filtered) set point alone on t_eval."""
    r = np.array([ramp(p, t)[0] for t in t_eval])
    if not setpoint_filter:
        return r
    wfil = 2.0 * math.pi * p.filter_frequency_below
    Dfil = p.filter_damping

    def f(t, y):
        return [y[1], wfil * (wfil * (ramp(p, t)[0] - y[0]) - 2.0 * Dfil * y[1])]
    pts = _breakpoints(p, 1, "pi", float(t_eval[-1]))
    out = np.empty(len(t_eval))
    y = [0.0, 0.0]
    for a, b in zip(pts[:-1], pts[1:]):
        last = b == pts[-1]
        mask = (t_eval >= a) & ((t_eval <= b) if last else (t_eval < b))
        sol = solve_ivp(f, (a, b), y, method="DOP853", rtol=1e-12, atol=1e-12, dense_output=True)
        if mask.any():
            out[mask] = sol.sol(t_eval[mask])[0]
        y = sol.y[:, -1]
    return out


def peak(res: dict, key: str = "shaft_torque") -> tuple[float, float]:
    """(max value, time) of res[key] on its time grid."""
    i = int(np.argmax(res[key]))
    return float(res[key][i]), float(res["t"][i])


def shares(res: dict, shaft: str = "activity_shaft_stiffness") -> tuple[float, float, float]:
    """(motor %, shaft %, fan %) of the final activities."""
    a = np.array([res["activity_motor_inertia"][-1], res[shaft][-1], res["activity_fan_inertia"][-1]])
    return tuple(float(v) for v in 100.0 * a / a.sum())


def table33(ramp_time: float = 10.0, stop: float = 30.0, params: BookParameters = BookParameters(),
            shaft: str = "activity_shaft_stiffness") -> dict:
    """Table 3.3: activity shares (motor %, shaft %, fan %) at the end of a 0..stop s run.

    'without': Activity_Index_direct (direct start, Akima table, elastic shaft).
    'with': Activity_Index_controller (PI start, set point filtered) with the given ramp_time
    (the book file's Activity_Index_controller uses 20 s, Transient_SpeedControler 10 s).
    stop: the models have no experiment annotation; 30 s (both transients have settled by then).
    shaft: 'activity_shaft_stiffness' (the book's sensor: spring-damper torque x relative speed)
    or 'activity_shaft_spring_only'.
    The chapter prints without: fan 46.7, shaft 9, motor 44.3; with: fan 87.7, shaft 0.3, motor 12.
    """
    tt = np.array([0.0, stop])
    d = simulate(3, "direct", params, stop, t_eval=tt, interpolation="akima")
    c = simulate(3, "pi", params.with_(ramp_time=ramp_time), stop, t_eval=tt)
    return {"without": shares(d, shaft), "with": shares(c, shaft)}


# --------------------------------------------------------------------------------------------
# The book's result file Transient_Resonance.mat (Dymola, model Transient_Resonance, 0..20 s)
# --------------------------------------------------------------------------------------------

# Samples of files/Transient_Resonance.mat (data_2 trajectories, float32): (t s, variable, value).
# Variables: inertia_motor.w (motor speed, rad/s), spring.tau (SpringDamper torque = flange_b.tau,
# N.m; the shaft_torque of this module is -spring.tau), inertia_fan.w (fan speed, rad/s).
# Times on the file's 0.004 s output grid; 5.376 s is the row of the largest -spring.tau
# (4503.24 N.m), 5.508 s that of the smallest (-3097.37 N.m).
_RES_ROWS = (
    (0.1, 10.02656364440918, -703.2615966796875, 0.1460745483636856),
    (0.2, -3.4642179012298584, -368.92474365234375, 0.4908193051815033),
    (0.3, 17.689037322998047, -152.3133087158203, 0.5391042828559875),
    (0.5, 10.374785423278809, -53.31552505493164, 1.071044921875),
    (0.8, 29.707561492919922, 12.182111740112305, 1.6209810972213745),
    (1.0, 22.326560974121094, -252.25181579589844, 2.174717664718628),
    (1.5, 37.7847900390625, -576.6603393554688, 3.2968571186065674),
    (2.0, 58.481990814208984, -966.5845336914062, 4.424278259277344),
    (2.5, 85.4788818359375, -1318.878173828125, 5.5477447509765625),
    (3.0, 118.51203155517578, -1492.3939208984375, 6.666578769683838),
    (3.5, 155.3931121826172, -1329.95947265625, 7.794405460357666),
    (4.0, 191.5337677001953, -680.038818359375, 8.962458610534668),
    (4.5, 218.62733459472656, 581.3502807617188, 10.229504585266113),
    (4.8, 253.51104736328125, -1758.1278076171875, 10.898005485534668),
    (5.0, 222.03298950195312, 2302.666259765625, 11.70794677734375),
    (5.2, 119.98088836669922, 918.9969482421875, 13.237238883972168),
    (5.3, 292.43023681640625, 125.25213623046875, 11.942283630371094),
    (5.34, 272.8395690917969, -3191.710693359375, 12.224681854248047),
    (5.36, 241.3832550048828, -4212.27099609375, 12.580147743225098),
    (5.376, 209.88780212402344, -4503.23876953125, 12.915257453918457),
    (5.38, 201.6217498779297, -4494.14453125, 13.000909805297852),
    (5.4, 161.6901397705078, -3955.778076171875, 13.407267570495605),
    (5.44, 117.2315902709961, -982.239013671875, 13.881000518798828),
    (5.5, 191.69064331054688, 3028.9765625, 13.322840690612793),
    (5.508, 210.31903076171875, 3097.37158203125, 13.173588752746582),
    (5.52, 238.56773376464844, 2924.267578125, 12.952635765075684),
    (5.6, 282.0468444824219, -2982.9990234375, 12.72538948059082),
    (5.8, 281.5589294433594, 1973.2857666015625, 13.220744132995605),
    (6.0, 166.47845458984375, 1588.67919921875, 14.679519653320312),
    (6.5, 181.8734893798828, -480.1263427734375, 15.702705383300781),
    (7.0, 229.52310180664062, -1625.647216796875, 16.56965446472168),
    (7.5, 274.42730712890625, -1303.5850830078125, 17.498544692993164),
    (8.0, 292.67364501953125, -704.5220947265625, 18.281597137451172),
    (9.0, 299.6943359375, -505.0503845214844, 18.734424591064453),
    (10.0, 300.4815673828125, -486.0047607421875, 18.780437469482422),
    (12.0, 300.5608825683594, -484.0534362792969, 18.785058975219727),
    (14.0, 300.5621337890625, -484.022216796875, 18.785133361816406),
    (16.0, 300.5621032714844, -484.0229187011719, 18.785131454467773),
    (18.0, 300.5621032714844, -484.0235595703125, 18.78512954711914),
    (20.0, 300.56207275390625, -484.0237731933594, 18.78512954711914),
)
BOOK_RESONANCE_SAMPLES = [
    (t, name, v) for (t, wm, tau, wf) in _RES_ROWS
    for name, v in (("inertia_motor.w", wm), ("spring.tau", tau), ("inertia_fan.w", wf))
]
# Whole-file extremes (for reference): inertia_motor.w min -3.6597 (t 0.192 s), max 306.0137;
# -spring.tau max 4503.2388 at 5.376 s, min -3097.3716 at 5.508 s; final (20 s) motor speed
# 300.56207, fan speed 18.785130, -spring.tau 484.02377.
BOOK_RESONANCE_EXTREMES = {"motor_speed_min": -3.6597254276275635, "motor_speed_max": 306.0137023925781,
                           "shaft_torque_max": 4503.23876953125, "shaft_torque_max_time": 5.376,
                           "shaft_torque_min": -3097.37158203125, "shaft_torque_min_time": 5.508}

# Mapping of the .mat variables to this module's outputs (value in module = sign * value in .mat).
MAT_TO_OUTPUT = {"inertia_motor.w": ("motor_speed", 1.0), "spring.tau": ("shaft_torque", -1.0),
                 "inertia_fan.w": ("fan_speed", 1.0)}


def compare_resonance(res: dict | None = None) -> dict:
    """Worst |module - book| over BOOK_RESONANCE_SAMPLES, per variable, absolute and relative to the
    variable's range over the samples. res: a level-3 direct Akima simulation (run if None)."""
    if res is None:
        times = np.array(sorted({t for t, _, _ in BOOK_RESONANCE_SAMPLES}))
        res = simulate(3, "direct", stop=20.0, t_eval=times, interpolation="akima")
    return _compare(BOOK_RESONANCE_SAMPLES, MAT_TO_OUTPUT, res)


# Samples of files/Transient_InductionMachine_graphic.mat (Dymola; the machine aimc on a 230 V
# line-to-line star source, delta windings, switched on at 1 s by idealCloser, rotor aimc.Jr 1.72 +
# inertia_motor 1.72, SpringDamper spring c=866, lossyGear, inertia_fan 3000, fan TorqueDirection
# true; 0..20 s): (t, aimc.wMechanical rad/s, spring.tau N.m, inertia_fan.w rad/s,
# aimc.tauElectrical N.m). 7.496 s is the row of the largest -spring.tau (1936.757 N.m), 1.012 s that
# of the largest aimc.tauElectrical (1500.303 N.m). Simulate with BookParameters.book_machine_files().
_MACHINE_ROWS = (
    (0.5, 7.46521854749771e-12, -3.097467282664468e-10, 3.7922399595546885e-13, 1.8465978746107226e-10),
    (1.004, 0.01924063079059124, -0.019016606733202934, 6.095500992842062e-08, 76.86579132080078),
    (1.012, 1.7186232805252075, -4.578430652618408, 4.9025988118955866e-05, 1500.3031005859375),
    (1.02, 4.227724552154541, -28.285995483398438, 0.0006512716063298285, 30.548599243164062),
    (1.1, 9.29249382019043, -460.7442321777344, 0.08983789384365082, 366.0150146484375),
    (1.2, 3.584491491317749, -642.0135498046875, 0.40686532855033875, 634.8949584960938),
    (1.5, 16.11639404296875, -672.9087524414062, 0.859174370765686, 920.0677490234375),
    (2.0, 25.219362258911133, -151.87142944335938, 1.8921273946762085, 571.2202758789062),
    (3.0, 55.032981872558594, -498.24383544921875, 3.9179840087890625, 533.9059448242188),
    (4.0, 92.2818603515625, -883.5250854492188, 6.002117156982422, 605.0877075195312),
    (5.0, 136.28564453125, -1036.958740234375, 8.171174049377441, 713.1531982421875),
    (6.0, 182.9749298095703, -750.5946044921875, 10.536887168884277, 860.5387573242188),
    (7.0, 224.53440856933594, -71.08061218261719, 13.29658031463623, 994.5813598632812),
    (7.4, 250.62440490722656, -785.9364624023438, 14.326208114624023, 1056.2838134765625),
    (7.48, 242.09495544433594, -1904.555419921875, 14.788357734680176, 1084.3319091796875),
    (7.496, 238.15994262695312, -1936.756591796875, 14.918705940246582, 1077.90673828125),
    (7.52, 232.37850952148438, -1828.8515625, 15.109879493713379, 1059.822998046875),
    (8.0, 254.2061309814453, -6.842926979064941, 16.434326171875, 1043.9490966796875),
    (9.0, 288.0726623535156, -674.3277587890625, 18.289615631103516, 804.58642578125),
    (10.0, 299.5466003417969, -517.5225830078125, 18.73240852355957, 522.8585815429688),
    (12.0, 300.7857360839844, -485.0760498046875, 18.799150466918945, 485.1917724609375),
    (15.0, 300.7983703613281, -484.77471923828125, 18.799863815307617, 484.78564453125),
    (20.0, 300.7979736328125, -484.78765869140625, 18.799882888793945, 484.7868957519531),
)
BOOK_MACHINE_SAMPLES = [
    (r[0], name, v) for r in _MACHINE_ROWS
    for name, v in zip(("aimc.wMechanical", "spring.tau", "inertia_fan.w", "aimc.tauElectrical"), r[1:])
]
MACHINE_MAT_TO_OUTPUT = {"aimc.wMechanical": ("motor_speed", 1.0), "spring.tau": ("shaft_torque", -1.0),
                         "inertia_fan.w": ("fan_speed", 1.0), "aimc.tauElectrical": ("motor_torque", 1.0)}

# Samples of files/Test_InductionMachine2.mat (Dymola, 0..20 s, two rigid drive trains side by side):
# the table drive (CombiTable1D TorqueSpeed, linear, = level b, Transient_Dynamic) inertia_motor1.w,
# lossyGear1.flange_a.tau (gear input torque = shaft_torque), inertia_fan1.w; and the machine drive
# (aimc, delta, switched on at 0 s, rotor 1.72 + inertia_motor 1.72, rigid) aimc.wMechanical,
# lossyGear.flange_a.tau, inertia_fan.w, aimc.tauElectrical. 5.944 s: largest lossyGear1.flange_a.tau
# (981.729 N.m); whole-file largest lossyGear.flange_a.tau 1178.436 N.m at 0.012 s.
_RIGID_ROWS = (
    (0.004, 0.12803490459918976, 399.1329345703125, 0.00800218153744936, 0.004163656383752823, 60.254703521728516, 0.00026022852398455143, 76.88101196289062),
    (0.02, 0.6407380104064941, 399.837158203125, 0.040046125650405884, 0.9215167164802551, 13.027571678161621, 0.057594794780015945, 16.621063232421875),
    (0.1, 3.2177255153656006, 403.3819885253906, 0.20110784471035004, 3.1140596866607666, 114.41151428222656, 0.1946287304162979, 145.96719360351562),
    (0.2, 6.470293998718262, 407.8684387207031, 0.40439337491989136, 5.82365083694458, 302.58111572265625, 0.36397817730903625, 386.0233459472656),
    (0.5, 16.432605743408203, 421.6955261230469, 1.0270378589630127, 14.079270362854004, 755.43359375, 0.8799543976783752, 963.5902709960938),
    (1.0, 33.68720245361328, 445.9489440917969, 2.10545015335083, 28.958589553833008, 448.6776428222656, 1.809911847114563, 571.2431640625),
    (2.0, 70.3380355834961, 498.7494812011719, 4.396127223968506, 60.744205474853516, 430.3071594238281, 3.7965128421783447, 543.5882568359375),
    (3.0, 109.9113540649414, 584.004638671875, 6.869459629058838, 94.85210418701172, 488.40203857421875, 5.928256511688232, 609.8673095703125),
    (4.0, 153.4255828857422, 689.4346313476562, 9.589098930358887, 131.49124145507812, 567.1820678710938, 8.218202590942383, 698.1246948242188),
    (5.0, 201.04747009277344, 843.25634765625, 12.56546688079834, 171.25509643554688, 676.1470947265625, 10.70344352722168, 819.35888671875),
    (5.5, 226.7515411376953, 927.3226318359375, 14.171971321105957, 192.60205078125, 744.6452026367188, 12.037628173828125, 895.2744750976562),
    (5.944, 250.0352783203125, 981.729248046875, 15.627204895019531, 212.47740173339844, 811.6435546875, 13.279837608337402, 968.85693359375),
    (6.0, 252.91888427734375, 979.8839721679688, 15.807430267333984, 215.0428009033203, 820.2008666992188, 13.44017505645752, 978.1539916992188),
    (6.5, 275.61279296875, 884.1053466796875, 17.225799560546875, 238.33224487304688, 888.4522705078125, 14.89576530456543, 1049.627685546875),
    (7.0, 289.8680419921875, 680.4911499023438, 18.11675262451172, 261.1629943847656, 905.4584350585938, 16.32268714904785, 1054.4664306640625),
    (8.0, 298.7543029785156, 520.2927856445312, 18.672143936157227, 292.11737060546875, 661.8165893554688, 18.257335662841797, 718.2752075195312),
    (10.0, 300.447509765625, 483.9735412597656, 18.777969360351562, 300.6704406738281, 487.84942626953125, 18.791902542114258, 488.8087463378906),
    (15.0, 300.4568176269531, 483.6848449707031, 18.77855110168457, 300.7982482910156, 484.7851257324219, 18.799890518188477, 484.78521728515625),
    (20.0, 300.4568176269531, 483.6848449707031, 18.77855110168457, 300.7981872558594, 484.8330383300781, 18.79988670349121, 484.8464050292969),
)
BOOK_DYNAMIC_SAMPLES = [  # level b (table drive of Test_InductionMachine2.mat)
    (r[0], name, v) for r in _RIGID_ROWS
    for name, v in zip(("inertia_motor1.w", "lossyGear1.flange_a.tau", "inertia_fan1.w"), r[1:4])
]
DYNAMIC_MAT_TO_OUTPUT = {"inertia_motor1.w": ("motor_speed", 1.0), "lossyGear1.flange_a.tau": ("shaft_torque", 1.0),
                         "inertia_fan1.w": ("fan_speed", 1.0)}
BOOK_RIGID_MACHINE_SAMPLES = [  # level d, rigid shaft (machine drive of Test_InductionMachine2.mat)
    (r[0], name, v) for r in _RIGID_ROWS
    for name, v in zip(("aimc.wMechanical", "lossyGear.flange_a.tau", "inertia_fan.w", "aimc.tauElectrical"), r[4:])
]
RIGID_MACHINE_MAT_TO_OUTPUT = {"aimc.wMechanical": ("motor_speed", 1.0), "lossyGear.flange_a.tau": ("shaft_torque", 1.0),
                               "inertia_fan.w": ("fan_speed", 1.0), "aimc.tauElectrical": ("motor_torque", 1.0)}


def _compare(samples, mapping, res) -> dict:
    out = {}
    for var, (key, sign) in mapping.items():
        pts = [(t, sign * v) for t, n, v in samples if n == var]
        ref = np.array([v for _, v in pts])
        mine = np.interp([t for t, _ in pts], res["t"], res[key])
        err = np.abs(mine - ref)
        k = int(np.argmax(err))
        rng = float(ref.max() - ref.min())
        out[var] = dict(output=key, worst_abs=float(err[k]), at=pts[k][0], range=rng,
                        worst_rel_range=float(err[k] / rng))
    return out


def compare_book_files() -> dict:
    """This module against the three result files (sample tables above): {file: {variable: {...}}}."""
    res = {}
    tt = np.array(sorted({t for t, _, _ in BOOK_MACHINE_SAMPLES}))
    r = simulate(4, "direct", BookParameters.book_machine_files(), stop=20.0, t_eval=tt)
    res["Transient_InductionMachine_graphic.mat"] = _compare(BOOK_MACHINE_SAMPLES, MACHINE_MAT_TO_OUTPUT, r)
    tt = np.array(sorted({t for t, _, _ in BOOK_DYNAMIC_SAMPLES}))
    r = simulate(2, "direct", BookParameters(), stop=20.0, t_eval=tt, interpolation="linear")
    res["Test_InductionMachine2.mat (table drive, level b)"] = _compare(BOOK_DYNAMIC_SAMPLES, DYNAMIC_MAT_TO_OUTPUT, r)
    r = simulate(4, "direct", BookParameters.book_machine_files(machine_switch_time=0.0), stop=20.0, t_eval=tt, rigid=True)
    res["Test_InductionMachine2.mat (machine drive, rigid)"] = _compare(BOOK_RIGID_MACHINE_SAMPLES,
                                                                       RIGID_MACHINE_MAT_TO_OUTPUT, r)
    return res


# --------------------------------------------------------------------------------------------
# Script
# --------------------------------------------------------------------------------------------

def _timed(f, *a, **k):
    import time
    t0 = time.perf_counter()
    r = f(*a, **k)
    return r, time.perf_counter() - t0


def _refined_peak(level, start, params=BookParameters(), key="shaft_torque", stop=30.0, **kw):
    """Peak of `key` on the 1 ms grid, refined on a 1 us grid around it."""
    res, dt = _timed(simulate, level, start, params, stop, **kw)
    v, tp = peak(res, key)
    fine = np.linspace(max(tp - 2e-3, 0.0), min(tp + 2e-3, stop), 4001)
    tt = np.unique(np.concatenate([fine, [stop]]))
    r2 = simulate(level, start, params, stop, t_eval=tt, **kw)
    i = int(np.argmax(r2[key][:-1]))
    return res, (float(r2[key][i]), float(r2["t"][i])), dt


if __name__ == "__main__":
    import warnings
    warnings.simplefilter("ignore", RuntimeWarning)  # scipy num_jac overflow on the activity columns
    p = BookParameters()
    (w_a, T_a), dt = _timed(steady_state, p)
    print(f"level a (linear table, Steady_State): equilibrium motor speed {w_a:.6f} rad/s, torque "
          f"{T_a:.4f} N.m, fan speed {w_a / p.gear_ratio:.6f} rad/s  [steady_state {dt * 1e3:.1f} ms]")
    w_ak, T_ak = steady_state(p, "akima")
    print(f"level a (Akima table):  equilibrium motor speed {w_ak:.6f} rad/s, torque {T_ak:.4f} N.m")
    p19 = p.with_(speed_fan_nominal=19.37)
    w19, T19 = steady_state(p19)
    print(f"level a with Steady_State's own w_nominal 19.37: {w19:.6f} rad/s, {T19:.4f} N.m")
    print()
    for lev, name, kw in ((2, "b", {}), (3, "c", {}), (3, "c", {"interpolation": "linear"})):
        res, (pk, tpk), dt = _refined_peak(lev, "direct", **kw)
        print(f"level {name} direct ({res['info']['interpolation']} table): peak shaft torque {pk:.3f} N.m at "
              f"{tpk:.5f} s; min {res['shaft_torque'].min():.3f}; final motor speed {res['motor_speed'][-1]:.5f}, "
              f"fan {res['fan_speed'][-1]:.6f} rad/s; min motor speed {res['motor_speed'].min():.4f}  "
              f"[simulate {dt:.2f} s, {res['info']['method']}, {res['info']['steps']} steps]")
    res, (pk, tpk), dt = _refined_peak(3, "direct", p.with_(J_motor=3.44))
    print(f"level c direct (Akima), J_motor 3.44 (the machine files' rotor + inertia_motor): peak shaft "
          f"torque {pk:.3f} N.m at {tpk:.5f} s")
    res, (pk, tpk), dt = _refined_peak(4, "direct")
    ws_, Ts_ = machine_steady_state(p)
    print(f"level d direct (dq machine, J 1.72, 230 V per winding, switch-on 0 s, elastic): peak shaft torque "
          f"{pk:.3f} N.m at {tpk:.5f} s; min {res['shaft_torque'].min():.3f}; peak motor torque "
          f"{res['motor_torque'].max():.2f}, min {res['motor_torque'].min():.2f}; peak current "
          f"{res['stator_current_rms'].max():.1f} A rms; final motor speed {res['motor_speed'][-1]:.5f} "
          f"(equivalent-circuit equilibrium {ws_:.5f} rad/s, {Ts_:.4f} N.m)  [simulate {dt:.2f} s, "
          f"{res['info']['method']}, {res['info']['steps']} steps]")
    res, (pk, tpk), dt = _refined_peak(4, "direct", rigid=True)
    print(f"level d direct, rigid shaft: peak shaft torque {pk:.3f} N.m at {tpk:.5f} s  [simulate {dt:.2f} s]")
    pb = BookParameters.book_machine_files()
    res, (pk, tpk), dt = _refined_peak(4, "direct", pb, stop=20.0)
    print(f"level d, book machine file configuration (delta 230 V, J 1.72+1.72, switch-on 1 s, elastic): "
          f"peak shaft torque {pk:.3f} N.m at {tpk:.5f} s (file: 1936.757 at 7.496 s); final speed "
          f"{res['motor_speed'][-1]:.5f}  [simulate {dt:.2f} s]")
    print()
    for st in ("pi", "inverse"):
        for rt in (10.0, 20.0):
            for lev in (3, 2):
                res, (pk, tpk), dt = _refined_peak(lev, st, p.with_(ramp_time=rt))
                print(f"level {'bc'[lev - 2]} {st:7s} ramp {rt:4.0f} s: peak shaft torque {pk:.3f} N.m at {tpk:.4f} s; "
                      f"peak motor torque {res['motor_torque'].max():.3f}; final speed {res['motor_speed'][-1]:.5f}  "
                      f"[simulate {dt:.2f} s, {res['info']['method']}]")
    res, (pk, tpk), dt = _refined_peak(3, "pi", p.with_(K_shaft=866e3))
    print(f"Transient_SpeedControler2 (c = 866e3), PI ramp 10 s: peak shaft torque {pk:.3f} N.m at {tpk:.4f} s "
          f"[simulate {dt:.2f} s]")
    print()
    for rt in (10.0, 20.0):
        r, dt = _timed(table33, rt)
        r2 = table33(rt, shaft="activity_shaft_spring_only")
        fmt = lambda s: "motor %.2f %%, shaft %.2f %%, fan %.2f %%" % s  # noqa: E731
        print(f"Table 3.3, 0..30 s, controller ramp {rt:.0f} s (book's sensor): without: {fmt(r['without'])}; "
              f"with: {fmt(r['with'])}  [table33 {dt:.2f} s]")
        print(f"                               (spring only):  without: {fmt(r2['without'])}; with: {fmt(r2['with'])}")
    print("  chapter: without: motor 44.3 %, shaft 9 %, fan 46.7 %; with: motor 12 %, shaft 0.3 %, fan 87.7 %")
    print()
    print("level d machine (Transient_InductionMachine_graphic.mat / Test_InductionMachine2.mat, data_1):")
    for k in ("R_s", "R_r", "L_s_sigma", "L_r_sigma", "L_m", "pole_pairs", "U_supply", "f_supply"):
        print(f"  {k} = {BOOK_VALUES[k][0]!r}: {BOOK_VALUES[k][1]}")
    for k, (v, s) in BOOK_EXTRA.items():
        print(f"  {k} = {v!r}: {s}")
    tabl = TorqueTable("linear")
    print("  equivalent circuit (230 V per winding) vs table TorqueSpeed:")
    print("    w rad/s  T_table  T_circuit  diff %")
    for w, T in zip(BOOK_TABLE_SPEED, BOOK_TABLE_TORQUE):
        Tc = float(machine_steady_torque(p, w))
        print(f"    {w:6.1f} {T:8.1f} {Tc:9.2f} {100 * (Tc - T) / T if T else float('nan'):8.2f}")
    print()
    cmp_, dt = _timed(compare_resonance)
    print(f"level c (Akima) vs Transient_Resonance.mat ({len(BOOK_RESONANCE_SAMPLES)} samples)  [compare_resonance {dt:.2f} s]:")
    for var, c in cmp_.items():
        print(f"  {var:16s} -> {c['output']:12s}: worst |diff| {c['worst_abs']:.4g} at {c['at']} s, "
              f"range {c['range']:.5g}, worst/range {100 * c['worst_rel_range']:.3f} %")
    cmpb, dt = _timed(compare_book_files)
    print(f"[compare_book_files {dt:.2f} s]")
    for f, d in cmpb.items():
        print(f"  {f}:")
        for var, c in d.items():
            print(f"    {var:24s} -> {c['output']:12s}: worst |diff| {c['worst_abs']:.4g} at {c['at']} s, "
                  f"range {c['range']:.5g}, worst/range {100 * c['worst_rel_range']:.3f} %")
