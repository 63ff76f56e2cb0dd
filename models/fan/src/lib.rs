//! Fan: the reducer, the fan inertia and its aerodynamic load as an FMU of its own
//! (docs/motor-fan-system-spec.md). Torque in (on the reducer's high-speed shaft), speed out:
//! J_fan dw/dt = T_low - k w |w|, T_low from the reducer (ratio, efficiency by power direction).
//! Coupling expected: DriveShaft.torque -> `shaft_torque`, `angle_high`/`speed_high` ->
//! DriveShaft.angle_b/speed_b.

use components::{FanLoad, Inertia, Reducer, SHAFT_PORT};
use drive_train::{subsystem_info, FanParameters};
use fmu_runtime::prelude::*;

pub struct Fan {
    fan: FanParameters,
    shaft_torque: Input,
    w: State,
    angle: State,
    power_flow: Mode,
    power_reversal: Indicator,
    y_speed_high: Output,
    y_angle_high: Output,
    y_fan_speed: Output,
    y_aero_torque: Output,
    inertia: Element,
    reducer_loss: Element,
    load: Element,
    port: Element,
}

const DOCUMENTATION: &str = r#"
<p>The fan of the cooling tower (chapter 3, Figure 3.2) with its reducer as a subsystem: the torque on the reducer's
high-speed shaft reaches the fan as N eta T when the power flows to the fan and N T / eta when it flows back
(the direction is the discrete mode <code>reducer_power_flow</code>, switched at a state event where the power
T N w changes sign, as in MotorFan);
J_fan dw/dt = T_low - T_fan_nominal w |w| / speed_fan_nominal<sup>2</sup>. Seen from the high-speed axis the fan inertia is J_fan / N<sup>2</sup> = 11.72 kg m<sup>2</sup>
(eqs. 3.4-3.7).</p>
<p>Coupling: torque in, angle and speed out. Connect DriveShaft.torque to <code>shaft_torque</code>, and
<code>angle_high</code> and <code>speed_high</code> (the reducer input angle and speed, N x the fan's, states) to
DriveShaft.angle_b and speed_b. Input derivatives and first output
derivatives are supported for extrapolating masters.</p>
"#;

impl Fan {
    /// J_fan dw/dt = T_low - k w |w|, T_low through the reducer in the current power direction.
    fn acceleration<R: Real>(&self, k: &Knowns<R>) -> R {
        let reducer = self.fan.reducer(k);
        let low_torque = reducer.low_side_torque_flowing_n_m(k[self.shaft_torque], k[self.power_flow] >= 0);
        self.fan.inertia(k).acceleration_rad_per_s2(low_torque - self.fan.load(k).torque_n_m(k[self.w]))
    }
}

impl Model for Fan {
    fn info() -> ModelInfo {
        subsystem_info(
            "Fan",
            "Cooling-tower fan with its reducer and aerodynamic load, torque in / speed out (chapter 3, sections 3.1-3.3) as a co-simulation subsystem",
            5.0,
            DOCUMENTATION,
        )
    }

    /// Physical couplings (speeds, angles, torques) are smooth: extrapolate them by default, so
    /// masters that hold inputs over a step couple accurately (docs/motor-fan-system-spec.md).
    fn extrapolates_inputs() -> bool {
        true
    }

    fn declare(d: &mut Declarations) -> Self {
        Fan {
            fan: FanParameters::declare(d),
            shaft_torque: d.input("shaft_torque", 0.0, "N.m").describe("Torque on the reducer's high-speed shaft (connect DriveShaft.torque)"),
            w: d.state("w_fan", 0.0, "rad/s").nominal(10.0).describe("Fan speed (low-speed side)"),
            angle: d.state("phi_fan", 0.0, "rad").nominal(10.0).describe("Fan angle (low-speed side)"),
            power_flow: d.mode("reducer_power_flow", 1).range(-1, 1).describe(
                "Direction of the power through the reducer: 1 towards the fan (efficiency eta), -1 back (1/eta)",
            ),
            power_reversal: d.event_indicator(
                "reducer_power_reversal",
                "the power through the reducer, shaft_torque N w_fan, signed positive while reducer_power_flow holds",
            ),
            y_speed_high: d.output("speed_high", "rad/s").describe("Reducer input speed on the high-speed axis, N x fan speed"),
            y_angle_high: d.output("angle_high", "rad").describe("Reducer input angle on the high-speed axis, N x fan angle"),
            y_fan_speed: d.output("fan_speed", "rad/s").describe("Fan speed (low-speed side)"),
            y_aero_torque: d.output("aero_torque", "N.m").describe("Aerodynamic torque of the blades, T_fan_nominal w |w| / speed_fan_nominal^2"),
            inertia: d.element("inertia", "Fan", Effect { what: "blade inertia", ..Inertia::INERTIA }).describe("the fan inertia, power J dw/dt w"),
            reducer_loss: {
                d.element("reduction_ratio", "Reducer", Reducer::RATIO).describe("the reducer's ratio N, speed_high = N w_fan");
                d.element("reducer_efficiency", "Reducer", Reducer::EFFICIENCY).describe("the reducer's loss, shaft_torque N w_fan minus the power delivered to the fan")
            },
            load: d.element("aerodynamic_load", "Fan", FanLoad::LOAD).describe("the fan's aerodynamic load, power T_fan w_fan"),
            port: d.element("shaft_port", "Reducer", SHAFT_PORT).describe("the reducer's high-speed shaft, power shaft_torque N w_fan from the driveshaft"),
        }
    }

    /// The reducer's efficiency switches where the power through it reverses: a state event, as
    /// in MotorFan (the same `Reducer` rules from `components`), so the coupled system and the
    /// monolithic FMU integrate the same reducer and no solver step straddles the kink.
    fn event_indicators(&self, k: &Knowns, z: &mut EventIndicators) {
        let reducer = self.fan.reducer(k);
        z[self.power_reversal] = reducer.power_flow_indicator(k[self.power_flow], k[self.shaft_torque], reducer.ratio * k[self.w]);
    }

    /// At P = T N w = 0 the direction follows dP/dt; the input's own rate is unknown to the
    /// model, so dP/dt is taken as T N dw/dt (at rest with no torque the mode holds).
    fn update_modes(&self, k: &Knowns, next: &mut ModeUpdate) {
        let reducer = self.fan.reducer(k);
        let (torque, speed) = (k[self.shaft_torque], reducer.ratio * k[self.w]);
        let rate = torque * reducer.ratio * self.acceleration(k);
        next[self.power_flow] = reducer.next_power_flow(k[self.power_flow], torque * speed, rate);
    }

    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        let (inertia, w) = (self.fan.inertia(k), k[self.w]);
        let acceleration = self.acceleration(k);
        der[self.w] = acceleration;
        der[self.angle] = w;
        let reducer = self.fan.reducer(k);
        let (torque, speed_high) = (k[self.shaft_torque], reducer.ratio * w);
        der.power(self.inertia, inertia.power_w(acceleration, w));
        der.power(self.reducer_loss, reducer.loss_flowing_w(torque, speed_high, k[self.power_flow] >= 0));
        der.power(self.load, self.fan.load(k).torque_n_m(w) * w);
        der.power(self.port, torque * speed_high);
    }

    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        let w = k[self.w];
        out[self.y_speed_high] = self.fan.reducer(k).ratio * w;
        out[self.y_angle_high] = self.fan.reducer(k).ratio * k[self.angle];
        out[self.y_fan_speed] = w;
        out[self.y_aero_torque] = self.fan.load(k).torque_n_m(w);
    }
}

fmu_runtime::export_fmu!(Fan);
