//! Property test: whatever sequence of FMI calls a master makes, no FMU in dist/ crashes, hangs,
//! returns an illegal status, fails silently, or stays damaged after fmi2Reset.
//!
//! Each case instantiates one FMU (Co-Simulation or Model Exchange, logging on or off, with or
//! without memory callbacks) and makes 1-40 random calls: any fmi2 function, in any mode, with
//! value references inside and outside the model, NaN/inf/huge/tiny values, NULL arrays where a
//! length says there is data, zero/negative/NaN step sizes, time going backwards, FMU-state
//! handles that were freed or made up, corrupted serialized states, and strings that are not
//! valid UTF-8. After every call:
//! * the status is one of fmi2OK..fmi2Discard or fmi2Error (no fmi2Fatal: that would be a panic
//!   inside a model; no out-of-range value);
//! * every fmi2Error, fmi2Discard and fmi2Fatal came with a logger message of that status;
//! * the call returned within `CALL_TIME_LIMIT` (a hang guard, not a speed claim).
//!
//! At the end the instance is reset and must then run its default experiment exactly (bit for
//! bit) as a fresh instance does.
//!
//! `FUZZ_CASES` sets the total number of cases over all FMUs (default 10 000); `PROPTEST_SEED`
//! -free: the runner's seed is fixed per FMU so a failure replays. The FMUs are fuzzed side by
//! side, one thread per core (`FUZZ_THREADS` sets the count).

use std::ffi::{c_char, c_int, CString};
use std::ptr;
use std::sync::Arc;
use std::time::{Duration, Instant};

use fmi_host::dist::every_fmu;
use fmi_host::ffi::{EventInfo, FmuStatePtr};
use fmi_host::{Causality, Fmi2Type, Fmu, Instance, InstantiateOptions, Status, StatusKind, ValueReference, VariableType};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestCaseError, TestRng, TestRunner};

/// A call slower than this is taken for a hang (the slowest legal call, a long doStep hitting the
/// solver's step limit, takes well under a second).
const CALL_TIME_LIMIT: Duration = Duration::from_secs(20);

/// A real value a master might pass, sane or not.
fn any_real() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -10.0..10.0f64,
        1 => Just(0.0),
        1 => Just(-0.0),
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => Just(f64::MAX),
        1 => Just(-f64::MAX),
        1 => Just(f64::MIN_POSITIVE),
        1 => Just(1e-300),
        1 => Just(1e30),
        2 => any::<f64>(),
    ]
}

/// A communication step size. With `FUZZ_SHORT_STEPS` set (under valgrind, where integrating
/// is 50x slower and only the memory handling matters), the long steps become 1e-4 s.
fn any_step() -> impl Strategy<Value = f64> {
    let long = |h: f64| if std::env::var_os("FUZZ_SHORT_STEPS").is_some() { 1e-4 } else { h };
    prop_oneof![
        6 => prop_oneof![Just(1e-4), Just(1e-3), Just(long(1e-2)), Just(long(0.1)), Just(long(1.0))],
        1 => Just(0.0),
        1 => Just(-1e-3),
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(1e-300),
        1 => Just(long(1e9)),
    ]
}

/// Bytes for a string argument: valid UTF-8, invalid UTF-8, or empty (never with an inner NUL,
/// which C cannot pass).
fn any_text() -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![
        Just(b"logAll".to_vec()),
        Just(b"logStatusError".to_vec()),
        Just(Vec::new()),
        Just(vec![0xff, 0xfe, b'x']),
        Just(vec![0xc3, 0x28]),
        proptest::collection::vec(1u8..=255, 0..12),
    ]
}

/// Where a value reference comes from: a variable of the model (any type), or none.
#[derive(Clone, Copy, Debug)]
enum VrPick {
    Existing(usize),
    JustPastTheEnd,
    Huge,
}

fn any_vr() -> impl Strategy<Value = VrPick> {
    prop_oneof![8 => any::<usize>().prop_map(VrPick::Existing), 1 => Just(VrPick::JustPastTheEnd), 1 => Just(VrPick::Huge)]
}

fn any_vrs() -> impl Strategy<Value = Vec<VrPick>> {
    proptest::collection::vec(any_vr(), 0..4)
}

/// Which communication point a doStep claims.
#[derive(Clone, Copy, Debug)]
enum When {
    /// The instance's time (what a correct master passes).
    Now,
    /// Before it: time going backwards.
    Earlier,
    /// Any number.
    Value(f64),
}

