//! modelDescription.xml for FMI 2.0 (FMI 2.0.4, section 2.2): ScalarVariables, and a
//! ModelStructure of 1-based indices into them.

use std::borrow::Cow;

use crate::description::{real_text, Dependencies, Package, Structure};
use crate::model::Model;
use crate::variables::{BaseType, Variable, VariableTable};
use crate::xml::{close, document, empty, enumerations, finish, write_items, header_attributes, open, start_text, variable_attributes, write_default_experiment, write_log_categories, write_units, yes_no, Xml, NO_ATTRIBUTES, TOKEN_PLACEHOLDER};

/// FMI 2.0 lists variables by index: the position in ModelVariables, from 1 (a value
/// reference is the position, from 0).
fn index(value_reference: usize) -> usize {
    value_reference + 1
}

fn write_unknowns(w: &mut Xml, list: &str, unknowns: &[(usize, Dependencies)]) {
    if unknowns.is_empty() {
        return;
    }
    open(w, list, NO_ATTRIBUTES);
    for (vr, deps) in unknowns {
        let mut attrs = vec![("index", index(*vr).to_string())];
        if let Some(set) = deps {
            attrs.push(("dependencies", set.iter().map(|k| index(*k).to_string()).collect::<Vec<_>>().join(" ")));
        }
        empty(w, "Unknown", &attrs);
    }
    close(w, list);
}

fn write_variable(w: &mut Xml, v: &Variable, table: &VariableTable) {
    open(w, "ScalarVariable", &variable_attributes(v));
    let mut t: Vec<(&str, Cow<str>)> = Vec::with_capacity(6);
    t.extend(start_text(v).map(|s| ("start", Cow::Owned(s))));
    match v.base_type() {
        BaseType::Integer => {
            if let Some(m) = v.min {
                t.push(("min", Cow::Owned((m as i32).to_string())));
            }
            if let Some(m) = v.max {
                t.push(("max", Cow::Owned((m as i32).to_string())));
            }
            if v.items.is_empty() {
                empty(w, "Integer", &t);
            } else {
                t.insert(0, ("declaredType", Cow::Borrowed(v.name.as_str())));
                empty(w, "Enumeration", &t);
            }
        }
        BaseType::Boolean => empty(w, "Boolean", &t),
        _ => {
            if let Some(of) = v.derivative_of {
                t.push(("derivative", Cow::Owned(index(table.variables[of as usize].value_reference as usize).to_string())));
            }
            if let Some(u) = &v.unit {
                t.push(("unit", Cow::Borrowed(u.as_str())));
            }
            if let Some(m) = v.min {
                t.push(("min", Cow::Owned(real_text(m))));
            }
            if let Some(m) = v.max {
                t.push(("max", Cow::Owned(real_text(m))));
            }
            if let Some(n) = v.nominal {
                t.push(("nominal", Cow::Owned(real_text(n))));
            }
            empty(w, "Real", &t);
        }
    }
    close(w, "ScalarVariable");
}

/// The FMI 2.0 description, with the guid left as `TOKEN_PLACEHOLDER`.
pub fn write<M: Model>(table: &VariableTable, structure: &Structure, package: &Package, default_floor: Option<f64>) -> String {
    let info = M::info();
    let mut w = document();
    let mut header = vec![("fmiVersion", "2.0".to_string()), ("modelName", info.name.into()), ("guid", TOKEN_PLACEHOLDER.into())];
    header.extend(header_attributes::<M>(table, package));
    header.push(("numberOfEventIndicators", table.indicators.len().to_string()));
    open(&mut w, "fmiModelDescription", &header);
    empty(
        &mut w,
        "ModelExchange",
        &[
            ("modelIdentifier", info.name.into()),
            ("needsExecutionTool", yes_no(false)),
            ("completedIntegratorStepNotNeeded", yes_no(true)),
            ("canBeInstantiatedOnlyOncePerProcess", yes_no(false)),
            ("canNotUseMemoryManagementFunctions", yes_no(true)),
            ("canGetAndSetFMUstate", yes_no(true)),
            ("canSerializeFMUstate", yes_no(true)),
            ("providesDirectionalDerivative", yes_no(true)),
        ],
    );
    empty(
        &mut w,
        "CoSimulation",
        &[
            ("modelIdentifier", info.name.into()),
            ("needsExecutionTool", yes_no(false)),
            ("canHandleVariableCommunicationStepSize", yes_no(true)),
            ("canInterpolateInputs", yes_no(true)),
            ("maxOutputDerivativeOrder", "1".into()),
            ("canRunAsynchronuously", yes_no(false)),
            ("canBeInstantiatedOnlyOncePerProcess", yes_no(false)),
            ("canNotUseMemoryManagementFunctions", yes_no(true)),
            ("canGetAndSetFMUstate", yes_no(true)),
            ("canSerializeFMUstate", yes_no(true)),
            ("providesDirectionalDerivative", yes_no(true)),
        ],
    );
    write_units(&mut w, table, &[]);
    if enumerations(table).next().is_some() {
        open(&mut w, "TypeDefinitions", NO_ATTRIBUTES);
        for v in enumerations(table) {
            open(&mut w, "SimpleType", &[("name", v.name.clone())]);
            open(&mut w, "Enumeration", NO_ATTRIBUTES);
            write_items(&mut w, v);
            close(&mut w, "Enumeration");
            close(&mut w, "SimpleType");
        }
        close(&mut w, "TypeDefinitions");
    }
    write_log_categories(&mut w);
    write_default_experiment::<M>(&mut w, default_floor);
    open(&mut w, "ModelVariables", NO_ATTRIBUTES);
    for v in &table.variables {
        write_variable(&mut w, v, table);
    }
    close(&mut w, "ModelVariables");
    open(&mut w, "ModelStructure", NO_ATTRIBUTES);
    write_unknowns(&mut w, "Outputs", &structure.outputs);
    write_unknowns(&mut w, "Derivatives", &structure.derivatives);
    write_unknowns(&mut w, "InitialUnknowns", &structure.initial_unknowns);
    close(&mut w, "ModelStructure");
    close(&mut w, "fmiModelDescription");
    finish(w)
}
