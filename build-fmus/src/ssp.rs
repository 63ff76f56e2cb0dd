//! Writing a checked [`System`] as an SSP 1.0 archive (`<Name>.ssp`):
//!
//! ```text
//! SystemStructure.ssd          the system: components, their connectors, connections
//! resources/<Identifier>.fmu   each FMU the components use, once
//! ```
//!
//! The SSD uses the SSP 1.0 namespaces (`http://ssp-standard.org/SSP1/...`), which is what
//! fmpy's SSP runner (0.3.32) reads, with the prefixes `ssd:`, `ssc:` and `ssv:` exactly (ecos
//! looks elements up by prefixed name, not by namespace); it is written with quick-xml.
//!
//! Parameter values become an inline `ssv:ParameterSet` in each component's
//! `ssd:ParameterBindings`, all named [`PARAMETER_SET`]. libcosim applies them as they are;
//! ecos groups the sets of all components by name and applies one only when asked
//! (`EcosSimulation.init(parameter_set="initialValues")`); fmpy 0.3.32 reads them but applies
//! only its `parameter_set` argument.
//!
//! The archive is deterministic like the FMUs (fixed dates and permissions) and written
//! through a temporary file renamed into place.

use std::fs;
use std::io::{Cursor, Write};
use std::path::Path;

use quick_xml::events::{BytesDecl, BytesEnd, BytesStart, Event};
use quick_xml::Writer;
use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, DateTime, ZipWriter};

use crate::systems::{System, Value};

pub const SSD: &str = "http://ssp-standard.org/SSP1/SystemStructureDescription";
pub const SSC: &str = "http://ssp-standard.org/SSP1/SystemStructureCommon";
pub const SSV: &str = "http://ssp-standard.org/SSP1/SystemStructureParameterValues";

/// The name of every component's parameter set (one name: ecos applies sets by name).
pub const PARAMETER_SET: &str = "initialValues";

/// The name of the description inside the archive.
pub const SSD_ENTRY: &str = "SystemStructure.ssd";

type Xml = Writer<Vec<u8>>;

fn start<'a>(name: &'a str, attrs: &[(&str, &str)]) -> BytesStart<'a> {
    let mut e = BytesStart::new(name);
    for (k, v) in attrs {
        e.push_attribute((*k, *v));
    }
    e
}

fn open(w: &mut Xml, name: &str, attrs: &[(&str, &str)]) {
    w.write_event(Event::Start(start(name, attrs)))
        .expect("writing to memory");
}

fn empty(w: &mut Xml, name: &str, attrs: &[(&str, &str)]) {
    w.write_event(Event::Empty(start(name, attrs)))
        .expect("writing to memory");
}

fn close(w: &mut Xml, name: &str) {
    w.write_event(Event::End(BytesEnd::new(name)))
        .expect("writing to memory");
}

/// A real as XML text: the shortest text that reads back as the same f64.
fn real(x: f64) -> String {
    format!("{x:?}")
}