/// A saved-state handle to use: one of ours (possibly already freed), NULL, or made up.
#[derive(Clone, Copy, Debug)]
enum StatePick {
    Ours(usize),
    Null,
    MadeUp(usize),
}

fn any_state() -> impl Strategy<Value = StatePick> {
    prop_oneof![6 => any::<usize>().prop_map(StatePick::Ours), 1 => Just(StatePick::Null), 1 => any::<usize>().prop_map(StatePick::MadeUp)]
}

/// How to damage a serialized state before handing it back.
#[derive(Clone, Debug)]
enum Damage {
    None,
    FlipBit(usize),
    Truncate(usize),
    Append(Vec<u8>),
    Random(Vec<u8>),
}

fn any_damage() -> impl Strategy<Value = Damage> {
    prop_oneof![
        2 => Just(Damage::None),
        4 => any::<usize>().prop_map(Damage::FlipBit),
        2 => any::<usize>().prop_map(Damage::Truncate),
        1 => proptest::collection::vec(any::<u8>(), 1..16).prop_map(Damage::Append),
        1 => proptest::collection::vec(any::<u8>(), 0..64).prop_map(Damage::Random),
    ]
}

#[derive(Clone, Debug)]
enum Call {
    SetDebugLogging { on: bool, categories: Vec<Vec<u8>>, null_array: bool },
    SetupExperiment { tolerance: Option<f64>, start: f64, stop: Option<f64> },
    EnterInitializationMode,
    ExitInitializationMode,
    Terminate,
    Reset,
    GetReal { vrs: Vec<VrPick>, null_values: bool },
    SetReal { vrs: Vec<VrPick>, values: Vec<f64>, null_values: bool },
    GetInteger { vrs: Vec<VrPick> },
    SetInteger { vrs: Vec<VrPick>, values: Vec<i32> },
    GetBoolean { vrs: Vec<VrPick> },
    SetBoolean { vrs: Vec<VrPick>, values: Vec<c_int> },
    GetString { vrs: Vec<VrPick> },
    SetString { vrs: Vec<VrPick>, values: Vec<Vec<u8>> },
    DoStep { when: When, h: f64, no_set_prior: bool },
    CancelStep,
    GetStatus { kind: u8, which: u8 },
    GetFmuState { into: Option<StatePick> },
    SetFmuState(StatePick),
    FreeFmuState(StatePick),
    SerializeAndRestore { state: StatePick, damage: Damage },
    DirectionalDerivative { unknowns: Vec<VrPick>, knowns: Vec<VrPick>, seeds: Vec<f64> },
    SetInputDerivatives { vrs: Vec<VrPick>, orders: Vec<c_int>, values: Vec<f64> },
    GetOutputDerivatives { vrs: Vec<VrPick>, orders: Vec<c_int> },
    EnterEventMode,
    NewDiscreteStates,
    EnterContinuousTimeMode,
    SetTime(f64),
    SetContinuousStates { values: Vec<f64>, null: bool },
    GetRealArray { which: u8, len_offset: i8 },
    CompletedIntegratorStep { no_set_prior: bool },
    /// The legal start (setup, enter, exit), so random calls also reach the stepping modes.
    Initialize,
}

