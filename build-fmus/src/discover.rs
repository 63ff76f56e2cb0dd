//! Finding the workspace root and the model crates in it.
//!
//! A *model crate* is a workspace member whose directory lies under `models/` and whose
//! `Cargo.toml` asks for a `cdylib` in `[lib] crate-type`. `models/components`, a plain
//! rlib, is not one. Everything here reads manifests only: nothing is built.

use std::fs;
use std::path::{Component, Path, PathBuf};
use std::process::Command;

/// One model crate found in the workspace.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ModelCrate {
    /// The package name, as given to `cargo build -p` (`rlc-circuit`).
    pub package: String,
    /// The library target's name (`rlc_circuit`): `[lib] name`, or the package name with
    /// `-` replaced by `_`. The built file is `lib<lib_name>.so`.
    pub lib_name: String,
    /// The crate's directory.
    pub dir: PathBuf,
}

/// Finds the workspace root.
///
/// In order: the parent of this crate's manifest directory as it was at compile time (true
/// whenever the tool is started with `cargo run`), then `cargo locate-project --workspace`
/// run from the current directory. A directory counts as the root only if its `Cargo.toml`
/// has a `[workspace]` table.
pub fn workspace_root(cargo: &std::ffi::OsStr) -> Result<PathBuf, String> {
    if let Some(parent) = Path::new(env!("CARGO_MANIFEST_DIR")).parent() {
        if is_workspace_root(parent) {
            return Ok(parent.to_path_buf());
        }
    }
    let manifest = locate_workspace_manifest(cargo, None).map_err(|stderr| {
        format!("could not find the workspace root (run this from inside the workspace, or pass --workspace DIR): {stderr}")
    })?;
    match manifest.parent() {
        Some(dir) if is_workspace_root(dir) => Ok(dir.to_path_buf()),
        _ => Err(format!(
            "{} is not a workspace manifest",
            manifest.display()
        )),
    }
}

/// Whether `dir/Cargo.toml` exists and has a `[workspace]` table.
pub fn is_workspace_root(dir: &Path) -> bool {
    read_manifest(&dir.join("Cargo.toml"))
        .map(|t| t.contains_key("workspace"))
        .unwrap_or(false)
}

/// Lists the model crates of the workspace at `root`, sorted by package name.
///
/// Members come from `[workspace] members` (entries may use `*` and `?` globs, as cargo
/// allows) less `[workspace] exclude`; of those, only directories under `root/models/`
/// whose manifest has `cdylib` in `[lib] crate-type` are model crates.
pub fn discover_models(root: &Path) -> Result<Vec<ModelCrate>, String> {
    let root_manifest = root.join("Cargo.toml");
    let table = read_manifest(&root_manifest)?;
    let workspace = table
        .get("workspace")
        .and_then(|w| w.as_table())
        .ok_or_else(|| format!("{} has no [workspace] table", root_manifest.display()))?;
    let members = string_list(workspace, "members", &root_manifest)?;
    let exclude: Vec<PathBuf> = string_list(workspace, "exclude", &root_manifest)?
        .iter()
        .map(|e| normalize(Path::new(e)))
        .collect();

    let mut dirs: Vec<PathBuf> = Vec::new();
    for pattern in &members {
        for rel in expand_member(root, pattern)? {
            let rel = normalize(&rel);
            if !exclude.contains(&rel) && !dirs.contains(&rel) {
                dirs.push(rel);
            }
        }
    }

    let mut models = Vec::new();
    for rel in dirs {
        if rel.components().next() != Some(Component::Normal("models".as_ref())) {
            continue;
        }
        let dir = root.join(&rel);
        if let Some(model) = read_model_crate(&dir)? {
            models.push(model);
        }
    }
    models.sort_by(|a, b| a.package.cmp(&b.package));
    Ok(models)
}

