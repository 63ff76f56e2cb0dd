//! 1000 instantiate / initialize / step / save-restore-serialize / terminate / free cycles per
//! FMU in dist/ (FMI 2.0) and dist/fmi3/ (FMI 3.0): the workload `./test.sh` runs under valgrind
//! memcheck, which must report zero errors and zero leaked bytes (definitely or indirectly lost).
//! `FMI_VERSIONS` (`2`, `3`, default both) picks the versions (tests/valgrind.sh runs 1000 cycles
//! of FMI 2.0 and 200 of FMI 3.0).
//!
//! ```sh
//! cargo run --release -p fmi-host --example lifecycle_cycles -- [cycles]
//! FMI_VERSIONS=2 valgrind --leak-check=full --error-exitcode=1 target/release/examples/lifecycle_cycles 1000
//! ```

use fmi_host::dist::every_fmu_of_every_version as every_fmu;
use fmi_host::{Causality, Fmi2Type, Instance, InstantiateOptions, Status, VariableType};

fn main() {
    let cycles: usize = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(1000);
    for fmu in every_fmu() {
        let md = fmu.model_description();
        let e = md.default_experiment.clone().expect("a DefaultExperiment");
        let (start, step) = (e.start_time.unwrap_or(0.0), e.step_size.unwrap());
        let outputs: Vec<u32> = md
            .model_variables
            .iter()
            .filter(|v| v.causality == Causality::Output && v.variable_type == VariableType::Real)
            .map(|v| v.value_reference)
            .collect();
        // FMI 3.0 adds the independent variable `time` and one Float64 per event indicator,
        // which fmi3GetFloat64 computes on its own path: read them too.
        let extra: Vec<u32> = md
            .model_variables
            .iter()
            .filter(|v| v.causality == Causality::Independent || v.name.starts_with("event_indicator."))
            .map(|v| v.value_reference)
            .collect();
        for cycle in 0..cycles {
            // Alternate the interfaces and the memory callbacks.
            let kind = if cycle % 4 == 3 { Fmi2Type::ModelExchange } else { Fmi2Type::CoSimulation };
            let options = InstantiateOptions::new(format!("cycle{cycle}")).fmu_type(kind).memory_callbacks(cycle % 2 == 0);
            let mut inst = Instance::new(&fmu, options).expect("instantiate");
            assert_eq!(inst.setup_experiment(None, start, None), Status::OK);
            assert_eq!(inst.enter_initialization_mode(), Status::OK);
            assert_eq!(inst.exit_initialization_mode(), Status::OK);
            if kind == Fmi2Type::CoSimulation {
                for k in 0..3 {
                    assert_eq!(inst.do_step(start + k as f64 * step, step, true), Status::OK);
                }
                let (_, state) = inst.get_fmu_state();
                let state = state.expect("a state");
                let (_, bytes) = inst.serialize_fmu_state(&state);
                let (s, copy) = inst.deserialize_fmu_state(&bytes);
                assert_eq!(s, Status::OK);
                assert_eq!(inst.set_fmu_state(&copy.expect("a copy")), Status::OK);
                // One state freed by hand, the other left for fmi2FreeInstance / fmi3FreeInstance.
                assert_eq!(inst.free_fmu_state(state), Status::OK);
                // A refused call (its message is allocated and freed too).
                assert_eq!(inst.do_step(-1.0, step, true), Status::ERROR);
            }
            let (s, y) = inst.get_reals(&outputs);
            assert!(s == Status::OK && y.iter().all(|v| v.is_finite()));
            let (s, y) = inst.get_reals(&extra);
            assert!(s == Status::OK && y.iter().all(|v| v.is_finite()), "{}: {s:?} {y:?}", md.model_name);
            if cycle % 3 == 0 {
                assert_eq!(inst.reset(), Status::OK);
            } else {
                assert_eq!(inst.terminate(), Status::OK);
            }
            inst.free();
        }
        println!("{:<22} {} {cycles} cycles", md.model_name, fmu.fmi_version());
    }
}
