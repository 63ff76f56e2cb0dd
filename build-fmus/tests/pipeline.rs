//! The whole pipeline on a throwaway workspace made in a temp directory: discovery, one
//! cargo build (the default one: cargo zigbuild for glibc 2.17, stripped), loading each
//! library, zipping. The fake model exports the three `fmu_runtime_*` symbols by hand, so this
//! test needs neither the runtime nor a real model.

use std::fs;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const FAKE_LIB: &str = r#"
use std::ffi::c_char;
#[no_mangle]
pub extern "C" fn fmu_runtime_model_identifier() -> *const c_char { c"FakeModel".as_ptr() }
#[no_mangle]
pub extern "C" fn fmu_runtime_model_description() -> *const c_char {
    c"<?xml version=\"1.0\" encoding=\"UTF-8\"?>
<fmiModelDescription fmiVersion=\"2.0\" modelName=\"FakeModel\" guid=\"{0}\">
  <CoSimulation modelIdentifier=\"FakeModel\"/>
  <ModelVariables>
    <ScalarVariable name=\"x\" valueReference=\"0\"><Real/></ScalarVariable>
    <ScalarVariable name=\"y\" valueReference=\"1\"><Real/></ScalarVariable>
    <ScalarVariable name=\"z\" valueReference=\"2\"><Real/></ScalarVariable>
  </ModelVariables>
</fmiModelDescription>
".as_ptr()
}
#[no_mangle]
pub extern "C" fn fmu_runtime_documentation() -> *const c_char {
    c"<!DOCTYPE html><html><body>Fake model, ünïcode</body></html>".as_ptr()
}
/// A panic caught before the C boundary, as fmu-runtime's fmi2 functions catch them: 1 when
/// it unwound to catch_unwind (the stripped library kept its unwind tables).
#[no_mangle]
pub extern "C" fn fake_panic_is_caught() -> i32 {
    std::panic::set_hook(Box::new(|_| {}));
    std::panic::catch_unwind(|| -> i32 { panic!("a model bug") }).is_err() as i32
}
"#;

fn write(root: &Path, rel: &str, text: &str) {
    let path = root.join(rel);
    fs::create_dir_all(path.parent().unwrap()).unwrap();
    fs::write(path, text).unwrap();
}

fn manifest(name: &str, lib: &str) -> String {
    format!("[package]\nname = \"{name}\"\nversion = \"0.1.0\"\nedition = \"2021\"\n{lib}\n")
}

/// A workspace with a model, a model without the symbols, and a plain rlib.
fn fake_workspace(root: &Path) {
    write(
        root,
        "Cargo.toml",
        "[workspace]\nresolver = \"2\"\nmembers = [\"models/*\"]\n",
    );
    write(
        root,
        "models/fake-model/Cargo.toml",
        &manifest("fake-model", "[lib]\ncrate-type = [\"cdylib\", \"rlib\"]"),
    );
    write(root, "models/fake-model/src/lib.rs", FAKE_LIB);
    write(
        root,
        "models/no-export/Cargo.toml",
        &manifest("no-export", "[lib]\ncrate-type = [\"cdylib\"]"),
    );
    write(
        root,
        "models/no-export/src/lib.rs",
        "#[no_mangle] pub extern \"C\" fn other() {}\n",
    );
    write(
        root,
        "models/components/Cargo.toml",
        &manifest("components", ""),
    );
    write(root, "models/components/src/lib.rs", "pub fn x() {}\n");
}

fn run(root: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_build-fmus"))
        .arg("--workspace")
        .arg(root)
        .args(args)
        .env("CARGO_TARGET_DIR", root.join("target"))
        .env_remove("CARGO_BUILD_TARGET_DIR")
        .output()
        .unwrap()
}

/// Where the default build puts the libraries: `target/<triple>/release` (cargo zigbuild) on
/// x86_64 glibc Linux, `target/release` elsewhere.
fn release_dir(root: &Path) -> PathBuf {
    if cfg!(all(
        target_os = "linux",
        target_env = "gnu",
        target_arch = "x86_64"
    )) {
        root.join("target/x86_64-unknown-linux-gnu/release")
    } else if cfg!(all(
        target_os = "linux",
        target_env = "gnu",
        target_arch = "aarch64"
    )) {
        root.join("target/aarch64-unknown-linux-gnu/release")
    } else {
        root.join("target/release")
    }
}

