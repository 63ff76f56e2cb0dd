//! The pieces of modelDescription.xml that FMI 2.0 and FMI 3.0 write alike (quick-xml): the
//! writer, UnitDefinitions, LogCategories, DefaultExperiment, the package attributes, and the
//! token (FMI 2.0 `guid`, FMI 3.0 `instantiationToken`) as a hash of the content.

use std::collections::BTreeSet;

use quick_xml::events::{BytesDecl, BytesEnd, BytesStart, Event};
use quick_xml::Writer;

use crate::description::{real_text, Package};
use crate::log::CATEGORIES;
use crate::model::Model;
use crate::state::{fnv1a64, FNV_OFFSET};
use crate::units;
use crate::variables::{Variable, VariableTable};

pub type Xml = Writer<Vec<u8>>;

/// A writer with the XML declaration written.
pub fn document() -> Xml {
    let mut w = Writer::new_with_indent(Vec::new(), b' ', 2);
    w.write_event(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None))).expect("writing to memory");
    w
}

/// The finished text, with a final newline.
pub fn finish(w: Xml) -> String {
    let mut xml = String::from_utf8(w.into_inner()).expect("UTF-8 in, UTF-8 out");
    xml.push('\n');
    xml
}

pub fn open(w: &mut Xml, name: &str, attrs: &[(&str, String)]) {
    let mut e = BytesStart::new(name);
    for (k, v) in attrs {
        e.push_attribute((*k, v.as_str()));
    }
    w.write_event(Event::Start(e)).expect("writing to memory");
}

pub fn empty(w: &mut Xml, name: &str, attrs: &[(&str, String)]) {
    let mut e = BytesStart::new(name);
    for (k, v) in attrs {
        e.push_attribute((*k, v.as_str()));
    }
    w.write_event(Event::Empty(e)).expect("writing to memory");
}

pub fn close(w: &mut Xml, name: &str) {
    w.write_event(Event::End(BytesEnd::new(name))).expect("writing to memory");
}

pub fn yes_no(b: bool) -> String {
    if b { "true" } else { "false" }.to_string()
}

/// The placeholder the token replaces after hashing.
pub const TOKEN_PLACEHOLDER: &str = "{00000000-0000-0000-0000-000000000000}";

/// A guid in the usual 8-4-4-4-12 form from two FNV-1a hashes of the content.
pub fn token_of(content: &str) -> String {
    let a = fnv1a64(FNV_OFFSET, content.as_bytes());
    let b = fnv1a64(a ^ 0x9e37_79b9_7f4a_7c15, content.as_bytes());
    let hex = format!("{a:016x}{b:016x}");
    format!("{{{}-{}-{}-{}-{}}}", &hex[0..8], &hex[8..12], &hex[12..16], &hex[16..20], &hex[20..32])
}

/// The attributes of `fmiModelDescription` after its name and token, which both versions share:
/// description, the package's, generationTool, generationDateAndTime.
pub fn header_attributes<M: Model>(package: &Package) -> Vec<(&'static str, String)> {
    let mut header = vec![("description", M::info().description.to_string())];
    header.extend(package.attributes());
    header.push(("generationTool", format!("fmu-runtime {}", env!("CARGO_PKG_VERSION"))));
    if let Some(date) = package.generation_date_and_time() {
        header.push(("generationDateAndTime", date));
    }
    header
}

/// UnitDefinitions: every unit a variable uses (and `more`, units of variables the writer adds),
/// in SI base units.
pub fn write_units(w: &mut Xml, table: &VariableTable, more: &[&str]) {
    let mut used: BTreeSet<&str> = table.variables.iter().filter_map(|v| v.unit.as_deref()).collect();
    used.extend(more);
    if used.is_empty() {
        return;
    }
    open(w, "UnitDefinitions", &[]);
    for name in used {
        // An unknown unit is one of the model's problems (reported with its file and line, and
        // the model is not exported): the description is still written, without it.
        let Some(b) = units::lookup(name) else { continue };
        open(w, "Unit", &[("name", name.to_string())]);
        let mut attrs = Vec::new();
        for (k, e) in [("kg", b.kg), ("m", b.m), ("s", b.s), ("A", b.a), ("K", b.k), ("mol", b.mol), ("cd", b.cd), ("rad", b.rad)] {
            if e != 0 {
                attrs.push((k, e.to_string()));
            }
        }
        if b.factor != 1.0 {
            attrs.push(("factor", real_text(b.factor)));
        }
        if b.offset != 0.0 {
            attrs.push(("offset", real_text(b.offset)));
        }
        empty(w, "BaseUnit", &attrs);
        close(w, "Unit");
    }
    close(w, "UnitDefinitions");
}

pub fn write_log_categories(w: &mut Xml) {
    open(w, "LogCategories", &[]);
    for (name, description) in CATEGORIES {
        empty(w, "Category", &[("name", name.to_string()), ("description", description.to_string())]);
    }
    close(w, "LogCategories");
}

pub fn write_default_experiment<M: Model>(w: &mut Xml) {
    let e = M::info().default_experiment;
    empty(
        w,
        "DefaultExperiment",
        &[
            ("startTime", real_text(e.start_time)),
            ("stopTime", real_text(e.stop_time)),
            ("tolerance", real_text(crate::integrate::declared_tolerance(M::tolerance_floor()))),
            ("stepSize", real_text(e.step_size)),
        ],
    );
}

/// The attributes every variable element starts with, in both standards: name, valueReference,
/// description, causality, variability, initial.
pub fn variable_attributes(v: &Variable) -> Vec<(&'static str, String)> {
    let mut a = vec![("name", v.name.clone()), ("valueReference", v.value_reference.to_string())];
    if !v.description.is_empty() {
        a.push(("description", v.description.clone()));
    }
    a.push(("causality", v.causality.as_str().to_string()));
    a.push(("variability", v.variability.as_str().to_string()));
    if let Some(i) = v.initial {
        a.push(("initial", i.as_str().to_string()));
    }
    a
}

/// A variable's start attribute's text, if it has one: a calculated variable has none (a
/// mode's start is only the model's first guess).
pub fn start_text(v: &Variable) -> Option<String> {
    if v.initial == Some(crate::variables::Initial::Calculated) {
        return None;
    }
    v.start.map(|s| match s {
        crate::variables::Start::Real(x) => real_text(x),
        crate::variables::Start::Integer(n) => n.to_string(),
        crate::variables::Start::Boolean(b) => yes_no(b),
    })
}

/// The enumerated variables (structural choices), each with its own type named after it.
pub fn enumerations(table: &VariableTable) -> impl Iterator<Item = &Variable> {
    table.variables.iter().filter(|v| !v.items.is_empty())
}

/// The items of an enumerated variable's type, as `Item` elements (the same in both versions).
pub fn write_items(w: &mut Xml, v: &Variable) {
    let first = v.min.unwrap_or(1.0) as i32;
    for (k, (name, description)) in v.items.iter().enumerate() {
        let mut attrs = vec![("name", name.clone()), ("value", (first + k as i32).to_string())];
        if !description.is_empty() {
            attrs.push(("description", description.clone()));
        }
        empty(w, "Item", &attrs);
    }
}
