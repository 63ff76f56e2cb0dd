//! The date each FMU's modelDescription.xml gives as its `generationDateAndTime`: reproducible,
//! the same for the same source, never the clock's. `SOURCE_DATE_EPOCH` (the reproducible-builds
//! convention, seconds since 1970 UTC) if the caller set it, else the date of the last commit of
//! the project's git repository; without either the FMUs carry no date. `export_fmu!` reads the
//! variable when the model crate is compiled (cargo recompiles a model crate when it changes), so
//! the date is baked into the binary and the XML it writes at run time is the one packaged.

use std::path::Path;
use std::process::Command;

/// The variable `export_fmu!` reads at compile time.
pub const VAR: &str = "SOURCE_DATE_EPOCH";

/// The commit date of the last commit of the git repository holding `root`, in seconds.
pub fn commit_date(root: &Path) -> Option<String> {
    let out = Command::new("git").arg("-C").arg(root).args(["log", "-1", "--format=%ct"]).output().ok()?;
    if !out.status.success() {
        return None;
    }
    let date = String::from_utf8(out.stdout).ok()?.trim().to_owned();
    date.parse::<i64>().is_ok().then_some(date)
}

/// Sets `SOURCE_DATE_EPOCH` for the cargo build this process starts, from git, unless the caller
/// set it (an empty value counts as unset); returns the value the build uses (None: no date).
pub fn export(root: &Path) -> Option<String> {
    if let Some(set) = std::env::var_os(VAR).filter(|v| !v.is_empty()) {
        return set.into_string().ok();
    }
    let date = commit_date(root)?;
    std::env::set_var(VAR, &date);
    Some(date)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::TempDir;

    #[test]
    fn the_date_of_a_commit_or_none() {
        let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        if repo.join(".git").exists() {
            let date = commit_date(&repo).expect("a commit date in this repository");
            assert!(date.parse::<i64>().unwrap() > 1_600_000_000, "{date}");
            assert_eq!(commit_date(&repo), Some(date), "the same for the same commit");
        }
        // Outside any repository: no date rather than the clock's.
        let tmp = TempDir::new("source-date");
        if commit_date(&std::env::temp_dir()).is_none() {
            assert_eq!(commit_date(tmp.path()), None);
        }
    }
}
