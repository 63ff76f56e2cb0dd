"""MotorFan level c, direct-on-line start, in plain Python: the equations every Python contender
of the benchmark integrates (scipy's solve_ivp, and the pythonfmu FMU `MotorFanPy`).

Equations (docs/motor-fan-spec.md, level c), states y = (w_m, theta, w_fan):
    T_m     = steady-state equivalent-circuit torque at w_m (spec, "Steady state by hand")
    dtheta  = w_m - N w_fan
    T_shaft = K theta + D dtheta
    T_ls    = N eta T_shaft   if T_shaft N w_fan >= 0 (power towards the fan)
              N T_shaft / eta otherwise
    J_m   dw_m/dt   = T_m - T_shaft
    J_fan dw_fan/dt = T_ls - k w_fan |w_fan|

The torque is `motor_fan_reference.motor_torque` (tests/python) written with Python's built-in
complex numbers: numpy on one scalar costs ~10x more per call, and a Python user who writes an
ODE right-hand side uses scalars. `check_against_reference` compares the two.

Only the three mechanical states: MotorFan.fmu also integrates three activity integrals (and
carries eight frozen states) at level c, so the comparison leaves it the larger system.
"""

from __future__ import annotations

import math

#: The default parameter values of MotorFan.fmu (models/drive-train, models/motor-fan);
#: bench/run.py checks them against the FMU's modelDescription.xml start values.
DEFAULTS = dict(
    J_motor=1.72, J_fan=1172.0, gear_ratio=10.0, gear_efficiency=0.97, K_shaft=906.85, D_shaft=5.0,
    k_fan=42.9, R_s=0.012, R_r=0.020, L_s_sigma=2.5e-4, L_r_sigma=2.5e-4, L_m=0.01, pole_pairs=2.0,
    U_supply=400.0, f_supply=50.0,
)


class LevelC:
    """The level-c right-hand side at fixed parameters (a dict like DEFAULTS)."""

    def __init__(self, p: dict | None = None):
        p = dict(DEFAULTS, **(p or {}))
        self.p = p
        self.ws = 2.0 * math.pi * p["f_supply"]
        self.w_sync = self.ws / p["pole_pairs"]
        self.v = p["U_supply"] / math.sqrt(3.0)
        self.z_s = complex(p["R_s"], self.ws * p["L_s_sigma"])
        self.z_m = complex(0.0, self.ws * p["L_m"])
        self.x_r = self.ws * p["L_r_sigma"]
        self.R_r = p["R_r"]
        self.N, self.eta = p["gear_ratio"], p["gear_efficiency"]
        self.K, self.D = p["K_shaft"], p["D_shaft"]
        self.J_m, self.J_fan, self.k = p["J_motor"], p["J_fan"], p["k_fan"]

    def motor_torque(self, w_m: float) -> float:
        """T_m = 3 |I_r|^2 (R_r/s) / (ws/p) of the T-equivalent circuit; 0 at synchronism."""
        s = 1.0 - w_m / self.w_sync
        if s == 0.0:
            return 0.0
        z_r = complex(self.R_r / s, self.x_r)
        z_m = self.z_m
        i_s = self.v / (self.z_s + z_m * z_r / (z_m + z_r))
        i_r = i_s * z_m / (z_m + z_r)
        return 3.0 * (i_r.real * i_r.real + i_r.imag * i_r.imag) * (self.R_r / s) / self.w_sync

    def shaft_torque(self, y) -> float:
        w_m, theta, w_fan = y
        return self.K * theta + self.D * (w_m - self.N * w_fan)

    def rhs(self, t: float, y) -> list:
        """dy/dt for y = (w_m, theta, w_fan); the reducer's efficiency by the power's direction."""
        w_m, theta, w_fan = y
        t_shaft = self.K * theta + self.D * (w_m - self.N * w_fan)
        return self.rhs_branch(t, y, t_shaft * self.N * w_fan >= 0.0)

    def rhs_branch(self, t: float, y, towards_fan: bool) -> list:
        """dy/dt with the reducer's efficiency of one power direction, whatever the sign of the
        power: smooth across the kink where the shaft torque changes sign, for a reference that
        locates that kink as an event and restarts there (bench/run.py)."""
        w_m, theta, w_fan = y
        n = self.N
        twist_rate = w_m - n * w_fan
        t_shaft = self.K * theta + self.D * twist_rate
        t_low = n * self.eta * t_shaft if towards_fan else n * t_shaft / self.eta
        return [
            (self.motor_torque(w_m) - t_shaft) / self.J_m,
            twist_rate,
            (t_low - self.k * w_fan * abs(w_fan)) / self.J_fan,
        ]

    def rk4(self, t: float, y: list, h: float, substeps: int = 1) -> list:
        """Classical fixed-step Runge-Kutta from t to t + h in `substeps` equal steps."""
        dt = h / substeps
        f = self.rhs
        for i in range(substeps):
            ti = t + i * dt
            k1 = f(ti, y)
            k2 = f(ti + 0.5 * dt, [a + 0.5 * dt * b for a, b in zip(y, k1)])
            k3 = f(ti + 0.5 * dt, [a + 0.5 * dt * b for a, b in zip(y, k2)])
            k4 = f(ti + dt, [a + dt * b for a, b in zip(y, k3)])
            y = [a + dt / 6.0 * (b + 2.0 * c + 2.0 * d + e) for a, b, c, d, e in zip(y, k1, k2, k3, k4)]
        return y


def check_against_reference(model: LevelC, reference_module) -> float:
    """Largest relative difference between `motor_torque` here and the numpy one of
    tests/python/motor_fan_reference.py over 0..0.999 of the synchronous speed."""
    params = reference_module.MotorFanParams.from_values(dict(model.p, speed_setpoint=0.0, ramp_time=0.0))
    worst = 0.0
    for i in range(1000):
        w = model.w_sync * i / 1000.0
        ours, theirs = model.motor_torque(w), float(reference_module.motor_torque(params, w))
        worst = max(worst, abs(ours - theirs) / abs(theirs))
    return worst
