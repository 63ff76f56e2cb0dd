//! Parameters from elementary geometries (chapter section 3.2.2, eqs. 3.1-3.2 and Table 3.2), so
//! that a spec can derive a lumped parameter from a drawing and a material: the storage and
//! dissipation parameters of each domain, and the material constants the specs use, each with
//! its source. SI units throughout; the chapter's equations are images in the text, so the
//! standard formulas are stated here.
//!
//! ```
//! use components::geometry::{self, STEEL_SHEAR_MODULUS_PA};
//! use components::TorsionSpring;
//! // Eq. 3.2: a steel driveshaft of 40 mm, 1 m long (hand: pi 0.04^4 / 32 = 2.5133e-7 m4,
//! // x 81 GPa = 20 357.5 N m/rad).
//! let k = geometry::shaft_torsional_stiffness_n_m_per_rad(STEEL_SHEAR_MODULUS_PA, 0.04, 1.0);
//! assert!((k - 20_357.5).abs() < 0.1);
//! let shaft = TorsionSpring { stiffness_n_m_per_rad: k, damping_n_m_s_per_rad: 0.0 };
//! assert!(shaft.torque_n_m(0.01, 0.0) > 200.0);
//! ```

use fmu_runtime::real::Real;
use crate::magnetic::Reluctance;
use crate::thermal::{ThermalConductance, ThermalNode};
use std::f64::consts::PI;

/// Young's modulus of steel, Pa: E = 210 000 N/mm2 (EN 1993-1-1, Eurocode 3, section 3.2.6).
pub const STEEL_YOUNG_MODULUS_PA: f64 = 210e9;

/// Shear modulus of steel, Pa: G = E / (2 (1 + nu)) = 81 000 N/mm2 with nu = 0.3 (EN 1993-1-1,
/// section 3.2.6).
pub const STEEL_SHEAR_MODULUS_PA: f64 = 81e9;

/// Density of steel, kg/m3: 7.85 kg/dm3, the density with which the European dimension standards
/// for steel bars and tubes (EN 10060, EN 10220) compute their masses per metre.
pub const STEEL_DENSITY_KG_PER_M3: f64 = 7850.0;

/// Resistivity of copper at 20 degrees C, Ohm m: 1.678e-8 for pure copper (CRC Handbook of
/// Chemistry and Physics, "Electrical resistivity of pure metals", 293 K), rounded. Annealed
/// commercial wire is specified at 1/58 Ohm mm2/m = 1.724e-8 Ohm m (the International Annealed
/// Copper Standard, IEC 60028), about 3 % more; the resistivity rises 0.39 %/K.
pub const COPPER_RESISTIVITY_OHM_M: f64 = 1.68e-8;

/// Bulk modulus of a mineral hydraulic oil (the MIL-PRF-5606 aviation fluid and its kin), Pa:
/// air-free oil at moderate pressure and temperature lies at 1.4-1.8 GPa (Merritt, Hydraulic
/// Control Systems, Wiley 1967, chapter 2; the default oil of Modelica hydraulic libraries,
/// e.g. Wolfram SystemModeler's Hydraulic.Media.Oil, is 1.4 GPa). Entrained air and flexible
/// hoses lower the effective value of a real circuit, to 0.7 GPa in Merritt's design advice: a
/// spec states which it takes. A phosphate-ester fluid (Skydrol) is close in bulk modulus but
/// denser (about 1000 kg/m3).
pub const HYDRAULIC_OIL_BULK_MODULUS_PA: f64 = 1.5e9;

/// Density of a mineral hydraulic oil, kg/m3: 0.85-0.87 kg/L at 15 degrees C on MIL-PRF-5606
/// fluids' data sheets; 850 kg/m3 is also the Modelica hydraulic libraries' default oil.
pub const HYDRAULIC_OIL_DENSITY_KG_PER_M3: f64 = 850.0;

/// Kinematic viscosity of a MIL-PRF-5606 oil at 40 degrees C, m2/s: 13.2 mm2/s, the
/// specification's minimum at that temperature (the least viscous fluid leaks most). It is a
/// strong function of temperature: about 5 mm2/s at 100 degrees C, hundreds at -40 degrees C.
pub const HYDRAULIC_OIL_KINEMATIC_VISCOSITY_M2_PER_S: f64 = 13.2e-6;

