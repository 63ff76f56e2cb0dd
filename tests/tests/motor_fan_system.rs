//! Acceptance of the subsystem FMUs (docs/motor-fan-system-spec.md) coupled by the Rust master
//! (`fmi_host::master`) against the monolithic MotorFan at level c:
//!
//! "Coupled runs of the direct-on-line start at communication step 1 ms agree with monolithic
//! MotorFan level c: fan speed within 0.5 % of rated speed at every output point, peak shaft
//! torque within 3 %."
//!
//! Rated speed: the monolithic final fan speed (15.35 rad/s). Both runs are sampled on the
//! same 1 ms grid over 30 s. `FMU_DIST_DIR` overrides the folder holding the FMUs.

mod coupling;

use coupling::{compare, Figures, Fmus, Scenario, Setup, STOP_TIME};

const STEP: f64 = 1e-3;
const FAN_SPEED_TOLERANCE_PCT: f64 = 0.5;
const PEAK_TORQUE_TOLERANCE_PCT: f64 = 3.0;

fn check(scenario: Scenario, setup: Setup) -> Figures {
    let fmus = Fmus::load();
    let monolithic = fmus.monolithic(scenario, STEP);
    let coupled = fmus.coupled(scenario, &setup, STEP);
    assert_eq!(coupled.results.len(), 30_001);
    assert_eq!(*coupled.results.time().last().unwrap(), STOP_TIME);
    let f = compare(&coupled, &monolithic);
    eprintln!(
        "{} at 1 ms: fan speed error max {:.3} % of {:.3} rad/s (t = {:.3} s); peak shaft torque {:.1} vs {:.1} N m ({:.3} %)",
        setup.name, f.max_fan_speed_error_pct, f.rated_fan_speed, f.max_fan_speed_error_time,
        f.peak_torque, f.peak_torque_monolithic, f.peak_torque_error_pct
    );
    assert!(
        f.max_fan_speed_error_pct <= FAN_SPEED_TOLERANCE_PCT,
        "{}: fan speed off by {:.3} % of rated at t = {} s",
        setup.name, f.max_fan_speed_error_pct, f.max_fan_speed_error_time
    );
    assert!(
        f.peak_torque_error_pct <= PEAK_TORQUE_TOLERANCE_PCT,
        "{}: peak shaft torque {} vs {} N m",
        setup.name, f.peak_torque, f.peak_torque_monolithic
    );
    f
}

/// The coupled system is read from `models/systems/MotorFanSystem.toml`, the SSP's declaration:
/// it is the spec's direct-on-line coupling, and the PI start adds the controller to it.
#[test]
fn the_coupled_system_is_the_declared_direct_on_line_coupling() {
    let fmus = Fmus::load();
    let dol = fmus.system(Scenario::DIRECT_ON_LINE);
    let names: Vec<&str> = dol.components.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["InductionMotor", "DriveShaft", "Fan"], "the Gauss-Seidel order");
    let connections: Vec<String> = dol.connections.iter().map(|c| c.to_string()).collect();
    let direct_on_line = [
        "InductionMotor.angle -> DriveShaft.angle_a",
        "Fan.angle_high -> DriveShaft.angle_b",
        "InductionMotor.speed -> DriveShaft.speed_a",
        "Fan.speed_high -> DriveShaft.speed_b",
        "DriveShaft.torque -> InductionMotor.load_torque",
        "DriveShaft.torque -> Fan.shaft_torque",
    ];
    assert_eq!(connections, direct_on_line);
    assert_eq!(dol.components[0].integers, [("drive".to_owned(), 1)], "the machine drives the motor");
    assert!(dol.components.iter().all(|c| c.reals.is_empty() && c.booleans.is_empty()));
    assert!(dol.components[1..].iter().all(|c| c.integers.is_empty()));

    let pi = fmus.system(Scenario { gear_efficiency: Some(1.0), ..Scenario::PI_START });
    let names: Vec<&str> = pi.components.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["InductionMotor", "DriveShaft", "Fan", "SpeedController"]);
    let connections: Vec<String> = pi.connections.iter().map(|c| c.to_string()).collect();
    assert_eq!(connections[..6], direct_on_line);
    assert_eq!(
        connections[6..],
        ["InductionMotor.speed -> SpeedController.measured_speed", "SpeedController.torque_command -> InductionMotor.torque_command"]
    );
    assert_eq!(pi.components[0].integers, [("drive".to_owned(), 2)], "torque_command drives the motor");
    assert_eq!(pi.components[2].reals, [("gear_efficiency".to_owned(), 1.0)]);
    let controller: Vec<(&str, f64)> = pi.components[3].reals.iter().map(|(n, v)| (n.as_str(), *v)).collect();
    assert_eq!(controller, Fmus::PI_COUPLED);
}

#[test]
fn direct_on_line_jacobi_at_1ms_agrees_with_monolithic_level_c() {
    check(Scenario::DIRECT_ON_LINE, Setup::jacobi());
}

#[test]
fn direct_on_line_gauss_seidel_at_1ms_agrees_with_monolithic_level_c() {
    check(Scenario::DIRECT_ON_LINE, Setup::gauss_seidel());
}

/// The controlled start (start_mode 2) with the SpeedController in the loop, same criteria.
#[test]
fn pi_start_with_the_speed_controller_at_1ms_agrees_with_monolithic_level_c() {
    check(Scenario::PI_START, Setup::jacobi());
    check(Scenario::PI_START, Setup::gauss_seidel());
}

/// Step rejection on the real subsystems at a coarse 10 ms communication step: steps are
/// rejected and redone from restored FMU states, the run reaches 30 s with every 10 ms point
/// recorded, and it is closer to the monolithic run than the same master without rejection.
#[test]
fn step_rejection_at_10ms_rejects_steps_and_improves_the_coupled_run() {
    let fmus = Fmus::load();
    let h = 1e-2;
    let monolithic = fmus.monolithic(Scenario::DIRECT_ON_LINE, h);
    let plain = fmus.coupled(Scenario::DIRECT_ON_LINE, &Setup::jacobi(), h);
    let controlled = fmus.coupled(Scenario::DIRECT_ON_LINE, &Setup::jacobi().error_control(1e-3), h);
    let s = &controlled.stats;
    eprintln!("{s:?}");
    assert!(s.rejected_steps > 0, "{s:?}");
    assert!(s.accepted_steps > s.communication_steps, "{s:?}");
    assert_eq!(s.communication_steps, 3000);
    assert_eq!(controlled.results.time(), plain.results.time());
    let (e_plain, e_controlled) = (compare(&plain, &monolithic), compare(&controlled, &monolithic));
    eprintln!(
        "10 ms Jacobi: fan speed error {:.3} % plain, {:.3} % with rejection",
        e_plain.max_fan_speed_error_pct, e_controlled.max_fan_speed_error_pct
    );
    assert!(e_controlled.max_fan_speed_error_pct < 0.5 * e_plain.max_fan_speed_error_pct);
}
