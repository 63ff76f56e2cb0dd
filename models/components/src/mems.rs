//! Micro-electro-mechanical elements (the MEMS accelerometer of chapter section 3.4.1.1, Figure
//! 3.14, question 2): a proof mass on a folded-beam suspension, the air films that damp it, and
//! the parallel-plate capacitors that sense its motion and pull on it. Table 3.2's idea at the
//! micrometre scale: each lumped parameter from the drawing's dimensions and the material, with
//! the formula's source. SI units throughout (a 2 um beam is 2e-6 m).
//!
//! ```
//! use components::mems::{self, ParallelPlate, POLYSILICON_YOUNG_MODULUS_PA, VACUUM_PERMITTIVITY_F_PER_M};
//! // A folded flexure of 2 um x 2 um polysilicon beams 92 um long: k = 2 E t w^3 / L^3 = 6.58 N/m.
//! let k = mems::folded_flexure_stiffness_n_per_m(POLYSILICON_YOUNG_MODULUS_PA, 2e-6, 2e-6, 92e-6);
//! assert!((k - 6.575).abs() < 1e-3);
//! // The sense capacitor it moves: 8.736e-9 m2 of electrode at 1 um, 77.4 fF at rest; it snaps
//! // to a single electrode at sqrt(8 k g^3 / (27 eps A)) = 5.02 V.
//! let plate = ParallelPlate { permittivity_f_per_m: VACUUM_PERMITTIVITY_F_PER_M, area_m2: 8.736e-9, gap_m: 1e-6 };
//! assert!((plate.capacitance_f(0.0) - 77.35e-15).abs() < 0.01e-15);
//! assert!((plate.pull_in_voltage_v(k) - 5.019).abs() < 1e-3);
//! ```

use fmu_runtime::real::Real;
use fmu_runtime::elements::{Domain, Effect, Kind};
use std::f64::consts::PI;

/// Permittivity of vacuum, F/m: 8.8541878128e-12 (CODATA 2018). Air's relative permittivity
/// (1.0006 at 1 atm) is taken as 1.
pub const VACUUM_PERMITTIVITY_F_PER_M: f64 = 8.8541878128e-12;

/// Young's modulus of LPCVD polysilicon, Pa: 160 GPa, the value MEMS design texts take for it
/// (it lies between single-crystal silicon's 130 and 188 GPa, [100] and [111]); tensile tests
/// of MUMPs polysilicon give 158-169 GPa (Sharpe et al., 1997, and the round robins that
/// followed). A spec states which it takes.
pub const POLYSILICON_YOUNG_MODULUS_PA: f64 = 160e9;

/// Density of polysilicon, kg/m3: that of silicon, 2329 kg/m3 (CRC Handbook), rounded.
pub const POLYSILICON_DENSITY_KG_PER_M3: f64 = 2330.0;

/// Dynamic viscosity of air at 25 degrees C, Pa s: 1.85e-5 (tables, e.g. the CRC Handbook's
/// 18.5 uPa s at 300 K); Sutherland's law (mu0 = 1.716e-5 Pa s at 273.15 K, S = 110.4 K) gives
/// 1.84e-5. Independent of pressure (kinetic theory) until the gap is a few mean free paths:
/// then the film's effective viscosity falls (see [`squeeze_film_effective_viscosity_pa_s`]).
pub const AIR_VISCOSITY_PA_S: f64 = 1.85e-5;

/// Molar mass of dry air, kg/mol: 28.9647 g/mol (the US Standard Atmosphere 1976).
pub const AIR_MOLAR_MASS_KG_PER_MOL: f64 = 0.0289647;

/// Molar gas constant, J/(mol K) (CODATA 2018, exact since the 2019 SI).
pub const GAS_CONSTANT_J_PER_MOL_K: f64 = 8.314462618;

