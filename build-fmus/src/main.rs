//! `build-fmus`: builds every model crate of the workspace and packages each as
//! `dist/<ModelIdentifier>.fmu` (FMI 2.0 Co-Simulation).
//!
//! The steps, one module each:
//! 1. [`discover`]: find the workspace root and the model crates (members under `models/`
//!    whose `[lib] crate-type` has `cdylib`);
//! 2. [`toolchain`] and [`cargo`]: build all their libraries with one
//!    `cargo zigbuild --release --lib --target <triple>.2.17 -p ...` (zig and cargo-zigbuild,
//!    pinned, installed on first use), so they need glibc 2.17 at most, stripped; or with one
//!    plain `cargo build --release --lib -p ...` with `--host-build`;
//! 3. [`extract`]: load each library and copy out its modelIdentifier, modelDescription.xml
//!    and documentation page, which `fmu_runtime::export_fmu!` exports;
//! 4. [`package`]: zip them with the library into a deterministic `.fmu`, with the model's
//!    figures from `docs/figures/<ModelIdentifier>_*.png` ([`figures`]) in its documentation;
//! 5. [`systems`] and [`ssp`]: for each system declared in `models/systems/<Name>.toml`,
//!    check its components and connections against the FMUs' variables (each description read
//!    by `fmi_host::ModelDescription`, the tests' reader) and write `<Name>.ssp` (SSP 1.0:
//!    SystemStructure.ssd and the FMUs under resources/).
//!
//! Run it with `cargo run --release -p build-fmus` from anywhere in the workspace.

mod cargo;
mod discover;
mod extract;
mod figures;
mod icon;
mod package;
mod scaffold;
mod source_date;
mod ssp;
mod systems;
mod toolchain;

use std::collections::BTreeMap;
use std::ffi::OsString;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use discover::ModelCrate;

const USAGE: &str = "\
build-fmus: builds model crates and packages <out>/<ModelIdentifier>.fmu (FMI 2.0 CS and ME),
then <out>/<System>.ssp for each system declared in models/systems/<System>.toml

Usage: cargo run --release -p build-fmus [-- OPTIONS]          every model of the workspace
       build-fmus build <crate directory | model name> [OPTIONS]  one model, wherever it lives
       build-fmus new <ModelName> [--path DIR]                   a new model crate to edit
       build-fmus list                                           the workspace's model crates
       build-fmus effects <model name>                           its Table 3.1 and the activity
                                                                 table of its default experiment

Options:
  --out DIR          write the .fmu files to DIR (default: <workspace>/dist, or <crate>/dist
                     for `build <crate directory>` outside the workspace)
  --only NAME        package only this model: its package name (rlc-circuit) or its
                     modelIdentifier (RlcCircuit); repeat to select several
  --workspace DIR    the workspace root (default: the workspace this tool belongs to,
                     else the one around the current directory)
  --path DIR         with `new`: where the crate's directory is made (default: .)
  --host-build       build with a plain `cargo build` for this machine's glibc (unstripped,
                     into <target>/release), instead of the default glibc 2.17 build
  -h, --help         print this help and exit

A model crate is a crate whose [lib] crate-type has \"cdylib\" and whose src/lib.rs ends with
fmu_runtime::export_fmu!(<Model>): the workspace members under models/, or any crate made by
`build-fmus new` (standalone: its own [workspace], path dependencies on fmu-runtime and
components). Every model takes the same steps:
`cargo zigbuild --release --lib --target x86_64-unknown-linux-gnu.2.17`, which links the
library against glibc 2.17 so that it loads on every Linux since 2012, stripped of its symbol
table (zig and cargo-zigbuild at the versions of build-fmus/toolchain-requirements.txt are
installed from PyPI into <repository>/.build-tools/ on first use, with `python3 -m venv`;
$BUILD_FMUS_PYTHON and $BUILD_FMUS_TOOLS_DIR override both; --host-build skips this), the
library landing in <target>/x86_64-unknown-linux-gnu/release ($CARGO and $CARGO_TARGET_DIR
are honoured; a standalone crate builds into its own target/ unless CARGO_TARGET_DIR shares
one, which reuses the compiled dependencies), then its library is
loaded to read its modelDescription.xml, documentation and the problems its declarations have
(a model with problems is refused, each named with its file, line and fix), and zipped:
  modelDescription.xml, model.png (an icon drawn from the identifier),
  binaries/linux64/<ModelIdentifier>.so, documentation/index.html