/// Dynamic viscosity of that oil at 40 degrees C, Pa s: mu = rho nu = 850 x 13.2e-6 = 0.0112.
pub const HYDRAULIC_OIL_DYNAMIC_VISCOSITY_PA_S: f64 = HYDRAULIC_OIL_DENSITY_KG_PER_M3 * HYDRAULIC_OIL_KINEMATIC_VISCOSITY_M2_PER_S;

/// Eq. 3.1 as the chapter writes it: the inertia of a cylinder of mass M and radius r about its
/// axis, J = M r^2 / 2, kg m2.
/// ```
/// use components::geometry::cylinder_inertia_kg_m2;
/// assert_eq!(cylinder_inertia_kg_m2(100.0, 0.3), 4.5); // 100 x 0.09 / 2
/// ```
pub fn cylinder_inertia_kg_m2<R: Real>(mass_kg: R, radius_m: R) -> R {
    mass_kg * 0.5 * radius_m * radius_m
}

/// Inertia of a hollow cylinder (a tube, a rotor on its bore) about its axis, from its material:
/// J = rho pi L (R^4 - r^4) / 2, kg m2 (eq. 3.1 integrated over the annulus).
/// ```
/// use components::geometry::{hollow_cylinder_inertia_kg_m2, STEEL_DENSITY_KG_PER_M3};
/// // A steel rotor R = 100 mm on a 50 mm bore radius, 200 mm long:
/// // 7850 pi 0.2 (1e-4 - 6.25e-6) / 2 = 0.23120 kg m2.
/// let j = hollow_cylinder_inertia_kg_m2(STEEL_DENSITY_KG_PER_M3, 0.1, 0.05, 0.2);
/// assert!((j - 0.23120).abs() < 1e-5);
/// ```
pub fn hollow_cylinder_inertia_kg_m2<R: Real>(density_kg_per_m3: R, outer_radius_m: R, inner_radius_m: R, length_m: R) -> R {
    density_kg_per_m3 * PI * length_m * (outer_radius_m.powi(4) - inner_radius_m.powi(4)) / 2.0
}

/// Inertia of a solid cylinder about its axis from its material, rho pi L R^4 / 2, kg m2: the
/// hollow one with no bore.
/// ```
/// use components::geometry::{solid_cylinder_inertia_kg_m2, STEEL_DENSITY_KG_PER_M3};
/// // R = 100 mm, 200 mm long: 49.32 kg, J = 49.32 x 0.01 / 2 = 0.24662 kg m2.
/// let j = solid_cylinder_inertia_kg_m2(STEEL_DENSITY_KG_PER_M3, 0.1, 0.2);
/// assert!((j - 0.24662).abs() < 1e-5);
/// ```
pub fn solid_cylinder_inertia_kg_m2<R: Real>(density_kg_per_m3: R, radius_m: R, length_m: R) -> R {
    hollow_cylinder_inertia_kg_m2(density_kg_per_m3, radius_m, R::from(0.0), length_m)
}

/// Eq. 3.2: the torsional stiffness of a tube of length L, outer and inner diameters D and d,
/// shear modulus G: K = G pi (D^4 - d^4) / (32 L), N m/rad (G times the polar moment of area
/// over the length).
/// ```
/// use components::geometry::{tube_torsional_stiffness_n_m_per_rad, STEEL_SHEAR_MODULUS_PA};
/// // A steel tube 40/30 mm, 1 m: pi (2.56e-6 - 8.1e-7) / 32 = 1.7181e-7 m4, x 81 GPa = 13 916 N m/rad.
/// let k = tube_torsional_stiffness_n_m_per_rad(STEEL_SHEAR_MODULUS_PA, 0.04, 0.03, 1.0);
/// assert!((k - 13_916.3).abs() < 0.1);
/// ```
pub fn tube_torsional_stiffness_n_m_per_rad<R: Real>(shear_modulus_pa: R, outer_diameter_m: R, inner_diameter_m: R, length_m: R) -> R {
    shear_modulus_pa * PI * (outer_diameter_m.powi(4) - inner_diameter_m.powi(4)) / (length_m * 32.0)
}

