"""PowerSteering's equations written out independently (docs/power-steering-spec.md), for the tests:
the linear case, where every mode is fixed and the model is x' = A x + b(t).

The linear case: the driver imposes the angle (driver_input = 1), an ideal worm (both efficiencies
1, no column friction: the gear's direction and its stops change nothing), treads that never slide
(a friction far above any tire torque: they stay at 0), rigid tie rods, and an assistance that
never saturates (checked by the tests on the FMU's own outputs). States, absolute coordinates:

    x = [y, y', theta_sw, w_sw, theta_c, w_c, i, I]

y the driver's filtered angle, theta_sw the steering wheel, theta_c the column, i the motor current,
I the current loop's integral. The wheels turn by delta = (r / b) theta_c and the tires' twist is
delta (their treads stuck at 0). Both wheels: every per-wheel value counts twice.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

WHEELS = 2.0


@dataclass
class Steering:
    K_arm: float
    D_arm: float
    J_steering_wheel: float
    K_torsion_bar: float
    J_column: float
    worm_ratio: float
    R_motor: float
    L_motor: float
    k_motor: float
    J_motor: float
    b_motor: float
    assist_gain: float
    assist_damping: float
    Kp_current: float
    Ki_current: float
    r_pinion: float
    m_rack: float
    lever_arm: float
    J_rim: float
    K_tire: float
    D_tire: float
    K_kingpin_gravity: float
    driver_filter_w: float
    driver_filter_damping: float

    @classmethod
    def from_start_values(cls, start: dict[str, float], **overrides: float) -> "Steering":
        values = {name: float(start[name]) for name in cls.__dataclass_fields__}
        values.update(overrides)
        return cls(**values)

    def matrix(self) -> np.ndarray:
        """A of x' = A x + b(t) (b: the profile into the driver's filter)."""
        s = self
        rho = s.r_pinion / s.lever_arm  # wheel angle per column angle
        n = s.worm_ratio
        inertia = s.J_column + s.m_rack * s.r_pinion**2 + rho**2 * WHEELS * s.J_rim + n**2 * s.J_motor
        kw = s.driver_filter_w
        a = np.zeros((8, 8))
        # y'' = w^2 (u - y) - 2 D w y'
        a[0, 1] = 1.0
        a[1, 0], a[1, 1] = -(kw**2), -2.0 * s.driver_filter_damping * kw
        # J_sw w_sw' = K_arm (y - th_sw) + D_arm (y' - w_sw) - K_tb (th_sw - th_c)
        a[2, 3] = 1.0
        a[3, 0] = s.K_arm / s.J_steering_wheel
        a[3, 1] = s.D_arm / s.J_steering_wheel
        a[3, 2] = -(s.K_arm + s.K_torsion_bar) / s.J_steering_wheel
        a[3, 3] = -s.D_arm / s.J_steering_wheel
        a[3, 4] = s.K_torsion_bar / s.J_steering_wheel
        # the current loop: i_ref = (K_a T_bar - D_a w_c) / (N k) (an ideal worm), u = Kp e + Ki I
        gain = 1.0 / (n * s.k_motor)
        d_iref = np.zeros(8)
        d_iref[2], d_iref[4] = gain * s.assist_gain * s.K_torsion_bar, -gain * s.assist_gain * s.K_torsion_bar
        d_iref[5] = -gain * s.assist_damping
        d_e = d_iref.copy()
        d_e[6] -= 1.0
        d_u = s.Kp_current * d_e
        d_u[7] += s.Ki_current
        # L i' = u - R i - k N w_c
        a[6] = d_u / s.L_motor
        a[6, 6] -= s.R_motor / s.L_motor
        a[6, 5] -= s.k_motor * n / s.L_motor
        # I' = e
        a[7] = d_e
        # (J_c + m_r r^2 + rho^2 J_rims + N^2 J_m) w_c' = T_bar - rho (T_tire + T_gravity) + N (k i - b N w_c)
        a[4, 5] = 1.0
        a[5, 2] = s.K_torsion_bar / inertia
        a[5, 4] = (-s.K_torsion_bar - rho * rho * WHEELS * (s.K_tire + s.K_kingpin_gravity)) / inertia
        a[5, 5] = (-rho * rho * WHEELS * s.D_tire - n * n * s.b_motor) / inertia
        a[5, 6] = n * s.k_motor / inertia
        return a

    def rhs(self, amplitude: float, frequency: float):
        """f(t, x) for scipy, the driver's profile A sin(2 pi f t) into the filter."""
        a = self.matrix()
        kw = self.driver_filter_w

        def f(t, x):
            dx = a @ x
            dx[1] += kw**2 * amplitude * math.sin(2.0 * math.pi * frequency * t)
            return dx

        return f

    def outputs(self, x: np.ndarray) -> dict[str, np.ndarray]:
        """The FMU's outputs from a trajectory x (8 x n)."""
        y, yd, th_sw, w_sw, th_c, w_c, i, integral = x
        rho = self.r_pinion / self.lever_arm
        bar = self.K_torsion_bar * (th_sw - th_c)
        return {
            "steering_wheel_angle": th_sw,
            "driver_torque": self.K_arm * (y - th_sw) + self.D_arm * (yd - w_sw),
            "torsion_bar_torque": bar,
            "rack_position": self.r_pinion * th_c,
            "wheel_angle": rho * th_c,
            "motor_current": i,
            "current_command": (self.assist_gain * bar - self.assist_damping * w_c) / (self.worm_ratio * self.k_motor),
        }
