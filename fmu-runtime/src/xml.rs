//! The pieces of modelDescription.xml that FMI 2.0 and FMI 3.0 write alike (quick-xml): the
//! writer, UnitDefinitions, LogCategories, DefaultExperiment, the package attributes, and the
//! token (FMI 2.0 `guid`, FMI 3.0 `instantiationToken`) as hashes of the content.

use std::borrow::Cow;
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

/// No attributes, for `open` and `empty`.
pub const NO_ATTRIBUTES: &[(&str, &str)] = &[];

/// An element's start with its attributes, in one buffer sized for them (a description has
/// an element or two per variable: growing a buffer per attribute cost more than the rest).
fn start<'a, S: AsRef<str>>(name: &'a str, attrs: &[(&str, S)]) -> BytesStart<'a> {
    // Name, then ` key="value"` per attribute, with room for a few escapes.
    let room = name.len() + attrs.iter().map(|(k, v)| k.len() + v.as_ref().len() + 4).sum::<usize>() + 16;
    let mut buffer = String::with_capacity(room);
    buffer.push_str(name);
    let mut e = BytesStart::from_content(buffer, name.len());
    for (k, v) in attrs {
        e.push_attribute((*k, v.as_ref()));
    }
    e
}

pub fn open<S: AsRef<str>>(w: &mut Xml, name: &str, attrs: &[(&str, S)]) {
    w.write_event(Event::Start(start(name, attrs))).expect("writing to memory");
}

pub fn empty<S: AsRef<str>>(w: &mut Xml, name: &str, attrs: &[(&str, S)]) {
    w.write_event(Event::Empty(start(name, attrs))).expect("writing to memory");
}

pub fn close(w: &mut Xml, name: &str) {
    w.write_event(Event::End(BytesEnd::new(name))).expect("writing to memory");
}

pub fn yes_no(b: bool) -> String {
    if b { "true" } else { "false" }.to_string()
}

/// The placeholder the token replaces after hashing.
pub const TOKEN_PLACEHOLDER: &str = "{00000000-0000-0000-0000-000000000000}";

/// The token's first half: the FNV-1a hash of the description written without the
/// ModelStructure's dependency lists (and with the token left as `TOKEN_PLACEHOLDER`), which
/// the binary recomputes at instantiation without probing the equations.
pub fn interface_hash(skeleton: &str) -> u64 {
    fnv1a64(FNV_OFFSET, skeleton.as_bytes())
}

/// The token in the usual 8-4-4-4-12 guid form: the 16 hex digits of `interface` (the first
/// three groups), then 16 of the FNV-1a hash of the whole draft seeded with it. Two
/// descriptions that differ anywhere, dependency lists included, have different tokens.
pub fn token(interface: u64, draft: &str) -> String {
    let whole = fnv1a64(interface ^ 0x9e37_79b9_7f4a_7c15, draft.as_bytes());
    let hex = format!("{interface:016x}{whole:016x}");
    format!("{{{}-{}-{}-{}-{}}}", &hex[0..8], &hex[8..12], &hex[12..16], &hex[16..20], &hex[20..32])
}

/// What instantiation checks a master's token against: its first half (`interface_hash`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TokenCheck {
    /// The token's text up to the end of the first half: "{xxxxxxxx-xxxx-xxxx-".
    prefix: String,
    /// The prefix with the rest elided, for messages and serialized FMU states:
    /// "{xxxxxxxx-xxxx-xxxx-...}".
    shown: String,
}

impl TokenCheck {
    pub fn new(interface: u64) -> TokenCheck {
        let hex = format!("{interface:016x}");
        let prefix = format!("{{{}-{}-{}-", &hex[0..8], &hex[8..12], &hex[12..16]);
        TokenCheck { shown: format!("{prefix}...}}"), prefix }
    }

    /// Whether `token` is a token of this library's description: the 8-4-4-4-12 form in
    /// braces, beginning with this interface hash (the second half, the hash of the dependency
    /// lists among the rest, is not checked: the binary does not probe its equations to know it).
    pub fn accepts(&self, token: &str) -> bool {
        let b = token.as_bytes();
        b.len() == 38
            && token.starts_with(&self.prefix)
            && b[37] == b'}'
            && b[20..37].iter().enumerate().all(|(i, c)| if i == 4 { *c == b'-' } else { c.is_ascii_hexdigit() && !c.is_ascii_uppercase() })
    }