with the figures <project>/docs/figures/<ModelIdentifier>_*.png as documentation/<file>.png.
Each FMU's generationDateAndTime is $SOURCE_DATE_EPOCH if set, else the date of the project's
last git commit (baked into the binary at compile time; without either, none).

A system (models/systems/<System>.toml: components, connections \"a.y -> b.u\" from an
output to an input, optional parameter values) is checked against the FMUs' variables and
written as an SSP 1.0 archive: SystemStructure.ssd and resources/<ModelIdentifier>.fmu.
With --only, a system is written only if all of its FMUs were selected.
";

/// What to do: build and package (the default), scaffold a new model crate, or list.
#[derive(Debug, Default, PartialEq, Eq)]
enum Command {
    /// Every model of the workspace (no argument), or `build <crate directory or name>`.
    #[default]
    BuildAll,
    Build(String),
    /// `new <Name>`: a model crate in `--path DIR` (default: the current directory).
    New(String),
    /// `list`: the model crates and systems this workspace can build.
    List,
    /// `effects <model>`: Table 3.1 and the activity table of its default experiment.
    Effects(String),
}

/// The parsed command line.
#[derive(Debug, Default, PartialEq, Eq)]
struct Options {
    command: Command,
    out: Option<PathBuf>,
    only: Vec<String>,
    workspace: Option<PathBuf>,
    path: Option<PathBuf>,
    host_build: bool,
    help: bool,
}

/// Parses the arguments after the program name. `--opt VALUE` and `--opt=VALUE` both work.
fn parse_args(args: impl IntoIterator<Item = OsString>) -> Result<Options, String> {
    let mut opts = Options::default();
    let mut args = args.into_iter();
    while let Some(arg) = args.next() {
        let text = arg
            .to_str()
            .ok_or_else(|| format!("argument {arg:?} is not UTF-8"))?
            .to_owned();
        let (flag, inline) = match text.split_once('=') {
            Some((f, v)) if f.starts_with("--") => (f.to_owned(), Some(OsString::from(v))),
            _ => (text.clone(), None),
        };
        let mut value = |name: &str| -> Result<OsString, String> {
            inline
                .clone()
                .or_else(|| args.next())
                .filter(|v| !v.is_empty())
                .ok_or_else(|| format!("{name} needs a value"))
        };
        match flag.as_str() {
            "build" if opts.command == Command::BuildAll => {
                let target = args.next().and_then(|n| n.into_string().ok()).filter(|n| !n.is_empty() && !n.starts_with("--"));
                opts.command = Command::Build(target.ok_or("build needs a model crate's directory or a model's name, e.g. `build ./elevator-drive` or `build MotorFan`")?);
            }
            "new" if opts.command == Command::BuildAll => {
                let name = args.next().and_then(|n| n.into_string().ok()).filter(|n| !n.is_empty());
                opts.command = Command::New(name.ok_or("new needs a model name, e.g. `new ElevatorDrive`")?);
            }
            "list" if opts.command == Command::BuildAll => opts.command = Command::List,
            "effects" if opts.command == Command::BuildAll => {
                let name = args.next().and_then(|n| n.into_string().ok()).filter(|n| !n.is_empty() && !n.starts_with("--"));
                opts.command = Command::Effects(name.ok_or("effects needs a model's name or package, e.g. `effects MotorFan`")?);
            }
            "--path" => opts.path = Some(value("--path")?.into()),
            "-h" | "--help" => opts.help = true,
            "--host-build" => opts.host_build = true,
            "--out" => opts.out = Some(value("--out")?.into()),
            "--workspace" => opts.workspace = Some(value("--workspace")?.into()),
            "--only" => {
                let name = value("--only")?;
                let name = name
                    .into_string()
                    .map_err(|n| format!("--only {n:?} is not UTF-8"))?;
                opts.only.push(name);
            }
            _ => return Err(format!("unknown argument `{text}`")),
        }
    }
    Ok(opts)
}

