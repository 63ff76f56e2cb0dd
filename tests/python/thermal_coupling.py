"""A coupling example: the TGV thermal FMU driven by another FMU's torque, in a small master.

MotorFan (the cooling-tower drive, direct-on-line start) and TractionMotorThermal are stepped in
lockstep with a fixed communication step; at each communication point MotorFan's output
`motor_torque` is passed to the thermal FMU's input `torque_in` (heat_source = 2), which turns it
into Joule losses P_J = P_J,nom (C / C_nom)^2. The thermal model is set to the motor's own
torque class (`torque_nominal` = MotorFan's steady motor torque, 1042 N m): the same rated losses
at the same relative load.

Run it alone to print the trajectory summary:
    .venv/bin/python tests/python/thermal_coupling.py
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from conftest import DIST_DIR  # noqa: E402
from fmi_host import Slave  # noqa: E402

# The thermal model's nominal torque for this example: MotorFan's steady motor torque, N m
# (the hand-computed equilibrium of its motor and fan, see tests/python/test_motor_fan.py).
MOTOR_FAN_RATED_TORQUE = 1042.21


def couple(stop_time: float = 30.0, step: float = 0.01, nodes: int = 1) -> dict[str, np.ndarray]:
    """Steps MotorFan and TractionMotorThermal together; returns the exchanged and observed signals."""
    motor = Slave(DIST_DIR / "MotorFan.fmu", "motor").instantiate()
    thermal = Slave(DIST_DIR / "TractionMotorThermal.fmu", "thermal").instantiate()
    try:
        motor.initialize(0.0, stop_time)
        thermal.fmu.setupExperiment(startTime=0.0, stopTime=stop_time)
        thermal.fmu.setInteger([thermal.vr["heat_source"], thermal.vr["nodes"]], [2, nodes])
        thermal.set(torque_nominal=MOTOR_FAN_RATED_TORQUE)
        thermal.fmu.enterInitializationMode()
        thermal.fmu.exitInitializationMode()
        thermal.initialized = True
        rows = []
        n = int(round(stop_time / step))
        for i in range(n + 1):
            t = i * step
            (torque,) = motor.get("motor_torque")
            thermal.set(torque_in=torque)
            rows.append([t, torque, *thermal.get("P_joule", "T_winding", "T_iron")])
            if i < n:
                motor.do_step(t, step)
                thermal.do_step(t, step)
        a = np.array(rows)
        return {"time": a[:, 0], "torque": a[:, 1], "P_joule": a[:, 2], "T_winding": a[:, 3], "T_iron": a[:, 4]}
    finally:
        thermal.close()
        motor.close()


if __name__ == "__main__":
    r = couple()
    print(f"{len(r['time'])} communication points, peak motor torque {r['torque'].max():.0f} N m, "
          f"peak losses {r['P_joule'].max() / 1e3:.1f} kW, winding {r['T_winding'][0] - 273.15:.2f} -> "
          f"{r['T_winding'][-1] - 273.15:.3f} C after {r['time'][-1]:g} s")