/// The model crate in `dir`, wherever it lives (inside this workspace or outside it), with
/// the cargo workspace it belongs to: `dir` itself when its manifest has a `[workspace]`
/// table (a crate made by `build-fmus new`), else the one `cargo locate-project` finds.
/// An error names the directory and the fix.
pub fn model_crate_at(dir: &Path, cargo: &std::ffi::OsStr) -> Result<(ModelCrate, PathBuf), String> {
    let manifest = dir.join("Cargo.toml");
    if !manifest.is_file() {
        return Err(format!(
            "{} has no Cargo.toml: pass a model crate's directory (made by `build-fmus new <Name>`) or a model's name",
            dir.display()
        ));
    }
    let dir = fs::canonicalize(dir).unwrap_or_else(|_| dir.to_path_buf());
    let model = read_model_crate(&dir)?.ok_or_else(|| {
        format!(
            "{} is not a model crate: its [lib] needs crate-type = [\"cdylib\", \"rlib\"] and src/lib.rs must end with fmu_runtime::export_fmu!(<Model>)",
            manifest.display()
        )
    })?;
    if is_workspace_root(&dir) {
        return Ok((model, dir));
    }
    let found = locate_workspace_manifest(cargo, Some(&dir)).map_err(|stderr| format!("could not find the cargo workspace of {}: {stderr}", dir.display()))?;
    match found.parent() {
        Some(root) => Ok((model, root.to_path_buf())),
        None => Err(format!("could not find the cargo workspace of {}: cargo named {}", dir.display(), found.display())),
    }
}

/// The manifest of the cargo workspace that `dir` (default: the current directory) belongs to,
/// from `cargo locate-project --workspace`; the error is cargo's own message.
fn locate_workspace_manifest(cargo: &std::ffi::OsStr, dir: Option<&Path>) -> Result<PathBuf, String> {
    let mut command = Command::new(cargo);
    if let Some(dir) = dir {
        command.current_dir(dir);
    }
    let out = command
        .args(["locate-project", "--workspace", "--message-format", "plain"])
        .output()
        .map_err(|e| format!("could not run `cargo locate-project`: {e}"))?;
    if !out.status.success() {
        return Err(String::from_utf8_lossy(&out.stderr).trim().to_string());
    }
    Ok(PathBuf::from(String::from_utf8_lossy(&out.stdout).trim()))
}

/// Reads one member's manifest; `Some` if it builds a cdylib.
fn read_model_crate(dir: &Path) -> Result<Option<ModelCrate>, String> {
    let manifest = dir.join("Cargo.toml");
    let table = read_manifest(&manifest)?;
    let Some(package) = table
        .get("package")
        .and_then(|p| p.get("name"))
        .and_then(|n| n.as_str())
    else {
        // A virtual manifest (a nested workspace) or no package: not a model.
        return Ok(None);
    };
    let lib = table.get("lib").and_then(|l| l.as_table());
    let is_cdylib = lib
        .and_then(|l| l.get("crate-type").or_else(|| l.get("crate_type")))
        .and_then(|c| c.as_array())
        .is_some_and(|types| types.iter().any(|t| t.as_str() == Some("cdylib")));
    if !is_cdylib {
        return Ok(None);
    }
    let lib_name = lib
        .and_then(|l| l.get("name"))
        .and_then(|n| n.as_str())
        .map(str::to_owned)
        .unwrap_or_else(|| package.replace('-', "_"));
    Ok(Some(ModelCrate {
        package: package.to_owned(),
        lib_name,
        dir: dir.to_path_buf(),
    }))
}

/// Parses a `Cargo.toml` into a TOML table.
fn read_manifest(path: &Path) -> Result<toml::Table, String> {
    let text =
        fs::read_to_string(path).map_err(|e| format!("could not read {}: {e}", path.display()))?;
    text.parse::<toml::Table>()
        .map_err(|e| format!("could not parse {}: {e}", path.display()))
}

/// An optional array of strings in `table[key]`.
fn string_list(table: &toml::Table, key: &str, file: &Path) -> Result<Vec<String>, String> {
    let Some(value) = table.get(key) else {
        return Ok(Vec::new());
    };
    let bad = || {
        format!(
            "{}: workspace.{key} must be an array of strings",
            file.display()
        )
    };
    value
        .as_array()
        .ok_or_else(bad)?
        .iter()
        .map(|v| v.as_str().map(str::to_owned).ok_or_else(bad))
        .collect()
}