/// Names compared loosely: case, `-` and `_` do not matter, so `rlc-circuit`,
/// `rlc_circuit` and `RlcCircuit` are one name.
fn loose(name: &str) -> String {
    name.chars()
        .filter(|c| *c != '-' && *c != '_')
        .flat_map(char::to_lowercase)
        .collect()
}

/// Which models `--only` selects before anything is built.
struct Selection {
    /// Models to build.
    build: Vec<ModelCrate>,
    /// Models chosen by package or lib name (packaged whatever their identifier).
    by_crate: Vec<String>,
    /// `--only` names that name no crate: perhaps a modelIdentifier, known only after the
    /// build. When there are any, every model is built.
    by_identifier: Vec<String>,
}

fn select(models: &[ModelCrate], only: &[String]) -> Selection {
    if only.is_empty() {
        return Selection {
            build: models.to_vec(),
            by_crate: models.iter().map(|m| m.package.clone()).collect(),
            by_identifier: Vec::new(),
        };
    }
    let mut by_crate = Vec::new();
    let mut by_identifier = Vec::new();
    for name in only {
        let hits: Vec<&ModelCrate> = models
            .iter()
            .filter(|m| loose(&m.package) == loose(name) || loose(&m.lib_name) == loose(name))
            .collect();
        if hits.is_empty() {
            by_identifier.push(name.clone());
        }
        by_crate.extend(hits.into_iter().map(|m| m.package.clone()));
    }
    let build = if by_identifier.is_empty() {
        models
            .iter()
            .filter(|m| by_crate.contains(&m.package))
            .cloned()
            .collect()
    } else {
        models.to_vec()
    };
    Selection {
        build,
        by_crate,
        by_identifier,
    }
}

/// `path` relative to the current directory when it lies below it.
fn shown(path: &Path) -> String {
    let cwd = std::env::current_dir().ok();
    let rel = cwd.as_deref().and_then(|c| path.strip_prefix(c).ok());
    match rel {
        Some(r) if !r.as_os_str().is_empty() => r.display().to_string(),
        _ => path.display().to_string(),
    }
}

/// What one run builds from: the workspace's model crates, or one model crate anywhere.
/// Both go through the same steps (cargo build, extract, package): a chapter model and a
/// user's model take one path.
struct Project {
    /// Where cargo runs (its manifest is `root/Cargo.toml`); `docs/figures` and the default
    /// `dist/` live here too.
    root: PathBuf,
    /// Where cargo puts the libraries.
    target_dir: PathBuf,
    /// The model crates `--only` chooses from.
    models: Vec<ModelCrate>,
    /// Whether `models/systems/*.toml` are packaged (the workspace only).
    systems: bool,
}

/// The workspace: `--workspace DIR`, else the one this tool belongs to.
fn workspace_project(opts: &Options, cargo_program: &std::ffi::OsStr) -> Result<Project, String> {
    let root = match &opts.workspace {
        Some(dir) => {
            if !discover::is_workspace_root(dir) {
                return Err(format!(
                    "{} has no Cargo.toml with a [workspace] table",
                    dir.display()
                ));
            }
            fs::canonicalize(dir).unwrap_or_else(|_| dir.clone())
        }
        None => discover::workspace_root(cargo_program)?,
    };
    let models = discover::discover_models(&root)?;
    if models.is_empty() {
        return Err(format!(
            "no model crates in {}: none of the workspace members under models/ has \
             crate-type \"cdylib\"",
            root.display()
        ));
    }
    let target_dir = cargo::target_dir(&root);
    Ok(Project { root, target_dir, models, systems: true })
}