fn any_call() -> impl Strategy<Value = Call> {
    let reals = || proptest::collection::vec(any_real(), 0..4);
    prop_oneof![
        1 => (any::<bool>(), proptest::collection::vec(any_text(), 0..3), any::<bool>())
            .prop_map(|(on, categories, null_array)| Call::SetDebugLogging { on, categories, null_array }),
        1 => (proptest::option::of(any_real()), any_real(), proptest::option::of(any_real()))
            .prop_map(|(tolerance, start, stop)| Call::SetupExperiment { tolerance, start, stop }),
        1 => Just(Call::EnterInitializationMode),
        1 => Just(Call::ExitInitializationMode),
        1 => Just(Call::Terminate),
        1 => Just(Call::Reset),
        1 => (any_vrs(), any::<bool>()).prop_map(|(vrs, null_values)| Call::GetReal { vrs, null_values }),
        1 => (any_vrs(), reals(), any::<bool>()).prop_map(|(vrs, values, null_values)| Call::SetReal { vrs, values, null_values }),
        1 => any_vrs().prop_map(|vrs| Call::GetInteger { vrs }),
        1 => (any_vrs(), proptest::collection::vec(any::<i32>(), 0..4)).prop_map(|(vrs, values)| Call::SetInteger { vrs, values }),
        1 => any_vrs().prop_map(|vrs| Call::GetBoolean { vrs }),
        1 => (any_vrs(), proptest::collection::vec(any::<c_int>(), 0..4)).prop_map(|(vrs, values)| Call::SetBoolean { vrs, values }),
        1 => any_vrs().prop_map(|vrs| Call::GetString { vrs }),
        1 => (any_vrs(), proptest::collection::vec(any_text(), 0..4)).prop_map(|(vrs, values)| Call::SetString { vrs, values }),
        10 => (prop_oneof![6 => Just(When::Now), 1 => Just(When::Earlier), 1 => any_real().prop_map(When::Value)], any_step(), any::<bool>())
            .prop_map(|(when, h, no_set_prior)| Call::DoStep { when, h, no_set_prior }),
        1 => Just(Call::CancelStep),
        1 => (0u8..3, 0u8..5).prop_map(|(kind, which)| Call::GetStatus { kind, which }),
        1 => proptest::option::of(any_state()).prop_map(|into| Call::GetFmuState { into }),
        1 => any_state().prop_map(Call::SetFmuState),
        1 => any_state().prop_map(Call::FreeFmuState),
        1 => (any_state(), any_damage()).prop_map(|(state, damage)| Call::SerializeAndRestore { state, damage }),
        1 => (any_vrs(), any_vrs(), reals()).prop_map(|(unknowns, knowns, seeds)| Call::DirectionalDerivative { unknowns, knowns, seeds }),
        1 => (any_vrs(), proptest::collection::vec(-1 as c_int..4, 0..4), reals())
            .prop_map(|(vrs, orders, values)| Call::SetInputDerivatives { vrs, orders, values }),
        1 => (any_vrs(), proptest::collection::vec(-1 as c_int..4, 0..4)).prop_map(|(vrs, orders)| Call::GetOutputDerivatives { vrs, orders }),
        1 => Just(Call::EnterEventMode),
        1 => Just(Call::NewDiscreteStates),
        1 => Just(Call::EnterContinuousTimeMode),
        1 => any_real().prop_map(Call::SetTime),
        1 => (proptest::collection::vec(any_real(), 0..8), any::<bool>()).prop_map(|(values, null)| Call::SetContinuousStates { values, null }),
        1 => (0u8..4, -1i8..2).prop_map(|(which, len_offset)| Call::GetRealArray { which, len_offset }),
        1 => any::<bool>().prop_map(|no_set_prior| Call::CompletedIntegratorStep { no_set_prior }),
        4 => Just(Call::Initialize),
    ]
}

/// One case: the instance's options and its calls.
#[derive(Clone, Debug)]
struct Case {
    model_exchange: bool,
    logging_on: bool,
    memory_callbacks: bool,
    calls: Vec<Call>,
}

fn any_case() -> impl Strategy<Value = Case> {
    // Half the cases start with a legal initialization, so the random calls also hit the
    // stepping modes in depth, not only the refusals before initialization.
    (any::<bool>(), any::<bool>(), prop_oneof![4 => Just(true), 1 => Just(false)], any::<bool>(), proptest::collection::vec(any_call(), 1..40))
        .prop_map(|(model_exchange, logging_on, memory_callbacks, initialized_first, mut calls)| {
            if initialized_first {
                calls.insert(0, Call::Initialize);
            }
            Case { model_exchange, logging_on, memory_callbacks, calls }
        })
}

/// What the test knows about the FMU under test.
struct Target {
    fmu: Arc<Fmu>,
    vrs: Vec<ValueReference>,
    n_states: usize,
    n_event_indicators: usize,
    outputs: Vec<ValueReference>,
    start: f64,
    step: f64,
}

impl Target {
    fn of(fmu: &Arc<Fmu>) -> Target {
        let md = fmu.model_description();
        let e = md.default_experiment.clone().expect("every FMU has a DefaultExperiment");
        Target {
            fmu: fmu.clone(),
            vrs: md.model_variables.iter().map(|v| v.value_reference).collect(),
            n_states: md.model_variables.iter().filter(|v| v.derivative.is_some()).count(),
            n_event_indicators: md.number_of_event_indicators.unwrap_or(0) as usize,
            outputs: md
                .model_variables
                .iter()
                .filter(|v| v.causality == Causality::Output && v.variable_type == VariableType::Real)
                .map(|v| v.value_reference)
                .collect(),
            start: e.start_time.unwrap_or(0.0),
            step: e.step_size.unwrap(),
        }
    }

