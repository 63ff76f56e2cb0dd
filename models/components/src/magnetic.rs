//! Magnetic circuits (chapter section 3.5.2, Figures 3.25-3.27, questions 1-7).
//!
//! The analogy of question 1: the magnetomotive force (mmf, A, i.e. ampere-turns) is the
//! magnetic effort and the flux (Wb) the magnetic flow. Flux conservation over a closed surface
//! plays Kirchhoff's current law; Ampere's circuital law (the mmfs around a loop add up to the
//! enclosed N i) plays Kirchhoff's voltage law. A reluctance is the "resistance" of question 2,
//! mmf = reluctance x flux; unlike a resistor it stores energy (flux^2 reluctance / 2) rather than
//! dissipating it: the power flowing into a magnetic element is mmf x d(flux)/dt, not mmf x flux.
//! A winding (the transformer T of Figure 3.26) couples the electric and magnetic ports.

use fmu_runtime::real::Real;
use fmu_runtime::elements::{Domain, Effect, Kind};
use std::f64::consts::PI;

use crate::electrical::{Inductor, Resistor};

/// Permeability of vacuum (and air), H/m: the chapter's value, mu0 = 4 pi 1e-7 SI (question 4).
pub const MU_0_H_PER_M: f64 = 4.0e-7 * PI;

/// A linear reluctance: mmf = reluctance x flux (question 2).
/// ```
/// use components::Reluctance;
/// // Question 4: two radial gaps r1 = 15 mm to r2 = 16.5 mm over b = 2 mm, N = 1000 turns:
/// // L = N^2 / R = pi mu0 b N^2 / ln(r2/r1) = 82.84 mH.
/// let gap = Reluctance::radial_air_gap(0.015, 0.0165, 0.002);
/// let circuit = gap.series(gap);
/// let l = 1000.0f64.powi(2) * circuit.permeance_h();
/// assert!((l - 0.08284).abs() < 1e-5);
/// assert!((circuit.flux_wb(circuit.mmf_a(1e-4)) - 1e-4).abs() < 1e-18);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reluctance<R = f64> {
    pub reluctance_per_h: R,
}

impl Reluctance {
    /// Its effect (Table 3.1, question 2): magnetic storage, mmf = reluctance x flux.
    pub const RELUCTANCE: Effect = Effect { domains: &[Domain::Magnetic], kind: Kind::StorageC, what: "reluctance" };
}

impl<R: Real> Reluctance<R> {
    /// A flux tube of uniform section: R = length / (mu0 mu_r area) (question 2).
    pub fn uniform(length_m: R, area_m2: R, relative_permeability: R) -> Self {
        Reluctance { reluctance_per_h: length_m / (relative_permeability * MU_0_H_PER_M * area_m2) }
    }

    /// An air gap crossed radially between two coaxial cylinders of radii `inner_radius_m` and
    /// `outer_radius_m` over an axial width `width_m` (the gap between a detection ring and its
    /// yoke, Figure 3.25). The flux through a cylinder of radius r is B 2 pi r width, so
    /// H = flux / (mu0 2 pi r width) and mmf = integral of H dr = flux ln(r2/r1) / (2 pi mu0 width).
    pub fn radial_air_gap(inner_radius_m: R, outer_radius_m: R, width_m: R) -> Self {
        Reluctance::radial(inner_radius_m, outer_radius_m, width_m, R::from(1.0))
    }

    /// A hollow cylinder crossed axially (flux along the axis) between the radii `inner_radius_m`
    /// and `outer_radius_m` over `length_m`: a uniform tube of section pi (r_o^2 - r_i^2). The
    /// book's torque-sensor model builds its yoke's outer shell and the detection rings of such
    /// tubes (book file Chap3_TorqueSensor.mo, AxialIron1 and AxialIron2).
    /// ```
    /// use components::Reluctance;
    /// // The ring of part A: 10 mm long, 12 to 15 mm, mu_r 1000
    /// let ring = Reluctance::axial_annulus(0.010, 0.012, 0.015, 1000.0);
    /// let area = std::f64::consts::PI * (0.015f64.powi(2) - 0.012f64.powi(2));
    /// assert!((ring.reluctance_per_h - Reluctance::uniform(0.010, area, 1000.0).reluctance_per_h).abs() < 1e-6);
    /// ```
    pub fn axial_annulus(length_m: R, inner_radius_m: R, outer_radius_m: R, relative_permeability: R) -> Self {
        let area = (outer_radius_m * outer_radius_m - inner_radius_m * inner_radius_m) * PI;
        Reluctance::uniform(length_m, area, relative_permeability)
    }