/// `build <target>`: a directory is a model crate wherever it lives (a member of the workspace
/// is built as one); anything else is a model's name in the workspace, as with `--only`.
/// Returns the project and the names to select in it.
fn target_project(target: &str, opts: &Options, cargo_program: &std::ffi::OsStr) -> Result<(Project, Vec<String>), String> {
    let dir = Path::new(target);
    let looks_like_path = dir.is_dir() || target.contains('/') || target.starts_with('.');
    if !looks_like_path {
        let mut only = opts.only.clone();
        only.push(target.to_owned());
        return Ok((workspace_project(opts, cargo_program)?, only));
    }
    let (model, cargo_root) = discover::model_crate_at(dir, cargo_program)?;
    if let Ok(ws) = workspace_project(opts, cargo_program) {
        if ws.models.iter().any(|m| m.dir == model.dir) {
            return Ok((ws, vec![model.package]));
        }
        let target_dir = cargo::target_dir(&cargo_root);
        if let Some(twin) = ws.models.iter().find(|m| m.lib_name == model.lib_name && target_dir == ws.target_dir) {
            return Err(format!(
                "{} builds lib{}.so into {}, where the workspace's {} puts its own: rename the crate, \
                 or build it with another CARGO_TARGET_DIR",
                model.dir.display(),
                model.lib_name,
                target_dir.display(),
                twin.package
            ));
        }
    }
    let only = vec![model.package.clone()];
    let project = Project {
        root: model.dir.clone(),
        target_dir: cargo::target_dir(&cargo_root),
        models: vec![model],
        systems: false,
    };
    Ok((project, only))
}

/// Builds, extracts and packages; returns the error that stops the run, or the number of
/// models that failed.
fn run(opts: &Options) -> Result<usize, String> {
    let started = Instant::now();
    let cargo_program = cargo::cargo_program();
    let (project, only) = match &opts.command {
        Command::Build(target) => target_project(target, opts, &cargo_program)?,
        Command::Effects(name) => (workspace_project(opts, &cargo_program)?, vec![name.clone()]),
        _ => (workspace_project(opts, &cargo_program)?, opts.only.clone()),
    };
    let effects_only = matches!(opts.command, Command::Effects(_));
    let Project { root, target_dir, models, systems } = &project;
    let selection = select(models, &only);
    let toolchain = toolchain::ensure(opts.host_build, &toolchain::tools_dir(&repository()))?;
    // generationDateAndTime: the source's date, baked into each binary when cargo compiles it.
    source_date::export(root);
    cargo::build(&cargo_program, &toolchain, root, target_dir, &selection.build)?;

    // Created only when the first FMU is ready, so a run that fails leaves nothing behind.
    let out_dir = opts.out.clone().unwrap_or_else(|| root.join("dist"));

    let mut failed = 0;
    let mut written = 0;
    let mut unmatched = selection.by_identifier.clone();
    let mut identifiers: BTreeMap<String, String> = BTreeMap::new(); // identifier -> package
    let mut descriptions: BTreeMap<String, String> = BTreeMap::new(); // packaged: identifier -> XML
    for model in &selection.build {
        let lib_path = cargo::library_path(target_dir, toolchain.triple(), &model.lib_name);
        let info = match extract::extract(&lib_path, &model.package) {
            Ok(info) => info,
            Err(e) => {
                eprintln!("error: {e}");
                failed += 1;
                continue;
            }
        };
        let chosen_by_id: Vec<String> = selection
            .by_identifier
            .iter()
            .filter(|n| loose(n) == loose(&info.identifier))
            .cloned()
            .collect();
        unmatched.retain(|n| !chosen_by_id.contains(n));
        if !selection.by_crate.contains(&model.package) && chosen_by_id.is_empty() {
            continue;
        }
        if let Some(other) = identifiers.insert(info.identifier.clone(), model.package.clone()) {
            eprintln!(
                "error: {} and {other} both have modelIdentifier {}; each FMU needs its own",
                model.package, info.identifier
            );
            failed += 1;
            continue;
        }
        if effects_only {
            let text = if info.effects.is_empty() { "no elements declared (a signal block)\n" } else { &info.effects };
            print!("{}: effects (the chapter's Tables 3.1 and 3.3)\n{text}", info.identifier);
            written += 1;
            continue;
        }
        match package_one(root, &out_dir, &lib_path, &info) {
            Ok((path, size)) => {
                written += 1;
                descriptions.insert(info.identifier.clone(), info.description().to_owned());
                println!(
                    "  {:<20}{}  ({} kB, {} variables)",
                    info.identifier,
                    shown(&path),
                    size.div_ceil(1000),
                    info.variable_count()
                );
            }
            Err(e) => {
                eprintln!("error: {}: {e}", model.package);
                failed += 1;
            }
        }
    }
    if !unmatched.is_empty() {
        let known: Vec<String> = models.iter().map(|m| m.package.clone()).collect();
        eprintln!(
            "error: --only {} matched no model (packages: {}; a modelIdentifier works too)",
            unmatched.join(", "),
            known.join(", ")
        );
        failed += unmatched.len();
    }
    if effects_only {
        return Ok(failed);
    }
    let (systems_written, systems_failed) = if *systems {
        package_systems(root, &out_dir, &descriptions, !only.is_empty())
    } else {
        (0, 0)
    };
    failed += systems_failed;
    println!(
        "Packaged {written} FMU{}{} into {} in {:.1} s ({}){}",
        if written == 1 { "" } else { "s" },
        match systems_written {
            0 => String::new(),
            1 => " and 1 system".to_owned(),
            n => format!(" and {n} systems"),
        },
        shown(&out_dir),
        started.elapsed().as_secs_f64(),
        match toolchain {
            toolchain::Toolchain::Zig { .. } => format!("binaries for glibc {} or newer, stripped", toolchain::GLIBC),
            toolchain::Toolchain::Host => "--host-build: binaries for this machine's glibc".to_owned(),
        },
        if failed > 0 {
            format!("; {failed} failed")
        } else {
            String::new()
        }
    );
    Ok(failed)
}