/// The `SystemStructure.ssd` of a system.
pub fn ssd_xml(system: &System) -> String {
    let mut w = Writer::new_with_indent(Vec::new(), b' ', 2);
    w.write_event(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None)))
        .expect("writing to memory");
    let tool = format!("build-fmus {}", env!("CARGO_PKG_VERSION"));
    let mut root = vec![
        ("xmlns:ssd", SSD),
        ("xmlns:ssc", SSC),
        ("xmlns:ssv", SSV),
        ("version", "1.0"),
        ("name", system.name.as_str()),
        ("generationTool", tool.as_str()),
    ];
    if let Some(d) = &system.description {
        root.push(("description", d.as_str()));
    }
    open(&mut w, "ssd:SystemStructureDescription", &root);

    let mut sys = vec![("name", system.name.as_str())];
    if let Some(d) = &system.description {
        sys.push(("description", d.as_str()));
    }
    open(&mut w, "ssd:System", &sys);
    open(&mut w, "ssd:Elements", &[]);
    for c in &system.components {
        let source = c.source();
        open(
            &mut w,
            "ssd:Component",
            &[
                ("name", c.name.as_str()),
                ("type", "application/x-fmu-sharedlibrary"),
                ("source", source.as_str()),
            ],
        );
        if !c.connectors.is_empty() {
            open(&mut w, "ssd:Connectors", &[]);
            for k in &c.connectors {
                open(
                    &mut w,
                    "ssd:Connector",
                    &[("name", k.name.as_str()), ("kind", k.kind.name())],
                );
                let ty = format!("ssc:{}", k.var_type.name());
                match &k.unit {
                    Some(u) => empty(&mut w, &ty, &[("unit", u.as_str())]),
                    None => empty(&mut w, &ty, &[]),
                }
                close(&mut w, "ssd:Connector");
            }
            close(&mut w, "ssd:Connectors");
        }
        if !c.parameters.is_empty() {
            open(&mut w, "ssd:ParameterBindings", &[]);
            open(&mut w, "ssd:ParameterBinding", &[]);
            open(&mut w, "ssd:ParameterValues", &[]);
            open(
                &mut w,
                "ssv:ParameterSet",
                &[("version", "1.0"), ("name", PARAMETER_SET)],
            );
            open(&mut w, "ssv:Parameters", &[]);
            for (name, ty, value) in &c.parameters {
                open(&mut w, "ssv:Parameter", &[("name", name.as_str())]);
                let text = match value {
                    Value::Real(x) => real(*x),
                    Value::Integer(i) => i.to_string(),
                    Value::Boolean(b) => b.to_string(),
                    Value::String(s) => s.clone(),
                };
                empty(
                    &mut w,
                    &format!("ssv:{}", ty.name()),
                    &[("value", text.as_str())],
                );
                close(&mut w, "ssv:Parameter");
            }
            close(&mut w, "ssv:Parameters");
            close(&mut w, "ssv:ParameterSet");
            close(&mut w, "ssd:ParameterValues");
            close(&mut w, "ssd:ParameterBinding");
            close(&mut w, "ssd:ParameterBindings");
        }
        close(&mut w, "ssd:Component");
    }
    close(&mut w, "ssd:Elements");
    if !system.connections.is_empty() {
        open(&mut w, "ssd:Connections", &[]);
        for (from, to) in &system.connections {
            empty(
                &mut w,
                "ssd:Connection",
                &[
                    ("startElement", from.instance.as_str()),
                    ("startConnector", from.variable.as_str()),
                    ("endElement", to.instance.as_str()),
                    ("endConnector", to.variable.as_str()),
                ],
            );
        }
        close(&mut w, "ssd:Connections");
    }
    close(&mut w, "ssd:System");

    if !system.units.is_empty() {
        open(&mut w, "ssd:Units", &[]);
        for u in &system.units {
            open(&mut w, "ssc:Unit", &[("name", u.name.as_str())]);
            // Always a BaseUnit (SSP requires one; fmpy's reader fails without it).
            let base: Vec<(&str, &str)> = u
                .base_unit
                .iter()
                .map(|(k, v)| (k.as_str(), v.as_str()))
                .collect();
            empty(&mut w, "ssc:BaseUnit", &base);
            close(&mut w, "ssc:Unit");
        }
        close(&mut w, "ssd:Units");
    }
    if system.start_time.is_some() || system.stop_time.is_some() {
        let (t0, t1) = (system.start_time.map(real), system.stop_time.map(real));
        let mut attrs = Vec::new();
        if let Some(t) = &t0 {
            attrs.push(("startTime", t.as_str()));
        }
        if let Some(t) = &t1 {
            attrs.push(("stopTime", t.as_str()));
        }
        empty(&mut w, "ssd:DefaultExperiment", &attrs);
    }
    close(&mut w, "ssd:SystemStructureDescription");
    let mut xml = String::from_utf8(w.into_inner()).expect("quick-xml writes UTF-8");
    xml.push('\n');
    xml
}