    fn vr(&self, pick: VrPick) -> ValueReference {
        match pick {
            VrPick::Existing(i) => self.vrs[i % self.vrs.len()],
            VrPick::JustPastTheEnd => self.vrs.len() as ValueReference,
            VrPick::Huge => ValueReference::MAX,
        }
    }

    fn vrs(&self, picks: &[VrPick]) -> Vec<ValueReference> {
        picks.iter().map(|p| self.vr(*p)).collect()
    }

    fn name(&self) -> &str {
        &self.fmu.model_description().model_name
    }

    fn instantiate(&self, name: &str, model_exchange: bool, logging_on: bool, memory_callbacks: bool) -> Instance {
        let kind = if model_exchange { Fmi2Type::ModelExchange } else { Fmi2Type::CoSimulation };
        let options = InstantiateOptions::new(name).fmu_type(kind).logging_on(logging_on).memory_callbacks(memory_callbacks);
        Instance::new(&self.fmu, options).unwrap_or_else(|e| panic!("{}: instantiate: {e}", self.name()))
    }

    /// The reference run after a (re)start: the default experiment's first steps (Co-Simulation)
    /// or the initial outputs, states and derivatives (Model Exchange), as bits.
    fn reference_run(&self, inst: &mut Instance, model_exchange: bool) -> Result<Vec<u64>, String> {
        let check = |s: Status, what: &str| if s == Status::OK { Ok(()) } else { Err(format!("{what}: {s:?}")) };
        check(inst.setup_experiment(None, self.start, None), "setup")?;
        check(inst.enter_initialization_mode(), "enter initialization")?;
        check(inst.exit_initialization_mode(), "exit initialization")?;
        let mut bits = Vec::new();
        if model_exchange {
            let mut x = vec![0.0; self.n_states];
            let mut dx = vec![0.0; self.n_states];
            let mut info = EventInfo::default();
            check(inst.new_discrete_states(&mut info).map_err(|e| e.to_string())?, "new discrete states")?;
            check(inst.enter_continuous_time_mode().map_err(|e| e.to_string())?, "continuous time mode")?;
            check(inst.get_continuous_states(&mut x).map_err(|e| e.to_string())?, "states")?;
            check(inst.get_derivatives(&mut dx).map_err(|e| e.to_string())?, "derivatives")?;
            bits.extend(x.iter().chain(&dx).map(|v| v.to_bits()));
        } else {
            for k in 0..5 {
                check(inst.do_step(self.start + k as f64 * self.step, self.step, true), "step")?;
            }
        }
        let (status, y) = inst.get_reals(&self.outputs);
        check(status, "outputs")?;
        bits.extend(y.iter().map(|v| v.to_bits()));
        Ok(bits)
    }
}

/// A live instance and what the test tracks beside it.
struct Run<'a> {
    target: &'a Target,
    inst: Instance,
    /// The time a correct master would pass to the next doStep.
    time: f64,
    /// Every FMU-state handle handed out (freed ones stay, to be used again on purpose).
    states: Vec<FmuStatePtr>,
}

fn text(bytes: &[u8]) -> CString {
    CString::new(bytes.to_vec()).expect("no NUL byte in generated text")
}