/// Writes `<out_dir>/<System>.ssp` for each system of `models/systems/` (one progress line
/// each); `packaged` maps the modelIdentifier of each FMU packaged in this run to its
/// modelDescription.xml. With `partial` (`--only`), a system that needs an FMU left out is
/// skipped; otherwise that is an error. Returns (systems written, failures).
fn package_systems(
    root: &Path,
    out_dir: &Path,
    packaged: &BTreeMap<String, String>,
    partial: bool,
) -> (usize, usize) {
    let declarations = match systems::discover(root) {
        Ok(d) => d,
        Err(e) => {
            eprintln!("error: {e}");
            return (0, 1);
        }
    };
    let (mut written, mut failed) = (0, 0);
    let mut interfaces = BTreeMap::new();
    for (id, xml) in packaged {
        match fmi_host::ModelDescription::parse(xml) {
            Ok(md) => {
                interfaces.insert(id.clone(), md);
            }
            Err(e) if !declarations.is_empty() => {
                eprintln!("error: {id}: {e}");
                failed += 1;
            }
            Err(_) => {}
        }
    }
    for (_, decl) in &declarations {
        let left_out: Vec<&str> = decl
            .fmus()
            .into_iter()
            .filter(|f| !packaged.contains_key(*f))
            .collect();
        if partial && !left_out.is_empty() {
            println!(
                "  {:<20}skipped: --only left out {}",
                decl.name,
                left_out.join(", ")
            );
            continue;
        }
        let path = out_dir.join(format!("{}.ssp", decl.name));
        let result = systems::resolve(decl, &interfaces)
            .and_then(|s| ssp::write_ssp(&path, &s, out_dir).map(|size| (s, size)));
        match result {
            Ok((s, size)) => {
                written += 1;
                println!(
                    "  {:<20}{}  ({} kB, {} components, {} connections)",
                    s.name,
                    shown(&path),
                    size.div_ceil(1000),
                    s.components.len(),
                    s.connections.len()
                );
            }
            Err(e) => {
                eprintln!("error: {e}");
                failed += 1;
            }
        }
    }
    (written, failed)
}