/// Stiffness of a fixed-guided beam bent in its plane (one end clamped, the other guided: it
/// translates without turning), k = 12 E I / L^3 with I = t w^3 / 12, i.e. E t w^3 / L^3, N/m:
/// w the beam's width in the direction of motion, t its thickness, L its length.
/// ```
/// use components::mems::fixed_guided_beam_stiffness_n_per_m;
/// // 160 GPa, 2 x 2 um, 100 um: 160e9 x 2e-6 x 8e-18 / 1e-12 = 2.56 N/m.
/// assert!((fixed_guided_beam_stiffness_n_per_m(160e9, 2e-6, 2e-6, 100e-6) - 2.56).abs() < 1e-12);
/// ```
pub fn fixed_guided_beam_stiffness_n_per_m<R: Real>(young_modulus_pa: R, thickness_m: R, width_m: R, length_m: R) -> R {
    young_modulus_pa * thickness_m * width_m.powi(3) / length_m.powi(3)
}

/// Stiffness of a folded-flexure suspension along its compliant axis, k = 24 E I / L^3 =
/// 2 E t w^3 / L^3, N/m (Tang, Nguyen and Howe, "Laterally driven polysilicon resonant
/// microstructures", Sensors and Actuators 20, 1989; Senturia, Microsystem Design, 2001): four
/// folds, each two fixed-guided beams of length L in series (E t w^3 / (2 L^3) a fold), the
/// four folds in parallel. The truss that joins a fold's two beams is taken rigid.
/// ```
/// use components::mems::{fixed_guided_beam_stiffness_n_per_m, folded_flexure_stiffness_n_per_m};
/// let beam = fixed_guided_beam_stiffness_n_per_m(160e9, 2e-6, 2e-6, 92e-6);
/// let k = folded_flexure_stiffness_n_per_m(160e9, 2e-6, 2e-6, 92e-6);
/// assert!((k - 4.0 * beam / 2.0).abs() < 1e-12); // 4 folds in parallel, 2 beams in series each
/// assert!((k - 6.5752).abs() < 1e-4);
/// ```
pub fn folded_flexure_stiffness_n_per_m<R: Real>(young_modulus_pa: R, thickness_m: R, width_m: R, length_m: R) -> R {
    fixed_guided_beam_stiffness_n_per_m(young_modulus_pa, thickness_m, width_m, length_m) * 2.0
}

/// Mean free path of a gas's molecules, lambda = (mu / p) sqrt(pi R T / (2 M)), m (kinetic
/// theory of hard spheres, the relation between viscosity and mean free path): air at 1 atm and
/// 25 degrees C, 66.9 nm; it grows as 1/p, which is what a vacuum package plays on.
/// ```
/// use components::mems::{mean_free_path_m, AIR_MOLAR_MASS_KG_PER_MOL, AIR_VISCOSITY_PA_S};
/// let lambda = mean_free_path_m(AIR_VISCOSITY_PA_S, 101_325.0, 298.15, AIR_MOLAR_MASS_KG_PER_MOL);
/// assert!((lambda - 66.94e-9).abs() < 0.01e-9);
/// ```
pub fn mean_free_path_m<R: Real>(viscosity_pa_s: R, pressure_pa: R, temperature_k: R, molar_mass_kg_per_mol: R) -> R {
    viscosity_pa_s / pressure_pa * (temperature_k * (PI * GAS_CONSTANT_J_PER_MOL_K) / (molar_mass_kg_per_mol * 2.0)).sqrt()
}

/// Effective viscosity of a squeezed gas film whose gap is not many mean free paths wide (slip
/// at the walls, transition regime): mu_eff = mu / (1 + 9.638 Kn^1.159), Kn = lambda / gap
/// (Veijola, Kuisma, Lahdenpera and Ryhanen, "Equivalent-circuit model of the squeezed gas film
/// in a silicon accelerometer", Sensors and Actuators A 48, 1995: a fit within 5 % for
/// 0 <= Kn <= 880), Pa s.
/// ```
/// use components::mems::squeeze_film_effective_viscosity_pa_s;
/// assert_eq!(squeeze_film_effective_viscosity_pa_s(1.85e-5, 0.0), 1.85e-5); // continuum
/// // A 1 um gap in air (Kn = 0.0669): 70 % of the viscosity.
/// assert!((squeeze_film_effective_viscosity_pa_s(1.85e-5, 0.06694) / 1.85e-5 - 0.7043).abs() < 1e-4);
/// ```
pub fn squeeze_film_effective_viscosity_pa_s<R: Real>(viscosity_pa_s: R, knudsen: R) -> R {
    viscosity_pa_s / (knudsen.powf(R::from(1.159)) * 9.638 + 1.0)
}