/// Expands a `members` entry into directories relative to `root`: each path component may
/// hold `*` / `?` wildcards, which match directory names (hidden ones only if the pattern
/// component itself starts with `.`). A plain entry is returned as is, existing or not,
/// so that a missing member is reported when its manifest is read.
fn expand_member(root: &Path, pattern: &str) -> Result<Vec<PathBuf>, String> {
    let mut found = vec![PathBuf::new()];
    for part in pattern
        .split(['/', '\\'])
        .filter(|p| !p.is_empty() && *p != ".")
    {
        if !part.contains(['*', '?']) {
            found.iter_mut().for_each(|p| p.push(part));
            continue;
        }
        let mut next = Vec::new();
        for base in &found {
            let Ok(entries) = fs::read_dir(root.join(base)) else {
                continue;
            };
            let mut names: Vec<String> = entries
                .filter_map(|e| e.ok())
                .filter(|e| e.file_type().map(|t| t.is_dir()).unwrap_or(false))
                .filter_map(|e| e.file_name().into_string().ok())
                .filter(|n| glob_match(part, n) && (part.starts_with('.') || !n.starts_with('.')))
                .collect();
            names.sort();
            next.extend(names.into_iter().map(|n| base.join(n)));
        }
        found = next;
    }
    // A glob also matches directories without a manifest; cargo skips those silently.
    if pattern.contains(['*', '?']) {
        found.retain(|p| root.join(p).join("Cargo.toml").is_file());
    }
    Ok(found)
}

/// `*` (any run of characters) and `?` (one character) matching of one path component.
fn glob_match(pattern: &str, name: &str) -> bool {
    fn go(p: &[char], n: &[char]) -> bool {
        match p.split_first() {
            None => n.is_empty(),
            Some(('*', rest)) => (0..=n.len()).any(|i| go(rest, &n[i..])),
            Some(('?', rest)) => !n.is_empty() && go(rest, &n[1..]),
            Some((c, rest)) => n.first() == Some(c) && go(rest, &n[1..]),
        }
    }
    let p: Vec<char> = pattern.chars().collect();
    let n: Vec<char> = name.chars().collect();
    go(&p, &n)
}

