//! The FMUs under test: every `*.fmu` in `dist/` (or in the folder named by `FMU_DIST_DIR`), and
//! their FMI 3.0 builds in `dist/fmi3/` (`<dist>/fmi3`).
//!
//! [`versions`] is the FMI versions the version-aware tests run: both, unless `FMI_VERSIONS`
//! names a subset (`FMI_VERSIONS=2`, `FMI_VERSIONS=3`, `FMI_VERSIONS=2,3`).

use std::path::PathBuf;
use std::sync::Arc;

use crate::{Fmu, FmiVersion};

/// `FMU_DIST_DIR`, or `<workspace>/dist`: the FMI 2.0 FMUs.
pub fn dist_dir() -> PathBuf {
    std::env::var_os("FMU_DIST_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..").join("dist"))
}

/// The folder of one version's FMUs: [`dist_dir`] (FMI 2.0) or its `fmi3` folder (FMI 3.0).
pub fn dist_dir_for(version: FmiVersion) -> PathBuf {
    match version {
        FmiVersion::Fmi2 => dist_dir(),
        FmiVersion::Fmi3 => dist_dir().join("fmi3"),
    }
}

/// The FMI versions to test: `FMI_VERSIONS` (`2`, `3` or `2,3`), else both.
pub fn versions() -> Vec<FmiVersion> {
    let Some(text) = std::env::var("FMI_VERSIONS").ok().filter(|t| !t.trim().is_empty()) else {
        return vec![FmiVersion::Fmi2, FmiVersion::Fmi3];
    };
    let mut versions: Vec<FmiVersion> = text
        .split(',')
        .map(|v| match v.trim() {
            "2" | "2.0" => FmiVersion::Fmi2,
            "3" | "3.0" => FmiVersion::Fmi3,
            other => panic!("FMI_VERSIONS={text:?}: {other:?} is not 2 or 3"),
        })
        .collect();
    versions.sort();
    versions.dedup();
    versions
}

/// The paths of every FMU of one version, sorted; panics with the build command if none.
pub fn every_fmu_path_for(version: FmiVersion) -> Vec<PathBuf> {
    let dir = dist_dir_for(version);
    let mut paths: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| {
            panic!("{dir:?} ({version}): {e}: run `cargo run --release -p build-fmus` first (or set FMI_VERSIONS to the versions you have)")
        })
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "fmu"))
        .collect();
    paths.sort();
    assert!(!paths.is_empty(), "no FMU in {dir:?}: run `cargo run --release -p build-fmus` first");
    paths
}

/// The paths of every FMI 2.0 FMU in the dist folder, sorted; panics with the build command if none.
pub fn every_fmu_path() -> Vec<PathBuf> {
    every_fmu_path_for(FmiVersion::Fmi2)
}

/// Every FMU of one version, loaded (and checked to be of that version).
pub fn every_fmu_for(version: FmiVersion) -> Vec<Arc<Fmu>> {
    every_fmu_path_for(version)
        .iter()
        .map(|p| {
            let fmu = Fmu::load(p).unwrap_or_else(|e| panic!("{p:?}: {e}"));
            assert_eq!(fmu.fmi_version(), version, "{p:?}: fmiVersion {}", fmu.model_description().fmi_version);
            fmu
        })
        .collect()
}

/// Every FMI 2.0 FMU in the dist folder, loaded.
pub fn every_fmu() -> Vec<Arc<Fmu>> {
    every_fmu_for(FmiVersion::Fmi2)
}

/// Every FMU of every version of [`versions`] (FMI 2.0's first), loaded.
pub fn every_fmu_of_every_version() -> Vec<Arc<Fmu>> {
    versions().into_iter().flat_map(every_fmu_for).collect()
}