    /// A hollow cylinder crossed radially between `inner_radius_m` and `outer_radius_m` over an
    /// axial width `width_m`, of relative permeability `relative_permeability`:
    /// R = ln(r_o/r_i) / (2 pi mu0 mu_r width) (the air gaps of question 4 at mu_r = 1, the
    /// yoke's poles of the book's model at mu_r 1000: RadialIron1 and RadialIron2).
    /// ```
    /// use components::Reluctance;
    /// let air = Reluctance::radial(0.015, 0.0165, 0.002, 1.0);
    /// assert_eq!(air, Reluctance::radial_air_gap(0.015, 0.0165, 0.002));
    /// let iron = Reluctance::radial(0.015, 0.0165, 0.002, 1000.0);
    /// assert!((air.reluctance_per_h / iron.reluctance_per_h - 1000.0).abs() < 1e-9);
    /// ```
    pub fn radial(inner_radius_m: R, outer_radius_m: R, width_m: R, relative_permeability: R) -> Self {
        Reluctance {
            reluctance_per_h: (outer_radius_m / inner_radius_m).ln()
                / (relative_permeability * (2.0 * PI * MU_0_H_PER_M) * width_m),
        }
    }

    /// Two reluctances crossed by the same flux (series, as resistors).
    pub fn series(self, other: Reluctance<R>) -> Reluctance<R> {
        Reluctance { reluctance_per_h: self.reluctance_per_h + other.reluctance_per_h }
    }

    /// Permeance 1 / R, H (the inductance of a one-turn winding on this circuit).
    pub fn permeance_h(&self) -> R {
        R::from(1.0) / self.reluctance_per_h
    }

    /// Magnetomotive force across the reluctance for a flux, A.
    pub fn mmf_a(&self, flux_wb: R) -> R {
        self.reluctance_per_h * flux_wb
    }

    /// Flux through the reluctance under an mmf, Wb.
    pub fn flux_wb(&self, mmf_a: R) -> R {
        mmf_a / self.reluctance_per_h
    }

    /// Stored magnetic energy R flux^2 / 2, J.
    pub fn energy_j(&self, flux_wb: R) -> R {
        self.reluctance_per_h * 0.5 * flux_wb * flux_wb
    }
}

/// A winding of N turns with its copper resistance on a magnetic circuit (the transformer T of
/// Figure 3.26): Ampere's law gives its mmf N i, Lenz's (Faraday's) law its induced voltage
/// N d(flux)/dt, so u = R i + N d(flux)/dt. With the flux as state the winding stays right when
/// the circuit's reluctance changes with time (the twist-dependent air gap of ring B).
/// ```
/// use components::{Reluctance, Winding};
/// let coil = Winding { turns: 1000.0, resistance_ohm: 30.0 };
/// let circuit = Reluctance { reluctance_per_h: 1.2e7 };
/// assert!((coil.inductance_h(circuit) - 1000.0f64.powi(2) / 1.2e7).abs() < 1e-15); // N^2 / R
/// // Ampere: N i = R flux, so the current follows from the flux (the state).
/// let flux = 1e-5;
/// assert!((coil.current_a(flux, circuit) - 1.2e7 * flux / 1000.0).abs() < 1e-12);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Winding<R = f64> {
    pub turns: R,
    pub resistance_ohm: R,
}

impl Winding {
    /// Its effect (Figure 3.26's T): a lossless transformer between the electric and magnetic ports.
    pub const TRANSFORMER: Effect = Effect { domains: &[Domain::Electrical, Domain::Magnetic], kind: Kind::Transformer, what: "winding" };
}

impl<R: Real> Winding<R> {
    /// Ampere's circuital law: the mmf of the winding carrying a current, A.
    pub fn mmf_a(&self, current_a: R) -> R {
        self.turns * current_a
    }

    /// The current for a flux in a circuit of reluctance `circuit`: N i = R flux, A.
    pub fn current_a(&self, flux_wb: R, circuit: Reluctance<R>) -> R {
        circuit.mmf_a(flux_wb) / self.turns
    }

    /// Lenz's law: d(flux)/dt = (u - R i) / N, for a terminal voltage and the current, Wb/s.
    pub fn flux_rate_wb_per_s(&self, voltage_v: R, current_a: R) -> R {
        (voltage_v - self.resistance().voltage_v(current_a)) / self.turns
    }