/// Eq. 3.2 for a solid round shaft (no bore): K = G pi d^4 / (32 L), N m/rad (the example at the
/// top of this module; [`TorsionBar::round_bar_stiffness_n_m_per_rad`](crate::TorsionBar::round_bar_stiffness_n_m_per_rad)
/// is this one).
pub fn shaft_torsional_stiffness_n_m_per_rad<R: Real>(shear_modulus_pa: R, diameter_m: R, length_m: R) -> R {
    tube_torsional_stiffness_n_m_per_rad(shear_modulus_pa, diameter_m, R::from(0.0), length_m)
}

/// Area of a circle of a diameter (a rod's section, a piston's face), pi d^2 / 4, m2.
/// ```
/// use components::geometry::circle_area_m2;
/// assert!((circle_area_m2(0.014) - 1.53938e-4).abs() < 1e-9); // pi 0.007^2
/// ```
pub fn circle_area_m2<R: Real>(diameter_m: R) -> R {
    annulus_area_m2(diameter_m, R::from(0.0))
}

/// Area of an annulus (a cylinder's rod-side piston face), pi (D^2 - d^2) / 4, m2.
/// ```
/// use components::geometry::annulus_area_m2;
/// // A 40 mm piston on a 20 mm rod: pi (1.6e-3 - 4e-4) / 4 = 9.4248e-4 m2.
/// assert!((annulus_area_m2(0.04, 0.02) - 9.4248e-4).abs() < 1e-8);
/// ```
pub fn annulus_area_m2<R: Real>(outer_diameter_m: R, inner_diameter_m: R) -> R {
    (outer_diameter_m * outer_diameter_m - inner_diameter_m * inner_diameter_m) * PI / 4.0
}

/// Axial stiffness of a bar in tension or compression (a tie rod), k = E A / L, N/m (Table 3.2:
/// the translational twin of eq. 3.2).
/// ```
/// use components::geometry::{axial_stiffness_n_per_m, circle_area_m2, STEEL_YOUNG_MODULUS_PA};
/// // A steel tie rod of 14 mm, 300 mm long: 210e9 x 1.5394e-4 / 0.3 = 1.0776e8 N/m.
/// let k = axial_stiffness_n_per_m(STEEL_YOUNG_MODULUS_PA, circle_area_m2(0.014), 0.3);
/// assert!((k / 1.0776e8 - 1.0).abs() < 1e-4);
/// ```
pub fn axial_stiffness_n_per_m<R: Real>(young_modulus_pa: R, area_m2: R, length_m: R) -> R {
    young_modulus_pa * area_m2 / length_m
}

/// Hydraulic capacitance of a fluid volume V of bulk modulus B, C = V / B, m3/Pa (Table 3.2: a
/// chamber's pressure rises as dp/dt = net inflow / C).
/// ```
/// use components::geometry::{fluid_capacitance_m3_per_pa, HYDRAULIC_OIL_BULK_MODULUS_PA};
/// // 0.1 L of oil: 1e-4 / 1.5e9 = 6.667e-14 m3/Pa (100 mm3 of inflow raise it by 15 bar).
/// let c = fluid_capacitance_m3_per_pa(1e-4, HYDRAULIC_OIL_BULK_MODULUS_PA);
/// assert!((c - 6.6667e-14).abs() < 1e-18);
/// assert!((1e-7 / c - 15e5).abs() < 1e-3);
/// ```
pub fn fluid_capacitance_m3_per_pa<R: Real>(volume_m3: R, bulk_modulus_pa: R) -> R {
    volume_m3 / bulk_modulus_pa
}