/// Zips one model into one FMU per FMI version its library exports, `<out_dir>/<folder>/<identifier>.fmu`
/// (the library names each folder; FMI 2.0's is `out_dir` itself, FMI 3.0's `fmi3`), creating the
/// folders if needed, with its figures from `<root>/docs/figures`; returns the first one's (FMI
/// 2.0's) path and size.
fn package_one(
    root: &Path,
    out_dir: &Path,
    lib_path: &Path,
    info: &extract::ModelInfo,
) -> Result<(PathBuf, u64), String> {
    let binary =
        fs::read(lib_path).map_err(|e| format!("could not read {}: {e}", lib_path.display()))?;
    let figures = figures::find(root, &info.identifier)?;
    let icon = icon::png(&info.identifier);
    let mut first = None;
    for edition in &info.editions {
        let dir = out_dir.join(&edition.folder);
        fs::create_dir_all(&dir).map_err(|e| format!("could not create {}: {e}", dir.display()))?;
        let path = dir.join(format!("{}.fmu", info.identifier));
        let documentation = figures::with_figures(&edition.documentation, &figures);
        let size = package::write_fmu(
            &path,
            &package::FmuContents {
                platform: &edition.platform,
                identifier: &info.identifier,
                model_description: edition.description.as_bytes(),
                icon: &icon,
                binary: &binary,
                documentation: documentation.as_bytes(),
                figures: &figures,
            },
        )?;
        first.get_or_insert((path, size));
    }
    first.ok_or_else(|| format!("{}: the library exports no FMI version", info.identifier))
}