    /// Inductance of the winding on a circuit, N^2 / R, H (question 4).
    pub fn inductance_h(&self, circuit: Reluctance<R>) -> R {
        self.turns * self.turns * circuit.permeance_h()
    }

    /// The equivalent R-L impedance of this winding on a fixed circuit (question 5).
    pub fn as_rl(&self, circuit: Reluctance<R>) -> RlWinding<R> {
        RlWinding { inductance_h: self.inductance_h(circuit), resistance_ohm: self.resistance_ohm }
    }

    fn resistance(&self) -> Resistor<R> {
        Resistor { resistance_ohm: self.resistance_ohm }
    }
}

/// A winding seen from its terminals only: a resistance in series with a fixed inductance,
/// u = R i + L di/dt (question 5 compares it with [`Winding`] on its magnetic circuit).
/// ```
/// use components::RlWinding;
/// let rl = RlWinding { inductance_h: 0.0828, resistance_ohm: 30.0 };
/// // At rest under 5 V the current rises at U / L; at U / R it stops.
/// assert!((rl.current_rate_a_per_s(5.0, 0.0) - 5.0 / 0.0828).abs() < 1e-9);
/// assert!(rl.current_rate_a_per_s(5.0, 5.0 / 30.0).abs() < 1e-12);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RlWinding<R = f64> {
    pub inductance_h: R,
    pub resistance_ohm: R,
}

impl<R: Real> RlWinding<R> {
    /// di/dt for a terminal voltage and the current, A/s.
    pub fn current_rate_a_per_s(&self, voltage_v: R, current_a: R) -> R {
        let r = Resistor { resistance_ohm: self.resistance_ohm };
        Inductor { inductance_h: self.inductance_h }.current_rate_a_per_s(voltage_v - r.voltage_v(current_a))
    }
}

/// Where the teeth of a [`ToothedAirGap`] face each other: this gives the facing section per
/// radian of overlap of a tooth pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ToothFaces<R = f64> {
    /// Teeth on two coaxial cylinders across a radial gap at `radius_m`, over an axial length
    /// `axial_length_m`: radius x axial length per radian.
    Radial { radius_m: R, axial_length_m: R },
    /// Teeth on two facing annuli (radii `inner_radius_m` to `outer_radius_m`) across an axial
    /// gap: (r_o^2 - r_i^2) / 2 per radian. The book's variable gap (book file
    /// Chap3_TorqueSensor.mo, component AxialTorqueSensor) is of this kind.
    Axial { inner_radius_m: R, outer_radius_m: R },
}

impl<R: Real> ToothFaces<R> {
    /// Facing section of one tooth pair per radian of overlap, m2/rad.
    pub fn area_per_rad_m2(&self) -> R {
        match *self {
            ToothFaces::Radial { radius_m, axial_length_m } => radius_m * axial_length_m,
            ToothFaces::Axial { inner_radius_m, outer_radius_m } => {
                (outer_radius_m * outer_radius_m - inner_radius_m * inner_radius_m) * 0.5
            }
        }
    }
}

/// The air gap whose reluctance depends on the twist angle (question 7's new component, for
/// ring B): `teeth` teeth of angular width `tooth_width_rad` on the ring fixed to one end of the
/// torsion bar face as many teeth on the ring fixed to the other across a gap of length
/// `gap_length_m` (radial or axial: [`ToothFaces`]). The twist slides the teeth past each other:
/// the overlap of each tooth pair is rest_overlap + twist (between 0 and the tooth width), the
/// gap's section teeth x overlap x the faces' section per radian, and R = gap / (mu0 section).
/// Fringing (the quarter-circle field lines of Figure 3.25) is neglected, as the chapter does.
/// ```
/// use components::{ToothFaces, ToothedAirGap};
/// let gap = ToothedAirGap { teeth: 8.0, faces: ToothFaces::Radial { radius_m: 0.012, axial_length_m: 0.005 },
///     gap_length_m: 3e-4, tooth_width_rad: 22.5f64.to_radians(), rest_overlap_rad: 11.25f64.to_radians() };
/// // Twisting one way widens the overlap and lowers the reluctance.
/// assert!(gap.reluctance(0.01).reluctance_per_h < gap.reluctance(0.0).reluctance_per_h);
/// assert!((gap.overlap_rad(0.0) - 11.25f64.to_radians()).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToothedAirGap<R = f64> {
    pub teeth: R,
    pub faces: ToothFaces<R>,
    pub gap_length_m: R,
    pub tooth_width_rad: R,
    pub rest_overlap_rad: R,
}