/// Stiffness of a piston of area A on a trapped fluid volume V: k = A^2 B / V = A^2 / C, N/m
/// (the hydraulic spring of an actuator; the two chambers of a double-acting cylinder act in
/// parallel, k = A^2 B (1/V1 + 1/V2)).
/// ```
/// use components::geometry::{hydraulic_stiffness_n_per_m, HYDRAULIC_OIL_BULK_MODULUS_PA};
/// // 20 cm2 on 0.1 L: 4e-6 x 1.5e9 / 1e-4 = 6e7 N/m.
/// let k = hydraulic_stiffness_n_per_m(2e-3, HYDRAULIC_OIL_BULK_MODULUS_PA, 1e-4);
/// assert!((k - 6e7).abs() < 1e-3);
/// ```
pub fn hydraulic_stiffness_n_per_m<R: Real>(piston_area_m2: R, bulk_modulus_pa: R, volume_m3: R) -> R {
    piston_area_m2 * piston_area_m2 / fluid_capacitance_m3_per_pa(volume_m3, bulk_modulus_pa)
}

/// Hydraulic resistance of a round pipe in laminar flow (Hagen-Poiseuille), R = 128 mu L /
/// (pi d^4), Pa s/m3: dp = R Q (Table 3.2). Valid while the Reynolds number 4 rho Q / (pi mu d)
/// stays below about 2000.
/// ```
/// use components::geometry::laminar_pipe_resistance_pa_s_per_m3;
/// // 1 m of 4 mm bore, mu = 0.012 Pa s: 128 x 0.012 / (pi x 2.56e-10) = 1.9099e9 Pa s/m3.
/// let r = laminar_pipe_resistance_pa_s_per_m3(0.012, 1.0, 0.004);
/// assert!((r / 1.9099e9 - 1.0).abs() < 1e-4);
/// ```
pub fn laminar_pipe_resistance_pa_s_per_m3<R: Real>(dynamic_viscosity_pa_s: R, length_m: R, diameter_m: R) -> R {
    dynamic_viscosity_pa_s * 128.0 * length_m / (diameter_m.powi(4) * PI)
}

/// Hydraulic resistance of the leakage gap between a piston (or a pump's barrel) and its bore:
/// laminar flow through a concentric annulus of diameter D, radial clearance h << D and length
/// L, R = 12 mu L / (pi D h^3), Pa s/m3 (a slot of width pi D). A fully eccentric piston leaks
/// 2.5 times more.
/// ```
/// use components::geometry::annular_gap_resistance_pa_s_per_m3;
/// // D = 40 mm, h = 10 um, L = 30 mm, mu = 0.012 Pa s: 12 x 0.012 x 0.03 / (pi x 0.04 x 1e-15)
/// // = 3.4377e13 Pa s/m3: 0.29 cm3/s of leakage under 100 bar.
/// let r = annular_gap_resistance_pa_s_per_m3(0.012, 0.03, 0.04, 10e-6);
/// assert!((r / 3.4377e13 - 1.0).abs() < 1e-4);
/// assert!((1e7 / r - 2.909e-7).abs() < 1e-10);
/// ```
pub fn annular_gap_resistance_pa_s_per_m3<R: Real>(dynamic_viscosity_pa_s: R, length_m: R, diameter_m: R, clearance_m: R) -> R {
    dynamic_viscosity_pa_s * 12.0 * length_m / (diameter_m * PI * clearance_m.powi(3))
}

/// Electrical resistance of a conductor of resistivity rho, length l and section A, R = rho l /
/// A, Ohm (Table 3.2).
/// ```
/// use components::geometry::{conductor_resistance_ohm, COPPER_RESISTIVITY_OHM_M};
/// // 10 m of 1.5 mm2 copper: 1.68e-8 x 10 / 1.5e-6 = 0.112 Ohm.
/// assert!((conductor_resistance_ohm(COPPER_RESISTIVITY_OHM_M, 10.0, 1.5e-6) - 0.112).abs() < 1e-12);
/// ```
pub fn conductor_resistance_ohm<R: Real>(resistivity_ohm_m: R, length_m: R, area_m2: R) -> R {
    resistivity_ohm_m * length_m / area_m2
}

