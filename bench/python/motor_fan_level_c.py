"""MotorFan level c, direct-on-line start, in plain Python: the equations every Python contender
of the benchmark integrates (scipy's solve_ivp, and the pythonfmu FMU `MotorFanPy`).

Equations (docs/motor-fan-spec.md, level c, at MotorFan's defaults), states y = (w_m, theta, w_fan):
    T_m     = the torque-speed table read by Akima's spline at w_m (level c's default reading,
              motor_table_interpolation 0), a straight line along the end slope beyond the table
    dtheta  = w_m - N w_fan
    T_shaft = K theta + D dtheta
    T_ls    = N eta T_shaft   if T_shaft N w_fan >= 0 (power towards the fan)
              N T_shaft / eta otherwise
    J_m   dw_m/dt   = T_m - T_shaft
    J_fan dw_fan/dt = T_ls - k w_fan |w_fan|,   k = T_fan_nominal / speed_fan_nominal^2

The table is read with Python floats: Akima's slopes and each segment's cubic are computed once
(`AkimaTable`, from Akima's definition, as the spec writes it), and a call is one `bisect` and a
Horner polynomial. scipy's Akima1DInterpolator costs ~10 us per scalar call, more than the rest of
the right-hand side, and a Python user who writes an ODE right-hand side for speed uses scalars.
`check_against_reference` compares the torque with tests/python/motor_fan_reference.py's (scipy's
Akima1DInterpolator with the same linear extrapolation).

Only the three mechanical states: MotorFan.fmu also integrates three activity integrals (and
carries frozen states) at level c, so the comparison leaves it the larger system.
"""

from __future__ import annotations

from bisect import bisect_right

#: The book's torque-speed table (book file Chap3_CoolingTowerFan.mo, component TorqueSpeed):
#: rad/s, N m; MotorFan's motor_table_speed_1..10 and motor_table_torque_1..10.
BOOK_TABLE = ((0.0, 454.0), (80.0, 579.0), (160.0, 784.0), (220.0, 997.0), (240.0, 1057.0),
              (250.0, 1071.0), (260.0, 1060.0), (280.0, 919.0), (300.0, 500.0), (314.0, 0.0))

#: The default Real parameter values of MotorFan.fmu these equations use (models/drive-train,
#: models/motor-fan); bench/run.py checks them against the FMU's modelDescription.xml start values.
DEFAULTS = dict(
    J_motor=1.72, J_fan=3000.0, gear_ratio=16.0, gear_efficiency=0.94,
    K_shaft=866.0, D_shaft=866.0 / 100.0 / (886.0 / 1.7) ** 0.5,
    T_fan_nominal=7742.6, speed_fan_nominal=19.373154697137,
    **{f"motor_table_speed_{i + 1}": w for i, (w, _) in enumerate(BOOK_TABLE)},
    **{f"motor_table_torque_{i + 1}": t for i, (_, t) in enumerate(BOOK_TABLE)},
)

#: The Integer and Boolean start values that make MotorFan.fmu compute these equations (the
#: level and start are also set explicitly by the hosts); checked by bench/run.py too.
#: motor_model 1: the table; motor_table_interpolation 0: Akima at level c.
DISCRETE_DEFAULTS = dict(level=3, start_mode=1, motor_model=1, motor_table_interpolation=0, keep_shaft_stiffness=True)