/// Effective viscosity of a gas film sheared between two plates sliding past each other (Couette
/// flow) with first-order slip at both walls: mu_eff = mu / (1 + 2 Kn), Kn = lambda / gap, Pa s.
/// ```
/// use components::mems::slide_film_effective_viscosity_pa_s;
/// assert!((slide_film_effective_viscosity_pa_s(1.85e-5, 0.05) - 1.85e-5 / 1.1).abs() < 1e-18);
/// ```
pub fn slide_film_effective_viscosity_pa_s<R: Real>(viscosity_pa_s: R, knudsen: R) -> R {
    viscosity_pa_s / (knudsen * 2.0 + 1.0)
}

/// Damping coefficient of a squeezed film between two parallel strips of length L and width W
/// (L >> W, the gas escaping across W) at gap h, the gas incompressible (squeeze number
/// 12 mu omega W^2 / (p h^2) << 1): b = mu L W^3 / h^3, N s/m. The Reynolds equation across the
/// strip gives the parabolic pressure p(y) = 6 mu v (W^2/4 - y^2) / h^3, whose integral over
/// the strip is the force mu L W^3 v / h^3 (Starr 1990; Senturia, Microsystem Design, section
/// 13.4; Blech's series for a finite plate tends to it as W / L -> 0, its first term with
/// 96 / pi^4 = 0.986 of it).
/// ```
/// use components::mems::squeeze_film_strip_damping_n_s_per_m;
/// // A finger side of 104 um x 2 um at 1 um in air: 1.85e-5 x 104e-6 x 8 = 1.539e-8 N s/m.
/// let b = squeeze_film_strip_damping_n_s_per_m(1.85e-5, 104e-6, 2e-6, 1e-6);
/// assert!((b - 1.5392e-8).abs() < 1e-12);
/// // Halving the gap damps 8 times more.
/// assert!((squeeze_film_strip_damping_n_s_per_m(1.85e-5, 104e-6, 2e-6, 0.5e-6) / b - 8.0).abs() < 1e-12);
/// ```
pub fn squeeze_film_strip_damping_n_s_per_m<R: Real>(viscosity_pa_s: R, length_m: R, width_m: R, gap_m: R) -> R {
    viscosity_pa_s * length_m * width_m.powi(3) / gap_m.powi(3)
}

/// Damping coefficient of a gas film sheared between a plate of area A sliding parallel to a
/// fixed one at gap d, the velocity profile linear (Couette flow, the film thin beside the
/// shear wave's penetration depth sqrt(2 mu / (rho omega))): b = mu A / d, N s/m.
/// ```
/// use components::mems::slide_film_damping_n_s_per_m;
/// // 6.18e-8 m2 of proof mass 1.6 um above the substrate: 1.85e-5 x 6.18e-8 / 1.6e-6 = 7.146e-7 N s/m.
/// assert!((slide_film_damping_n_s_per_m(1.85e-5, 6.18e-8, 1.6e-6) - 7.1456e-7).abs() < 1e-11);
/// ```
pub fn slide_film_damping_n_s_per_m<R: Real>(viscosity_pa_s: R, area_m2: R, gap_m: R) -> R {
    viscosity_pa_s * area_m2 / gap_m
}

