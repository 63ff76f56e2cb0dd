//! The motor-fan start-up coupled from its subsystem FMUs (docs/motor-fan-system-spec.md) and
//! compared with the monolithic `MotorFan.fmu` at level c. Shared by the acceptance test
//! `tests/motor_fan_system.rs` and the example `examples/coupling_table.rs`.
//!
//! `FMU_DIST_DIR` overrides the folder holding the FMUs (default `<workspace>/dist`).
#![allow(dead_code)]

use std::sync::Arc;

use fmi_host::master::declaration::workspace_system;
use fmi_host::master::{Algorithm, Component, ErrorControl, Master, Outcome, System};
use fmi_host::dist::dist_dir;
use fmi_host::Fmu;

/// Simulated time of the start-up, s (MotorFan's DefaultExperiment).
pub const STOP_TIME: f64 = 30.0;

pub fn load(model: &str) -> Arc<Fmu> {
    let path = dist_dir().join(format!("{model}.fmu"));
    Fmu::load(&path).unwrap_or_else(|e| {
        panic!("{}: {e} (run `cargo run --release -p build-fmus` first)", path.display())
    })
}

/// Which start-up is compared.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scenario {
    /// MotorFan's start_mode: 1 = direct on line, 2 = PI speed control (adds the
    /// SpeedController and sets InductionMotor.drive = 2).
    pub start_mode: i32,
    /// `gear_efficiency` set in both MotorFan and Fan; None: the default (0.94, the book's).
    pub gear_efficiency: Option<f64>,
}

impl Scenario {
    pub const DIRECT_ON_LINE: Scenario = Scenario { start_mode: 1, gear_efficiency: None };
    pub const PI_START: Scenario = Scenario { start_mode: 2, gear_efficiency: None };
}

/// The four subsystem FMUs and the monolithic one, loaded once.
pub struct Fmus {
    pub motor: Arc<Fmu>,
    pub shaft: Arc<Fmu>,
    pub fan: Arc<Fmu>,
    pub controller: Arc<Fmu>,
    pub monolithic: Arc<Fmu>,
}

impl Fmus {
    pub fn load() -> Fmus {
        Fmus {
            motor: load("InductionMotor"),
            shaft: load("DriveShaft"),
            fan: load("Fan"),
            controller: load("SpeedController"),
            monolithic: load("MotorFan"),
        }
    }

    /// The FMU of a modelIdentifier the system names.
    fn of(&self, identifier: &str) -> Arc<Fmu> {
        Arc::clone(match identifier {
            "InductionMotor" => &self.motor,
            "DriveShaft" => &self.shaft,
            "Fan" => &self.fan,
            "SpeedController" => &self.controller,
            other => panic!("MotorFanSystem names {other:?}, which these tests do not load"),
        })
    }

    /// The coupled system: MotorFanSystem as `models/systems/MotorFanSystem.toml` declares it
    /// for `dist/MotorFanSystem.ssp` (motor, shaft, fan, in this order, which is the Gauss-Seidel
    /// order; the direct-on-line connections and `InductionMotor.drive = 1`), with the
    /// scenario's changes: `gear_efficiency` in the Fan, and for the PI start `drive = 2` and the
    /// SpeedController in the loop (not part of the SSP).
    /// The PI start is coupled with the chapter's first controller (Kp 200, Ki 2000, limit
    /// 2500 N m), not the book's: the book's Kp = 10000 N m s/rad on the motor's 1.72 kg m2 closes
    /// a speed loop at 5800 rad/s, which a 1 ms communication step (the master samples the speed
    /// and holds the command for a step: 5.8 rad per step, beyond the 2 that such a sampled loop
    /// tolerates) makes unstable, and the book's 2*3.14*800 rad/s torque actuator lag belongs to
    /// the monolithic converter only (SpeedController has none). Both sides get these values.
    pub const PI_COUPLED: [(&'static str, f64); 3] = [("Kp_speed", 200.0), ("Ki_speed", 2000.0), ("T_limit", 2500.0)];

    pub fn system(&self, scenario: Scenario) -> System {
        let declaration = workspace_system("MotorFanSystem").unwrap_or_else(|e| panic!("{e}"));
        let mut system = System::declared(&declaration, |id| self.of(id))
            .unwrap_or_else(|e| panic!("MotorFanSystem: {e}"));
        fn component<'a>(system: &'a mut System, name: &str) -> &'a mut Component {
            system.component_mut(name).unwrap_or_else(|e| panic!("MotorFanSystem: {e}"))
        }
        if let Some(eta) = scenario.gear_efficiency {
            component(&mut system, "Fan").set_real("gear_efficiency", eta);
        }
        if scenario.start_mode == 2 {
            component(&mut system, "InductionMotor").set_integer("drive", 2);
            let controller = Self::PI_COUPLED.iter().fold(Component::new("SpeedController", &self.controller), |c, (name, v)| c.real(*name, *v));
            system
                .with(controller)
                .connect("InductionMotor.speed", "SpeedController.measured_speed")
                .connect("SpeedController.torque_command", "InductionMotor.torque_command")
        } else {
            system
        }
    }