/// The archive's bytes: the SSD, then `fmus` as `resources/<identifier>.fmu` (stored, not
/// deflated again: an FMU is a zip already).
pub fn ssp_bytes(ssd: &str, fmus: &[(&str, &[u8])]) -> Result<Vec<u8>, String> {
    let zip_err = |e: zip::result::ZipError| format!("could not write the zip archive: {e}");
    let io_err = |e: std::io::Error| format!("could not write the zip archive: {e}");
    let base = SimpleFileOptions::default()
        .last_modified_time(DateTime::default())
        .system(zip::System::Unix)
        .unix_permissions(0o644);
    let mut zip = ZipWriter::new(Cursor::new(Vec::new()));
    zip.start_file(
        SSD_ENTRY,
        base.compression_method(CompressionMethod::Deflated)
            .compression_level(Some(9)),
    )
    .map_err(zip_err)?;
    zip.write_all(ssd.as_bytes()).map_err(io_err)?;
    for (identifier, bytes) in fmus {
        zip.start_file(
            format!("resources/{identifier}.fmu"),
            base.compression_method(CompressionMethod::Stored),
        )
        .map_err(zip_err)?;
        zip.write_all(bytes).map_err(io_err)?;
    }
    Ok(zip.finish().map_err(zip_err)?.into_inner())
}