fn main() -> ExitCode {
    let opts = match parse_args(std::env::args_os().skip(1)) {
        Ok(opts) => opts,
        Err(e) => {
            eprintln!("error: {e}\n\n{USAGE}");
            return ExitCode::FAILURE;
        }
    };
    if opts.help {
        print!("{USAGE}");
        return ExitCode::SUCCESS;
    }
    let result = match &opts.command {
        Command::BuildAll | Command::Build(_) | Command::Effects(_) => run(&opts),
        Command::New(name) => new_model(name, &opts),
        Command::List => list(&opts),
    };
    match result {
        Ok(0) => ExitCode::SUCCESS,
        Ok(_) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The repository this tool was built from (where `fmu-runtime` and `components` live).
fn repository() -> PathBuf {
    let here = Path::new(env!("CARGO_MANIFEST_DIR"));
    let root = here.parent().unwrap_or(here);
    fs::canonicalize(root).unwrap_or_else(|_| root.to_path_buf())
}

/// `new <Name> [--path DIR]`: scaffolds a model crate.
fn new_model(name: &str, opts: &Options) -> Result<usize, String> {
    let parent = opts.path.clone().unwrap_or_else(|| PathBuf::from("."));
    let dir = scaffold::create(name, &parent, &repository())?;
    println!("created {} (model {name}): edit src/lib.rs, then `build-fmus build {}`", shown(&dir), shown(&dir));
    Ok(0)
}

/// `list`: every model crate of the workspace, and the systems.
fn list(opts: &Options) -> Result<usize, String> {
    let root = match &opts.workspace {
        Some(dir) => dir.clone(),
        None => discover::workspace_root(&cargo::cargo_program())?,
    };
    let models = discover::discover_models(&root)?;
    println!("model crates in {} ({}):", shown(&root), models.len());
    for m in &models {
        println!("  {:<24} {}", m.package, shown(&m.dir));
    }
    let systems = systems::discover(&root)?;
    if !systems.is_empty() {
        println!("systems in {} ({}):", shown(&root.join("models/systems")), systems.len());
        for (_, decl) in &systems {
            println!("  {:<24} {}", decl.name, decl.fmus().join(", "));
        }
    }
    println!("and any model crate made by `build-fmus new`, wherever it lives: `build-fmus build <its directory>`");
    Ok(0)
}

/// Helpers shared by the unit tests.
#[cfg(test)]
mod testutil {
    use std::path::{Path, PathBuf};
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// A fresh directory under the system temp dir, removed on drop.
    pub struct TempDir(PathBuf);

    impl TempDir {
        pub fn new(tag: &str) -> TempDir {
            static NEXT: AtomicUsize = AtomicUsize::new(0);
            let n = NEXT.fetch_add(1, Ordering::Relaxed);
            let dir = std::env::temp_dir()
                .join(format!("build-fmus-test-{tag}-{}-{n}", std::process::id()));
            let _ = std::fs::remove_dir_all(&dir);
            std::fs::create_dir_all(&dir).unwrap();
            TempDir(dir)
        }

        pub fn path(&self) -> &Path {
            &self.0
        }
    }

    impl Drop for TempDir {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(a: &[&str]) -> Result<Options, String> {
        parse_args(a.iter().map(OsString::from))
    }

    fn model(package: &str) -> ModelCrate {
        ModelCrate {
            package: package.into(),
            lib_name: package.replace('-', "_"),
            dir: PathBuf::from("/ws/models").join(package),
        }
    }

    #[test]
    fn parses_the_options() {
        assert_eq!(args(&[]).unwrap(), Options::default());
        let o = args(&[
            "--out",
            "/tmp/x",
            "--only",
            "rlc-circuit",
            "--only=MotorFan",
            "--workspace=/ws",
        ])
        .unwrap();
        assert_eq!(o.out, Some(PathBuf::from("/tmp/x")));
        assert_eq!(o.only, ["rlc-circuit", "MotorFan"]);
        assert_eq!(o.workspace, Some(PathBuf::from("/ws")));
        assert_eq!(args(&["effects", "MotorFan"]).unwrap().command, Command::Effects("MotorFan".into()));
        assert!(args(&["effects"]).unwrap_err().contains("effects needs"));
        assert!(args(&["-h"]).unwrap().help);
        assert!(args(&["--host-build"]).unwrap().host_build);
        assert!(!args(&[]).unwrap().host_build);
        assert!(args(&["--help"]).unwrap().help);
        assert!(args(&["--out"])
            .unwrap_err()
            .contains("--out needs a value"));
        assert!(args(&["--only="])
            .unwrap_err()
            .contains("--only needs a value"));
        assert!(args(&["--bogus"])
            .unwrap_err()
            .contains("unknown argument `--bogus`"));
        assert!(args(&["stray"]).unwrap_err().contains("unknown argument"));
    }

    #[test]
    fn parses_the_subcommands() {
        assert_eq!(args(&[]).unwrap().command, Command::BuildAll);
        assert_eq!(args(&["build", "./elevator-drive"]).unwrap().command, Command::Build("./elevator-drive".into()));
        let o = args(&["build", "MotorFan", "--out", "/tmp/x"]).unwrap();
        assert_eq!((o.command, o.out), (Command::Build("MotorFan".into()), Some(PathBuf::from("/tmp/x"))));
        assert!(args(&["build"]).unwrap_err().contains("build needs a model crate's directory or a model's name"));
        assert!(args(&["build", "--out", "x"]).unwrap_err().contains("build needs"));
        let o = args(&["new", "ElevatorDrive", "--path", "/tmp"]).unwrap();
        assert_eq!((o.command, o.path), (Command::New("ElevatorDrive".into()), Some(PathBuf::from("/tmp"))));
        assert!(args(&["new"]).unwrap_err().contains("new needs a model name"));
        assert_eq!(args(&["list"]).unwrap().command, Command::List);
        assert!(args(&["list", "new", "X"]).unwrap_err().contains("unknown argument `new`"));
    }

    #[test]
    fn loose_names_match_across_spellings() {
        assert_eq!(loose("rlc-circuit"), loose("RlcCircuit"));
        assert_eq!(loose("rlc_circuit"), loose("RLC-Circuit"));
        assert_ne!(loose("rlc-circuit"), loose("motor-fan"));
    }

    #[test]
    fn only_selects_by_crate_name_or_defers_to_the_identifier() {
        let models = [
            model("motor-fan"),
            model("rlc-circuit"),
            model("shaft-line"),
        ];

        let all = select(&models, &[]);
        assert_eq!(all.build.len(), 3);
        assert!(all.by_identifier.is_empty());

        // Names that match crates build only those crates.
        let s = select(&models, &["rlc-circuit".into(), "MotorFan".into()]);
        let built: Vec<_> = s.build.iter().map(|m| m.package.as_str()).collect();
        assert_eq!(built, ["motor-fan", "rlc-circuit"]);
        assert!(s.by_identifier.is_empty());

        // A name matching no crate may be a modelIdentifier: everything is built.
        let s = select(&models, &["rlc-circuit".into(), "Propeller".into()]);
        assert_eq!(s.build.len(), 3);
        assert_eq!(s.by_crate, ["rlc-circuit"]);
        assert_eq!(s.by_identifier, ["Propeller"]);
    }
}