/// Drops `.` components and trailing separators so equal paths compare equal.
fn normalize(path: &Path) -> PathBuf {
    path.components()
        .filter(|c| !matches!(c, Component::CurDir))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::TempDir;

    fn write(root: &Path, rel: &str, text: &str) {
        let path = root.join(rel);
        fs::create_dir_all(path.parent().unwrap()).unwrap();
        fs::write(path, text).unwrap();
    }

    fn package(name: &str, lib: &str) -> String {
        format!("[package]\nname = \"{name}\"\nversion = \"0.1.0\"\n\n{lib}\n[dependencies]\n")
    }

    /// A tree shaped like the real workspace, plus the cases discovery must tell apart.
    fn fake_workspace() -> TempDir {
        let tmp = TempDir::new("discover");
        let root = tmp.path();
        write(
            root,
            "Cargo.toml",
            r#"[workspace]
resolver = "2"
members = ["fmu-runtime", "models/components", "models/rlc-circuit", "models/extra/*",
           "./models/named/", "build-fmus", "models/excluded", "tools/cdylib-tool"]
exclude = ["models/excluded"]
"#,
        );
        write(root, "fmu-runtime/Cargo.toml", &package("fmu-runtime", ""));
        write(root, "build-fmus/Cargo.toml", &package("build-fmus", ""));
        write(
            root,
            "models/components/Cargo.toml",
            &package("components", ""),
        );
        write(
            root,
            "models/rlc-circuit/Cargo.toml",
            &package(
                "rlc-circuit",
                "[lib]\nname = \"rlc_circuit\"\ncrate-type = [\"cdylib\", \"rlib\"]\n",
            ),
        );
        // lib name defaults to the package name with '-' -> '_'
        write(
            root,
            "models/extra/motor-fan/Cargo.toml",
            &package("motor-fan", "[lib]\ncrate-type = [\"rlib\", \"cdylib\"]\n"),
        );
        // an rlib under the glob: skipped
        write(
            root,
            "models/extra/helpers/Cargo.toml",
            &package("helpers", "[lib]\ncrate-type = [\"rlib\"]\n"),
        );
        // a directory without a manifest under the glob: ignored, as cargo does
        fs::create_dir_all(root.join("models/extra/notes")).unwrap();
        write(
            root,
            "models/named/Cargo.toml",
            &package(
                "a-shaft",
                "[lib]\nname = \"shaft_lib\"\ncrate-type = [\"cdylib\"]\n",
            ),
        );
        write(
            root,
            "models/excluded/Cargo.toml",
            &package("excluded", "[lib]\ncrate-type = [\"cdylib\"]\n"),
        );
        // a cdylib outside models/: not a model
        write(
            root,
            "tools/cdylib-tool/Cargo.toml",
            &package("cdylib-tool", "[lib]\ncrate-type = [\"cdylib\"]\n"),
        );
        // a cdylib under models/ that is not a member: not a model
        write(
            root,
            "models/stray/Cargo.toml",
            &package("stray", "[lib]\ncrate-type = [\"cdylib\"]\n"),
        );
        tmp
    }

    #[test]
    fn finds_exactly_the_cdylib_members_under_models() {
        let tmp = fake_workspace();
        let root = tmp.path();
        let models = discover_models(root).unwrap();
        let got: Vec<(&str, &str)> = models
            .iter()
            .map(|m| (m.package.as_str(), m.lib_name.as_str()))
            .collect();
        assert_eq!(
            got,
            [
                ("a-shaft", "shaft_lib"),
                ("motor-fan", "motor_fan"),
                ("rlc-circuit", "rlc_circuit"),
            ]
        );
        assert_eq!(models[1].dir, root.join("models/extra/motor-fan"));
        assert_eq!(models[0].dir, root.join("models/named"));
    }

    #[test]
    fn a_model_crate_inside_a_users_own_workspace_builds_in_that_workspace() {
        // A model crate without a [workspace] table of its own, a member of a larger workspace
        // (the user's): `build-fmus build <dir>` must build it there (cargo locate-project).
        let tmp = TempDir::new("user-workspace");
        let root = fs::canonicalize(tmp.path()).unwrap();
        write(&root, "Cargo.toml", "[workspace]\nresolver = \"2\"\nmembers = [\"drives/elevator\"]\n");
        write(&root, "drives/elevator/Cargo.toml", &package("elevator", "[lib]\ncrate-type = [\"cdylib\", \"rlib\"]\n"));
        write(&root, "drives/elevator/src/lib.rs", "// a model\n");
        let (model, workspace) = model_crate_at(&root.join("drives/elevator"), std::ffi::OsStr::new("cargo")).unwrap();
        assert_eq!((model.package.as_str(), model.lib_name.as_str()), ("elevator", "elevator"));
        assert_eq!(workspace, root);
        // Its own [workspace] table (a crate made by `build-fmus new`) makes it its own root.
        write(&root, "alone/Cargo.toml", &format!("{}\n[workspace]\n", package("alone", "[lib]\ncrate-type = [\"cdylib\"]\n")));
        let (_, own) = model_crate_at(&root.join("alone"), std::ffi::OsStr::new("cargo")).unwrap();
        assert_eq!(own, root.join("alone"));
    }

    #[test]
    fn root_detection_needs_a_workspace_table() {
        let tmp = fake_workspace();
        assert!(is_workspace_root(tmp.path()));
        assert!(!is_workspace_root(&tmp.path().join("models/rlc-circuit")));
        assert!(!is_workspace_root(&tmp.path().join("nowhere")));
    }

    #[test]
    fn a_missing_member_manifest_is_an_error_naming_the_file() {
        let tmp = TempDir::new("discover-missing");
        write(
            tmp.path(),
            "Cargo.toml",
            "[workspace]\nmembers = [\"models/gone\"]\n",
        );
        let err = discover_models(tmp.path()).unwrap_err();
        assert!(err.contains("models/gone/Cargo.toml"), "{err}");
    }

    #[test]
    fn a_broken_manifest_is_an_error_naming_the_file() {
        let tmp = TempDir::new("discover-broken");
        write(
            tmp.path(),
            "Cargo.toml",
            "[workspace]\nmembers = [\"models/bad\"]\n",
        );
        write(tmp.path(), "models/bad/Cargo.toml", "[package\nname = ");
        let err = discover_models(tmp.path()).unwrap_err();
        assert!(
            err.contains("could not parse") && err.contains("models/bad"),
            "{err}"
        );
    }

    #[test]
    fn a_manifest_without_workspace_is_an_error() {
        let tmp = TempDir::new("discover-noworkspace");
        write(tmp.path(), "Cargo.toml", &package("solo", ""));
        let err = discover_models(tmp.path()).unwrap_err();
        assert!(err.contains("no [workspace] table"), "{err}");
    }

    #[test]
    fn glob_matching() {
        assert!(glob_match("*", "rlc-circuit"));
        assert!(glob_match("rlc-*", "rlc-circuit"));
        assert!(glob_match("*-circuit", "rlc-circuit"));
        assert!(glob_match("r?c*", "rlc-circuit"));
        assert!(!glob_match("fan*", "rlc-circuit"));
        assert!(!glob_match("?", ""));
        assert!(glob_match("*", ""));
    }
}