    /// The coupled start-up run with `setup` at communication step `h`: records fan speed and
    /// shaft torque.
    pub fn coupled(&self, scenario: Scenario, setup: &Setup, h: f64) -> Outcome {
        let master = setup
            .apply(Master::new(self.system(scenario), h, STOP_TIME))
            .record(["Fan.fan_speed", "DriveShaft.torque", "InductionMotor.speed"]);
        master.run().unwrap_or_else(|e| panic!("{}: {e}", setup.name))
    }

    /// MotorFan level c, sampled every `h`.
    pub fn monolithic(&self, scenario: Scenario, h: f64) -> Outcome {
        let mut motor_fan = Component::new("MotorFan", &self.monolithic)
            .integer("level", 3)
            .integer("start_mode", scenario.start_mode);
        if let Some(eta) = scenario.gear_efficiency {
            motor_fan = motor_fan.real("gear_efficiency", eta);
        }
        if scenario.start_mode == 2 {
            motor_fan = Self::PI_COUPLED.iter().fold(motor_fan, |c, (name, v)| c.real(*name, *v)).real("actuator_angular_frequency", 0.0);
        }
        Master::new(System::new().with(motor_fan), h, STOP_TIME)
            .record(["MotorFan.fan_speed", "MotorFan.shaft_torque", "MotorFan.motor_speed"])
            .run()
            .unwrap_or_else(|e| panic!("MotorFan: {e}"))
    }
}

/// A way of running the master: algorithm and options.
#[derive(Clone, Debug)]
pub struct Setup {
    pub name: String,
    pub algorithm: Algorithm,
    pub extrapolation: bool,
    pub error_control: Option<ErrorControl>,
}

impl Setup {
    fn apply(&self, master: Master) -> Master {
        master
            .algorithm(self.algorithm.clone())
            .extrapolation(self.extrapolation)
            .error_control(self.error_control)
    }

    /// Jacobi with the master's defaults (input extrapolation, no error control).
    pub fn jacobi() -> Setup {
        Setup { name: "Jacobi".into(), algorithm: Algorithm::Jacobi, extrapolation: true, error_control: None }
    }

    /// Gauss-Seidel in the order motor, shaft, fan (, controller), the master's defaults.
    pub fn gauss_seidel() -> Setup {
        Setup {
            name: "Gauss-Seidel".into(),
            algorithm: Algorithm::gauss_seidel(),
            extrapolation: true,
            error_control: None,
        }
    }

    /// Inputs held constant over a step (no input derivatives).
    pub fn held(mut self) -> Setup {
        self.extrapolation = false;
        self.name.push_str(", inputs held");
        self
    }

    /// With step rejection at this tolerance.
    pub fn error_control(mut self, tolerance: f64) -> Setup {
        self.error_control = Some(ErrorControl::new(tolerance));
        self.name.push_str(&format!(", error control {tolerance:e}"));
        self
    }
}

/// The acceptance figures of a coupled run against the monolithic one on the same grid.
#[derive(Clone, Copy, Debug)]
pub struct Figures {
    /// Rated fan speed: the monolithic final fan speed, rad/s.
    pub rated_fan_speed: f64,
    /// Largest |fan speed difference| over every output point, % of the rated speed.
    pub max_fan_speed_error_pct: f64,
    /// Time of that largest difference, s.
    pub max_fan_speed_error_time: f64,
    /// Peak |shaft torque|, coupled and monolithic, N m.
    pub peak_torque: f64,
    pub peak_torque_monolithic: f64,
    /// |peak - monolithic peak| / monolithic peak, %.
    pub peak_torque_error_pct: f64,
}

pub fn compare(coupled: &Outcome, monolithic: &Outcome) -> Figures {
    let t = coupled.results.time();
    assert_eq!(t, monolithic.results.time(), "same output grid");
    let w = coupled.results.column("Fan.fan_speed").unwrap();
    let w_ref = monolithic.results.column("MotorFan.fan_speed").unwrap();
    let rated = *w_ref.last().unwrap();
    let (mut max_err, mut at) = (0.0f64, 0.0);
    for ((a, b), time) in w.iter().zip(w_ref).zip(t) {
        let e = (a - b).abs();
        if e > max_err || e.is_nan() {
            max_err = e;
            at = *time;
        }
    }
    let peak = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let peak_torque = peak(coupled.results.column("DriveShaft.torque").unwrap());
    let peak_torque_monolithic = peak(monolithic.results.column("MotorFan.shaft_torque").unwrap());
    Figures {
        rated_fan_speed: rated,
        max_fan_speed_error_pct: 100.0 * max_err / rated,
        max_fan_speed_error_time: at,
        peak_torque,
        peak_torque_monolithic,
        peak_torque_error_pct: 100.0 * (peak_torque - peak_torque_monolithic).abs()
            / peak_torque_monolithic,
    }
}
