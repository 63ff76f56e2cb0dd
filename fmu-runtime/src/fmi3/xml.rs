//! modelDescription.xml for FMI 3.0 (FMI 3.0, section 2.4): typed variables (Float64, Int32,
//! Boolean), the independent variable `time`, one Float64 per event indicator, and a
//! ModelStructure of value references.

use std::borrow::Cow;

use super::functions::Extra;
use crate::description::{real_text, Dependencies, Package, Structure};
use crate::model::Model;
use crate::variables::{BaseType, Variable, VariableTable};
use crate::xml::{close, empty, enumerations, finish, write_items, header_attributes, open, start_text, variable_attributes, write_default_experiment, write_log_categories, write_units, yes_no, Xml, NO_ATTRIBUTES, TOKEN_PLACEHOLDER};

fn write_unknowns(w: &mut Xml, element: &str, unknowns: &[(usize, Dependencies)]) {
    for (vr, deps) in unknowns {
        let mut attrs = vec![("valueReference", vr.to_string())];
        if let Some(set) = deps {
            attrs.push(("dependencies", set.iter().map(|k| k.to_string()).collect::<Vec<_>>().join(" ")));
        }
        empty(w, element, &attrs);
    }
}

fn write_variable(w: &mut Xml, v: &Variable) {
    let mut a = variable_attributes(v);
    let owned = |(k, s): (&'static str, String)| (k, Cow::Owned(s));
    let element = match v.base_type() {
        BaseType::Integer => {
            a.extend(v.min.map(|m| ("min", (m as i32).to_string())).map(owned));
            a.extend(v.max.map(|m| ("max", (m as i32).to_string())).map(owned));
            if v.items.is_empty() {
                "Int32"
            } else {
                a.push(("declaredType", Cow::Borrowed(v.name.as_str())));
                "Enumeration"
            }
        }
        BaseType::Boolean => "Boolean",
        _ => {
            a.extend(v.unit.as_deref().map(|u| ("unit", Cow::Borrowed(u))));
            a.extend(v.min.map(|m| ("min", real_text(m))).map(owned));
            a.extend(v.max.map(|m| ("max", real_text(m))).map(owned));
            a.extend(v.nominal.map(|n| ("nominal", real_text(n))).map(owned));
            // FMI 3.0 names the state by its value reference (FMI 2.0 by its index).
            a.extend(v.derivative_of.map(|of| ("derivative", of.to_string())).map(owned));
            "Float64"
        }
    };
    a.extend(start_text(v).map(|s| ("start", s)).map(owned));
    empty(w, element, &a);
}

/// The FMI 3.0 description, with the instantiationToken left as `TOKEN_PLACEHOLDER`.
pub fn write<M: Model>(table: &VariableTable, structure: &Structure, package: &Package, default_floor: Option<f64>) -> String {
    let info = M::info();
    let extra = Extra::of(table);
    let mut w = crate::xml::document();
    let mut header = vec![("fmiVersion", "3.0".to_string()), ("modelName", info.name.into()), ("instantiationToken", TOKEN_PLACEHOLDER.into())];
    header.extend(header_attributes::<M>(table, package));
    open(&mut w, "fmiModelDescription", &header);
    let common = |w: &mut Xml, element: &str, more: &[(&'static str, String)]| {
        let mut attrs = vec![
            ("modelIdentifier", info.name.to_string()),
            ("needsExecutionTool", yes_no(false)),
            ("canBeInstantiatedOnlyOncePerProcess", yes_no(false)),
            ("canGetAndSetFMUState", yes_no(true)),
            ("canSerializeFMUState", yes_no(true)),
            ("providesDirectionalDerivatives", yes_no(true)),
            ("providesAdjointDerivatives", yes_no(true)),
            ("providesPerElementDependencies", yes_no(false)),
        ];
        attrs.extend_from_slice(more);
        empty(w, element, &attrs);
    };
    common(&mut w, "ModelExchange", &[("needsCompletedIntegratorStep", yes_no(false)), ("providesEvaluateDiscreteStates", yes_no(false))]);
    common(
        &mut w,
        "CoSimulation",
        &[
            ("canHandleVariableCommunicationStepSize", yes_no(true)),
            ("maxOutputDerivativeOrder", "1".into()),
            ("providesIntermediateUpdate", yes_no(false)),
            // At events, when the master uses event mode and allows early return.
            ("mightReturnEarlyFromDoStep", yes_no(true)),
            ("canReturnEarlyAfterIntermediateUpdate", yes_no(false)),
            ("hasEventMode", yes_no(true)),
            ("providesEvaluateDiscreteStates", yes_no(false)),
        ],
    );
    write_units(&mut w, table, &["s"]);
    if enumerations(table).next().is_some() {
        open(&mut w, "TypeDefinitions", NO_ATTRIBUTES);
        for v in enumerations(table) {
            open(&mut w, "EnumerationType", &[("name", v.name.clone())]);
            write_items(&mut w, v);
            close(&mut w, "EnumerationType");
        }
        close(&mut w, "TypeDefinitions");
    }
    write_log_categories(&mut w);
    write_default_experiment::<M>(&mut w, default_floor);
    open(&mut w, "ModelVariables", NO_ATTRIBUTES);
    empty(
        &mut w,
        "Float64",
        &[
            ("name", "time".into()),
            ("valueReference", extra.time.to_string()),
            ("description", "Simulation time".into()),
            ("causality", "independent".into()),
            ("variability", "continuous".into()),
            ("unit", "s".into()),
        ],
    );
    for v in &table.variables {
        write_variable(&mut w, v);
    }
    for (i, (name, description)) in table.indicators.iter().enumerate() {
        empty(
            &mut w,
            "Float64",
            &[
                ("name", format!("event_indicator.{name}")),
                ("valueReference", (extra.first_indicator as usize + i).to_string()),
                ("description", format!("Event indicator (an event where it changes sign): {description}")),
                ("causality", "local".into()),
                ("variability", "continuous".into()),
                ("initial", "calculated".into()),
            ],
        );
    }
    close(&mut w, "ModelVariables");
    open(&mut w, "ModelStructure", NO_ATTRIBUTES);
    write_unknowns(&mut w, "Output", &structure.outputs);
    write_unknowns(&mut w, "ContinuousStateDerivative", &structure.derivatives);
    write_unknowns(&mut w, "InitialUnknown", &structure.initial_unknowns);
    // The indicators' dependencies are not probed: none listed means "depends on every known".
    for i in 0..table.indicators.len() {
        empty(&mut w, "EventIndicator", &[("valueReference", (extra.first_indicator as usize + i).to_string())]);
    }
    close(&mut w, "ModelStructure");
    close(&mut w, "fmiModelDescription");
    finish(w)
}