/// Inductance of a long air-core solenoid of N turns, section A and length l >> its diameter,
/// L = mu0 N^2 A / l, H (Table 3.2: N^2 over the reluctance l / (mu0 A) of its core, see
/// [`Reluctance::uniform`]).
/// ```
/// use components::geometry::solenoid_inductance_h;
/// // 1000 turns on 1 cm2 over 100 mm: 4 pi 1e-7 x 1e6 x 1e-4 / 0.1 = 1.2566 mH.
/// assert!((solenoid_inductance_h(1000.0, 1e-4, 0.1) - 1.25664e-3).abs() < 1e-8);
/// ```
pub fn solenoid_inductance_h<R: Real>(turns: R, area_m2: R, length_m: R) -> R {
    turns * turns * Reluctance::uniform(length_m, area_m2, R::from(1.0)).permeance_h()
}

/// Thermal resistance of a plane wall of thickness e, conductivity lambda and area A, R = e /
/// (lambda A), K/W (Table 3.2; [`ThermalConductance::through_layer`] is its inverse).
/// ```
/// use components::geometry::plane_wall_thermal_resistance_k_per_w;
/// // 10 mm of steel (50 W/(m K)) over 0.2 m2: 0.01 / (50 x 0.2) = 1e-3 K/W.
/// assert!((plane_wall_thermal_resistance_k_per_w(0.01, 50.0, 0.2) - 1e-3).abs() < 1e-15);
/// ```
pub fn plane_wall_thermal_resistance_k_per_w<R: Real>(thickness_m: R, conductivity_w_per_m_k: R, area_m2: R) -> R {
    R::from(1.0) / ThermalConductance::through_layer(thickness_m, conductivity_w_per_m_k, area_m2).conductance_w_per_k
}

