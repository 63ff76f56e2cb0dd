//! The toolchain that builds the shipped libraries: `cargo zigbuild`, which links them with zig
//! against the symbol versions of glibc 2.17, so that an FMU loads on every Linux with glibc 2.17
//! (2012: CentOS 7, Ubuntu 14.04) or newer. A plain `cargo build` links against this machine's
//! glibc and asks for its newest symbols (`hypot@GLIBC_2.35` on a glibc 2.35 build machine).
//!
//! zig and cargo-zigbuild come from PyPI at the versions pinned in
//! `build-fmus/toolchain-requirements.txt`, installed by [`ensure`] into a virtual environment
//! under the repository's `.build-tools/` the first time they are needed. Nothing is installed
//! outside the repository: the caches of zig and cargo-zigbuild live in that environment too
//! (pip may keep the downloaded wheels in its own cache).

use std::env;
use std::ffi::OsString;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Instant, SystemTime, UNIX_EPOCH};

/// The pinned packages, compiled in (so an installed build-fmus carries its pins).
pub const REQUIREMENTS: &str = include_str!("../toolchain-requirements.txt");

/// The oldest glibc the shipped libraries need, as cargo-zigbuild's target suffix.
pub const GLIBC: &str = "2.17";

/// Written last into a finished environment.
const READY: &str = "build-fmus-ready";

/// How the model libraries are built.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Toolchain {
    /// `cargo zigbuild --target <triple>.2.17` with the environment at `venv`; the libraries
    /// land in `<target dir>/<triple>/release/` and are stripped of their symbol tables.
    Zig { venv: PathBuf, triple: String },
    /// A plain `cargo build` for this machine's glibc (`--host-build`, or a platform that has
    /// no glibc); the libraries land in `<target dir>/release/`, as cargo leaves them.
    Host,
}

impl Toolchain {
    /// The Rust target the libraries are built for, when it is not cargo's default.
    pub fn triple(&self) -> Option<&str> {
        match self {
            Toolchain::Zig { triple, .. } => Some(triple),
            Toolchain::Host => None,
        }
    }
}

/// This machine's glibc target, when it is one cargo-zigbuild links for an older glibc.
pub fn glibc_triple() -> Option<String> {
    if !cfg!(all(target_os = "linux", target_env = "gnu")) {
        return None;
    }
    match env::consts::ARCH {
        arch @ ("x86_64" | "aarch64") => Some(format!("{arch}-unknown-linux-gnu")),
        _ => None,
    }
}

/// The `name==version` lines of [`REQUIREMENTS`].
pub fn pins() -> Vec<&'static str> {
    REQUIREMENTS
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .collect()
}

/// The environment for these pins: `<tools>/zig-<FNV-1a of the requirements>`, so that
/// changing a pin makes a new environment rather than reusing a stale one.
pub fn venv_dir(tools: &Path) -> PathBuf {
    let hash = REQUIREMENTS
        .bytes()
        .fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
        });
    tools.join(format!("zig-{:012x}", hash >> 16))
}

/// Where the environments live: `$BUILD_FMUS_TOOLS_DIR`, else `<repository>/.build-tools`.
pub fn tools_dir(repository: &Path) -> PathBuf {
    env::var_os("BUILD_FMUS_TOOLS_DIR")
        .filter(|d| !d.is_empty())
        .map(PathBuf::from)
        .unwrap_or_else(|| repository.join(".build-tools"))
}

/// The Python that makes the environment: `$BUILD_FMUS_PYTHON`, else `python3`.
fn python() -> OsString {
    env::var_os("BUILD_FMUS_PYTHON")
        .filter(|p| !p.is_empty())
        .unwrap_or_else(|| OsString::from("python3"))
}

/// The environment's Python and cargo-zigbuild.
pub fn venv_python(venv: &Path) -> PathBuf {
    venv.join("bin").join("python")
}

pub fn cargo_zigbuild(venv: &Path) -> PathBuf {
    venv.join("bin").join("cargo-zigbuild")
}

/// The toolchain for this run: [`Toolchain::Host`] if asked for or if this machine has no
/// glibc target, else the zig toolchain, installed into `tools` first if it is not there.
pub fn ensure(host_build: bool, tools: &Path) -> Result<Toolchain, String> {
    let triple = match glibc_triple() {
        Some(t) if !host_build => t,
        _ => return Ok(Toolchain::Host),
    };
    let venv = venv_dir(tools);
    if !venv.join(READY).is_file() {
        install(tools, &venv)?;
    }
    Ok(Toolchain::Zig { venv, triple })
}

