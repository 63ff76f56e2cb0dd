//! EmptyStep: the benchmark's floor with our runtime. A model with one tunable parameter, one
//! output that copies it and no continuous state, so `fmi2DoStep` runs the runtime's whole call
//! path (pointer and state-machine checks, `catch_unwind`, communication-point check, input
//! bookkeeping, the integrator's entry) but integrates nothing. Lives under `bench/`, not
//! `models/`, so that `build-fmus` does not ship it in `dist/` and the generic tests do not see it;
//! `bench/run.sh` builds and packages it into `target/bench/`.

use fmu_runtime::prelude::*;

pub struct EmptyStep {
    value: Parameter,
    y: Output,
}

impl Model for EmptyStep {
    fn info() -> ModelInfo {
        ModelInfo {
            name: "EmptyStep",
            description: "Benchmark floor: no state, fmi2DoStep integrates nothing",
            default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 30.0, step_size: 1e-3 },
            solver: Solver::ExplicitRungeKutta,
            documentation: "<p>y = value. No continuous state: fmi2DoStep only runs the runtime's call path.</p>",
        }
    }

    fn declare(d: &mut Declarations) -> Self {
        EmptyStep {
            value: d.parameter("value", 1.0, "1").tunable().describe("Any number; copied to y"),
            y: d.output("y", "1").describe("The parameter value"),
        }
    }

    fn derivatives<R: Real>(&self, _k: &Knowns<R>, _der: &mut Derivatives<R>) {}

    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        out[self.y] = k[self.value];
    }
}

fmu_runtime::export_fmu!(EmptyStep);
