//! The components run over `fmu_runtime::real::Dual` give exact directional derivatives: each
//! checked against a sixth-order central difference of the same component run over `f64` (an
//! independent computation: six more plain evaluations), and the Dual's value against the f64
//! value bit for bit. The components are written once, over `R: Real`.

use components::{Fluxes, InductionMachine, Interpolation, Orifice, FanLoad, Inertia, Reducer, TorqueSpeedTable, TorsionSpring};
use fmu_runtime::real::{Dual, Real};

/// The derivative of `f` at `x` along x by Dual, by a sixth-order central difference of `f`
/// over f64 with step `h`, and whether the Dual's value is the f64 value bit for bit.
fn both(f: impl Fn(Dual) -> Dual, g: impl Fn(f64) -> f64, x: f64, h: f64) -> (f64, f64, bool) {
    let dual = f(Dual::new(x, 1.0));
    let d = |k: f64| g(x + k * h);
    let fd = (45.0 * (d(1.0) - d(-1.0)) - 9.0 * (d(2.0) - d(-2.0)) + (d(3.0) - d(-3.0))) / (60.0 * h);
    (dual.eps, fd, dual.re.to_bits() == g(x).to_bits())
}

/// Asserts the derivative agrees within `tolerance` (relative) and the value bit for bit, and
/// prints the figures.
fn check(what: &str, f: impl Fn(Dual) -> Dual, g: impl Fn(f64) -> f64, x: f64, h: f64, tolerance: f64) {
    let (ad, fd, same_value) = both(f, g, x, h);
    let relative = (ad - fd).abs() / fd.abs().max(f64::MIN_POSITIVE);
    println!("{what:<58} at {x:>12.6e}: AD {ad:>+.15e}  difference {fd:>+.15e}  relative {relative:.1e}");
    assert!(same_value, "{what}: the Dual's value is not the f64 value");
    assert!(relative <= tolerance, "{what} at {x}: AD {ad} against differences {fd} (relative {relative:.2e})");
}

/// The 160 kW, 400 V, 4-pole machine of the MotorFan model, its rotor resistance given.
fn machine<R: Real>(rotor_resistance_ohm: R) -> InductionMachine<R> {
    let p = |x: f64| R::from(x);
    InductionMachine {
        stator_resistance_ohm: p(0.012),
        rotor_resistance_ohm,
        stator_leakage_h: p(2.5e-4),
        rotor_leakage_h: p(2.5e-4),
        magnetizing_h: p(0.01),
        pole_pairs: p(2.0),
        line_voltage_rms_v: p(400.0),
        frequency_hz: p(50.0),
    }
}

#[test]
fn induction_machine_torque_by_speed_and_by_rotor_resistance() {
    // The T-equivalent circuit's torque (complex arithmetic over Dual) along the rotor speed,
    // on the stable branch, near the breakdown and as a brake (above synchronism).
    for w in [40.0, 140.0, 150.0, 155.0, 160.0] {
        check(
            "InductionMachine::steady_state(w).torque_n_m, d/dw",
            |w| machine(Dual::from(0.010)).steady_state(w).torque_n_m,
            |w| machine(0.010).steady_state(w).torque_n_m,
            w,
            1e-2,
            1e-8,
        );
    }
    // Along a parameter: the rotor resistance (the machine built of Duals).
    check(
        "InductionMachine::steady_state(150).torque_n_m, d/dR_r",
        |r| machine(r).steady_state(Dual::from(150.0)).torque_n_m,
        |r| machine(r).steady_state(150.0).torque_n_m,
        0.010,
        1e-5,
        1e-8,
    );
    // The dq model's torque along a flux (the level-d right-hand side).
    let psi = |sd: Dual| Fluxes { stator_d: sd, stator_q: Dual::from(-0.9), rotor_d: Dual::from(0.25), rotor_q: Dual::from(-0.8) };
    check(
        "InductionMachine::dq_response(psi, 150).torque_n_m, d/dpsi_sd",
        |sd| machine(Dual::from(0.010)).dq_response(psi(sd), Dual::from(150.0)).torque_n_m,
        |sd| machine(0.010).dq_response(Fluxes { stator_d: sd, stator_q: -0.9, rotor_d: 0.25, rotor_q: -0.8 }, 150.0).torque_n_m,
        0.3,
        1e-3,
        1e-8,
    );
}

