//! The values of one instance, and the typed views a model's equations read and write.
//!
//! A model never sees value references: it reads knowns through [`Knowns`] (`k[r_series]`,
//! `k[i_l]`, `k.time()`), writes outputs through [`Outputs`] (`out[i_absorbed] = ...`) and state
//! derivatives through [`Derivatives`] (`der[i_l] = ...`). The handles come from the model's own
//! declarations, so an index can never point at the wrong kind of variable.

use std::ops::{Index, IndexMut};

use crate::elements::Element;
use crate::real::Real;
use crate::variables::{BooleanParameter, Indicator, Input, IntegerParameter, Local, Mode, Output, Parameter, State};

/// The stores of one instance, each indexed by the slot the declaration gave.
#[derive(Clone, Debug, PartialEq)]
pub struct Values {
    /// Parameters and inputs.
    pub known: Vec<f64>,
    /// The continuous states, the one home of each state's value (`Slot::State`): the start
    /// values before initialization (a calculated state's as the model computes it), the
    /// current states after it. What a master reads and sets by value reference, what
    /// fmi2Get/SetContinuousStates copy and what the solver advances.
    pub states: Vec<f64>,
    /// Outputs, locals and calculated parameters.
    pub calculated: Vec<f64>,
    /// State derivatives at the current time.
    pub derivatives: Vec<f64>,
    pub integers: Vec<i32>,
    pub booleans: Vec<bool>,
}

/// What the equations may read at one instant: time, parameters, inputs, states. `R` is the
/// scalar of the reals ([`Real`]): `f64`, or a number that carries derivatives; the equations
/// written over any `R` serve both (docs/DESIGN.md, "Exact derivatives").
pub struct Knowns<'a, R = f64> {
    pub(crate) time: f64,
    pub(crate) known: &'a [R],
    pub(crate) states: &'a [R],
    pub(crate) integers: &'a [i32],
    pub(crate) booleans: &'a [bool],
}

impl<'a, R: Real> Knowns<'a, R> {
    /// Builds a view; `known` is the known-reals store, `states` the current state vector.
    pub fn new(time: f64, known: &'a [R], states: &'a [R], integers: &'a [i32], booleans: &'a [bool]) -> Self {
        Knowns { time, known, states, integers, booleans }
    }

    /// Simulation time, s.
    pub fn time(&self) -> f64 {
        self.time
    }
}

impl<R> Index<Parameter> for Knowns<'_, R> {
    type Output = R;
    fn index(&self, p: Parameter) -> &R {
        &self.known[p.0]
    }
}

impl<R> Index<Input> for Knowns<'_, R> {
    type Output = R;
    fn index(&self, u: Input) -> &R {
        &self.known[u.0]
    }
}

impl<R> Index<State> for Knowns<'_, R> {
    type Output = R;
    fn index(&self, x: State) -> &R {
        &self.states[x.state]
    }
}

impl<R> Index<IntegerParameter> for Knowns<'_, R> {
    type Output = i32;
    fn index(&self, n: IntegerParameter) -> &i32 {
        &self.integers[n.0]
    }
}

impl<R> Index<BooleanParameter> for Knowns<'_, R> {
    type Output = bool;
    fn index(&self, b: BooleanParameter) -> &bool {
        &self.booleans[b.0]
    }
}

/// Where `Model::outputs` writes outputs, locals and calculated parameters.
pub struct Outputs<'a, R = f64> {
    pub(crate) calculated: &'a mut [R],
}

impl<'a, R> Outputs<'a, R> {
    pub fn new(calculated: &'a mut [R]) -> Self {
        Outputs { calculated }
    }
}

impl<R> Index<Output> for Outputs<'_, R> {
    type Output = R;
    fn index(&self, y: Output) -> &R {
        &self.calculated[y.0]
    }
}

impl<R> IndexMut<Output> for Outputs<'_, R> {
    fn index_mut(&mut self, y: Output) -> &mut R {
        &mut self.calculated[y.0]
    }
}

impl<R> Index<Local> for Outputs<'_, R> {
    type Output = R;
    fn index(&self, y: Local) -> &R {
        &self.calculated[y.0]
    }
}

impl<R> IndexMut<Local> for Outputs<'_, R> {
    fn index_mut(&mut self, y: Local) -> &mut R {
        &mut self.calculated[y.0]
    }
}

/// Where `Model::derivatives` writes dx/dt, one entry per state, and each declared element's
/// power (`der.power(element, p)`, see [`crate::elements`]).
pub struct Derivatives<'a, R = f64> {
    pub(crate) rates: &'a mut [R],
    pub(crate) powers: Option<&'a mut [R]>,
    /// Whether an activity state's rate is the element's signed power p (for a solver that
    /// integrates |p| itself, as a quadrature: [`crate::rk::Tsit::with_quadratures`]) rather
    /// than |p|, the rate a Model Exchange master integrates.
    pub(crate) signed_activity: bool,
}