/// A parallel-plate capacitor whose gap a translation closes: C(s) = eps A / (g - s) for a
/// displacement s towards the fixed electrode (fringing fields left out). It couples the
/// electrical domain (charge, voltage) and the mechanical one (force, displacement): a C element
/// with two ports, storing W = C V^2 / 2. At constant voltage the electrode pulls the plate with
/// F = (V^2 / 2) dC/ds = eps A V^2 / (2 (g - s)^2), a force that grows as the gap closes: a
/// negative (softening) stiffness dF/ds = eps A V^2 / (g - s)^3.
///
/// Power at a (mean-square) voltage V^2 that may change in time: the source delivers
/// V i = V d(C V)/dt = V^2 dC/dt + (C/2) d(V^2)/dt, the capacitor stores
/// dW/dt = (V^2/2) dC/dt + (C/2) d(V^2)/dt, and the difference (V^2/2) dC/dt = F ds/dt goes to the
/// mechanical side. With a carrier far above the mechanical modes (a read-out's square wave),
/// the plate sees the mean of V^2: every law here takes the mean square.
/// ```
/// use components::mems::ParallelPlate;
/// let c = ParallelPlate { permittivity_f_per_m: 8.8541878128e-12, area_m2: 8.736e-9, gap_m: 1e-6 };
/// let (v2, s, ds, dv2) = (4.0, 0.2e-6, 1e-3, 100.0); // V^2, displacement, its rate, d(V^2)/dt
/// // The balance of the two ports: source = stored + mechanical.
/// let mechanical = c.force_n(v2, s) * ds;
/// assert!((c.source_power_w(v2, dv2, s, ds) - c.storage_power_w(v2, dv2, s, ds) - mechanical).abs() < 1e-25);
/// // The force is the energy's derivative at constant voltage: (W(s + h) - W(s - h)) / 2h.
/// let h = 1e-12;
/// let dw = (c.energy_j(v2, s + h) - c.energy_j(v2, s - h)) / (2.0 * h);
/// assert!((dw / c.force_n(v2, s) - 1.0).abs() < 1e-6);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParallelPlate<R = f64> {
    /// eps0 eps_r of the gap's medium, F/m.
    pub permittivity_f_per_m: R,
    /// Overlapping electrode area, m2.
    pub area_m2: R,
    /// Gap at s = 0, m.
    pub gap_m: R,
}

impl ParallelPlate {
    /// Its effect (Table 3.1): electrostatic storage coupling the electrical and mechanical
    /// (translation) domains.
    pub const TRANSDUCER: Effect = Effect { domains: &[Domain::Electrical, Domain::Translational], kind: Kind::StorageC, what: "capacitive transducer (parallel plates)" };
    /// The voltage that charges it: a source in the electrical domain.
    pub const DRIVE: Effect = Effect { domains: &[Domain::Electrical], kind: Kind::Source, what: "electrode voltage" };
}

impl<R: Real> ParallelPlate<R> {
    /// eps A, F m.
    pub fn permittivity_area_f_m(&self) -> R {
        self.permittivity_f_per_m * self.area_m2
    }

    /// C = eps A / (g - s), F.
    pub fn capacitance_f(&self, displacement_m: R) -> R {
        self.permittivity_area_f_m() / (self.gap_m - displacement_m)
    }

    /// dC/ds = eps A / (g - s)^2, F/m.
    pub fn capacitance_gradient_f_per_m(&self, displacement_m: R) -> R {
        let gap = self.gap_m - displacement_m;
        self.permittivity_area_f_m() / (gap * gap)
    }

    /// The electrode's pull on the plate, towards the electrode, (V^2/2) dC/ds, N.
    pub fn force_n(&self, mean_square_voltage_v2: R, displacement_m: R) -> R {
        mean_square_voltage_v2 * 0.5 * self.capacitance_gradient_f_per_m(displacement_m)
    }

    /// The electrostatic stiffness dF/ds = eps A V^2 / (g - s)^3, N/m: positive, it softens the
    /// suspension it acts against.
    pub fn softening_n_per_m(&self, mean_square_voltage_v2: R, displacement_m: R) -> R {
        let gap = self.gap_m - displacement_m;
        self.permittivity_area_f_m() * mean_square_voltage_v2 / (gap * gap * gap)
    }

    /// Stored energy C V^2 / 2, J.
    pub fn energy_j(&self, mean_square_voltage_v2: R, displacement_m: R) -> R {
        self.capacitance_f(displacement_m) * 0.5 * mean_square_voltage_v2
    }