#[test]
fn the_slip_for_a_torque_carries_the_derivatives_of_its_implicit_function() {
    // stable_slip_for_torque is a root (bisection on values, then the implicit function's
    // derivatives): along the torque, along the rotor resistance, and beyond the breakdown
    // torque (clamped: the breakdown slip's derivative).
    for t in [-1500.0, 300.0, 1000.0, 2500.0] {
        check(
            "InductionMachine::stable_slip_for_torque(T), d/dT",
            |t| machine(Dual::from(0.010)).stable_slip_for_torque(t),
            |t| machine(0.010).stable_slip_for_torque(t),
            t,
            1.0,
            1e-7,
        );
    }
    check(
        "InductionMachine::stable_slip_for_torque(1000), d/dR_r",
        |r| machine(r).stable_slip_for_torque(Dual::from(1000.0)),
        |r| machine(r).stable_slip_for_torque(1000.0),
        0.010,
        1e-5,
        1e-7,
    );
    let beyond = machine(0.010).steady_state_at_slip(machine(0.010).breakdown_slip()).torque_n_m * 1.5;
    check(
        "InductionMachine::stable_slip_for_torque(beyond breakdown), d/dR_r",
        |r| machine(r).stable_slip_for_torque(Dual::from(beyond)),
        |r| machine(r).stable_slip_for_torque(beyond),
        0.010,
        1e-5,
        1e-7,
    );
}

#[test]
fn a_turbulent_orifice_flow_by_pressure_and_by_area() {
    let orifice = |area: Dual| Orifice { discharge_coefficient: Dual::from(0.61), area_m2: area, density_kg_per_m3: Dual::from(850.0) };
    let plain = |area: f64| Orifice { discharge_coefficient: 0.61, area_m2: area, density_kg_per_m3: 850.0 };
    for dp in [-3e6, 2e5, 2e6] {
        check(
            "Orifice::flow_m3_per_s(dp), d/ddp",
            |dp| orifice(Dual::from(7.85e-7)).flow_m3_per_s(dp),
            |dp| plain(7.85e-7).flow_m3_per_s(dp),
            dp,
            1e-3 * dp.abs(),
            1e-8,
        );
    }
    check(
        "Orifice::flow_m3_per_s(2e6), d/dA",
        |a| orifice(a).flow_m3_per_s(Dual::from(2e6)),
        |a| plain(a).flow_m3_per_s(2e6),
        7.85e-7,
        1e-9,
        1e-8,
    );
}

/// The book's torque-speed table (Chap3_CoolingTowerFan.mo, TorqueSpeed).
fn book<R: Real>(interpolation: Interpolation) -> TorqueSpeedTable<10, R> {
    TorqueSpeedTable {
        speed_rad_per_s: [0.0, 80.0, 160.0, 220.0, 240.0, 250.0, 260.0, 280.0, 300.0, 314.0].map(R::from),
        torque_n_m: [454.0, 579.0, 784.0, 997.0, 1057.0, 1071.0, 1060.0, 919.0, 500.0, 0.0].map(R::from),
        interpolation,
    }
}