/// Writes `<out_dir>/<name>.ssp` for a checked system, reading each FMU from
/// `<out_dir>/<identifier>.fmu`; returns the path's size in bytes.
pub fn write_ssp(path: &Path, system: &System, fmu_dir: &Path) -> Result<u64, String> {
    let mut identifiers: Vec<&str> = Vec::new();
    for c in &system.components {
        if !identifiers.contains(&c.fmu.as_str()) {
            identifiers.push(&c.fmu);
        }
    }
    let mut fmus = Vec::new();
    for id in &identifiers {
        let p = fmu_dir.join(format!("{id}.fmu"));
        let bytes = fs::read(&p).map_err(|e| format!("could not read {}: {e}", p.display()))?;
        fmus.push((*id, bytes));
    }
    let refs: Vec<(&str, &[u8])> = fmus.iter().map(|(i, b)| (*i, b.as_slice())).collect();
    let bytes = ssp_bytes(&ssd_xml(system), &refs)?;
    crate::package::write_atomically(path, &bytes)?;
    Ok(bytes.len() as u64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::systems::tests::system;
    use quick_xml::{Reader, XmlVersion};
    use std::io::Read;

    /// (depth, element name, attributes) of one element.
    type Element = (usize, String, Vec<(String, String)>);

    /// Every element, in document order.
    fn elements(xml: &str) -> Vec<Element> {
        let mut reader = Reader::from_str(xml);
        let mut depth = 0;
        let mut out = Vec::new();
        loop {
            let ev = reader.read_event().expect("well-formed");
            let (e, empty) = match ev {
                Event::Start(e) => (e, false),
                Event::Empty(e) => (e, true),
                Event::End(_) => {
                    depth -= 1;
                    continue;
                }
                Event::Eof => break,
                _ => continue,
            };
            let attrs = e
                .attributes()
                .map(|a| {
                    let a = a.unwrap();
                    (
                        a.key.as_ref().to_owned(),
                        a.normalized_value(XmlVersion::Implicit1_0)
                            .unwrap()
                            .into_owned(),
                    )
                })
                .collect();
            out.push((depth, e.name().as_ref().to_owned(), attrs));
            if !empty {
                depth += 1;
            }
        }
        out
    }

    fn attr<'a>(attrs: &'a [(String, String)], key: &str) -> Option<&'a str> {
        attrs
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    #[test]
    fn the_ssd_has_the_ssp_1_0_structure() {
        let xml = ssd_xml(&system());
        assert!(
            xml.starts_with("<?xml version=\"1.0\" encoding=\"UTF-8\"?>"),
            "{xml}"
        );
        let els = elements(&xml);
        let (d, root, attrs) = &els[0];
        assert_eq!((*d, root.as_str()), (0, "ssd:SystemStructureDescription"));
        assert_eq!(attr(attrs, "xmlns:ssd"), Some(SSD));
        assert_eq!(attr(attrs, "xmlns:ssc"), Some(SSC));
        assert_eq!(attr(attrs, "xmlns:ssv"), Some(SSV));
        assert_eq!(attr(attrs, "version"), Some("1.0"));
        assert_eq!(attr(attrs, "name"), Some("Demo"));
        // Escaped on writing, read back intact.
        assert_eq!(attr(attrs, "description"), Some("Two inertias & a shaft"));
        assert!(xml.contains("Two inertias &amp; a shaft"));

        // The top-level order the schema prescribes: System, Units, DefaultExperiment.
        let top: Vec<&str> = els
            .iter()
            .filter(|e| e.0 == 1)
            .map(|e| e.1.as_str())
            .collect();
        assert_eq!(top, ["ssd:System", "ssd:Units", "ssd:DefaultExperiment"]);
        let units_at = els.iter().position(|e| e.1 == "ssd:Units").unwrap();
        let in_system: Vec<&str> = els[..units_at]
            .iter()
            .filter(|e| e.0 == 2)
            .map(|e| e.1.as_str())
            .collect();
        assert_eq!(in_system, ["ssd:Elements", "ssd:Connections"]);

        let components: Vec<(&str, &str, &str)> = els
            .iter()
            .filter(|e| e.1 == "ssd:Component")
            .map(|e| {
                (
                    attr(&e.2, "name").unwrap(),
                    attr(&e.2, "type").unwrap(),
                    attr(&e.2, "source").unwrap(),
                )
            })
            .collect();
        assert_eq!(
            components,
            [
                (
                    "motor",
                    "application/x-fmu-sharedlibrary",
                    "resources/Inertia.fmu"
                ),
                (
                    "shaft",
                    "application/x-fmu-sharedlibrary",
                    "resources/Shaft.fmu"
                ),
                (
                    "fan",
                    "application/x-fmu-sharedlibrary",
                    "resources/Inertia.fmu"
                ),
            ]
        );
        // Connectors: name, kind, and the type element with its unit right inside.
        let i = els.iter().position(|e| e.1 == "ssd:Connector").unwrap();
        assert_eq!(attr(&els[i].2, "name"), Some("load"));
        assert_eq!(attr(&els[i].2, "kind"), Some("input"));
        assert_eq!(els[i + 1].1, "ssc:Real");
        assert_eq!(els[i + 1].0, els[i].0 + 1);
        assert_eq!(attr(&els[i + 1].2, "unit"), Some("N.m"));
        assert!(
            xml.contains("<ssd:Connector name=\"on\" kind=\"output\">\n            <ssc:Boolean/>"),
            "{xml}"
        );

        let connections: Vec<String> = els
            .iter()
            .filter(|e| e.1 == "ssd:Connection")
            .map(|e| {
                format!(
                    "{}.{} -> {}.{}",
                    attr(&e.2, "startElement").unwrap(),
                    attr(&e.2, "startConnector").unwrap(),
                    attr(&e.2, "endElement").unwrap(),
                    attr(&e.2, "endConnector").unwrap()
                )
            })
            .collect();
        assert_eq!(
            connections,
            [
                "motor.speed -> shaft.speed_a",
                "fan.speed -> shaft.speed_b",
                "shaft.torque -> motor.load",
                "shaft.torque -> fan.load"
            ]
        );

        // Units: each once, with its BaseUnit.
        let units: Vec<(&str, &[(String, String)])> = els
            .windows(2)
            .filter(|w| w[0].1 == "ssc:Unit")
            .map(|w| {
                assert_eq!(w[1].1, "ssc:BaseUnit");
                (attr(&w[0].2, "name").unwrap(), w[1].2.as_slice())
            })
            .collect();
        assert_eq!(units.len(), 2);
        assert_eq!(units[1].0, "rad/s");
        assert_eq!(attr(units[1].1, "s"), Some("-1"));
        assert_eq!(attr(units[1].1, "rad"), Some("1"));

        let exp = els.iter().find(|e| e.1 == "ssd:DefaultExperiment").unwrap();
        assert_eq!(attr(&exp.2, "startTime"), Some("0.0"));
        assert_eq!(attr(&exp.2, "stopTime"), Some("30.0"));
    }

    #[test]
    fn parameters_become_inline_parameter_sets() {
        let xml = ssd_xml(&system());
        let els = elements(&xml);
        let path: Vec<&str> = els
            .iter()
            .skip_while(|e| e.1 != "ssd:ParameterBindings")
            .take(7)
            .map(|e| e.1.as_str())
            .collect();
        assert_eq!(
            path,
            [
                "ssd:ParameterBindings",
                "ssd:ParameterBinding",
                "ssd:ParameterValues",
                "ssv:ParameterSet",
                "ssv:Parameters",
                "ssv:Parameter",
                "ssv:Integer"
            ]
        );
        let params: Vec<(String, String, String)> = els
            .windows(2)
            .filter(|w| w[0].1 == "ssv:Parameter")
            .map(|w| {
                (
                    attr(&w[0].2, "name").unwrap().to_owned(),
                    w[1].1.clone(),
                    attr(&w[1].2, "value").unwrap().to_owned(),
                )
            })
            .collect();
        assert_eq!(
            params,
            [
                ("drive".into(), "ssv:Integer".into(), "1".into()),
                ("K".into(), "ssv:Real".into(), "900.0".into())
            ]
        );
        let set = els.iter().find(|e| e.1 == "ssv:ParameterSet").unwrap();
        assert_eq!(attr(&set.2, "version"), Some("1.0"));
        assert_eq!(attr(&set.2, "name"), Some(PARAMETER_SET));
        // The binding sits after the connectors, inside the component (schema order).
        let motor = xml.split("<ssd:Component").nth(1).unwrap();
        assert!(
            motor.find("<ssd:Connectors>").unwrap()
                < motor.find("<ssd:ParameterBindings>").unwrap()
        );
    }

    #[test]
    fn a_system_without_units_times_or_connections_leaves_them_out() {
        let mut s = system();
        s.units.clear();
        s.connections.clear();
        s.start_time = None;
        s.stop_time = None;
        s.description = None;
        let xml = ssd_xml(&s);
        for absent in [
            "ssd:Units",
            "ssd:Connections",
            "ssd:DefaultExperiment",
            "description=",
        ] {
            assert!(!xml.contains(absent), "{absent} in {xml}");
        }
    }

    #[test]
    fn the_archive_holds_the_ssd_and_each_fmu_once() {
        let tmp = crate::testutil::TempDir::new("ssp");
        fs::write(tmp.path().join("Inertia.fmu"), b"PK inertia").unwrap();
        fs::write(tmp.path().join("Shaft.fmu"), b"PK shaft").unwrap();
        let path = tmp.path().join("Demo.ssp");
        let size = write_ssp(&path, &system(), tmp.path()).unwrap();
        assert_eq!(size, fs::metadata(&path).unwrap().len());
        let first = fs::read(&path).unwrap();

        let mut zip = zip::ZipArchive::new(fs::File::open(&path).unwrap()).unwrap();
        let names: Vec<String> = (0..zip.len())
            .map(|i| zip.by_index(i).unwrap().name().unwrap().to_string())
            .collect();
        assert_eq!(
            names,
            [
                "SystemStructure.ssd",
                "resources/Inertia.fmu",
                "resources/Shaft.fmu"
            ]
        );
        let mut ssd = String::new();
        zip.by_name("SystemStructure.ssd")
            .unwrap()
            .read_to_string(&mut ssd)
            .unwrap();
        assert_eq!(ssd, ssd_xml(&system()));
        let mut fmu = Vec::new();
        let mut entry = zip.by_name("resources/Shaft.fmu").unwrap();
        assert_eq!(entry.compression(), CompressionMethod::Stored);
        entry.read_to_end(&mut fmu).unwrap();
        assert_eq!(fmu, b"PK shaft");
        drop(entry);

        // Deterministic: the same inputs give the same bytes.
        write_ssp(&path, &system(), tmp.path()).unwrap();
        assert_eq!(fs::read(&path).unwrap(), first);
        // A missing FMU is named, and no archive is left half-written.
        fs::remove_file(tmp.path().join("Shaft.fmu")).unwrap();
        let other = tmp.path().join("Other.ssp");
        let err = write_ssp(&other, &system(), tmp.path()).unwrap_err();
        assert!(err.contains("Shaft.fmu"), "{err}");
        assert!(!other.exists());
    }
}
