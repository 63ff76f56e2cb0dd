//! Building the model libraries with cargo, and where cargo puts them.

use std::env;
use std::ffi::{OsStr, OsString};
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::discover::ModelCrate;
use crate::toolchain::{self, Toolchain};

/// The cargo to run: `$CARGO` (set by `cargo run`, so the same toolchain builds the
/// models) or else `cargo` from `PATH`.
pub fn cargo_program() -> OsString {
    env::var_os("CARGO")
        .filter(|c| !c.is_empty())
        .unwrap_or_else(|| OsString::from("cargo"))
}

/// The target directory cargo uses for the workspace at `root`: `$CARGO_TARGET_DIR`, else
/// `$CARGO_BUILD_TARGET_DIR`, else `<root>/target`. A relative directory from the
/// environment is taken, as cargo takes it, relative to the current directory.
pub fn target_dir(root: &Path) -> PathBuf {
    resolve_target_dir(
        root,
        env::var_os("CARGO_TARGET_DIR"),
        env::var_os("CARGO_BUILD_TARGET_DIR"),
        &env::current_dir().unwrap_or_else(|_| root.to_path_buf()),
    )
}

/// [`target_dir`] with its inputs explicit.
fn resolve_target_dir(
    root: &Path,
    target_dir: Option<OsString>,
    build_target_dir: Option<OsString>,
    cwd: &Path,
) -> PathBuf {
    match target_dir
        .filter(|d| !d.is_empty())
        .or(build_target_dir.filter(|d| !d.is_empty()))
    {
        Some(dir) => cwd.join(dir),
        None => root.join("target"),
    }
}

/// Where the release build of `lib_name` lands: `<target>/<triple>/release/lib<lib_name>.so`
/// when built for a target `triple` (the zig toolchain), `<target>/release/lib<lib_name>.so`
/// for a plain host build (the platform's own prefix and suffix elsewhere).
pub fn library_path(target_dir: &Path, triple: Option<&str>, lib_name: &str) -> PathBuf {
    let dir = match triple {
        Some(t) => target_dir.join(t),
        None => target_dir.to_path_buf(),
    };
    dir.join("release").join(format!(
        "{}{lib_name}{}",
        env::consts::DLL_PREFIX,
        env::consts::DLL_SUFFIX
    ))
}

/// The one build of every model library: with the zig toolchain
/// `cargo-zigbuild zigbuild --release --lib --target <triple>.2.17 --manifest-path
/// <root>/Cargo.toml -p a -p b ...`, stripped of symbol tables (`CARGO_PROFILE_RELEASE_STRIP`;
/// `.eh_frame` stays, panics still unwind to the C boundary); for a host build the same
/// arguments to `cargo build`, without `--target`, unstripped.
///
/// It runs in `root` (so the workspace's `.cargo/config.toml` applies) with an absolute
/// `CARGO_TARGET_DIR`, and inherits stdout and stderr so compiler errors reach the user.
pub fn build_command(
    cargo: &OsStr,
    toolchain: &Toolchain,
    root: &Path,
    target_dir: &Path,
    models: &[ModelCrate],
) -> Command {
    let mut cmd = match toolchain {
        Toolchain::Zig { venv, triple } => {
            let mut cmd = Command::new(toolchain::cargo_zigbuild(venv));
            cmd.arg("zigbuild")
                .arg("--release")
                .arg("--lib")
                .arg("--target")
                .arg(format!("{triple}.{}", toolchain::GLIBC));
            // cargo-zigbuild runs zig as `python -m ziglang`, with this environment's Python;
            // both tools keep their caches in the environment, not in ~/.cache.
            let cache = venv.join("cache");
            cmd.env("CARGO", cargo)
                .env("CARGO_ZIGBUILD_PYTHON_PATH", toolchain::venv_python(venv))
                .env("CARGO_ZIGBUILD_CACHE_DIR", cache.join("cargo-zigbuild"))
                .env("ZIG_GLOBAL_CACHE_DIR", cache.join("zig"))
                .env("ZIG_LOCAL_CACHE_DIR", cache.join("zig"))
                .env("CARGO_PROFILE_RELEASE_STRIP", "symbols");
            cmd
        }
        Toolchain::Host => {
            let mut cmd = Command::new(cargo);
            cmd.arg("build").arg("--release").arg("--lib");
            cmd
        }
    };
    cmd.current_dir(root)
        .arg("--manifest-path")
        .arg(root.join("Cargo.toml"));
    for model in models {
        cmd.arg("-p").arg(&model.package);
    }
    cmd.env("CARGO_TARGET_DIR", target_dir);
    cmd
}