#[test]
fn an_akima_table_read_at_a_dual_speed() {
    // Inside segments (the cubic), and beyond the last point (its tangent).
    for (interpolation, w) in [(Interpolation::Akima, 120.0), (Interpolation::Akima, 245.0), (Interpolation::Akima, 291.3), (Interpolation::Akima, 330.0), (Interpolation::Linear, 270.0)] {
        let (table, plain) = (book::<Dual>(interpolation), book::<f64>(interpolation));
        check(&format!("TorqueSpeedTable::torque_n_m(w) ({interpolation:?}), d/dw"), |w| table.torque_n_m(w), |w| plain.torque_n_m(w), w, 0.05, 1e-8);
    }
    // Along a point of the table (its ordinates are a model's parameters): the torque at the
    // 250 rad/s point moves the curve around it.
    let moved = |t: Dual| {
        let mut table = book::<Dual>(Interpolation::Akima);
        table.torque_n_m[5] = t;
        table
    };
    let moved_plain = |t: f64| {
        let mut table = book::<f64>(Interpolation::Akima);
        table.torque_n_m[5] = t;
        table
    };
    check("TorqueSpeedTable::torque_n_m(245) (Akima), d/dT_5", |t| moved(t).torque_n_m(Dual::from(245.0)), |t| moved_plain(t).torque_n_m(245.0), 1071.0, 0.05, 1e-8);
    // The operating point under a fan load k w^2 is a root (bisection on values); its
    // derivative along the load's coefficient, or along a point of the table, is the implicit
    // function's.
    let speed = |k: Dual| book::<Dual>(Interpolation::Akima).stable_speed_rad_per_s(|w: Dual| w * w * k).unwrap();
    let plain = |k: f64| book::<f64>(Interpolation::Akima).stable_speed_rad_per_s(|w: f64| w * w * k).unwrap();
    check("TorqueSpeedTable::stable_speed_rad_per_s(k w^2), d/dk", speed, plain, 0.01, 1e-5, 1e-7);
    let at_point = |t: Dual| {
        let mut table = book::<Dual>(Interpolation::Akima);
        table.torque_n_m[8] = t;
        table.stable_speed_rad_per_s(|w: Dual| w * w * 0.01).unwrap()
    };
    let at_point_plain = |t: f64| {
        let mut table = book::<f64>(Interpolation::Akima);
        table.torque_n_m[8] = t;
        table.stable_speed_rad_per_s(|w: f64| w * w * 0.01).unwrap()
    };
    check("TorqueSpeedTable::stable_speed_rad_per_s(k w^2), d/dT_8", at_point, at_point_plain, 500.0, 0.5, 1e-7);
    // The same balance with the circuit's torque (InductionMachine::stable_speed_rad_per_s).
    let load = FanLoad { coefficient_n_m_s2_per_rad2: 0.04 };
    check(
        "InductionMachine::stable_speed_rad_per_s(fan), d/dR_r",
        |r| machine(r).stable_speed_rad_per_s(|w| FanLoad { coefficient_n_m_s2_per_rad2: Dual::from(0.04) }.torque_n_m(w)).unwrap(),
        |r| machine(r).stable_speed_rad_per_s(|w| load.torque_n_m(w)).unwrap(),
        0.010,
        1e-5,
        1e-7,
    );
}

#[test]
fn the_motor_fan_level_c_right_hand_side_along_a_state() {
    // The crate's own example (lib.rs): the accelerations of motor and fan and the twist rate,
    // along the fan speed, through the inertias, the shaft, the lossy reducer and the blades.
    fn rhs<R: Real>(w_fan: R) -> R {
        let motor = Inertia { inertia_kg_m2: R::from(1.72) };
        let shaft = TorsionSpring { stiffness_n_m_per_rad: R::from(906.85), damping_n_m_s_per_rad: R::from(5.0) };
        let gear = Reducer { ratio: R::from(10.0), efficiency: R::from(0.97) };
        let fan = Inertia { inertia_kg_m2: R::from(1172.0) };
        let blades = FanLoad { coefficient_n_m_s2_per_rad2: R::from(42.9) };
        let (w_motor, twist, torque_motor) = (R::from(100.0), R::from(0.5), R::from(1000.0));
        let w_high = w_fan * gear.ratio;
        let t_shaft = shaft.torque_n_m(twist, w_motor - w_high);
        let dw_motor = motor.acceleration_rad_per_s2(torque_motor - t_shaft);
        let dw_fan = fan.acceleration_rad_per_s2(gear.low_side_torque_n_m(t_shaft, w_high) - blades.torque_n_m(w_fan));
        dw_motor * 3.0 + dw_fan
    }
    for w_fan in [2.0, 9.9, 12.0] {
        check("motor-fan level c: 3 dw_motor/dt + dw_fan/dt, d/dw_fan", rhs::<Dual>, rhs::<f64>, w_fan, 1e-3, 1e-8);
    }
}
