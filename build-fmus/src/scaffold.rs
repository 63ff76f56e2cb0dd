//! `build-fmus new <Name> [--path DIR]`: a new model crate, ready to edit and to build.
//!
//! The crate is standalone (its own `[workspace]`), so it can live anywhere, inside this
//! repository or outside it. It depends on this repository's `fmu-runtime` and `components` by
//! path, carries the same release profile as the workspace (panics unwind to the C boundary),
//! and starts with a complete, valid model — a first-order lag from an input to an output —
//! that the user replaces with their physics. Its test loads the FMU that `build-fmus build`
//! packages and steps it.

use std::fs;
use std::path::{Path, PathBuf};

/// What `new` writes: (path relative to the crate, contents).
pub fn files(name: &str, repository: &Path) -> Result<Vec<(PathBuf, String)>, String> {
    validate_name(name)?;
    let package = kebab(name);
    let lib = package.replace('-', "_");
    let repo = repository.display().to_string().replace('\\', "/");
    let cargo_toml = format!(
        r#"[package]
name = "{package}"
description = "{name} FMU"
edition = "2021"
version = "0.1.0"
publish = false

[lib]
name = "{lib}"
crate-type = ["cdylib", "rlib"]

[dependencies]
fmu-runtime = {{ path = "{repo}/fmu-runtime" }}
components = {{ path = "{repo}/models/components" }}

[dev-dependencies]
fmi-host = {{ path = "{repo}/tests" }}

# A standalone crate: build it with `build-fmus build <this directory>`.
[workspace]

# As in the FMU workspace: panics unwind to the C boundary, where they become fmi2Fatal.
[profile.release]
panic = "unwind"
opt-level = 3
debug = false
codegen-units = 4
"#
    );
    let model = format!(
        r#"//! {name}: describe the model and cite the equations it comes from.
//!
//! Start: a first-order lag, tau dy/dt = u - y. Replace it with your physics, composed from
//! `components` (inertias, springs, machines, thermal nodes, reluctances).

use fmu_runtime::prelude::*;

pub struct {name} {{
    tau: Parameter,
    u: Input,
    x: State,
    y: Output,
}}

impl Model for {name} {{
    fn info() -> ModelInfo {{
        ModelInfo {{
            name: "{name}",
            description: "A first-order lag (replace with your model's one-sentence description)",
            default_experiment: DefaultExperiment {{ start_time: 0.0, stop_time: 5.0, step_size: 0.01 }},
            solver: Solver::ExplicitRungeKutta,
            documentation: "<p>tau dy/dt = u - y</p>",
        }}
    }}

    fn declare(d: &mut Declarations) -> Self {{
        {name} {{
            tau: d.parameter("tau", 1.0, "s").positive().describe("Time constant"),
            u: d.input("u", 1.0, "1").describe("Input"),
            x: d.state("x", 0.0, "1").describe("State of the lag"),
            y: d.output("y", "1").describe("Output, the lagged input"),
        }}
    }}

    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {{
        der[self.x] = (k[self.u] - k[self.x]) / k[self.tau];
    }}

    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {{
        out[self.y] = k[self.x];
    }}
}}

fmu_runtime::export_fmu!({name});
"#
    );
    let test = format!(
        r#"//! Loads the FMU that `build-fmus build` packaged into dist/ and steps it as a master would.

use fmi_host::{{Causality, Fmu, Status, VariableType}};

#[test]
fn the_packaged_fmu_steps() {{
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("dist/{name}.fmu");
    let fmu = Fmu::load(&path).unwrap_or_else(|e| panic!("{{}}: {{e}} (run `build-fmus build .` first)", path.display()));
    let outputs: Vec<u32> = fmu
        .model_description()
        .model_variables
        .iter()
        .filter(|v| v.causality == Causality::Output && v.variable_type == VariableType::Real)
        .map(|v| v.value_reference)
        .collect();
    let mut inst = fmu.instantiate("test", false, false).expect("instantiate");
    assert_eq!(inst.setup_experiment(None, 0.0, None), Status::OK);
    assert_eq!(inst.enter_initialization_mode(), Status::OK);
    assert_eq!(inst.exit_initialization_mode(), Status::OK);
    for k in 0..100 {{
        assert_eq!(inst.do_step(k as f64 * 0.01, 0.01, true), Status::OK);
    }}
    let (status, y) = inst.get_reals(&outputs);
    assert_eq!(status, Status::OK);
    assert!(y.iter().all(|v| v.is_finite()), "{{y:?}}");
}}
"#
    );
    let readme = format!(
        "# {name}\n\nAn FMU made with the lumped-parameter FMU generator ({repo}).\n\n```sh\n\
         build-fmus build .        # writes dist/{name}.fmu (build-fmus: {repo}/target/release/build-fmus)\n\
         cargo test --release      # loads and steps dist/{name}.fmu\n```\n"
    );
    Ok(vec![
        (PathBuf::from("Cargo.toml"), cargo_toml),
        (PathBuf::from("src/lib.rs"), model),
        (PathBuf::from("tests/fmu.rs"), test),
        (PathBuf::from("README.md"), readme),
        (PathBuf::from(".gitignore"), "/target\n/dist\n".to_string()),
    ])
}