impl<'a, R: Real> Derivatives<'a, R> {
    pub fn new(rates: &'a mut [R]) -> Self {
        Derivatives { rates, powers: None, signed_activity: false }
    }

    /// Also records each element's power in `powers`, by element.
    pub fn with_powers(rates: &'a mut [R], powers: &'a mut [R]) -> Self {
        Derivatives { rates, powers: Some(powers), signed_activity: false }
    }

    /// Writes each activity state's rate as the signed power p, not |p|.
    pub(crate) fn with_signed_activities(rates: &'a mut [R]) -> Self {
        Derivatives { rates, powers: None, signed_activity: true }
    }

    /// Reports the power of a declared element, in W: what a source delivers, the rate dE/dt
    /// of what a storage element stores, what a dissipative element takes out (chapter eq.
    /// 3.3). The runtime integrates its absolute value into the element's activity and sums
    /// the powers into the energy balance. Report every element at every point, 0 where the
    /// configuration leaves it out.
    pub fn power(&mut self, element: Element, power_w: R) {
        if let Some(s) = element.activity {
            self.rates[s] = if self.signed_activity { power_w } else { power_w.abs() };
        }
        if let Some(p) = self.powers.as_deref_mut() {
            p[element.index] = power_w;
        }
    }
}

impl<R> Index<State> for Derivatives<'_, R> {
    type Output = R;
    fn index(&self, x: State) -> &R {
        &self.rates[x.state]
    }
}

impl<R> IndexMut<State> for Derivatives<'_, R> {
    fn index_mut(&mut self, x: State) -> &mut R {
        &mut self.rates[x.state]
    }
}

/// Where `Model::initial_states` writes the initial values of its calculated states.
pub struct InitialStates<'a, R = f64> {
    pub(crate) states: &'a mut [R],
}

impl<'a, R> InitialStates<'a, R> {
    pub fn new(states: &'a mut [R]) -> Self {
        InitialStates { states }
    }
}

impl<R> IndexMut<State> for InitialStates<'_, R> {
    fn index_mut(&mut self, x: State) -> &mut R {
        &mut self.states[x.state]
    }
}

impl<R> Index<State> for InitialStates<'_, R> {
    type Output = R;
    fn index(&self, x: State) -> &R {
        &self.states[x.state]
    }
}

impl<R> Index<Mode> for Knowns<'_, R> {
    type Output = i32;
    fn index(&self, m: Mode) -> &i32 {
        &self.integers[m.0]
    }
}

/// Where `Model::event_indicators` writes the indicators z, one per declared `Indicator`.
pub struct EventIndicators<'a> {
    pub(crate) z: &'a mut [f64],
}

impl<'a> EventIndicators<'a> {
    pub fn new(z: &'a mut [f64]) -> Self {
        EventIndicators { z }
    }
}

impl Index<Indicator> for EventIndicators<'_> {
    type Output = f64;
    fn index(&self, i: Indicator) -> &f64 {
        &self.z[i.0]
    }
}

impl IndexMut<Indicator> for EventIndicators<'_> {
    fn index_mut(&mut self, i: Indicator) -> &mut f64 {
        &mut self.z[i.0]
    }
}

/// What `Model::update_modes` may change at an event: the discrete modes (`next[mode] = 1`) and,
/// where the physics says so, a continuous state's value (`next.reinit(speed, 0.0)`: a body
/// that sticks stands exactly still).
pub struct ModeUpdate<'a> {
    pub(crate) integers: &'a mut [i32],
    pub(crate) states: &'a mut [f64],
    pub(crate) reinitialized: bool,
}

impl<'a> ModeUpdate<'a> {
    pub fn new(integers: &'a mut [i32], states: &'a mut [f64]) -> Self {
        ModeUpdate { integers, states, reinitialized: false }
    }

    /// Sets a continuous state to a new value at this event.
    pub fn reinit(&mut self, x: State, value: f64) {
        if self.states[x.state].to_bits() != value.to_bits() {
            self.states[x.state] = value;
            self.reinitialized = true;
        }
    }

    /// Whether `reinit` changed a state.
    pub fn reinitialized(&self) -> bool {
        self.reinitialized
    }
}

impl Index<Mode> for ModeUpdate<'_> {
    type Output = i32;
    fn index(&self, m: Mode) -> &i32 {
        &self.integers[m.0]
    }
}

impl IndexMut<Mode> for ModeUpdate<'_> {
    fn index_mut(&mut self, m: Mode) -> &mut i32 {
        &mut self.integers[m.0]
    }
}