impl<R: Real> ToothedAirGap<R> {
    /// Teeth half the pitch wide (2 pi / teeth), half overlapping at zero twist: the facing
    /// fraction of the faces is 1/4 + teeth twist / (2 pi), the book's formula (book file
    /// Chap3_TorqueSensor.mo, HollowCylinderAxialFluxVariable: A = pi (r_o^2 - r_i^2)
    /// (1/4 + N Teta / (2 pi)), N = 10 poles), valid while |twist| < pi / (2 teeth).
    /// ```
    /// use components::{ToothFaces, ToothedAirGap};
    /// use std::f64::consts::PI;
    /// let faces = ToothFaces::Axial { inner_radius_m: 0.012, outer_radius_m: 0.015 };
    /// let gap = ToothedAirGap::half_pitch(10.0, faces, 0.4e-3);
    /// let twist = -0.01;
    /// let book = PI * (0.015f64.powi(2) - 0.012f64.powi(2)) * (0.25 + 10.0 * twist / (2.0 * PI));
    /// assert!((gap.area_m2(twist) / book - 1.0).abs() < 1e-12);
    /// ```
    pub fn half_pitch(teeth: R, faces: ToothFaces<R>, gap_length_m: R) -> Self {
        ToothedAirGap { teeth, faces, gap_length_m, tooth_width_rad: R::from(PI) / teeth, rest_overlap_rad: R::from(PI) / (teeth * 2.0) }
    }

    /// Angular overlap of each tooth pair at a twist, rad, within [0, tooth width].
    pub fn overlap_rad(&self, twist_rad: R) -> R {
        (self.rest_overlap_rad + twist_rad).clamp(R::from(0.0), self.tooth_width_rad)
    }

    /// Facing section of the gap, m2.
    pub fn area_m2(&self, twist_rad: R) -> R {
        self.teeth * self.overlap_rad(twist_rad) * self.faces.area_per_rad_m2()
    }

    /// Reluctance at a twist (infinite when the teeth no longer face each other), 1/H.
    pub fn reluctance(&self, twist_rad: R) -> Reluctance<R> {
        Reluctance::uniform(self.gap_length_m, self.area_m2(twist_rad), R::from(1.0))
    }

    /// d(reluctance)/d(twist), 1/(H rad): -gap / (mu0 section^2) x d(section)/d(twist) while the
    /// teeth overlap partly, 0 where the overlap is clamped (the voltage a moving ring induces,
    /// the motional term, needs it).
    /// ```
    /// use components::{ToothFaces, ToothedAirGap};
    /// let gap = ToothedAirGap::half_pitch(10.0, ToothFaces::Axial { inner_radius_m: 0.012, outer_radius_m: 0.015 }, 0.4e-3);
    /// let h = 1e-7;
    /// let numeric = (gap.reluctance(h).reluctance_per_h - gap.reluctance(-h).reluctance_per_h) / (2.0 * h);
    /// assert!((gap.reluctance_rate_per_h_per_rad(0.0) / numeric - 1.0).abs() < 1e-6);
    /// ```
    pub fn reluctance_rate_per_h_per_rad(&self, twist_rad: R) -> R {
        let overlap = self.rest_overlap_rad + twist_rad;
        if overlap <= 0.0 || overlap >= self.tooth_width_rad {
            return R::from(0.0);
        }
        let area = self.area_m2(twist_rad);
        -self.gap_length_m / (area * MU_0_H_PER_M * area) * self.teeth * self.faces.area_per_rad_m2()
    }