/// Writes the crate into `<parent>/<package>`; refuses to overwrite an existing directory.
pub fn create(name: &str, parent: &Path, repository: &Path) -> Result<PathBuf, String> {
    let dir = parent.join(kebab(name));
    if dir.exists() {
        return Err(format!("{} already exists: choose another name or --path", dir.display()));
    }
    for (rel, text) in files(name, repository)? {
        let path = dir.join(rel);
        if let Some(p) = path.parent() {
            fs::create_dir_all(p).map_err(|e| format!("could not create {}: {e}", p.display()))?;
        }
        fs::write(&path, text).map_err(|e| format!("could not write {}: {e}", path.display()))?;
    }
    // The repository's lock file pins the same dependency versions, so a build sharing its
    // target directory reuses the compiled dependencies.
    let lock = repository.join("Cargo.lock");
    if lock.is_file() {
        fs::copy(&lock, dir.join("Cargo.lock")).map_err(|e| format!("could not copy {}: {e}", lock.display()))?;
    }
    Ok(dir)
}

/// A model name is its modelIdentifier and a Rust type name: UpperCamelCase ASCII.
pub fn validate_name(name: &str) -> Result<(), String> {
    let ok = name.chars().next().is_some_and(|c| c.is_ascii_uppercase()) && name.chars().all(|c| c.is_ascii_alphanumeric());
    if ok {
        Ok(())
    } else {
        Err(format!("'{name}' is not a model name: use UpperCamelCase letters and digits, e.g. ElevatorDrive"))
    }
}

/// `ElevatorDrive` -> `elevator-drive`.
pub fn kebab(name: &str) -> String {
    let mut out = String::new();
    for (i, c) in name.chars().enumerate() {
        if c.is_ascii_uppercase() && i > 0 {
            out.push('-');
        }
        out.push(c.to_ascii_lowercase());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::TempDir;

    #[test]
    fn names_become_packages_and_bad_names_are_refused() {
        assert_eq!(kebab("ElevatorDrive"), "elevator-drive");
        assert_eq!(kebab("Rlc2"), "rlc2");
        assert!(validate_name("ElevatorDrive").is_ok());
        for bad in ["elevator", "Elevator Drive", "", "Élan", "Drive-2"] {
            assert!(validate_name(bad).unwrap_err().contains("UpperCamelCase"), "{bad}");
        }
    }

    #[test]
    fn a_new_crate_is_complete_standalone_and_not_overwritten() {
        let tmp = TempDir::new("scaffold");
        let repo = Path::new("/opt/fmu-generator");
        let dir = create("ElevatorDrive", tmp.path(), repo).unwrap();
        assert_eq!(dir, tmp.path().join("elevator-drive"));
        let manifest = fs::read_to_string(dir.join("Cargo.toml")).unwrap();
        assert!(manifest.contains("name = \"elevator-drive\"") && manifest.contains("name = \"elevator_drive\""));
        assert!(manifest.contains("fmu-runtime = { path = \"/opt/fmu-generator/fmu-runtime\" }"));
        assert!(manifest.contains("\n[workspace]\n") && manifest.contains("panic = \"unwind\""));
        let model = fs::read_to_string(dir.join("src/lib.rs")).unwrap();
        assert!(model.contains("pub struct ElevatorDrive") && model.contains("fmu_runtime::export_fmu!(ElevatorDrive);"));
        assert!(!model.contains("unsafe"), "a model speaks physics only");
        assert!(fs::read_to_string(dir.join("tests/fmu.rs")).unwrap().contains("dist/ElevatorDrive.fmu"));
        let again = create("ElevatorDrive", tmp.path(), repo).unwrap_err();
        assert!(again.contains("already exists"), "{again}");
    }
}