    /// dW/dt = (V^2/2) dC/dt + (C/2) d(V^2)/dt, W.
    pub fn storage_power_w(&self, mean_square_voltage_v2: R, mean_square_rate_v2_per_s: R, displacement_m: R, velocity_m_per_s: R) -> R {
        mean_square_voltage_v2 * 0.5 * self.capacitance_gradient_f_per_m(displacement_m) * velocity_m_per_s
            + self.capacitance_f(displacement_m) * 0.5 * mean_square_rate_v2_per_s
    }

    /// Power the voltage source delivers, V i = V^2 dC/dt + (C/2) d(V^2)/dt, W.
    pub fn source_power_w(&self, mean_square_voltage_v2: R, mean_square_rate_v2_per_s: R, displacement_m: R, velocity_m_per_s: R) -> R {
        mean_square_voltage_v2 * self.capacitance_gradient_f_per_m(displacement_m) * velocity_m_per_s
            + self.capacitance_f(displacement_m) * 0.5 * mean_square_rate_v2_per_s
    }

    /// The pull-in voltage of a plate on a linear spring k facing this one electrode alone:
    /// the spring k s = eps A V^2 / (2 (g - s)^2) and the electrostatic stiffness equal at
    /// s = g/3, V_pi = sqrt(8 k g^3 / (27 eps A)), V (Senturia, Microsystem Design, section 6.4;
    /// Nathanson et al. 1967). Beyond it the plate has no rest position short of the electrode.
    /// ```
    /// use components::mems::ParallelPlate;
    /// let c = ParallelPlate { permittivity_f_per_m: 8.8541878128e-12, area_m2: 1e-8, gap_m: 2e-6 };
    /// let (k, v) = (2.0, c.pull_in_voltage_v(2.0));
    /// // At V_pi the equilibrium at g/3 is also where the total stiffness vanishes.
    /// let s = 2e-6 / 3.0;
    /// assert!((k * s / c.force_n(v * v, s) - 1.0).abs() < 1e-12);
    /// assert!((k / c.softening_n_per_m(v * v, s) - 1.0).abs() < 1e-12);
    /// ```
    pub fn pull_in_voltage_v(&self, stiffness_n_per_m: R) -> R {
        (stiffness_n_per_m * 8.0 * self.gap_m.powi(3) / (self.permittivity_area_f_m() * 27.0)).sqrt()
    }

    /// The pull-in voltage of a plate between two such electrodes at the same voltage (the
    /// differential sense capacitor with its excitation on both sides): the pulls cancel at
    /// s = 0, whose stiffness k - 2 eps A V^2 / g^3 vanishes at V = sqrt(k g^3 / (2 eps A)), V.
    /// ```
    /// use components::mems::ParallelPlate;
    /// let c = ParallelPlate { permittivity_f_per_m: 8.8541878128e-12, area_m2: 1e-8, gap_m: 2e-6 };
    /// let v = c.symmetric_pull_in_voltage_v(2.0);
    /// assert!((2.0 - 2.0 * c.softening_n_per_m(v * v, 0.0)).abs() < 1e-12);
    /// ```
    pub fn symmetric_pull_in_voltage_v(&self, stiffness_n_per_m: R) -> R {
        (stiffness_n_per_m * self.gap_m.powi(3) / (self.permittivity_area_f_m() * 2.0)).sqrt()
    }
}

/// The squeeze-film damping of the two films of a differential sense capacitor (a plate between
/// two electrodes, each film of area A = fingers x overlap x thickness at gap g, the gas escaping
/// across the thickness t): b(s) = mu_eff A t^2 (1 / (g - s)^3 + 1 / (g + s)^3), i.e. each side
/// [`squeeze_film_strip_damping_n_s_per_m`] summed over the fingers, with the gap the motion
/// leaves it. mu_eff is taken at the rest gap.
/// ```
/// use components::mems::SqueezeFilm;
/// let film = SqueezeFilm { effective_viscosity_pa_s: 1.3e-5, area_m2: 8.736e-9, width_m: 2e-6, gap_m: 1e-6 };
/// // At rest: 2 x 1.3e-5 x 8.736e-9 x 4e-12 / 1e-18 = 9.085e-7 N s/m.
/// assert!((film.damping_n_s_per_m(0.0) - 9.0854e-7).abs() < 1e-11);
/// // Half-way to one electrode that side damps 8 times more: (8 + 1/3.375) / 2 of the rest value.
/// assert!((film.damping_n_s_per_m(0.5e-6) / film.damping_n_s_per_m(0.0) - (8.0 + 1.0 / 3.375) / 2.0).abs() < 1e-12);
/// assert!((film.power_w(0.0, 1e-3) - 9.0854e-13).abs() < 1e-17); // b v^2
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SqueezeFilm<R = f64> {
    pub effective_viscosity_pa_s: R,
    /// Area of one side's films (the capacitor's electrode area), m2.
    pub area_m2: R,
    /// Width the gas escapes across (the fingers' thickness), m.
    pub width_m: R,
    /// Gap at rest, m.
    pub gap_m: R,
}