/// Runs [`build_command`]; an error names the packages and how cargo ended.
pub fn build(
    cargo: &OsStr,
    toolchain: &Toolchain,
    root: &Path,
    target_dir: &Path,
    models: &[ModelCrate],
) -> Result<(), String> {
    let names = models
        .iter()
        .map(|m| m.package.as_str())
        .collect::<Vec<_>>()
        .join(", ");
    let mut cmd = build_command(cargo, toolchain, root, target_dir, models);
    let program = cmd.get_program().to_string_lossy().into_owned();
    let status = cmd
        .status()
        .map_err(|e| format!("could not run {program}: {e}"))?;
    if status.success() {
        return Ok(());
    }
    let how = match status.code() {
        Some(code) => format!("exit code {code}"),
        None => "a signal".to_owned(),
    };
    let what = match toolchain {
        Toolchain::Zig { .. } => "cargo zigbuild",
        Toolchain::Host => "cargo build",
    };
    Err(format!(
        "{what} of the model crates failed ({how}): {names} (see cargo's messages above)"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn target_dir_prefers_the_environment() {
        let root = Path::new("/ws");
        let cwd = Path::new("/ws/models/x");
        assert_eq!(
            resolve_target_dir(root, None, None, cwd),
            Path::new("/ws/target")
        );
        assert_eq!(
            resolve_target_dir(root, Some("/t".into()), Some("/u".into()), cwd),
            Path::new("/t")
        );
        assert_eq!(
            resolve_target_dir(root, None, Some("/u".into()), cwd),
            Path::new("/u")
        );
        assert_eq!(
            resolve_target_dir(root, Some("tgt".into()), None, cwd),
            Path::new("/ws/models/x/tgt")
        );
        assert_eq!(
            resolve_target_dir(root, Some("".into()), None, cwd),
            Path::new("/ws/target")
        );
    }

    #[test]
    fn library_path_is_the_release_cdylib() {
        let p = library_path(Path::new("/ws/target"), None, "rlc_circuit");
        let zig = library_path(
            Path::new("/ws/target"),
            Some("x86_64-unknown-linux-gnu"),
            "rlc_circuit",
        );
        if cfg!(target_os = "linux") {
            assert_eq!(p, Path::new("/ws/target/release/librlc_circuit.so"));
            assert_eq!(
                zig,
                Path::new("/ws/target/x86_64-unknown-linux-gnu/release/librlc_circuit.so")
            );
        }
    }

    #[test]
    fn one_build_command_for_all_models() {
        let models = ["rlc-circuit", "motor-fan"].map(|p| ModelCrate {
            package: p.to_owned(),
            lib_name: p.replace('-', "_"),
            dir: PathBuf::from("/ws/models").join(p),
        });
        let cmd = build_command(
            OsStr::new("cargo"),
            &Toolchain::Host,
            Path::new("/ws"),
            Path::new("/ws/target"),
            &models,
        );
        let args: Vec<_> = cmd
            .get_args()
            .map(|a| a.to_string_lossy().into_owned())
            .collect();
        assert_eq!(
            args,
            [
                "build",
                "--release",
                "--lib",
                "--manifest-path",
                "/ws/Cargo.toml",
                "-p",
                "rlc-circuit",
                "-p",
                "motor-fan"
            ]
        );
        assert_eq!(cmd.get_current_dir(), Some(Path::new("/ws")));
        assert_eq!(cmd.get_program(), "cargo");

        let zig = Toolchain::Zig {
            venv: PathBuf::from("/repo/.build-tools/zig-x"),
            triple: "x86_64-unknown-linux-gnu".into(),
        };
        let cmd = build_command(
            OsStr::new("/bin/cargo"),
            &zig,
            Path::new("/ws"),
            Path::new("/ws/target"),
            &models[..1],
        );
        let args: Vec<_> = cmd
            .get_args()
            .map(|a| a.to_string_lossy().into_owned())
            .collect();
        assert_eq!(
            cmd.get_program(),
            "/repo/.build-tools/zig-x/bin/cargo-zigbuild"
        );
        assert_eq!(
            args,
            [
                "zigbuild",
                "--release",
                "--lib",
                "--target",
                "x86_64-unknown-linux-gnu.2.17",
                "--manifest-path",
                "/ws/Cargo.toml",
                "-p",
                "rlc-circuit"
            ]
        );
        let env = |k: &str| {
            cmd.get_envs()
                .find(|(name, _)| *name == k)
                .and_then(|(_, v)| v)
                .map(|v| v.to_string_lossy().into_owned())
        };
        assert_eq!(
            env("CARGO_PROFILE_RELEASE_STRIP").as_deref(),
            Some("symbols")
        );
        assert_eq!(env("CARGO").as_deref(), Some("/bin/cargo"));
        assert_eq!(
            env("CARGO_ZIGBUILD_PYTHON_PATH").as_deref(),
            Some("/repo/.build-tools/zig-x/bin/python")
        );
        assert_eq!(env("CARGO_TARGET_DIR").as_deref(), Some("/ws/target"));
    }

    #[test]
    fn a_failed_build_names_the_packages() {
        let models = [ModelCrate {
            package: "rlc-circuit".into(),
            lib_name: "rlc_circuit".into(),
            dir: "/nowhere".into(),
        }];
        // `false` stands in for a cargo that fails.
        let err = build(
            OsStr::new("false"),
            &Toolchain::Host,
            Path::new("/"),
            Path::new("/tmp"),
            &models,
        )
        .unwrap_err();
        assert!(
            err.contains("rlc-circuit") && err.contains("exit code 1"),
            "{err}"
        );
    }
}
