//! Every system declared in `models/systems/*.toml` (each written by build-fmus as
//! `dist/<Name>.ssp`) couples in the Rust master from that same declaration: its FMUs load from
//! `dist/`, its parameters are set by type, its connections resolve in a feedthrough order, and
//! it steps.
//!
//! `FMU_DIST_DIR` overrides the folder holding the FMUs (default `<workspace>/dist`).

use std::path::Path;

use fmi_host::dist::dist_dir;
use fmi_host::master::declaration::discover;
use fmi_host::master::{Master, System};
use fmi_host::Fmu;

#[test]
fn every_declared_system_couples_in_the_master() {
    let workspace = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let declarations = discover(&workspace).unwrap();
    let names: Vec<&str> = declarations.iter().map(|(_, d)| d.name.as_str()).collect();
    assert!(names.contains(&"MotorFanSystem") && names.contains(&"SteeringSystem"), "{names:?}");
    for (path, decl) in &declarations {
        let system = System::declared(decl, |id| {
            let fmu = dist_dir().join(format!("{id}.fmu"));
            Fmu::load(&fmu).unwrap_or_else(|e| panic!("{}: {e} (run `cargo run --release -p build-fmus` first)", fmu.display()))
        })
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert_eq!(system.components.len(), decl.components.len());
        assert_eq!(system.connections.len(), decl.connections.len());
        let set: usize = system.components.iter().map(|c| c.reals.len() + c.integers.len() + c.booleans.len()).sum();
        assert_eq!(set, decl.parameters.len(), "{}: every parameter is set", decl.name);
        let h = 1e-3;
        let outcome = Master::new(system, h, 10.0 * h)
            .run()
            .unwrap_or_else(|e| panic!("{}: {e}", decl.name));
        assert_eq!(outcome.stats.communication_steps, 10, "{}", decl.name);
    }
}