impl SqueezeFilm {
    /// Its effect (Table 3.1): a dissipation in translation.
    pub const DAMPING: Effect = Effect { domains: &[Domain::Translational], kind: Kind::Dissipation, what: "squeeze-film damping" };
}

impl<R: Real> SqueezeFilm<R> {
    /// b(s), N s/m.
    pub fn damping_n_s_per_m(&self, displacement_m: R) -> R {
        let side = |gap: R| squeeze_film_strip_damping_n_s_per_m(self.effective_viscosity_pa_s, self.area_m2 / self.width_m, self.width_m, gap);
        side(self.gap_m - displacement_m) + side(self.gap_m + displacement_m)
    }

    /// The film's force on the plate, -b(s) v, N.
    pub fn force_n(&self, displacement_m: R, velocity_m_per_s: R) -> R {
        -self.damping_n_s_per_m(displacement_m) * velocity_m_per_s
    }

    /// Power dissipated, b(s) v^2, W (never negative).
    pub fn power_w(&self, displacement_m: R, velocity_m_per_s: R) -> R {
        self.damping_n_s_per_m(displacement_m) * velocity_m_per_s * velocity_m_per_s
    }
}

/// The slide-film (Couette) damping of the gas between an in-plane moving plate and the
/// substrate under it: b = mu_eff A / d, a [`crate::TranslationalDamper`] of that coefficient.
/// ```
/// use components::mems::SlideFilm;
/// let film = SlideFilm { effective_viscosity_pa_s: 1.705e-5, area_m2: 6.18e-8, gap_m: 1.6e-6 };
/// assert!((film.damper().damping_n_s_per_m - 6.5856e-7).abs() < 1e-11);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlideFilm<R = f64> {
    pub effective_viscosity_pa_s: R,
    /// The moving plate's area facing the substrate, m2.
    pub area_m2: R,
    /// Its height above the substrate, m.
    pub gap_m: R,
}

impl SlideFilm {
    /// Its effect (Table 3.1): a dissipation in translation.
    pub const DAMPING: Effect = Effect { domains: &[Domain::Translational], kind: Kind::Dissipation, what: "slide-film (Couette) damping" };
}

impl<R: Real> SlideFilm<R> {
    pub fn damper(&self) -> crate::TranslationalDamper<R> {
        crate::TranslationalDamper { damping_n_s_per_m: slide_film_damping_n_s_per_m(self.effective_viscosity_pa_s, self.area_m2, self.gap_m) }
    }
}

/// The d'Alembert force of a frame's acceleration on a mass seen in the frame, F = -m a: a source
/// in translation for the mass's motion relative to the frame (an accelerometer's input).
/// ```
/// use components::mems::FrameAcceleration;
/// let inertial = FrameAcceleration { mass_kg: 2.877e-10 };
/// assert!((inertial.force_n(98.0665) + 2.8214e-8).abs() < 1e-12); // 10 g on 0.29 ug
/// assert!((inertial.power_w(98.0665, -1e-3) - 2.8214e-11).abs() < 1e-15); // F v
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameAcceleration<R = f64> {
    pub mass_kg: R,
}

impl FrameAcceleration {
    /// Its effect (Table 3.1): a source in translation.
    pub const SOURCE: Effect = Effect { domains: &[Domain::Translational], kind: Kind::Source, what: "frame acceleration (inertial force -m a)" };
}