impl Run<'_> {
    fn state(&self, pick: StatePick) -> FmuStatePtr {
        match pick {
            StatePick::Ours(i) if !self.states.is_empty() => self.states[i % self.states.len()],
            StatePick::Ours(_) | StatePick::Null => ptr::null_mut(),
            // An address that looks like a pointer but was never handed out.
            StatePick::MadeUp(n) => (0x1000 + (n % 0x10000) * 8) as FmuStatePtr,
        }
    }

    /// Makes one call; returns its status.
    fn call(&mut self, call: &Call) -> Status {
        let t = self.target;
        let f = t.fmu.functions();
        let c = self.inst.raw_component();
        // SAFETY (every unsafe block below): arrays are valid for the lengths passed with them,
        // or NULL on purpose (a misuse the FMU must refuse without reading through it); string
        // arguments are NUL-terminated and live until the call returns; FMU-state handles are
        // opaque values the FMU must validate, never dereferenced by this test.
        match call {
            Call::SetDebugLogging { on, categories, null_array } => {
                let owned: Vec<CString> = categories.iter().map(|b| text(b)).collect();
                let raw: Vec<*const c_char> = owned.iter().map(|s| s.as_ptr()).collect();
                let array = if *null_array { ptr::null() } else { raw.as_ptr() };
                unsafe { (f.set_debug_logging)(c, *on as c_int, raw.len(), array) }
            }
            Call::SetupExperiment { tolerance, start, stop } => unsafe {
                (f.setup_experiment)(c, tolerance.is_some() as c_int, tolerance.unwrap_or(0.0), *start, stop.is_some() as c_int, stop.unwrap_or(0.0))
            },
            Call::EnterInitializationMode => unsafe { (f.enter_initialization_mode)(c) },
            Call::ExitInitializationMode => unsafe { (f.exit_initialization_mode)(c) },
            Call::Terminate => unsafe { (f.terminate)(c) },
            Call::Reset => {
                let s = unsafe { (f.reset)(c) };
                if s == Status::OK {
                    self.time = 0.0;
                }
                s
            }
            Call::GetReal { vrs, null_values } => {
                let vrs = t.vrs(vrs);
                let mut v = vec![0.0; vrs.len()];
                let out = if *null_values && !vrs.is_empty() { ptr::null_mut() } else { v.as_mut_ptr() };
                unsafe { (f.get_real)(c, vrs.as_ptr(), vrs.len(), out) }
            }
            Call::SetReal { vrs, values, null_values } => {
                let vrs = t.vrs(vrs);
                let n = vrs.len().min(values.len());
                let input = if *null_values && n > 0 { ptr::null() } else { values.as_ptr() };
                unsafe { (f.set_real)(c, vrs.as_ptr(), n, input) }
            }
            Call::GetInteger { vrs } => {
                let vrs = t.vrs(vrs);
                let mut v = vec![0; vrs.len()];
                unsafe { (f.get_integer)(c, vrs.as_ptr(), vrs.len(), v.as_mut_ptr()) }
            }
            Call::SetInteger { vrs, values } => {
                let vrs = t.vrs(vrs);
                unsafe { (f.set_integer)(c, vrs.as_ptr(), vrs.len().min(values.len()), values.as_ptr()) }
            }
            Call::GetBoolean { vrs } => {
                let vrs = t.vrs(vrs);
                let mut v = vec![0; vrs.len()];
                unsafe { (f.get_boolean)(c, vrs.as_ptr(), vrs.len(), v.as_mut_ptr()) }
            }
            Call::SetBoolean { vrs, values } => {
                let vrs = t.vrs(vrs);
                unsafe { (f.set_boolean)(c, vrs.as_ptr(), vrs.len().min(values.len()), values.as_ptr()) }
            }
            Call::GetString { vrs } => {
                let vrs = t.vrs(vrs);
                let mut v: Vec<*const c_char> = vec![ptr::null(); vrs.len()];
                unsafe { (f.get_string)(c, vrs.as_ptr(), vrs.len(), v.as_mut_ptr()) }
            }
            Call::SetString { vrs, values } => {
                let vrs = t.vrs(vrs);
                let owned: Vec<CString> = values.iter().map(|b| text(b)).collect();
                let raw: Vec<*const c_char> = owned.iter().map(|s| s.as_ptr()).collect();
                unsafe { (f.set_string)(c, vrs.as_ptr(), vrs.len().min(raw.len()), raw.as_ptr()) }
            }
            Call::DoStep { when, h, no_set_prior } => {
                let at = match when {
                    When::Now => self.time,
                    When::Earlier => self.time - 1.0,
                    When::Value(v) => *v,
                };
                let s = unsafe { (f.do_step)(c, at, *h, *no_set_prior as c_int) };
                if s == Status::OK {
                    self.time = at + h;
                }
                s
            }
            Call::CancelStep => unsafe { (f.cancel_step)(c) },
            Call::GetStatus { kind, which } => {
                let kind = match kind {
                    0 => StatusKind::DoStepStatus,
                    1 => StatusKind::PendingStatus,
                    _ => StatusKind::LastSuccessfulTime,
                };
                unsafe {
                    match which {
                        0 => (f.get_status)(c, kind, &mut Status(0)),
                        1 => (f.get_real_status)(c, kind, &mut 0.0),
                        2 => (f.get_integer_status)(c, kind, &mut 0),
                        3 => (f.get_boolean_status)(c, kind, &mut 0),
                        _ => (f.get_string_status)(c, kind, &mut ptr::null()),
                    }
                }
            }
            Call::GetFmuState { into } => {
                let mut state = into.map(|p| self.state(p)).unwrap_or(ptr::null_mut());
                let s = unsafe { (f.get_fmu_state)(c, &mut state) };
                if s == Status::OK && !state.is_null() && !self.states.contains(&state) {
                    self.states.push(state);
                }
                s
            }
            Call::SetFmuState(pick) => {
                let s = unsafe { (f.set_fmu_state)(c, self.state(*pick)) };
                if s == Status::OK {
                    // The instance's time is now the saved one: ask it.
                    let mut last = 0.0;
                    if unsafe { (f.get_real_status)(c, StatusKind::LastSuccessfulTime, &mut last) } == Status::OK {
                        self.time = last;
                    }
                }
                s
            }
            Call::FreeFmuState(pick) => {
                let mut state = self.state(*pick);
                unsafe { (f.free_fmu_state)(c, &mut state) }
            }
            Call::SerializeAndRestore { state, damage } => {
                let state = self.state(*state);
                let mut size = 0usize;
                let s = unsafe { (f.serialized_fmu_state_size)(c, state, &mut size) };
                if s != Status::OK {
                    return s;
                }
                let mut bytes = vec![0u8; size];
                let s = unsafe { (f.serialize_fmu_state)(c, state, bytes.as_mut_ptr().cast(), size) };
                if s != Status::OK {
                    return s;
                }
                let intact = matches!(damage, Damage::None);
                match damage {
                    Damage::None => {}
                    Damage::FlipBit(i) if !bytes.is_empty() => {
                        let bit = i % (bytes.len() * 8);
                        bytes[bit / 8] ^= 1 << (bit % 8);
                    }
                    Damage::FlipBit(_) => {}
                    Damage::Truncate(n) => bytes.truncate(n % bytes.len().max(1)),
                    Damage::Append(extra) => bytes.extend_from_slice(extra),
                    Damage::Random(random) => bytes = random.clone(),
                }
                let mut restored: FmuStatePtr = ptr::null_mut();
                let s = unsafe { (f.de_serialize_fmu_state)(c, bytes.as_ptr().cast(), bytes.len(), &mut restored) };
                if !intact && s != Status::ERROR {
                    // Reported through the status check: damaged bytes must be refused.
                    return Status(-1);
                }
                if s == Status::OK && !restored.is_null() {
                    self.states.push(restored);
                }
                s
            }
            Call::DirectionalDerivative { unknowns, knowns, seeds } => {
                let (unknowns, knowns) = (t.vrs(unknowns), t.vrs(knowns));
                let n = knowns.len().min(seeds.len());
                let mut out = vec![0.0; unknowns.len()];
                unsafe { (f.get_directional_derivative)(c, unknowns.as_ptr(), unknowns.len(), knowns.as_ptr(), n, seeds.as_ptr(), out.as_mut_ptr()) }
            }
            Call::SetInputDerivatives { vrs, orders, values } => {
                let vrs = t.vrs(vrs);
                let n = vrs.len().min(orders.len()).min(values.len());
                unsafe { (f.set_real_input_derivatives)(c, vrs.as_ptr(), n, orders.as_ptr(), values.as_ptr()) }
            }
            Call::GetOutputDerivatives { vrs, orders } => {
                let vrs = t.vrs(vrs);
                let n = vrs.len().min(orders.len());
                let mut out = vec![0.0; n];
                unsafe { (f.get_real_output_derivatives)(c, vrs.as_ptr(), n, orders.as_ptr(), out.as_mut_ptr()) }
            }
            Call::EnterEventMode => unsafe { (f.enter_event_mode.expect("ME function"))(c) },
            Call::NewDiscreteStates => {
                let mut info = EventInfo::default();
                unsafe { (f.new_discrete_states.expect("ME function"))(c, &mut info) }
            }
            Call::EnterContinuousTimeMode => unsafe { (f.enter_continuous_time_mode.expect("ME function"))(c) },
            Call::SetTime(time) => unsafe { (f.set_time.expect("ME function"))(c, *time) },
            Call::SetContinuousStates { values, null } => {
                let p = if *null && !values.is_empty() { ptr::null() } else { values.as_ptr() };
                unsafe { (f.set_continuous_states.expect("ME function"))(c, p, values.len()) }
            }
            Call::GetRealArray { which, len_offset } => {
                let (function, n) = match which {
                    0 => (f.get_derivatives, t.n_states),
                    1 => (f.get_event_indicators, t.n_event_indicators),
                    2 => (f.get_continuous_states, t.n_states),
                    _ => (f.get_nominals_of_continuous_states, t.n_states),
                };
                // A wrong length (one too many or too few) must be refused, never overrun: the
                // buffer is always large enough for what the length claims.
                let n = (n as i64 + *len_offset as i64).max(0) as usize;
                let mut out = vec![0.0; n];
                unsafe { (function.expect("ME function"))(c, out.as_mut_ptr(), n) }
            }
            Call::CompletedIntegratorStep { no_set_prior } => {
                let (mut enter, mut terminate) = (0, 0);
                unsafe { (f.completed_integrator_step.expect("ME function"))(c, *no_set_prior as c_int, &mut enter, &mut terminate) }
            }
            Call::Initialize => {
                let mut s = self.inst.setup_experiment(None, t.start, None);
                if s == Status::OK {
                    s = self.inst.enter_initialization_mode();
                }
                if s == Status::OK {
                    s = self.inst.exit_initialization_mode();
                }
                if s == Status::OK {
                    self.time = t.start;
                }
                s
            }
        }
    }
}