/// Heat capacity of a body, C = m c, J/K (Table 3.2; the capacity of a [`ThermalNode`]).
/// ```
/// use components::geometry::heat_capacity_j_per_k;
/// assert_eq!(heat_capacity_j_per_k(10.0, 385.0), 3850.0); // 10 kg of copper, c = 385 J/(kg K)
/// ```
pub fn heat_capacity_j_per_k<R: Real>(mass_kg: R, specific_heat_j_per_kg_k: R) -> R {
    ThermalNode::of_mass(mass_kg, specific_heat_j_per_kg_k).heat_capacity_j_per_k
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mechanical::TorsionBar;

    #[test]
    fn eq_3_1_from_the_mass_agrees_with_the_material_form() {
        // A steel cylinder R = 0.1 m, L = 0.2 m: M = 7850 pi 0.01 0.2 = 49.323 kg (by hand),
        // J = M R^2 / 2 = 0.246615 kg m2.
        let mass = STEEL_DENSITY_KG_PER_M3 * PI * 0.1 * 0.1 * 0.2;
        assert!((mass - 49.323).abs() < 1e-3);
        let j = solid_cylinder_inertia_kg_m2(STEEL_DENSITY_KG_PER_M3, 0.1, 0.2);
        assert!((j - cylinder_inertia_kg_m2(mass, 0.1)).abs() < 1e-15);
        assert!((j - 0.246615).abs() < 1e-6);
        // A tube is the solid cylinder less its bore: J(R) - J(r).
        let bore = solid_cylinder_inertia_kg_m2(STEEL_DENSITY_KG_PER_M3, 0.05, 0.2);
        assert!((hollow_cylinder_inertia_kg_m2(STEEL_DENSITY_KG_PER_M3, 0.1, 0.05, 0.2) - (j - bore)).abs() < 1e-15);
    }

    #[test]
    fn eq_3_2_by_hand_and_the_torsion_bar_agree() {
        // pi 0.04^4 / 32 = 2.51327e-7 m4, x 81e9 / 1 m = 20 357.52 N m/rad.
        let k = shaft_torsional_stiffness_n_m_per_rad(81e9, 0.04, 1.0);
        assert!((k - 20_357.52).abs() < 0.01, "{k}");
        assert_eq!(TorsionBar::round_bar_stiffness_n_m_per_rad(81e9, 0.04, 1.0), k);
        // Twice as long, half as stiff; a 40/30 tube keeps 1 - (3/4)^4 = 68.36 % of it.
        assert!((shaft_torsional_stiffness_n_m_per_rad(81e9, 0.04, 2.0) - k / 2.0).abs() < 1e-9);
        assert!((tube_torsional_stiffness_n_m_per_rad(81e9, 0.04, 0.03, 1.0) / k - 0.68359375).abs() < 1e-12);
        // G = E / (2 (1 + nu)) with nu = 0.3: 80.77 GPa, which the constant rounds.
        assert!((STEEL_YOUNG_MODULUS_PA / 2.6 - STEEL_SHEAR_MODULUS_PA).abs() < 0.3e9);
    }

    #[test]
    fn hydraulic_parameters_by_hand() {
        // The hydraulic spring's frequency with a 500 kg referred mass on 20 cm2 over 0.1 L of
        // oil: k = 6e7 N/m, sqrt(6e7 / 500) / 2 pi = 55.13 Hz.
        let k = hydraulic_stiffness_n_per_m(2e-3, HYDRAULIC_OIL_BULK_MODULUS_PA, 1e-4);
        assert!(((k / 500.0).sqrt() / (2.0 * PI) - 55.13).abs() < 0.01);
        // The stiffness is A^2 over the capacitance: a piston displacement x squeezes A x of
        // fluid, raising the pressure by A x / C, pushing back with A^2 x / C.
        let c = fluid_capacitance_m3_per_pa(1e-4, HYDRAULIC_OIL_BULK_MODULUS_PA);
        let x = 1e-5;
        assert!((2e-3 * (2e-3 * x / c) - k * x).abs() < 1e-9 * k * x);
        // Hagen-Poiseuille at the oil's 0.01122 Pa s, 2 m of 6 mm: 128 x 0.01122 x 2 / (pi
        // 1.296e-9) = 7.0547e8 Pa s/m3.
        assert!((HYDRAULIC_OIL_DYNAMIC_VISCOSITY_PA_S - 0.01122).abs() < 1e-12);
        let r = laminar_pipe_resistance_pa_s_per_m3(HYDRAULIC_OIL_DYNAMIC_VISCOSITY_PA_S, 2.0, 0.006);
        assert!((r / 7.0547e8 - 1.0).abs() < 1e-5, "{r}");
        // The annular gap is a slot of width pi D: R = 12 mu L / (w h^3); halving h leaks 8 times more.
        let gap = annular_gap_resistance_pa_s_per_m3(0.012, 0.03, 0.04, 10e-6);
        assert!((gap / (12.0 * 0.012 * 0.03 / (PI * 0.04 * 1e-15)) - 1.0).abs() < 1e-12);
        assert!((gap / annular_gap_resistance_pa_s_per_m3(0.012, 0.03, 0.04, 5e-6) - 0.125).abs() < 1e-12);
    }

    #[test]
    fn electrical_and_thermal_parameters_by_hand() {
        // 100 m of 2.5 mm2 copper: 1.68e-8 x 100 / 2.5e-6 = 0.672 Ohm.
        assert!((conductor_resistance_ohm(COPPER_RESISTIVITY_OHM_M, 100.0, 2.5e-6) - 0.672).abs() < 1e-12);
        // Solenoid: 500 turns, 2 cm2, 50 mm: 4 pi 1e-7 x 250 000 x 2e-4 / 0.05 = 1.25664e-3 H.
        assert!((solenoid_inductance_h(500.0, 2e-4, 0.05) - 4e-7 * PI * 250_000.0 * 2e-4 / 0.05).abs() < 1e-15);
        assert!((solenoid_inductance_h(500.0, 2e-4, 0.05) - 1.25664e-3).abs() < 1e-8);
        // Plane wall: 0.6 mm of insulation at 0.14 W/(m K) over 0.54 m2 (the TGV motor's liner):
        // 6e-4 / 0.0756 = 7.937e-3 K/W.
        assert!((plane_wall_thermal_resistance_k_per_w(0.6e-3, 0.14, 0.54) - 7.937e-3).abs() < 1e-6);
        assert_eq!(heat_capacity_j_per_k(80.0, 385.0), 30_800.0);
    }
}
