"""What every figure script shares: paths, the command line, fmpy runs and saving a figure.

Each script in examples/ reproduces one of chapter 3's figures (or tables) from the FMUs in dist/
(built by `cargo run --release -p build-fmus`) and writes it to docs/figures/ (or --out DIR).
`--short` runs a short horizon (the pytest uses it); the full horizon is the chapter's.
Matplotlib runs with the non-interactive Agg backend: no display is needed.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from fmpy import simulate_fmu  # noqa: E402

REPO_ROOT = Path(__file__).resolve().parents[1]
DIST_DIR = Path(os.environ["FMU_DIST_DIR"]).resolve() if os.environ.get("FMU_DIST_DIR") else REPO_ROOT / "dist"
FIGURES_DIR = REPO_ROOT / "docs" / "figures"
DPI = 100


def parser(description: str) -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(description=description)
    p.add_argument("--out", type=Path, default=FIGURES_DIR, help=f"output directory (default: {FIGURES_DIR})")
    p.add_argument("--short", action="store_true", help="a short horizon and a coarse output step (for the tests)")
    return p


def fmu(name: str) -> Path:
    path = DIST_DIR / f"{name}.fmu"
    if not path.is_file():
        raise SystemExit(f"{path} is missing: run `cargo run --release -p build-fmus` first")
    return path


def simulate(model: str, stop_time: float, output_interval: float, start_values: dict, outputs: list[str]):
    """One Co-Simulation run in fmpy. For Co-Simulation fmpy's communication step is
    `output_interval` (its `step_size` is ignored): the FMU integrates between the points itself."""
    return simulate_fmu(
        str(fmu(model)),
        fmi_type="CoSimulation",
        start_time=0.0,
        stop_time=stop_time,
        output_interval=output_interval,
        start_values=start_values,
        output=outputs,
    )


def peak_abs(res, name: str) -> float:
    return float(np.max(np.abs(res[name])))


# the elastic shaft (keep_shaft_stiffness = true) and the rigid one, as drawn in Figures 3.10 and 3.13
SHAFT_STYLE = {True: dict(color="tab:red", lw=1.2), False: dict(color="tab:blue", lw=2, ls="--")}


def finish(fig, title: str, out: Path, name: str, legend_loc: str | None = "lower right") -> Path:
    """Grid (and unless legend_loc is None, a legend) on every axes, the title, then save."""
    for ax in fig.axes:
        ax.grid(alpha=0.3)
        if legend_loc and ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=8, loc=legend_loc)
    fig.suptitle(title)
    fig.tight_layout()
    return save(fig, out, name)


def save(fig, out: Path, name: str) -> Path:
    out.mkdir(parents=True, exist_ok=True)
    path = out / name
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    print(f"wrote {path}")
    return path


def start_value(model: str, name: str) -> float:
    """A variable's start value from the FMU's modelDescription.xml (the default it simulates with)."""
    from fmpy import read_model_description

    for v in read_model_description(str(fmu(model))).modelVariables:
        if v.name == name:
            return float(v.start)
    raise KeyError(f"{model} has no variable {name!r}")


# MotorFan (docs/motor-fan-spec.md): Integer parameters
LEVEL = {"a": 1, "b": 2, "c": 3, "d": 4}
DIRECT_ON_LINE, PI_CONTROL, INVERSE = 1, 2, 3
MOTOR_FAN_HORIZON = 30.0  # s, the FMU's DefaultExperiment
MOTOR_FAN_STEP = 1e-3  # s, communication step (fmpy: output_interval)


def motor_fan(start_values: dict, outputs: list[str], short: bool, horizon: float = MOTOR_FAN_HORIZON):
    """A MotorFan run: `horizon` s at 1 ms, or 3 s at 10 ms with --short."""
    stop, h = (3.0, 1e-2) if short else (horizon, MOTOR_FAN_STEP)
    return simulate_checked("MotorFan", stop, h, start_values, outputs)


def simulate_checked(model, stop, h, start_values, outputs):
    res = simulate(model, stop, h, start_values, outputs)
    for name in outputs:
        if not np.all(np.isfinite(res[name])):
            raise RuntimeError(f"{model} {start_values}: {name} is not finite")
    return res