/// Makes the environment in a fresh directory beside `venv` and renames it into place when
/// complete, so an interrupted install is never taken for a finished one and two builds that
/// install at once do not mix their files (the second rename fails; its copy is dropped).
fn install(tools: &Path, venv: &Path) -> Result<(), String> {
    let started = Instant::now();
    fs::create_dir_all(tools).map_err(|e| format!("could not create {}: {e}", tools.display()))?;
    let nanos = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| d.subsec_nanos())
        .unwrap_or(0);
    let tmp = tools.join(format!(".installing-{}-{nanos}", std::process::id()));
    let _ = fs::remove_dir_all(&tmp);
    println!(
        "Installing the pinned toolchain ({}) into {} (once)",
        pins().join(", "),
        venv.display()
    );
    let result = (|| {
        let python = python();
        run(
            Command::new(&python).arg("-m").arg("venv").arg(&tmp),
            &format!("{} -m venv", python.to_string_lossy()),
        )?;
        let requirements = tmp.join("toolchain-requirements.txt");
        fs::write(&requirements, REQUIREMENTS)
            .map_err(|e| format!("could not write {}: {e}", requirements.display()))?;
        run(
            Command::new(venv_python(&tmp))
                .args([
                    "-m",
                    "pip",
                    "install",
                    "--quiet",
                    "--disable-pip-version-check",
                ])
                .args(["--no-input", "--only-binary", ":all:", "-r"])
                .arg(&requirements),
            "pip install -r build-fmus/toolchain-requirements.txt",
        )?;
        fs::write(tmp.join(READY), REQUIREMENTS)
            .map_err(|e| format!("could not write into {}: {e}", tmp.display()))
    })();
    if let Err(e) = result {
        let _ = fs::remove_dir_all(&tmp);
        return Err(format!(
            "{e}\n  (build-fmus installs zig and cargo-zigbuild from PyPI to link the FMUs \
             against glibc {GLIBC}: it needs Python 3 with venv and pip, or $BUILD_FMUS_PYTHON; \
             --host-build builds for this machine's glibc instead)"
        ));
    }
    match fs::rename(&tmp, venv) {
        Ok(()) => {}
        Err(_) if venv.join(READY).is_file() => {
            let _ = fs::remove_dir_all(&tmp);
        }
        Err(e) => {
            let _ = fs::remove_dir_all(&tmp);
            return Err(format!(
                "could not move the toolchain to {}: {e}",
                venv.display()
            ));
        }
    }
    println!("  installed in {:.1} s", started.elapsed().as_secs_f64());
    Ok(())
}

fn run(cmd: &mut Command, what: &str) -> Result<(), String> {
    let status = cmd
        .status()
        .map_err(|e| format!("could not run {what}: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("{what} failed ({status})"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pins_are_exact_versions() {
        let pins = pins();
        assert_eq!(pins.len(), 2, "{pins:?}");
        for pin in &pins {
            let (name, version) = pin.split_once("==").expect("name==version");
            assert!(["ziglang", "cargo-zigbuild"].contains(&name), "{pin}");
            assert!(
                version.split('.').all(|p| p.parse::<u32>().is_ok()),
                "{pin}"
            );
        }
    }

    #[test]
    fn the_environment_is_named_by_its_pins() {
        let dir = venv_dir(Path::new("/repo/.build-tools"));
        let name = dir.file_name().unwrap().to_str().unwrap();
        assert!(name.starts_with("zig-") && name.len() == 16, "{name}");
        assert_eq!(dir, venv_dir(Path::new("/repo/.build-tools")));
    }

    #[test]
    fn host_build_installs_nothing() {
        let nowhere = Path::new("/nonexistent/build-fmus-tools");
        assert_eq!(ensure(true, nowhere), Ok(Toolchain::Host));
        assert!(!nowhere.exists());
    }

    #[test]
    fn glibc_linux_gets_a_triple() {
        if cfg!(all(
            target_os = "linux",
            target_env = "gnu",
            target_arch = "x86_64"
        )) {
            assert_eq!(glibc_triple().as_deref(), Some("x86_64-unknown-linux-gnu"));
        }
    }
}