/// Whether the ELF64 little-endian image has a section of this name.
fn has_section(elf: &[u8], name: &str) -> bool {
    let u16_at = |o: usize| u16::from_le_bytes(elf[o..o + 2].try_into().unwrap()) as usize;
    let u32_at = |o: usize| u32::from_le_bytes(elf[o..o + 4].try_into().unwrap()) as usize;
    let u64_at = |o: usize| u64::from_le_bytes(elf[o..o + 8].try_into().unwrap()) as usize;
    assert_eq!(
        &elf[..6],
        b"\x7fELF\x02\x01",
        "not a little-endian ELF64 file"
    );
    let (shoff, shentsize, shnum, shstrndx) =
        (u64_at(0x28), u16_at(0x3a), u16_at(0x3c), u16_at(0x3e));
    let names = u64_at(shoff + shstrndx * shentsize + 0x18);
    (0..shnum).any(|i| {
        let start = names + u32_at(shoff + i * shentsize);
        let end = start + elf[start..].iter().position(|&b| b == 0).unwrap();
        &elf[start..end] == name.as_bytes()
    })
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn builds_extracts_and_packages_a_fake_workspace() {
    let root: PathBuf =
        std::env::temp_dir().join(format!("build-fmus-pipeline-{}", std::process::id()));
    let _ = fs::remove_dir_all(&root);
    fake_workspace(&root);

    // Only the good model: success, one progress line with the variable count.
    let out_dir = root.join("out");
    let out = run(
        &root,
        &["--only", "FakeModel", "--out", out_dir.to_str().unwrap()],
    );
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert!(out.status.success(), "stdout:\n{stdout}\nstderr:\n{stderr}");
    assert!(
        stdout.contains("FakeModel") && stdout.contains("3 variables"),
        "{stdout}"
    );
    assert!(stdout.contains("Packaged 1 FMU"), "{stdout}");

    let fmu = out_dir.join("FakeModel.fmu");
    let first = fs::read(&fmu).unwrap();
    let mut archive = zip::ZipArchive::new(fs::File::open(&fmu).unwrap()).unwrap();
    let names: Vec<String> = archive
        .file_names()
        .map(|n| n.unwrap().into_owned())
        .collect();
    let lib_ext = std::env::consts::DLL_EXTENSION;
    assert_eq!(names.len(), 4, "{names:?}");
    assert_eq!(names[0], "modelDescription.xml");
    assert_eq!(names[1], "model.png");
    assert!(
        names[2].starts_with("binaries/") && names[2].ends_with(&format!("/FakeModel.{lib_ext}")),
        "{names:?}"
    );
    assert_eq!(names[3], "documentation/index.html");
    let mut icon = Vec::new();
    archive.by_name("model.png").unwrap().read_to_end(&mut icon).unwrap();
    assert!(icon.starts_with(b"\x89PNG\r\n\x1a\n"), "model.png is a PNG");
    let mut xml = String::new();
    archive
        .by_name("modelDescription.xml")
        .unwrap()
        .read_to_string(&mut xml)
        .unwrap();
    assert!(xml.contains("modelIdentifier=\"FakeModel\""));
    let built_path = release_dir(&root).join(format!(
        "{}fake_model{}",
        std::env::consts::DLL_PREFIX,
        std::env::consts::DLL_SUFFIX
    ));
    let built = fs::read(&built_path).unwrap();
    // The default build links for glibc 2.17 and strips the symbol table; a panic inside
    // the library still unwinds to its catch_unwind.
    if cfg!(all(
        target_os = "linux",
        target_env = "gnu",
        target_arch = "x86_64"
    )) {
        assert!(
            stdout.contains("binaries for glibc 2.17 or newer, stripped"),
            "{stdout}"
        );
        assert!(
            !has_section(&built, ".symtab"),
            "{} is not stripped",
            built_path.display()
        );
        assert!(
            has_section(&built, ".eh_frame"),
            "{} lost .eh_frame",
            built_path.display()
        );
    }
    let caught = unsafe {
        let lib = libloading::Library::new(&built_path).unwrap();
        let f: libloading::Symbol<unsafe extern "C" fn() -> i32> =
            lib.get(b"fake_panic_is_caught").unwrap();
        f()
    };
    assert_eq!(caught, 1, "the panic did not unwind to catch_unwind");
    let mut binary = Vec::new();
    archive
        .by_name(&names[2])
        .unwrap()
        .read_to_end(&mut binary)
        .unwrap();
    assert_eq!(binary, built);

    // A second run writes the same bytes.
    let out = run(
        &root,
        &["--only", "fake-model", "--out", out_dir.to_str().unwrap()],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(fs::read(&fmu).unwrap(), first);

    // All models, into the default dist/: the one without the symbols fails with a clear
    // message and exit code 1, the good one is still written.
    let out = run(&root, &[]);
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert_eq!(
        out.status.code(),
        Some(1),
        "stdout:\n{stdout}\nstderr:\n{stderr}"
    );
    assert!(
        stderr.contains("no-export: the library does not export `fmu_runtime_model_identifier`")
            && stderr.contains("export_fmu!"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(fs::read(root.join("dist/FakeModel.fmu")).unwrap(), first);

    // A name that is neither a crate nor an identifier.
    let out = run(&root, &["--only", "Nope"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("--only Nope matched no model"));

    // A crate that does not compile: cargo's messages, then one line naming the packages.
    write(
        &root,
        "models/fake-model/src/lib.rs",
        "pub fn x() -> u32 { \"no\" }\n",
    );
    let out = run(
        &root,
        &[
            "--only",
            "fake-model",
            "--out",
            root.join("out2").to_str().unwrap(),
        ],
    );
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("of the model crates failed") && stderr.contains("fake-model"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(
        !root.join("out2").exists(),
        "a failed build created the output directory"
    );

    let _ = fs::remove_dir_all(&root);
}

/// A model with an input and an output, for the systems test.
const GAIN_LIB: &str = r#"
use std::ffi::c_char;
#[no_mangle]
pub extern "C" fn fmu_runtime_model_identifier() -> *const c_char { c"Gain".as_ptr() }
#[no_mangle]
pub extern "C" fn fmu_runtime_model_description() -> *const c_char {
    c"<?xml version=\"1.0\" encoding=\"UTF-8\"?>
<fmiModelDescription fmiVersion=\"2.0\" modelName=\"Gain\" guid=\"{0}\">
  <CoSimulation modelIdentifier=\"Gain\"/>
  <UnitDefinitions><Unit name=\"rad/s\"><BaseUnit s=\"-1\" rad=\"1\"/></Unit></UnitDefinitions>
  <ModelVariables>
    <ScalarVariable name=\"k\" valueReference=\"0\" causality=\"parameter\" variability=\"fixed\"><Real start=\"2\"/></ScalarVariable>
    <ScalarVariable name=\"u\" valueReference=\"1\" causality=\"input\"><Real start=\"0\" unit=\"rad/s\"/></ScalarVariable>
    <ScalarVariable name=\"y\" valueReference=\"2\" causality=\"output\"><Real unit=\"rad/s\"/></ScalarVariable>
  </ModelVariables>
</fmiModelDescription>
".as_ptr()
}
#[no_mangle]
pub extern "C" fn fmu_runtime_documentation() -> *const c_char {
    c"<!DOCTYPE html><html><body>Gain</body></html>".as_ptr()
}
"#;

const LOOP_SYSTEM: &str = r#"
connections = ["a.y -> b.u", "b.y -> a.u"]

[parameters]
"b.k" = 0.5

[[components]]
name = "a"
fmu = "Gain"

[[components]]
name = "b"
fmu = "Gain"
"#;

#[test]
fn writes_an_ssp_for_each_declared_system() {
    let root: PathBuf =
        std::env::temp_dir().join(format!("build-fmus-systems-{}", std::process::id()));
    let _ = fs::remove_dir_all(&root);
    // Members listed one by one, as in this workspace: cargo takes a `models/*` glob to
    // cover models/systems/ too and fails on it, as it has no Cargo.toml.
    write(
        &root,
        "Cargo.toml",
        "[workspace]\nresolver = \"2\"\nmembers = [\"models/gain\"]\n",
    );
    write(
        &root,
        "models/gain/Cargo.toml",
        &manifest("gain", "[lib]\ncrate-type = [\"cdylib\"]"),
    );
    write(&root, "models/gain/src/lib.rs", GAIN_LIB);
    write(&root, "models/systems/Loop.toml", LOOP_SYSTEM);

    let out_dir = root.join("out");
    let out = run(&root, &["--out", out_dir.to_str().unwrap()]);
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert!(out.status.success(), "stdout:\n{stdout}\nstderr:\n{stderr}");
    assert!(
        stdout.contains("Loop")
            && stdout.contains("Loop.ssp")
            && stdout.contains("2 components, 2 connections"),
        "{stdout}"
    );
    assert!(stdout.contains("Packaged 1 FMU and 1 system"), "{stdout}");

    let ssp = out_dir.join("Loop.ssp");
    let mut archive = zip::ZipArchive::new(fs::File::open(&ssp).unwrap()).unwrap();
    let names: Vec<String> = archive
        .file_names()
        .map(|n| n.unwrap().into_owned())
        .collect();
    assert_eq!(names, ["SystemStructure.ssd", "resources/Gain.fmu"]);
    let mut fmu = Vec::new();
    archive
        .by_name("resources/Gain.fmu")
        .unwrap()
        .read_to_end(&mut fmu)
        .unwrap();
    assert_eq!(fmu, fs::read(out_dir.join("Gain.fmu")).unwrap());
    let mut ssd = String::new();
    archive
        .by_name("SystemStructure.ssd")
        .unwrap()
        .read_to_string(&mut ssd)
        .unwrap();
    for part in [
        "xmlns:ssd=\"http://ssp-standard.org/SSP1/SystemStructureDescription\"",
        "<ssd:Component name=\"b\" type=\"application/x-fmu-sharedlibrary\" source=\"resources/Gain.fmu\">",
        "<ssd:Connector name=\"u\" kind=\"input\">",
        "<ssc:Real unit=\"rad/s\"/>",
        "<ssv:Parameter name=\"k\">",
        "<ssv:Real value=\"0.5\"/>",
        "<ssd:Connection startElement=\"b\" startConnector=\"y\" endElement=\"a\" endConnector=\"u\"/>",
        "<ssc:Unit name=\"rad/s\">",
    ] {
        assert!(ssd.contains(part), "{part} not in\n{ssd}");
    }

    // A declaration naming a variable the FMU lacks: a clear error, exit code 1; the other
    // system is still written.
    write(
        &root,
        "models/systems/Broken.toml",
        "connections = [\"a.y -> a.v\", \"a.u -> a.y\"]\n[[components]]\nname = \"a\"\nfmu = \"Gain\"\n",
    );
    fs::remove_file(&ssp).unwrap();
    let out = run(&root, &["--out", out_dir.to_str().unwrap()]);
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert_eq!(
        out.status.code(),
        Some(1),
        "stdout:\n{stdout}\nstderr:\n{stderr}"
    );
    assert!(
        stderr.contains("system Broken")
            && stderr
                .contains("a (Gain) has no variable \"v\" (inputs: u; outputs: y; parameters: k)")
            && stderr.contains("a.u is an input, not an output"),
        "{stderr}"
    );
    assert!(ssp.exists(), "{stdout}");
    assert!(!out_dir.join("Broken.ssp").exists());
    assert!(stdout.contains("1 failed"), "{stdout}");

    // A system whose FMU is not among those --only selects is skipped, not an error.
    write(
        &root,
        "models/systems/Broken.toml",
        "[[components]]\nname = \"g\"\nfmu = \"Ghost\"\n",
    );
    let out = run(
        &root,
        &["--only", "Gain", "--out", out_dir.to_str().unwrap()],
    );
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert!(out.status.success(), "stdout:\n{stdout}\nstderr:\n{stderr}");
    assert!(
        stdout.contains("skipped: --only left out Ghost"),
        "{stdout}"
    );
    // ... but without --only it is: the FMU does not exist.
    let out = run(&root, &["--out", out_dir.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).contains("component g: no FMU \"Ghost\" was built (FMUs: Gain)"),
        "{}",
        text(&out.stderr)
    );

    let _ = fs::remove_dir_all(&root);
}
