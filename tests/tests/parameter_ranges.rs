//! Parameters outside their physical range are refused with fmi2Error and a logger message that
//! names the parameter, and the modelDescription declares the bounds where physics gives them.
//!
//! * every Real parameter of every FMU in dist/ is set just outside each declared bound (below
//!   `min`, above `max`, and 0 for strictly positive quantities such as an inertia or a
//!   stiffness, whose `min` is the smallest positive double) and every Integer parameter outside
//!   its range: refused, named;
//! * every declared bound itself is accepted (FMI's `min`/`max` are inclusive: a master that
//!   sweeps or clamps to the declared range is never refused inside it), and initialization then
//!   either succeeds with every Real finite or fails naming the parameter;
//! * relations between parameters that no single bound expresses are refused when
//!   initialization ends, again naming the parameter;
//! * every parameter whose unit is that of a non-negative quantity (mass, inertia, inductance,
//!   resistance, heat capacity, stiffness, absolute temperature, ...) declares `min >= 0`, and
//!   every efficiency declares `max = 1`.

use fmi_host::dist::every_fmu;
use fmi_host::{Causality, Fmu, Instance, Status, VariableType};

/// Units of quantities that cannot be negative.
const NON_NEGATIVE_UNITS: &[&str] =
    &["kg", "kg.m2", "H", "H-1", "F", "Ohm", "J/K", "W/K", "J/(kg.K)", "N.m/rad", "N.m.s/rad", "N.m.s2/rad2", "K", "Hz", "m"];

fn logged_error_naming(inst: &Instance, mark: usize, name: &str) -> bool {
    inst.log().since(mark).iter().any(|r| r.status == Status::ERROR && r.message.contains(name))
}

/// Candidate values outside the declared range of a Real parameter.
fn outside(min: Option<f64>, max: Option<f64>) -> Vec<f64> {
    let mut v = Vec::new();
    if let Some(m) = min {
        v.push(m - 1e-3 * m.abs().max(1.0));
        v.push(-1e300);
    }
    if let Some(m) = max {
        v.push(m + 1e-3 * m.abs().max(1.0));
        v.push(1e300);
    }
    v
}

fn instance(fmu: &std::sync::Arc<Fmu>) -> Instance {
    let mut inst = fmu.instantiate("ranges", false, false).expect("instantiate");
    assert_eq!(inst.setup_experiment(None, 0.0, None), Status::OK);
    inst
}

#[test]
fn out_of_range_parameters_are_refused_by_name() {
    let mut tried = 0;
    for fmu in every_fmu() {
        let md = fmu.model_description();
        let mut inst = instance(&fmu);
        for v in md.model_variables.iter().filter(|v| v.causality == Causality::Parameter) {
            match v.variable_type {
                VariableType::Real => {
                    for x in outside(v.min, v.max) {
                        let mark = inst.log().len();
                        let s = inst.set_real(&[v.value_reference], &[x]);
                        assert_eq!(s, Status::ERROR, "{}: {} = {x} accepted", md.model_name, v.name);
                        assert!(logged_error_naming(&inst, mark, &v.name), "{}: refusal of {} = {x} does not name it", md.model_name, v.name);
                        tried += 1;
                    }
                    // 0 for a strictly positive quantity (an inertia, an inductance), which declares
                    // the smallest positive double as its min: refused by name.
                    if v.min.is_some_and(|m| m > 0.0 && m < 1e-300) {
                        let mark = inst.log().len();
                        assert_eq!(inst.set_real(&[v.value_reference], &[0.0]), Status::ERROR, "{}: {} = 0 accepted", md.model_name, v.name);
                        assert!(logged_error_naming(&inst, mark, &v.name), "{}: refusal of {} = 0 does not name it", md.model_name, v.name);
                        tried += 1;
                    }
                }
                VariableType::Integer => {
                    for x in [v.min.map(|m| m as i32 - 1), v.max.map(|m| m as i32 + 1)].into_iter().flatten() {
                        let mark = inst.log().len();
                        let s = inst.set_integer(&[v.value_reference], &[x]);
                        assert_eq!(s, Status::ERROR, "{}: {} = {x} accepted", md.model_name, v.name);
                        assert!(logged_error_naming(&inst, mark, &v.name), "{}: refusal of {} = {x} does not name it", md.model_name, v.name);
                        tried += 1;
                    }
                }
                _ => {}
            }
        }
        // None of the refused values stuck: the instance initializes with its defaults.
        assert_eq!(inst.enter_initialization_mode(), Status::OK);
        assert_eq!(inst.exit_initialization_mode(), Status::OK, "{}", md.model_name);
    }
    println!("{tried} out-of-range parameter values refused, each naming its parameter");
}