class AkimaTable:
    """T(w) through points (x_i, y_i) of increasing x by Akima's spline (H. Akima, J. ACM 17(4),
    1970; CombiTable1D's ContinuousDerivative): on each segment the cubic Hermite polynomial with
    Akima's slopes at its ends, t_i = (|m_(i+1) - m_i| m_(i-1) + |m_(i-1) - m_(i-2)| m_i) /
    (|m_(i+1) - m_i| + |m_(i-1) - m_(i-2)|) (the mean of m_(i-1) and m_i where both weights are 0),
    the segment slopes m extended at each end by m_(-1) = 2 m_0 - m_1, m_(-2) = 3 m_0 - 2 m_1.
    Beyond the ends a straight line along the end point's slope (CombiTable1D's LastTwoPoints)."""

    def __init__(self, x, y):
        x, y = [float(v) for v in x], [float(v) for v in y]
        n = len(x)
        if n < 3 or any(b <= a for a, b in zip(x, x[1:])):
            raise ValueError(f"the table needs >= 3 points of increasing speed: {x}")
        m = [(y[i + 1] - y[i]) / (x[i + 1] - x[i]) for i in range(n - 1)]
        # m_ext[j + 2] = m_j for j = -2 .. n (two extensions at each end)
        m_ext = [3.0 * m[0] - 2.0 * m[1], 2.0 * m[0] - m[1], *m,
                 2.0 * m[-1] - m[-2], 3.0 * m[-1] - 2.0 * m[-2]]
        t = []
        for i in range(n):
            m_2, m_1, m0, m1 = m_ext[i], m_ext[i + 1], m_ext[i + 2], m_ext[i + 3]
            w_left, w_right = abs(m1 - m0), abs(m_1 - m_2)
            t.append(0.5 * (m_1 + m0) if w_left + w_right == 0.0 else (w_left * m_1 + w_right * m0) / (w_left + w_right))
        # Segment i: y_i + (w - x_i) (b + (w - x_i) (c + (w - x_i) d)).
        self.segments = []
        for i in range(n - 1):
            h = x[i + 1] - x[i]
            c = (3.0 * m[i] - 2.0 * t[i] - t[i + 1]) / h
            d = (t[i] + t[i + 1] - 2.0 * m[i]) / (h * h)
            self.segments.append((x[i], y[i], t[i], c, d))
        self.x, self.y, self.slopes = x, y, t
        self.x_first, self.x_last = x[0], x[-1]
        # bisect over the interior break points gives the segment index directly
        self.breaks = x[1:-1]

    def __call__(self, w: float) -> float:
        if w <= self.x_first:
            return self.y[0] + self.slopes[0] * (w - self.x_first)
        if w >= self.x_last:
            return self.y[-1] + self.slopes[-1] * (w - self.x_last)
        x0, y0, b, c, d = self.segments[bisect_right(self.breaks, w)]
        u = w - x0
        return y0 + u * (b + u * (c + u * d))


class LevelC:
    """The level-c right-hand side at fixed parameters (a dict like DEFAULTS)."""

    def __init__(self, p: dict | None = None):
        p = dict(DEFAULTS, **(p or {}))
        self.p = p
        n = len(BOOK_TABLE)
        self.motor_torque = AkimaTable([p[f"motor_table_speed_{i + 1}"] for i in range(n)],
                                       [p[f"motor_table_torque_{i + 1}"] for i in range(n)])
        self.N, self.eta = p["gear_ratio"], p["gear_efficiency"]
        self.K, self.D = p["K_shaft"], p["D_shaft"]
        self.J_m, self.J_fan = p["J_motor"], p["J_fan"]
        self.k = p["T_fan_nominal"] / p["speed_fan_nominal"] ** 2

    def shaft_torque(self, y) -> float:
        w_m, theta, w_fan = y
        return self.K * theta + self.D * (w_m - self.N * w_fan)

    def rhs(self, t: float, y) -> list:
        """dy/dt for y = (w_m, theta, w_fan); the reducer's efficiency by the direction of the
        power through it, T_shaft N w_fan (as MotorFan's mode reducer_power_flow)."""
        w_m, theta, w_fan = y
        t_shaft = self.K * theta + self.D * (w_m - self.N * w_fan)
        return self.rhs_branch(t, y, t_shaft * self.N * w_fan >= 0.0)

    def rhs_branch(self, t: float, y, towards_fan: bool) -> list:
        """dy/dt with the reducer's efficiency of one power direction, whatever the sign of the
        power: smooth across the kink where the power reverses, for a reference that locates that
        kink as an event and restarts there (bench/run.py)."""
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


def check_against_reference(model: LevelC, reference_module, values: dict) -> float:
    """Largest difference between `motor_torque` here and tests/python/motor_fan_reference.py's
    `motor_torque` at level c (scipy's Akima1DInterpolator) over -20 .. 340 rad/s (the table and
    both extrapolations), relative to the table's largest torque. `values`: MotorFan's parameter
    values by name (its modelDescription.xml start values)."""
    params = reference_module.MotorFanParams.from_values(dict(values, level=3))
    assert params.curve == "akima", params.curve
    peak = max(abs(t) for t in model.motor_torque.y)
    worst = 0.0
    for i in range(3601):
        w = -20.0 + 0.1 * i
        ours, theirs = model.motor_torque(w), float(reference_module.motor_torque(params, w))
        worst = max(worst, abs(ours - theirs) / peak)
    return worst