/// What the calls of one FMU's cases did (to show that the sequences reach every mode).
#[derive(Default)]
struct Tally {
    calls: u64,
    ok: u64,
    steps_ok: u64,
    errors: u64,
    discards: u64,
}

fn run_case(target: &Target, case: &Case, reference: &[Vec<u64>; 2], tally: &mut Tally) -> Result<(), TestCaseError> {
    let inst = target.instantiate("fuzzed", case.model_exchange, case.logging_on, case.memory_callbacks);
    let mut run = Run { target, inst, time: 0.0, states: Vec::new() };
    for (i, call) in case.calls.iter().enumerate() {
        let mark = run.inst.log().len();
        let started = Instant::now();
        let status = run.call(call);
        let took = started.elapsed();
        tally.calls += 1;
        match status {
            Status::OK => {
                tally.ok += 1;
                if matches!(call, Call::DoStep { .. }) {
                    tally.steps_ok += 1;
                }
            }
            Status::ERROR => tally.errors += 1,
            Status::DISCARD => tally.discards += 1,
            _ => {}
        }
        let context = || format!("{}: call {i} {call:?}", target.name());
        prop_assert!(took < CALL_TIME_LIMIT, "{}: took {took:?} (hang guard)", context());
        prop_assert!(status != Status(-1), "{}: damaged serialized bytes were not refused with fmi2Error", context());
        prop_assert!(matches!(status.0, 0..=3), "{}: status {status:?} (fmi2Fatal means a model panicked)", context());
        if matches!(status, Status::ERROR | Status::DISCARD) {
            prop_assert!(
                run.inst.log().has_status_since(mark, status),
                "{}: returned {status:?} without a logger message of that status",
                context()
            );
        }
    }
    // After fmi2Reset the instance must run exactly like a fresh one (the reference).
    let s = run.inst.reset();
    prop_assert_eq!(s, Status::OK, "{}: fmi2Reset after the sequence", target.name());
    let again = target.reference_run(&mut run.inst, case.model_exchange).map_err(|e| TestCaseError::fail(format!("{}: after reset: {e}", target.name())))?;
    prop_assert!(again == reference[case.model_exchange as usize], "{}: after reset the run differs from a fresh instance's", target.name());
    Ok(())
}