    /// The twists at which a tooth pair stops overlapping or overlaps fully: beyond them the
    /// reluctance no longer changes (or is infinite).
    pub fn twist_range_rad(&self) -> (R, R) {
        (-self.rest_overlap_rad, self.tooth_width_rad - self.rest_overlap_rad)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const N: f64 = 1000.0;

    #[test]
    fn uniform_reluctance_is_length_over_permeability_and_section() {
        // 1 mm of air over 1 cm2: 1e-3 / (4 pi 1e-7 * 1e-4) = 7.9577e6 1/H
        let r = Reluctance::uniform(1e-3, 1e-4, 1.0);
        assert!((r.reluctance_per_h - 1e-3 / (4e-7 * PI * 1e-4)).abs() < 1e-6);
        let iron = Reluctance::uniform(1e-3, 1e-4, 2000.0);
        assert!((r.reluctance_per_h / iron.reluctance_per_h - 2000.0).abs() < 1e-9);
        assert_eq!(r.flux_wb(r.mmf_a(2e-6)), 2e-6);
    }

    #[test]
    fn radial_gap_tends_to_a_flat_gap_when_thin() {
        // r2 - r1 << r1: ln(r2/r1) ~ (r2 - r1)/r1, the section 2 pi r1 b of a flat gap
        let (r1, gap, b) = (0.015, 1e-7, 0.002);
        let radial = Reluctance::radial_air_gap(r1, r1 + gap, b).reluctance_per_h;
        let flat = Reluctance::uniform(gap, 2.0 * PI * r1 * b, 1.0).reluctance_per_h;
        assert!((radial / flat - 1.0).abs() < 1e-5, "{radial} vs {flat}");
    }

    #[test]
    fn radial_gap_equals_the_integral_of_thin_shells() {
        // independent check: sum of thin shells dr / (mu0 2 pi r b), midpoint rule
        let (r1, r2, b) = (0.015, 0.0165, 0.002);
        let n = 100_000;
        let dr = (r2 - r1) / n as f64;
        let sum: f64 = (0..n).map(|k| dr / (MU_0_H_PER_M * 2.0 * PI * (r1 + (k as f64 + 0.5) * dr) * b)).sum();
        let r = Reluctance::radial_air_gap(r1, r2, b).reluctance_per_h;
        assert!((r / sum - 1.0).abs() < 1e-9, "{r} vs {sum}");
    }

    #[test]
    fn winding_inductance_is_n_squared_over_reluctance_and_stores_li2_over_2() {
        let circuit = Reluctance { reluctance_per_h: 1.2e7 };
        let w = Winding { turns: N, resistance_ohm: 30.0 };
        let l = w.inductance_h(circuit);
        assert!((l - N * N / 1.2e7).abs() < 1e-15);
        // flux linkage N flux = L i, and the circuit's energy R flux^2 / 2 = L i^2 / 2
        let i = 1.5e-3;
        let flux = circuit.flux_wb(w.mmf_a(i));
        assert!((N * flux - l * i).abs() < 1e-15);
        assert!((circuit.energy_j(flux) - Inductor { inductance_h: l }.energy_j(i)).abs() < 1e-18);
        assert!((w.current_a(flux, circuit) - i).abs() < 1e-15);
    }

    #[test]
    fn winding_and_its_rl_equivalent_have_the_same_current_rate() {
        // on a fixed circuit, N dflux/dt = N d(L i / N)/dt = L di/dt
        let circuit = Reluctance { reluctance_per_h: 1.2e7 };
        let w = Winding { turns: N, resistance_ohm: 30.0 };
        let rl = w.as_rl(circuit);
        let (u, i) = (5.0, 0.02);
        let di_winding = w.flux_rate_wb_per_s(u, i) * circuit.reluctance_per_h / N;
        assert!((di_winding - rl.current_rate_a_per_s(u, i)).abs() < 1e-12 * di_winding.abs());
        // at rest the current is u / R
        assert_eq!(rl.current_rate_a_per_s(u, u / 30.0), 0.0);
    }

    #[test]
    fn toothed_gap_permeance_grows_linearly_with_overlap() {
        let g = ToothedAirGap {
            teeth: 8.0,
            faces: ToothFaces::Radial { radius_m: 0.012, axial_length_m: 0.005 },
            gap_length_m: 3e-4,
            tooth_width_rad: PI / 8.0,
            rest_overlap_rad: PI / 16.0,
        };
        let p = |t: f64| g.reluctance(t).permeance_h();
        // permeance mu0 n a r h / g is linear in the overlap a = a0 + twist
        let (a0, dt) = (PI / 16.0, 0.05);
        assert!((p(dt) / p(0.0) - (a0 + dt) / a0).abs() < 1e-12);
        assert!((p(-dt) / p(0.0) - (a0 - dt) / a0).abs() < 1e-12);
        let expected = MU_0_H_PER_M * 8.0 * a0 * 0.012 * 0.005 / 3e-4;
        assert!((p(0.0) / expected - 1.0).abs() < 1e-12);
        // the overlap saturates at the tooth width and at zero
        assert_eq!(g.overlap_rad(1.0), PI / 8.0);
        assert_eq!(g.overlap_rad(-1.0), 0.0);
        assert!(g.reluctance(-1.0).reluctance_per_h.is_infinite());
        assert_eq!(g.twist_range_rad(), (-PI / 16.0, PI / 16.0));
    }
}