/// A relation between parameters: set the values, initialize, expect fmi2Error naming `culprit`.
fn refused_at_initialization(model: &str, reals: &[(&str, f64)], integers: &[(&str, i32)], culprit: &str) {
    let fmu = every_fmu().into_iter().find(|f| f.model_description().model_name == model).unwrap_or_else(|| panic!("dist/{model}.fmu"));
    let mut inst = instance(&fmu);
    for (name, x) in reals {
        assert_eq!(inst.set_real(&[fmu.vr(name).unwrap()], &[*x]), Status::OK, "{name} = {x} is inside its own range");
    }
    for (name, n) in integers {
        assert_eq!(inst.set_integer(&[fmu.vr(name).unwrap()], &[*n]), Status::OK, "{name} = {n}");
    }
    assert_eq!(inst.enter_initialization_mode(), Status::OK);
    let mark = inst.log().len();
    assert_eq!(inst.exit_initialization_mode(), Status::ERROR, "{model}: {reals:?} {integers:?} accepted");
    assert!(logged_error_naming(&inst, mark, culprit), "{model}: the refusal does not name {culprit}: {:?}", inst.log().since(mark));
    // The instance is in the Error mode now: stepping is refused, not attempted.
    assert_eq!(inst.do_step(0.0, 1e-3, true), Status::ERROR);
}

#[test]
fn inconsistent_parameter_relations_are_refused_at_initialization() {
    // Two-node thermal model: the insulation cannot take more than the whole winding rise.
    refused_at_initialization("TractionMotorThermal", &[("dT_winding_iron_nominal", 150.0)], &[("thermal_data", 2)], "dT_winding_iron_nominal");
    // Inverse simulation needs a set point with a finite acceleration.
    refused_at_initialization("MotorFan", &[("ramp_time", 0.0)], &[("start_mode", 3), ("setpoint_filter", 0)], "ramp_time");
}

#[test]
fn physically_bounded_parameters_declare_their_bounds() {
    let mut checked = 0;
    for fmu in every_fmu() {
        let md = fmu.model_description();
        for v in md.model_variables.iter().filter(|v| v.causality == Causality::Parameter && v.variable_type == VariableType::Real) {
            let unit = v.unit.as_deref().unwrap_or("");
            if NON_NEGATIVE_UNITS.contains(&unit) {
                assert!(v.min.is_some_and(|m| m >= 0.0), "{}: {} [{unit}] declares no min >= 0", md.model_name, v.name);
                checked += 1;
            }
            let text = format!("{} {}", v.name, v.description.as_deref().unwrap_or("")).to_lowercase();
            if v.name.starts_with("eta") || text.contains("efficiency") {
                assert_eq!(v.max, Some(1.0), "{}: efficiency {} declares no max = 1", md.model_name, v.name);
                checked += 1;
            }
        }
    }
    println!("{checked} bounds declared where physics gives them");
}

/// Everything the log says since `mark`, for a failure message.
fn log_since(inst: &Instance, mark: usize) -> Vec<String> {
    inst.log().since(mark).iter().map(|r| r.message.clone()).collect()
}

#[test]
fn declared_bounds_are_accepted_and_initialization_succeeds_or_names_the_parameter() {
    let (mut accepted, mut initialized, mut refused) = (0, 0, Vec::new());
    for fmu in every_fmu() {
        let md = fmu.model_description();
        let real_vars: Vec<_> = md.model_variables.iter().filter(|v| v.variable_type == VariableType::Real).collect();
        let reals: Vec<u32> = real_vars.iter().map(|v| v.value_reference).collect();
        for v in md.model_variables.iter().filter(|v| v.causality == Causality::Parameter) {
            for bound in [v.min, v.max].into_iter().flatten() {
                let mut inst = instance(&fmu);
                let mark = inst.log().len();
                let s = match v.variable_type {
                    VariableType::Real => inst.set_real(&[v.value_reference], &[bound]),
                    VariableType::Integer => inst.set_integer(&[v.value_reference], &[bound as i32]),
                    _ => continue,
                };
                let what = format!("{}: {} = {bound:e}", md.model_name, v.name);
                assert_eq!(s, Status::OK, "{what}, a declared bound, refused: {:?}", log_since(&inst, mark));
                accepted += 1;
                assert_eq!(inst.enter_initialization_mode(), Status::OK, "{what}");
                match inst.exit_initialization_mode() {
                    Status::OK => {
                        let (s, values) = inst.get_reals(&reals);
                        assert_eq!(s, Status::OK, "{what}");
                        for (x, r) in values.iter().zip(&real_vars) {
                            assert!(x.is_finite(), "{what}: initialization succeeded but {} = {x}", r.name);
                        }
                        initialized += 1;
                    }
                    Status::ERROR => {
                        assert!(logged_error_naming(&inst, mark, &v.name), "{what}: initialization refused without naming {}: {:?}", v.name, log_since(&inst, mark));
                        refused.push(format!("{what}: {}", log_since(&inst, mark).join(" | ")));
                    }
                    s => panic!("{what}: fmi2ExitInitializationMode returned {s:?}: {:?}", log_since(&inst, mark)),
                }
            }
        }
    }
    for r in &refused {
        println!("  {r}");
    }
    println!("{accepted} declared bounds accepted by fmi2SetReal/fmi2SetInteger: {initialized} initialize, {} refused at initialization naming the parameter", refused.len());
}