/// One FMU's share of the cases, with its own fixed seed (index `n` in dist/'s order): its report
/// line, or the failure.
fn fuzz_one(n: usize, fmu: &Arc<Fmu>, per_fmu: u32) -> Result<String, String> {
    let target = Target::of(fmu);
    let reference = [false, true].map(|me| {
        let mut fresh = target.instantiate("fresh", me, false, true);
        target.reference_run(&mut fresh, me).unwrap_or_else(|e| panic!("{}: fresh run: {e}", target.name()))
    });
    let config = Config { cases: per_fmu, failure_persistence: None, max_shrink_iters: 2000, ..Config::default() };
    // A fixed seed per FMU: a failure replays exactly.
    let mut seed = [0u8; 32];
    seed[0] = n as u8;
    seed[1..9].copy_from_slice(&0x5eed_f00d_u64.to_le_bytes());
    let mut runner = TestRunner::new_with_rng(config, TestRng::from_seed(RngAlgorithm::ChaCha, &seed));
    let tally = std::cell::RefCell::new(Tally::default());
    let started = Instant::now();
    let result = runner.run(&any_case(), |case| run_case(&target, &case, &reference, &mut tally.borrow_mut()));
    if let Err(e) = result {
        return Err(format!("{}: {e}", target.name()));
    }
    let t = tally.into_inner();
    Ok(format!(
        "  {:<22} {per_fmu} sequences, {} calls: {} fmi2OK ({} doSteps), {} fmi2Error, {} fmi2Discard; {:.1} s",
        target.name(),
        t.calls,
        t.ok,
        t.steps_ok,
        t.errors,
        t.discards,
        started.elapsed().as_secs_f64()
    ))
}

