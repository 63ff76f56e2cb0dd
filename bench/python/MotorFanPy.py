"""MotorFanPy: MotorFan level c (direct-on-line start) as a pythonfmu 0.7.0 Co-Simulation FMU,
what a Python user would write instead of our Rust FMU. Built by bench/run.py with
`pythonfmu build -f bench/python/MotorFanPy.py bench/python/motor_fan_level_c.py`.

Each fmi2DoStep advances the three mechanical states with `substeps` classical RK4 steps
(motor_fan_level_c.LevelC.rk4: the book's Akima torque-speed table, N = 16, eta = 0.94 by the
direction of the power). The Rust host runs it with 1 and 2 substeps (bench/harness PY_SUBSTEPS);
bench/run.py's fmpy loop also with 4, 8, 16 until one's error is at or below our FMU's.
"""

from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real

from motor_fan_level_c import LevelC


class MotorFanPy(Fmi2Slave):
    author = "fmu-bench"
    description = "MotorFan level c, direct-on-line start, in Python (benchmark contender)"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.model = LevelC()
        self.substeps = 1
        self.motor_speed = 0.0
        self.shaft_twist = 0.0
        self.fan_speed = 0.0
        self.shaft_torque = 0.0
        self.register_variable(Integer("substeps", causality=Fmi2Causality.parameter, variability=Fmi2Variability.tunable))
        self.register_variable(Real("motor_speed", causality=Fmi2Causality.output))
        self.register_variable(Real("shaft_twist", causality=Fmi2Causality.output))
        self.register_variable(Real("fan_speed", causality=Fmi2Causality.output))
        self.register_variable(Real("shaft_torque", causality=Fmi2Causality.output))

    def do_step(self, current_time, step_size):
        y = [self.motor_speed, self.shaft_twist, self.fan_speed]
        y = self.model.rk4(current_time, y, step_size, self.substeps)
        self.motor_speed, self.shaft_twist, self.fan_speed = y
        self.shaft_torque = self.model.shaft_torque(y)
        return True
