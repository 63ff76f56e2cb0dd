//! The FMUs under test: every `*.fmu` in `dist/` (or in the folder named by `FMU_DIST_DIR`).

use std::path::PathBuf;
use std::sync::Arc;

use crate::Fmu;

/// `FMU_DIST_DIR`, or `<workspace>/dist`.
pub fn dist_dir() -> PathBuf {
    std::env::var_os("FMU_DIST_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..").join("dist"))
}

/// The paths of every FMU in the dist folder, sorted; panics with the build command if none.
pub fn every_fmu_path() -> Vec<PathBuf> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dist_dir())
        .expect("dist/ exists: run `cargo run --release -p build-fmus` first")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "fmu"))
        .collect();
    paths.sort();
    assert!(!paths.is_empty(), "no FMU in {:?}: run `cargo run --release -p build-fmus` first", dist_dir());
    paths
}

/// Every FMU in the dist folder, loaded.
pub fn every_fmu() -> Vec<Arc<Fmu>> {
    every_fmu_path().iter().map(|p| Fmu::load(p).unwrap_or_else(|e| panic!("{p:?}: {e}"))).collect()
}
