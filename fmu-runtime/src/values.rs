//! The values of one instance, and the typed views a model's equations read and write.
//!
//! A model never sees value references: it reads knowns through [`Knowns`] (`k[r_series]`,
//! `k[i_l]`, `k.time()`), writes outputs through [`Outputs`] (`out[i_absorbed] = ...`) and state
//! derivatives through [`Derivatives`] (`der[i_l] = ...`). The handles come from the model's own
//! declarations, so an index can never point at the wrong kind of variable.

use std::ops::{Index, IndexMut};

use crate::elements::Element;
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

/// What the equations may read at one instant: time, parameters, inputs, states.
pub struct Knowns<'a> {
    pub(crate) time: f64,
    pub(crate) known: &'a [f64],
    pub(crate) states: &'a [f64],
    pub(crate) integers: &'a [i32],
    pub(crate) booleans: &'a [bool],
}

impl<'a> Knowns<'a> {
    /// Builds a view; `known` is the known-reals store, `states` the current state vector.
    pub fn new(time: f64, known: &'a [f64], states: &'a [f64], integers: &'a [i32], booleans: &'a [bool]) -> Self {
        Knowns { time, known, states, integers, booleans }
    }

    /// Simulation time, s.
    pub fn time(&self) -> f64 {
        self.time
    }
}

impl Index<Parameter> for Knowns<'_> {
    type Output = f64;
    fn index(&self, p: Parameter) -> &f64 {
        &self.known[p.0]
    }
}

impl Index<Input> for Knowns<'_> {
    type Output = f64;
    fn index(&self, u: Input) -> &f64 {
        &self.known[u.0]
    }
}

impl Index<State> for Knowns<'_> {
    type Output = f64;
    fn index(&self, x: State) -> &f64 {
        &self.states[x.state]
    }
}

impl Index<IntegerParameter> for Knowns<'_> {
    type Output = i32;
    fn index(&self, n: IntegerParameter) -> &i32 {
        &self.integers[n.0]
    }
}

impl Index<BooleanParameter> for Knowns<'_> {
    type Output = bool;
    fn index(&self, b: BooleanParameter) -> &bool {
        &self.booleans[b.0]
    }
}

/// Where `Model::outputs` writes outputs, locals and calculated parameters.
pub struct Outputs<'a> {
    pub(crate) calculated: &'a mut [f64],
}

impl<'a> Outputs<'a> {
    pub fn new(calculated: &'a mut [f64]) -> Self {
        Outputs { calculated }
    }
}

impl Index<Output> for Outputs<'_> {
    type Output = f64;
    fn index(&self, y: Output) -> &f64 {
        &self.calculated[y.0]
    }
}

impl IndexMut<Output> for Outputs<'_> {
    fn index_mut(&mut self, y: Output) -> &mut f64 {
        &mut self.calculated[y.0]
    }
}

impl Index<Local> for Outputs<'_> {
    type Output = f64;
    fn index(&self, y: Local) -> &f64 {
        &self.calculated[y.0]
    }
}

impl IndexMut<Local> for Outputs<'_> {
    fn index_mut(&mut self, y: Local) -> &mut f64 {
        &mut self.calculated[y.0]
    }
}

/// Where `Model::derivatives` writes dx/dt, one entry per state, and each declared element's
/// power (`der.power(element, p)`, see [`crate::elements`]).
pub struct Derivatives<'a> {
    pub(crate) rates: &'a mut [f64],
    pub(crate) powers: Option<&'a mut [f64]>,
    /// Whether an activity state's rate is the element's signed power p (for a solver that
    /// integrates |p| itself, as a quadrature: [`crate::rk::Tsit::with_quadratures`]) rather
    /// than |p|, the rate a Model Exchange master integrates.
    pub(crate) signed_activity: bool,
}

impl<'a> Derivatives<'a> {
    pub fn new(rates: &'a mut [f64]) -> Self {
        Derivatives { rates, powers: None, signed_activity: false }
    }

    /// Also records each element's power in `powers`, by element.
    pub fn with_powers(rates: &'a mut [f64], powers: &'a mut [f64]) -> Self {
        Derivatives { rates, powers: Some(powers), signed_activity: false }
    }

    /// Writes each activity state's rate as the signed power p, not |p|.
    pub(crate) fn with_signed_activities(rates: &'a mut [f64]) -> Self {
        Derivatives { rates, powers: None, signed_activity: true }
    }

    /// Reports the power of a declared element, in W: what a source delivers, the rate dE/dt
    /// of what a storage element stores, what a dissipative element takes out (chapter eq.
    /// 3.3). The runtime integrates its absolute value into the element's activity and sums
    /// the powers into the energy balance. Report every element at every point, 0 where the
    /// configuration leaves it out.
    pub fn power(&mut self, element: Element, power_w: f64) {
        if let Some(s) = element.activity {
            self.rates[s] = if self.signed_activity { power_w } else { power_w.abs() };
        }
        if let Some(p) = self.powers.as_deref_mut() {
            p[element.index] = power_w;
        }
    }
}

impl Index<State> for Derivatives<'_> {
    type Output = f64;
    fn index(&self, x: State) -> &f64 {
        &self.rates[x.state]
    }
}

impl IndexMut<State> for Derivatives<'_> {
    fn index_mut(&mut self, x: State) -> &mut f64 {
        &mut self.rates[x.state]
    }
}

/// Where `Model::initial_states` writes the initial values of its calculated states.
pub struct InitialStates<'a> {
    pub(crate) states: &'a mut [f64],
}

impl<'a> InitialStates<'a> {
    pub fn new(states: &'a mut [f64]) -> Self {
        InitialStates { states }
    }
}

impl IndexMut<State> for InitialStates<'_> {
    fn index_mut(&mut self, x: State) -> &mut f64 {
        &mut self.states[x.state]
    }
}

impl Index<State> for InitialStates<'_> {
    type Output = f64;
    fn index(&self, x: State) -> &f64 {
        &self.states[x.state]
    }
}

impl Index<Mode> for Knowns<'_> {
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