    /// "{xxxxxxxx-xxxx-xxxx-...}": the part of the token the binary knows, for messages; also
    /// what identifies the FMU in its serialized FMU states.
    pub fn shown(&self) -> &str {
        &self.shown
    }
}

/// The attributes of `fmiModelDescription` after its name and token, which both versions share:
/// description, the package's, generationTool, generationDateAndTime, and
/// variableNamingConvention="structured" where a name uses array indices or a hierarchy.
pub fn header_attributes<M: Model>(table: &VariableTable, package: &Package) -> Vec<(&'static str, String)> {
    let mut header = vec![("description", M::info().description.to_string())];
    header.extend(package.attributes());
    header.push(("generationTool", format!("fmu-runtime {}", env!("CARGO_PKG_VERSION"))));
    if let Some(date) = package.generation_date_and_time() {
        header.push(("generationDateAndTime", date));
    }
    if table.structured_names() {
        header.push(("variableNamingConvention", "structured".to_string()));
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
    open(w, "UnitDefinitions", NO_ATTRIBUTES);
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
    open(w, "LogCategories", NO_ATTRIBUTES);
    for (name, description) in CATEGORIES {
        empty(w, "Category", &[("name", name.to_string()), ("description", description.to_string())]);
    }
    close(w, "LogCategories");
}

/// The DefaultExperiment: the model's own, with the tolerance it is made for at its default
/// parameters (`default_floor`: `model::default_tolerance_floor`).
pub fn write_default_experiment<M: Model>(w: &mut Xml, default_floor: Option<f64>) {
    let e = M::info().default_experiment;
    empty(
        w,
        "DefaultExperiment",
        &[
            ("startTime", real_text(e.start_time)),
            ("stopTime", real_text(e.stop_time)),
            ("tolerance", real_text(crate::integrate::declared_tolerance(default_floor))),
            ("stepSize", real_text(e.step_size)),
        ],
    );
}

/// The attributes every variable element starts with, in both standards: name, valueReference,
/// description, causality, variability, initial (borrowed where they can be: a description
/// writes one or two elements per variable).
pub fn variable_attributes(v: &Variable) -> Vec<(&'static str, Cow<'_, str>)> {
    let mut a = Vec::with_capacity(12);
    a.push(("name", Cow::Borrowed(v.name.as_str())));
    a.push(("valueReference", Cow::Owned(v.value_reference.to_string())));
    if !v.description.is_empty() {
        a.push(("description", Cow::Borrowed(v.description.as_str())));
    }
    a.push(("causality", Cow::Borrowed(v.causality.as_str())));
    a.push(("variability", Cow::Borrowed(v.variability.as_str())));
    if let Some(i) = v.initial {
        a.push(("initial", Cow::Borrowed(i.as_str())));
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_token_s_first_half_is_what_instantiation_checks() {
        let (interface, other) = (interface_hash("<skeleton/>"), interface_hash("<another/>"));
        let token = token(interface, "<whole/>");
        assert_eq!(token.len(), 38);
        assert!(token.starts_with('{') && token.ends_with('}') && token.matches('-').count() == 4, "{token}");
        let check = TokenCheck::new(interface);
        assert!(check.accepts(&token));
        // Another whole description with the same skeleton (other dependency lists): another
        // token, still accepted (its dependencies are not what the binary checks).
        let relisted = super::token(interface, "<whole with other dependencies/>");
        assert_ne!(relisted, token);
        assert!(check.accepts(&relisted));
        // Another skeleton, a truncated token, upper case, no braces: refused.
        assert!(!check.accepts(&super::token(other, "<whole/>")));
        assert!(!check.accepts(&token[..37]));
        assert!(!check.accepts(&token.to_uppercase()));
        assert!(!check.accepts(&token[1..37]));
        assert!(!check.accepts(&format!("{}x}}", &token[..36])));
        assert_eq!(check.shown(), format!("{}...}}", &token[..20]));
    }
}
