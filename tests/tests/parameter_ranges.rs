//! Parameters outside their physical range are refused with fmi2Error and a logger message that
//! names the parameter, and the modelDescription declares the bounds where physics gives them.
//!
//! * every Real parameter of every FMU in dist/ is set just outside each declared bound (below
//!   `min`, above `max`, and at `min` = 0 itself for strictly positive quantities such as an
//!   inertia or a stiffness) and every Integer parameter outside its range: refused, named;
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
                    // At min = 0: a non-negative quantity accepts 0, a strictly positive one (an
                    // inertia, an inductance: FMI's min is inclusive, so the XML cannot say it)
                    // refuses it by name.
                    if v.min == Some(0.0) {
                        let mark = inst.log().len();
                        match inst.set_real(&[v.value_reference], &[0.0]) {
                            Status::OK => {
                                // Restore the default for the next checks.
                                let start = v.start.as_ref().and_then(|s| s.as_f64()).unwrap();
                                assert_eq!(inst.set_real(&[v.value_reference], &[start]), Status::OK);
                            }
                            s => {
                                assert_eq!(s, Status::ERROR);
                                assert!(logged_error_naming(&inst, mark, &v.name), "{}: refusal of {} = 0 does not name it", md.model_name, v.name);
                                tried += 1;
                            }
                        }
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
    refused_at_initialization("TractionMotorThermal", &[("dT_winding_iron_nominal", 150.0)], &[], "dT_winding_iron_nominal");
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
