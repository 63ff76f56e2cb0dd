//! The direct feedthrough of an FMU's outputs: `<ModelStructure><Outputs>` of
//! `modelDescription.xml` (the host's [`crate::ModelDescription`] does not keep it).

use std::collections::HashMap;

use quick_xml::events::{BytesStart, Event};
use quick_xml::{Reader, XmlVersion};

use crate::error::{Error, Result};
use crate::fmu::Fmu;

/// For each output (1-based variable index), the variables it depends on directly; `None` when
/// the `dependencies` attribute is absent (the output may depend on every known).
#[derive(Clone, Debug, Default)]
pub(crate) struct OutputDependencies {
    outputs: HashMap<u32, Option<Vec<u32>>>,
}

impl OutputDependencies {
    /// Reads `modelDescription.xml` of the unpacked FMU.
    pub(crate) fn of(fmu: &Fmu) -> Result<OutputDependencies> {
        let path = fmu.unpacked_dir().join("modelDescription.xml");
        let xml = std::fs::read_to_string(&path).map_err(|source| Error::Io { path, source })?;
        OutputDependencies::parse(&xml)
    }

    pub(crate) fn parse(xml: &str) -> Result<OutputDependencies> {
        let mut reader = Reader::from_str(xml);
        let mut stack: Vec<String> = Vec::new();
        let mut deps = OutputDependencies::default();
        loop {
            let event = reader.read_event().map_err(|err| Error::Xml {
                position: reader.error_position(),
                message: err.to_string(),
            })?;
            match event {
                Event::Start(e) => {
                    deps.element(&stack, &e)?;
                    stack.push(e.name().as_ref().to_owned());
                }
                Event::Empty(e) => deps.element(&stack, &e)?,
                Event::End(_) => {
                    stack.pop();
                }
                Event::Eof => break,
                _ => {}
            }
        }
        Ok(deps)
    }

    fn element(&mut self, stack: &[String], e: &BytesStart<'_>) -> Result<()> {
        let in_outputs = stack.len() >= 2
            && stack[stack.len() - 2] == "ModelStructure"
            && stack[stack.len() - 1] == "Outputs";
        if !in_outputs || e.name().as_ref() != "Unknown" {
            return Ok(());
        }
        let (mut index, mut dependencies) = (None, None);
        for attr in e.attributes() {
            let attr = attr.map_err(|err| Error::ModelDescription(err.to_string()))?;
            let value = attr
                .normalized_value(XmlVersion::Implicit1_0)
                .map_err(|err| Error::ModelDescription(err.to_string()))?;
            match attr.key.as_ref() {
                "index" => index = Some(parse_index(&value)?),
                "dependencies" => {
                    dependencies = Some(
                        value
                            .split_whitespace()
                            .map(parse_index)
                            .collect::<Result<Vec<u32>>>()?,
                    )
                }
                _ => {}
            }
        }
        let index = index.ok_or_else(|| {
            Error::ModelDescription("<ModelStructure><Outputs><Unknown> has no index".into())
        })?;
        self.outputs.insert(index, dependencies);
        Ok(())
    }

    /// Whether output `output` (1-based variable index) depends directly on variable `known`
    /// (1-based). An output the structure does not list, or lists without `dependencies`, is
    /// taken to depend on everything (the safe answer).
    pub(crate) fn depends_on(&self, output: u32, known: u32) -> bool {
        match self.outputs.get(&output) {
            Some(Some(list)) => list.contains(&known),
            _ => true,
        }
    }
}

fn parse_index(text: &str) -> Result<u32> {
    text.trim().parse().map_err(|_| {
        Error::ModelDescription(format!("ModelStructure index {text:?} is not a number"))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_output_dependencies() {
        let xml = r#"<fmiModelDescription><ModelVariables/><ModelStructure>
            <Outputs><Unknown index="3" dependencies="1 2"/><Unknown index="4" dependencies=""/>
            <Unknown index="5"/></Outputs>
            <Derivatives><Unknown index="7" dependencies="1"/></Derivatives>
            </ModelStructure></fmiModelDescription>"#;
        let d = OutputDependencies::parse(xml).unwrap();
        assert!(d.depends_on(3, 1) && d.depends_on(3, 2) && !d.depends_on(3, 6));
        assert!(!d.depends_on(4, 1), "empty list: no dependency");
        assert!(d.depends_on(5, 1), "no attribute: depends on everything");
        assert!(
            d.depends_on(7, 2),
            "a derivative is not an output: conservative answer"
        );
    }
}