#[test]
fn random_call_sequences_never_crash_hang_or_fail_silently() {
    let fmus = every_fmu();
    let total: u32 = std::env::var("FUZZ_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(10_000);
    let per_fmu = total.div_ceil(fmus.len() as u32);
    // The FMUs are fuzzed side by side, one thread per core taking the next FMU (instances share
    // nothing: tests/tests/threads.rs); each FMU's cases and seed are the same as one at a time.
    // FUZZ_THREADS overrides the count (tests/valgrind.sh, under which threads only interleave, sets 1).
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let workers = std::env::var("FUZZ_THREADS").ok().and_then(|v| v.parse().ok()).unwrap_or(cores).clamp(1, fmus.len());
    let next = std::sync::atomic::AtomicUsize::new(0);
    let mut results: Vec<(usize, Result<String, String>)> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..workers)
            .map(|_| {
                s.spawn(|| {
                    let mut done = Vec::new();
                    loop {
                        let n = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                        let Some(fmu) = fmus.get(n) else { break };
                        done.push((n, fuzz_one(n, fmu, per_fmu)));
                    }
                    done
                })
            })
            .collect();
        handles.into_iter().flat_map(|h| h.join().expect("a fuzzing thread panicked")).collect()
    });
    results.sort_by_key(|(n, _)| *n);
    let mut report = Vec::new();
    for (_, result) in results {
        match result {
            Ok(line) => report.push(line),
            Err(failure) => panic!("{failure}"),
        }
    }
    println!("random FMI call sequences (crashes 0, hangs 0, illegal statuses 0, silent errors 0):\n{}", report.join("\n"));
}

/// Damage to a valid serialized state: 1-8 bit flips anywhere, or a truncation.
fn any_corruption() -> impl Strategy<Value = (Vec<usize>, Option<usize>)> {
    prop_oneof![
        3 => proptest::collection::vec(any::<usize>(), 1..9).prop_map(|flips| (flips, None)),
        1 => any::<usize>().prop_map(|cut| (Vec::new(), Some(cut))),
    ]
}

#[test]
fn corrupted_serialized_states_are_refused() {
    const CASES: u32 = 1000;
    let mut report = Vec::new();
    for fmu in every_fmu() {
        let target = Target::of(&fmu);
        let mut inst = target.instantiate("source", false, false, true);
        target.reference_run(&mut inst, false).unwrap_or_else(|e| panic!("{}: {e}", target.name()));
        let (status, state) = inst.get_fmu_state();
        assert_eq!(status, Status::OK);
        let (status, valid) = inst.serialize_fmu_state(&state.unwrap());
        assert_eq!(status, Status::OK);
        let receiver = std::cell::RefCell::new(target.instantiate("receiver", false, false, true));
        let mut runner = TestRunner::new_with_rng(
            Config { cases: CASES, failure_persistence: None, ..Config::default() },
            TestRng::from_seed(RngAlgorithm::ChaCha, &[7u8; 32]),
        );
        let result = runner.run(&any_corruption(), |(flips, cut)| {
            let mut bytes = valid.clone();
            for f in &flips {
                let bit = f % (bytes.len() * 8);
                bytes[bit / 8] ^= 1 << (bit % 8);
            }
            if let Some(cut) = cut {
                bytes.truncate(cut % bytes.len());
            }
            if bytes == valid {
                return Ok(()); // flips that cancel out leave a valid state
            }
            let mut receiver = receiver.borrow_mut();
            let mark = receiver.log().len();
            let (status, state) = receiver.deserialize_fmu_state(&bytes);
            prop_assert_eq!(status, Status::ERROR, "{}: damaged bytes accepted ({} flips, cut {:?})", target.name(), flips.len(), cut);
            prop_assert!(state.is_none());
            prop_assert!(receiver.log().has_status_since(mark, Status::ERROR), "{}: refusal not logged", target.name());
            Ok(())
        });
        if let Err(e) = result {
            panic!("{e}");
        }
        // The intact bytes still load: the refusals were about the damage.
        let (status, _) = receiver.borrow_mut().deserialize_fmu_state(&valid);
        assert_eq!(status, Status::OK, "{}", target.name());
        report.push(format!("  {:<22} {CASES} damaged copies of a {}-byte state refused", target.name(), valid.len()));
    }
    println!("corrupted serialized states:\n{}", report.join("\n"));
}
