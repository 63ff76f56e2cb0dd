//! `package-floors`: zips the two floor libraries into FMUs the host can load
//! (modelDescription.xml and binaries/<platform>/<modelIdentifier>.so; no documentation).
//! EmptyStep's description is the one fmu-runtime generated (read from the library, as
//! build-fmus does); NullStep, which has no runtime, gets the hand-written one below.

use std::ffi::CStr;
use std::io::Write;
use std::os::raw::c_char;
use std::path::Path;

use zip::write::SimpleFileOptions;

use crate::Args;

/// NullStep's modelDescription.xml: one output `y` (what its fmi2GetReal writes: 0).
const NULL_STEP_DESCRIPTION: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="NullStep" guid="{00000000-0000-0000-0000-000000000001}"
  description="Benchmark floor without a runtime: fmi2DoStep returns fmi2OK at once" numberOfEventIndicators="0">
  <CoSimulation modelIdentifier="NullStep" canHandleVariableCommunicationStepSize="true"/>
  <DefaultExperiment startTime="0" stopTime="30" stepSize="0.001"/>
  <ModelVariables>
    <ScalarVariable name="y" valueReference="0" causality="output" variability="continuous"><Real/></ScalarVariable>
  </ModelVariables>
  <ModelStructure>
    <Outputs><Unknown index="1"/></Outputs>
  </ModelStructure>
</fmiModelDescription>
"#;

fn write_fmu(out: &Path, identifier: &str, description: &str, library: &Path) -> Result<(), String> {
    let binary = std::fs::read(library).map_err(|e| format!("{}: {e}", library.display()))?;
    let path = out.join(format!("{identifier}.fmu"));
    let file = std::fs::File::create(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut zip = zip::ZipWriter::new(file);
    let options = SimpleFileOptions::default();
    let (platform, ext) = fmi_host::fmu::platform();
    for (name, bytes) in [
        ("modelDescription.xml".to_string(), description.as_bytes()),
        (format!("binaries/{platform}/{identifier}.{ext}"), binary.as_slice()),
    ] {
        zip.start_file(name, options).map_err(|e| e.to_string())?;
        zip.write_all(bytes).map_err(|e| e.to_string())?;
    }
    zip.finish().map_err(|e| e.to_string())?;
    eprintln!("wrote {}", path.display());
    Ok(())
}

/// The modelDescription.xml that `fmu_runtime::export_fmu!` compiled into a library.
fn runtime_description(library: &Path) -> Result<String, String> {
    // SAFETY: a library built from this workspace with export_fmu!; the symbol returns a
    // NUL-terminated string that lives as long as the library, copied before it is unloaded.
    unsafe {
        let lib = libloading::Library::new(library).map_err(|e| format!("{}: {e}", library.display()))?;
        let f: libloading::Symbol<unsafe extern "C" fn() -> *const c_char> =
            lib.get(b"fmu_runtime_model_description").map_err(|e| e.to_string())?;
        Ok(CStr::from_ptr(f()).to_string_lossy().into_owned())
    }
}

pub fn package(args: &Args) -> Result<(), String> {
    let out = args.path("--out")?;
    std::fs::create_dir_all(&out).map_err(|e| e.to_string())?;
    let empty = args.path("--empty-step")?;
    write_fmu(&out, "EmptyStep", &runtime_description(&empty)?, &empty)?;
    write_fmu(&out, "NullStep", NULL_STEP_DESCRIPTION, &args.path("--null-step")?)?;
    Ok(())
}
