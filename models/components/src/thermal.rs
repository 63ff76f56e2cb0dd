//! Heat transfer as lumped elements (chapter section 3.5.1, the thermal nodal diagrams of the
//! TGV motor): effort = temperature (K), flow = heat flow (W). A thermal node stores heat, a
//! conductance carries it between two nodes in proportion to their temperature difference —
//! the thermal twins of a capacitor and a resistor.

use fmu_runtime::real::Real;
use fmu_runtime::elements::{Domain, Effect, Kind};

/// A body at one uniform temperature: C dT/dt = net heat flow into it.
///
/// ```
/// use components::thermal::ThermalNode;
/// // 80 kg of copper: C = 80 kg x 385 J/(kg K) = 30.8 kJ/K.
/// let winding = ThermalNode::of_mass(80.0, 385.0);
/// assert_eq!(winding.heat_capacity_j_per_k, 30_800.0);
/// // 5 kW into it heats it at 5000 / 30800 = 0.162 K/s.
/// assert!((winding.temperature_rate_k_per_s(5_000.0) - 0.16234).abs() < 1e-5);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThermalNode<R = f64> {
    pub heat_capacity_j_per_k: R,
}

impl ThermalNode {
    /// Its effect (Table 3.1): a heat capacity, capacitive storage.
    pub const CAPACITY: Effect = Effect { domains: &[Domain::Thermal], kind: Kind::StorageC, what: "heat capacity" };
}

impl<R: Real> ThermalNode<R> {
    /// A node made of `mass_kg` of a material of specific heat `specific_heat_j_per_kg_k`.
    pub fn of_mass(mass_kg: R, specific_heat_j_per_kg_k: R) -> Self {
        ThermalNode { heat_capacity_j_per_k: mass_kg * specific_heat_j_per_kg_k }
    }

    /// dT/dt under a net heat flow into the node, K/s.
    pub fn temperature_rate_k_per_s(&self, net_heat_flow_w: R) -> R {
        net_heat_flow_w / self.heat_capacity_j_per_k
    }

    /// Heat stored above a reference temperature, C (T - T_ref), J.
    pub fn stored_heat_j(&self, temperature_k: R, reference_k: R) -> R {
        self.heat_capacity_j_per_k * (temperature_k - reference_k)
    }

    /// Two nodes lumped into one body at a single temperature: the capacities add.
    pub fn merged_with(&self, other: &ThermalNode<R>) -> ThermalNode<R> {
        ThermalNode { heat_capacity_j_per_k: self.heat_capacity_j_per_k + other.heat_capacity_j_per_k }
    }
}

/// A path for heat between two nodes (conduction through insulation, convection to the
/// cooling air): heat flow = G (T_hot - T_cold).
///
/// ```
/// use components::thermal::ThermalConductance;
/// // The chapter's nominal point: 5 kW of Joule losses give a 140 K rise, so G = 35.7 W/K.
/// let motor_to_air = ThermalConductance::from_operating_point(5_000.0, 140.0);
/// assert!((motor_to_air.conductance_w_per_k - 35.714).abs() < 1e-3);
/// assert!((motor_to_air.heat_flow_w(453.15, 313.15) - 5_000.0).abs() < 1e-9);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThermalConductance<R = f64> {
    pub conductance_w_per_k: R,
}

impl ThermalConductance {
    /// Its effect (Table 3.1): a thermal resistance (it passes its heat on: its activity is the
    /// heat flow through it, the energy balance leaves it out, see `fmu_runtime::elements`).
    pub const RESISTANCE: Effect = Effect { domains: &[Domain::Thermal], kind: Kind::Dissipation, what: "thermal resistance" };
}

impl<R: Real> ThermalConductance<R> {
    /// The conductance that carries `heat_flow_w` across a steady temperature drop `drop_k`.
    pub fn from_operating_point(heat_flow_w: R, drop_k: R) -> Self {
        ThermalConductance { conductance_w_per_k: heat_flow_w / drop_k }
    }