impl<R: Real> FrameAcceleration<R> {
    /// -m a, N.
    pub fn force_n(&self, acceleration_m_per_s2: R) -> R {
        -self.mass_kg * acceleration_m_per_s2
    }

    /// Power into the relative motion, -m a v, W.
    pub fn power_w(&self, acceleration_m_per_s2: R, velocity_m_per_s: R) -> R {
        self.force_n(acceleration_m_per_s2) * velocity_m_per_s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folded_flexure_by_hand() {
        // 2 E t w^3 / L^3 = 2 x 160e9 x 2e-6 x 8e-18 / (92e-6)^3 = 5.12e-12 / 7.78688e-13.
        let k = folded_flexure_stiffness_n_per_m(160e9, 2e-6, 2e-6, 92e-6);
        assert!((k - 5.12e-12 / 7.78688e-13).abs() < 1e-9, "{k}");
        // Twice as long: 8 times softer; twice as wide: 8 times stiffer; twice as thick: 2 times.
        assert!((folded_flexure_stiffness_n_per_m(160e9, 2e-6, 2e-6, 184e-6) * 8.0 - k).abs() < 1e-12);
        assert!((folded_flexure_stiffness_n_per_m(160e9, 2e-6, 4e-6, 92e-6) - 8.0 * k).abs() < 1e-9);
        assert!((folded_flexure_stiffness_n_per_m(160e9, 4e-6, 2e-6, 92e-6) - 2.0 * k).abs() < 1e-9);
    }

    #[test]
    fn the_squeeze_film_is_the_reynolds_strip_integrated() {
        // p(y) = 6 mu v (W^2/4 - y^2) / h^3 integrated over [-W/2, W/2] by the midpoint rule.
        let (mu, l, w, h, v): (f64, f64, f64, f64, f64) = (1.85e-5, 104e-6, 2e-6, 1e-6, 1e-3);
        let n = 100_000;
        let dy = w / n as f64;
        let force: f64 = (0..n)
            .map(|i| {
                let y = -w / 2.0 + (i as f64 + 0.5) * dy;
                6.0 * mu * v * (w * w / 4.0 - y * y) / h.powi(3) * l * dy
            })
            .sum();
        assert!((force / (squeeze_film_strip_damping_n_s_per_m(mu, l, w, h) * v) - 1.0).abs() < 1e-8);
    }

    #[test]
    fn pull_in_is_where_the_equilibrium_disappears() {
        // Below V_pi the static balance k s = F(s) has a root below g/3; above it none.
        let c = ParallelPlate { permittivity_f_per_m: VACUUM_PERMITTIVITY_F_PER_M, area_m2: 8.736e-9, gap_m: 1e-6 };
        let k = 6.575;
        let v_pi = c.pull_in_voltage_v(k);
        let has_root = |v: f64| (0..10_000).map(|i| i as f64 * 1e-10).any(|s| k * s >= c.force_n(v * v, s));
        assert!(has_root(0.999 * v_pi));
        assert!(!has_root(1.001 * v_pi));
        // A mean-square 8/27 k g^3 / (eps A): the spring and electrode balance exactly at g/3.
        assert!((k * c.gap_m / 3.0 - c.force_n(v_pi * v_pi, c.gap_m / 3.0)).abs() < 1e-18);
    }

    #[test]
    fn thin_films_damp_less() {
        let lambda = mean_free_path_m(AIR_VISCOSITY_PA_S, 101_325.0, 298.15, AIR_MOLAR_MASS_KG_PER_MOL);
        // Halving the pressure doubles the mean free path.
        assert!((mean_free_path_m(AIR_VISCOSITY_PA_S, 50_662.5, 298.15, AIR_MOLAR_MASS_KG_PER_MOL) / lambda - 2.0).abs() < 1e-12);
        let squeeze = squeeze_film_effective_viscosity_pa_s(AIR_VISCOSITY_PA_S, lambda / 1e-6);
        let slide = slide_film_effective_viscosity_pa_s(AIR_VISCOSITY_PA_S, lambda / 1e-6);
        assert!(squeeze < slide && slide < AIR_VISCOSITY_PA_S);
    }
}