    /// Conduction across a flat layer (slot insulation): G = lambda A / e.
    /// ```
    /// use components::thermal::ThermalConductance;
    /// // 0.6 mm of insulation at 0.14 W/(m K) over 0.54 m2: R = 7.94 mK/W.
    /// let liner = ThermalConductance::through_layer(0.6e-3, 0.14, 0.54);
    /// assert!((1.0 / liner.conductance_w_per_k - 0.6e-3 / (0.14 * 0.54)).abs() < 1e-15);
    /// ```
    pub fn through_layer(thickness_m: R, conductivity_w_per_m_k: R, area_m2: R) -> Self {
        ThermalConductance { conductance_w_per_k: conductivity_w_per_m_k * area_m2 / thickness_m }
    }

    /// Convection from a surface to a fluid: G = h A.
    pub fn convection(coefficient_w_per_m2_k: R, area_m2: R) -> Self {
        ThermalConductance { conductance_w_per_k: coefficient_w_per_m2_k * area_m2 }
    }

    /// A conductance given as its thermal resistance R, K/W: G = 1/R.
    pub fn of_resistance(resistance_k_per_w: R) -> Self {
        ThermalConductance { conductance_w_per_k: R::from(1.0) / resistance_k_per_w }
    }

    /// Heat flow from the `from` node to the `to` node, W.
    pub fn heat_flow_w(&self, from_k: R, to_k: R) -> R {
        self.conductance_w_per_k * (from_k - to_k)
    }

    /// Two conductances one after the other (heat crossing both): 1/G = 1/G1 + 1/G2.
    pub fn in_series_with(&self, other: &ThermalConductance<R>) -> ThermalConductance<R> {
        let g = R::from(1.0) / (R::from(1.0) / self.conductance_w_per_k + R::from(1.0) / other.conductance_w_per_k);
        ThermalConductance { conductance_w_per_k: g }
    }

    /// Steady temperature drop across the conductance under a heat flow, K.
    pub fn steady_drop_k(&self, heat_flow_w: R) -> R {
        heat_flow_w / self.conductance_w_per_k
    }

    /// Time constant of a node cooling through this conductance alone, C / G, s.
    pub fn time_constant_s(&self, node: &ThermalNode<R>) -> R {
        node.heat_capacity_j_per_k / self.conductance_w_per_k
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn series_conductances_add_their_drops() {
        let (a, b) = (ThermalConductance { conductance_w_per_k: 50.0 }, ThermalConductance { conductance_w_per_k: 200.0 });
        let ab = a.in_series_with(&b);
        // 1 kW: 20 K + 5 K = 25 K, i.e. G = 40 W/K.
        assert!((ab.steady_drop_k(1000.0) - (a.steady_drop_k(1000.0) + b.steady_drop_k(1000.0))).abs() < 1e-12);
        assert!((ab.conductance_w_per_k - 40.0).abs() < 1e-12);
    }

    #[test]
    fn a_node_relaxes_with_the_time_constant_c_over_g() {
        // Explicit Euler with a tiny step against the exponential e^{-t/tau}, tau = C/G.
        let node = ThermalNode::of_mass(10.0, 500.0);
        let g = ThermalConductance { conductance_w_per_k: 25.0 };
        let tau = g.time_constant_s(&node);
        assert_eq!(tau, 200.0);
        let (mut t, dt) = (100.0f64, 0.01);
        for _ in 0..(tau / dt) as usize {
            t += dt * node.temperature_rate_k_per_s(-g.heat_flow_w(t, 0.0));
        }
        assert!((t - 100.0 * (-1.0f64).exp()).abs() < 1e-3, "{t}");
        assert_eq!(node.merged_with(&node).heat_capacity_j_per_k, 10_000.0);
        assert_eq!(node.stored_heat_j(12.0, 10.0), 10_000.0);
    }
}
