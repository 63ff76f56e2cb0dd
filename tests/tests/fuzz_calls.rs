//! Property test: whatever sequence of FMI calls a master makes, no FMU in dist/ crashes, hangs,
//! returns an illegal status, fails silently, or stays damaged after fmi2Reset. Through the FMI
//! 2.0 API (dist/*.fmu) and the FMI 3.0 API (dist/fmi3/*.fmu): the FMI 3.0 sequences use the fmi3
//! functions (typed getters and setters with their value counts, fmi3UpdateDiscreteStates,
//! fmi3DoStep with its output flags, adjoint derivatives, the functions of the capabilities these
//! FMUs do not declare: clocks, configuration mode, Scheduled Execution's partitions, ...).
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
//! * the call returned within `CALL_TIME_LIMIT` (a hang guard, not a speed claim);
//! * a call the standard does not allow where the instance is (its state as the standard's state
//!   machine gives it, tracked from the calls and their statuses by [`Oracle2`] for FMI 2.0 and
//!   [`Oracle`] for FMI 3.0) returns fmi2Error / fmi3Error. FMI 2.0's rules these FMUs do not
//!   follow are reported as findings, not asserted (see [`Oracle2`]).
//!
//! At the end the instance is reset and must then run its default experiment exactly (bit for
//! bit) as a fresh instance does.
//!
//! `FUZZ_CASES` sets the total number of cases over all FMUs and both versions (default 10 000:
//! half through each version); `PROPTEST_SEED`-free: the runner's seed is fixed per FMU and
//! version so a failure replays. The FMUs are fuzzed side by side, one thread per core
//! (`FUZZ_THREADS` sets the count). `FMI_VERSIONS` (`2`, `3`) restricts the versions (each then
//! gets its half of the cases, as in the full run).

use std::ffi::{c_char, c_int, CString};
use std::ptr;
use std::sync::Arc;
use std::time::{Duration, Instant};

use fmi_host::dist::{every_fmu_for, versions};
use fmi_host::ffi::{EventInfo, Fmi3Functions, FmuStatePtr};
use fmi_host::{Api, Causality, Fmi2Type, FmiVersion, Fmu, Instance, InstantiateOptions, Status, StatusKind, ValueReference, VariableType};
use proptest::prelude::*;
use proptest::strategy::{BoxedStrategy, Union};
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

impl Damage {
    /// Damages `bytes`; whether they are still intact.
    fn apply(&self, bytes: &mut Vec<u8>) -> bool {
        match self {
            Damage::None => {}
            Damage::FlipBit(i) if !bytes.is_empty() => {
                let bit = i % (bytes.len() * 8);
                bytes[bit / 8] ^= 1 << (bit % 8);
            }
            Damage::FlipBit(_) => {}
            Damage::Truncate(n) => bytes.truncate(n % bytes.len().max(1)),
            Damage::Append(extra) => bytes.extend_from_slice(extra),
            Damage::Random(random) => *bytes = random.clone(),
        }
        matches!(self, Damage::None)
    }
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
    // FMI 3.0 only.
    /// fmi3Get/Set of a type these FMUs have no variable of: 0 Float32, 1 Int8, 2 UInt8,
    /// 3 Int16, 4 UInt16, 5 UInt32, 6 Int64, 7 UInt64, 8 Binary.
    OtherType { which: u8, set: bool, vrs: Vec<VrPick> },
    /// fmi3GetFloat64 / fmi3SetFloat64 whose nValues is not nValueReferences (all scalars).
    MismatchedCount { vrs: Vec<VrPick>, extra: u8, set: bool },
    /// A function of a capability these FMUs do not declare (clocks, configuration mode,
    /// evaluateDiscreteStates, event mode in Co-Simulation, per-element dependencies, model
    /// partitions).
    Unprovided(u8),
    AdjointDerivative { unknowns: Vec<VrPick>, knowns: Vec<VrPick>, seeds: Vec<f64> },
    /// fmi3GetNumberOfContinuousStates (0), fmi3GetNumberOfEventIndicators (1).
    GetNumberOf(u8),
}

/// The functions [`Call::Unprovided`] picks from.
const UNPROVIDED: [&str; 11] = [
    "fmi3GetClock",
    "fmi3SetClock",
    "fmi3GetIntervalDecimal",
    "fmi3EnterConfigurationMode",
    "fmi3ExitConfigurationMode",
    "fmi3EvaluateDiscreteStates",
    "fmi3EnterStepMode",
    "fmi3GetNumberOfVariableDependencies",
    "fmi3ActivateModelPartition",
    "fmi3SetClock (no values)",
    "fmi3GetClock (no values)",
];

/// One weighted kind of call: its weight, its strategy, and the one version that has it (`None`:
/// both have it).
type Arm = (u32, BoxedStrategy<Call>, Option<FmiVersion>);

fn both(weight: u32, calls: impl Strategy<Value = Call> + 'static) -> Arm {
    (weight, calls.boxed(), None)
}

fn only(version: FmiVersion, weight: u32, calls: impl Strategy<Value = Call> + 'static) -> Arm {
    (weight, calls.boxed(), Some(version))
}

/// A random call through `version`'s API: one weighted list of kinds of call for both versions.
/// FMI 3.0 has the calls of FMI 2.0 that it has too, with FMI 2.0's weights; `SetupExperiment` as
/// the experiment the next fmi3EnterInitializationMode gets (FMI 3.0 has no
/// fmi2SetupExperiment); and in place of fmi2CancelStep, fmi2Get*Status and
/// fmi2SetRealInputDerivatives the functions FMI 3.0 adds. The order of the list is part of the
/// fixed seeds' sequences (proptest's union draws differently for each position): append new
/// kinds at the end.
fn any_call(version: FmiVersion) -> impl Strategy<Value = Call> {
    use FmiVersion::{Fmi2, Fmi3};
    let reals = || proptest::collection::vec(any_real(), 0..4);
    let arms: Vec<Arm> = vec![
        both(
            1,
            (any::<bool>(), proptest::collection::vec(any_text(), 0..3), any::<bool>())
                .prop_map(|(on, categories, null_array)| Call::SetDebugLogging { on, categories, null_array }),
        ),
        both(
            1,
            (proptest::option::of(any_real()), any_real(), proptest::option::of(any_real()))
                .prop_map(|(tolerance, start, stop)| Call::SetupExperiment { tolerance, start, stop }),
        ),
        both(1, Just(Call::EnterInitializationMode)),
        both(1, Just(Call::ExitInitializationMode)),
        both(1, Just(Call::Terminate)),
        both(1, Just(Call::Reset)),
        both(1, (any_vrs(), any::<bool>()).prop_map(|(vrs, null_values)| Call::GetReal { vrs, null_values })),
        both(1, (any_vrs(), reals(), any::<bool>()).prop_map(|(vrs, values, null_values)| Call::SetReal { vrs, values, null_values })),
        both(1, any_vrs().prop_map(|vrs| Call::GetInteger { vrs })),
        both(1, (any_vrs(), proptest::collection::vec(any::<i32>(), 0..4)).prop_map(|(vrs, values)| Call::SetInteger { vrs, values })),
        both(1, any_vrs().prop_map(|vrs| Call::GetBoolean { vrs })),
        both(1, (any_vrs(), proptest::collection::vec(any::<c_int>(), 0..4)).prop_map(|(vrs, values)| Call::SetBoolean { vrs, values })),
        both(1, any_vrs().prop_map(|vrs| Call::GetString { vrs })),
        both(1, (any_vrs(), proptest::collection::vec(any_text(), 0..4)).prop_map(|(vrs, values)| Call::SetString { vrs, values })),
        both(
            10,
            (prop_oneof![6 => Just(When::Now), 1 => Just(When::Earlier), 1 => any_real().prop_map(When::Value)], any_step(), any::<bool>())
                .prop_map(|(when, h, no_set_prior)| Call::DoStep { when, h, no_set_prior }),
        ),
        only(Fmi2, 1, Just(Call::CancelStep)),
        only(Fmi2, 1, (0u8..3, 0u8..5).prop_map(|(kind, which)| Call::GetStatus { kind, which })),
        only(Fmi3, 1, (0u8..9, any::<bool>(), any_vrs()).prop_map(|(which, set, vrs)| Call::OtherType { which, set, vrs })),
        only(Fmi3, 1, (any_vrs(), 1u8..3, any::<bool>()).prop_map(|(vrs, extra, set)| Call::MismatchedCount { vrs, extra, set })),
        only(Fmi3, 1, (0..UNPROVIDED.len() as u8).prop_map(Call::Unprovided)),
        both(1, proptest::option::of(any_state()).prop_map(|into| Call::GetFmuState { into })),
        both(1, any_state().prop_map(Call::SetFmuState)),
        both(1, any_state().prop_map(Call::FreeFmuState)),
        both(1, (any_state(), any_damage()).prop_map(|(state, damage)| Call::SerializeAndRestore { state, damage })),
        both(1, (any_vrs(), any_vrs(), reals()).prop_map(|(unknowns, knowns, seeds)| Call::DirectionalDerivative { unknowns, knowns, seeds })),
        only(
            Fmi2,
            1,
            (any_vrs(), proptest::collection::vec(-1 as c_int..4, 0..4), reals())
                .prop_map(|(vrs, orders, values)| Call::SetInputDerivatives { vrs, orders, values }),
        ),
        only(Fmi3, 1, (any_vrs(), any_vrs(), reals()).prop_map(|(unknowns, knowns, seeds)| Call::AdjointDerivative { unknowns, knowns, seeds })),
        both(1, (any_vrs(), proptest::collection::vec(-1 as c_int..4, 0..4)).prop_map(|(vrs, orders)| Call::GetOutputDerivatives { vrs, orders })),
        both(1, Just(Call::EnterEventMode)),
        both(1, Just(Call::NewDiscreteStates)),
        both(1, Just(Call::EnterContinuousTimeMode)),
        both(1, any_real().prop_map(Call::SetTime)),
        both(1, (proptest::collection::vec(any_real(), 0..8), any::<bool>()).prop_map(|(values, null)| Call::SetContinuousStates { values, null })),
        both(1, (0u8..4, -1i8..2).prop_map(|(which, len_offset)| Call::GetRealArray { which, len_offset })),
        only(Fmi3, 1, (0u8..2).prop_map(Call::GetNumberOf)),
        both(1, any::<bool>().prop_map(|no_set_prior| Call::CompletedIntegratorStep { no_set_prior })),
        both(4, Just(Call::Initialize)),
    ];
    Union::new_weighted(arms.into_iter().filter(|(_, _, only)| only.is_none_or(|v| v == version)).map(|(weight, calls, _)| (weight, calls)).collect())
}

/// One case: the instance's options and its calls.
#[derive(Clone, Debug)]
struct Case {
    model_exchange: bool,
    logging_on: bool,
    memory_callbacks: bool,
    calls: Vec<Call>,
}

fn any_case(version: FmiVersion) -> impl Strategy<Value = Case> {
    let calls = any_call(version);
    // Half the cases start with a legal initialization, so the random calls also hit the
    // stepping modes in depth, not only the refusals before initialization.
    (any::<bool>(), any::<bool>(), prop_oneof![4 => Just(true), 1 => Just(false)], any::<bool>(), proptest::collection::vec(calls, 1..40))
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
    /// FMI 3.0: the independent variable `time` (read after fmi3SetFMUState).
    time: Option<ValueReference>,
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
            time: md.model_variables.iter().find(|v| v.causality == Causality::Independent).map(|v| v.value_reference),
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

    fn name(&self) -> String {
        format!("{} (FMI {})", self.fmu.model_description().model_name, self.fmu.fmi_version().text())
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
    /// FMI 3.0: (tolerance, start, stop) of the last `SetupExperiment`, for the next
    /// fmi3EnterInitializationMode.
    experiment: (Option<f64>, f64, Option<f64>),
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

    /// Makes one call through the FMU's API; returns its status.
    fn call(&mut self, call: &Call) -> Status {
        match self.target.fmu.api() {
            Api::Fmi2(_) => self.call2(call),
            Api::Fmi3(f) => self.call3(f, call),
        }
    }

    /// Makes one FMI 2.0 call; returns its status.
    fn call2(&mut self, call: &Call) -> Status {
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
            Call::OtherType { .. } | Call::MismatchedCount { .. } | Call::Unprovided(_) | Call::AdjointDerivative { .. } | Call::GetNumberOf(_) => {
                unreachable!("FMI 3.0 calls are not generated for FMI 2.0: {call:?}")
            }
        }
    }

    /// Makes one FMI 3.0 call; returns its status.
    fn call3(&mut self, f: &Fmi3Functions, call: &Call) -> Status {
        let t = self.target;
        let c = self.inst.raw_component();
        let b = |v: bool| v as u8;
        // SAFETY (every unsafe block below): as in `call2`. Value arrays are as long as the
        // larger of nValueReferences and nValues, so a count the FMU trusts never overruns.
        match call {
            Call::SetDebugLogging { on, categories, null_array } => {
                let owned: Vec<CString> = categories.iter().map(|b| text(b)).collect();
                let raw: Vec<*const c_char> = owned.iter().map(|s| s.as_ptr()).collect();
                let array = if *null_array { ptr::null() } else { raw.as_ptr() };
                unsafe { (f.set_debug_logging)(c, b(*on), raw.len(), array) }
            }
            Call::SetupExperiment { tolerance, start, stop } => {
                // FMI 3.0 has no fmi2SetupExperiment: the next fmi3EnterInitializationMode gets it.
                self.experiment = (*tolerance, *start, *stop);
                Status::OK
            }
            Call::EnterInitializationMode => {
                let (tolerance, start, stop) = self.experiment;
                unsafe { (f.enter_initialization_mode)(c, b(tolerance.is_some()), tolerance.unwrap_or(0.0), start, b(stop.is_some()), stop.unwrap_or(0.0)) }
            }
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
                unsafe { (f.get_float64)(c, vrs.as_ptr(), vrs.len(), out, vrs.len()) }
            }
            Call::SetReal { vrs, values, null_values } => {
                let vrs = t.vrs(vrs);
                let n = vrs.len().min(values.len());
                let input = if *null_values && n > 0 { ptr::null() } else { values.as_ptr() };
                unsafe { (f.set_float64)(c, vrs.as_ptr(), n, input, n) }
            }
            Call::GetInteger { vrs } => {
                let vrs = t.vrs(vrs);
                let mut v = vec![0; vrs.len()];
                unsafe { (f.get_int32)(c, vrs.as_ptr(), vrs.len(), v.as_mut_ptr(), vrs.len()) }
            }
            Call::SetInteger { vrs, values } => {
                let vrs = t.vrs(vrs);
                let n = vrs.len().min(values.len());
                unsafe { (f.set_int32)(c, vrs.as_ptr(), n, values.as_ptr(), n) }
            }
            Call::GetBoolean { vrs } => {
                let vrs = t.vrs(vrs);
                let mut v = vec![0u8; vrs.len()];
                unsafe { (f.get_boolean)(c, vrs.as_ptr(), vrs.len(), v.as_mut_ptr(), vrs.len()) }
            }
            Call::SetBoolean { vrs, values } => {
                // C bool: any byte the master passes (FMI 2.0's fmi2Boolean was an int).
                let vrs = t.vrs(vrs);
                let bytes: Vec<u8> = values.iter().map(|v| *v as u8).collect();
                let n = vrs.len().min(bytes.len());
                unsafe { (f.set_boolean)(c, vrs.as_ptr(), n, bytes.as_ptr(), n) }
            }
            Call::GetString { vrs } => {
                let vrs = t.vrs(vrs);
                let mut v: Vec<*const c_char> = vec![ptr::null(); vrs.len()];
                unsafe { (f.get_string)(c, vrs.as_ptr(), vrs.len(), v.as_mut_ptr(), vrs.len()) }
            }
            Call::SetString { vrs, values } => {
                let vrs = t.vrs(vrs);
                let owned: Vec<CString> = values.iter().map(|b| text(b)).collect();
                let raw: Vec<*const c_char> = owned.iter().map(|s| s.as_ptr()).collect();
                let n = vrs.len().min(raw.len());
                unsafe { (f.set_string)(c, vrs.as_ptr(), n, raw.as_ptr(), n) }
            }
            Call::OtherType { which, set, vrs } => {
                let vrs = t.vrs(vrs);
                let n = vrs.len();
                if *which as usize >= f.other_types.len() {
                    // Binary.
                    let mut sizes = vec![0usize; n];
                    let mut data: Vec<*const u8> = vec![ptr::null(); n];
                    return unsafe {
                        if *set {
                            (f.set_binary)(c, vrs.as_ptr(), n, sizes.as_ptr(), data.as_ptr(), n)
                        } else {
                            (f.get_binary)(c, vrs.as_ptr(), n, sizes.as_mut_ptr(), data.as_mut_ptr(), n)
                        }
                    };
                }
                let (_, get, set_fn, size) = f.other_types[*which as usize];
                let mut buffer = vec![0u64; (n * size).div_ceil(8).max(1)];
                unsafe {
                    if *set {
                        set_fn(c, vrs.as_ptr(), n, buffer.as_ptr().cast(), n)
                    } else {
                        get(c, vrs.as_ptr(), n, buffer.as_mut_ptr().cast(), n)
                    }
                }
            }
            Call::MismatchedCount { vrs, extra, set } => {
                let vrs = t.vrs(vrs);
                let n_values = vrs.len() + *extra as usize;
                let mut values = vec![0.0; n_values];
                unsafe {
                    if *set {
                        (f.set_float64)(c, vrs.as_ptr(), vrs.len(), values.as_ptr(), n_values)
                    } else {
                        (f.get_float64)(c, vrs.as_ptr(), vrs.len(), values.as_mut_ptr(), n_values)
                    }
                }
            }
            Call::Unprovided(which) => {
                let vr = [0 as ValueReference];
                let (mut flag, mut real, mut qualifier, mut count) = (0u8, 0.0f64, 0 as c_int, 0usize);
                unsafe {
                    match which {
                        0 => (f.get_clock)(c, vr.as_ptr(), 1, &mut flag),
                        1 => (f.set_clock)(c, vr.as_ptr(), 1, &flag),
                        2 => (f.get_interval_decimal)(c, vr.as_ptr(), 1, &mut real, &mut qualifier),
                        3 => (f.enter_configuration_mode)(c),
                        4 => (f.exit_configuration_mode)(c),
                        5 => (f.evaluate_discrete_states)(c),
                        6 => (f.enter_step_mode)(c),
                        7 => (f.get_number_of_variable_dependencies)(c, 0, &mut count),
                        8 => (f.activate_model_partition.expect("exported by these FMUs"))(c, 0, 0.0),
                        9 => (f.set_clock)(c, vr.as_ptr(), 0, &flag),
                        _ => (f.get_clock)(c, vr.as_ptr(), 0, &mut flag),
                    }
                }
            }
            Call::DoStep { when, h, no_set_prior } => {
                let at = match when {
                    When::Now => self.time,
                    When::Earlier => self.time - 1.0,
                    When::Value(v) => *v,
                };
                let (mut event, mut terminate, mut early, mut last) = (2u8, 2u8, 2u8, f64::NAN);
                let s = unsafe { (f.do_step)(c, at, *h, b(*no_set_prior), &mut event, &mut terminate, &mut early, &mut last) };
                if s == Status::OK {
                    self.time = at + h;
                    // These FMUs handle events inside the step and never return early: an OK
                    // step says so, and its lastSuccessfulTime is its end.
                    if (event, terminate, early) != (0, 0, 0) || last != at + h {
                        return Status(-2);
                    }
                }
                s
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
                    // The instance's time is now the saved one: read the independent variable.
                    let mut now = 0.0;
                    if let Some(vr) = t.time {
                        if unsafe { (f.get_float64)(c, &vr, 1, &mut now, 1) } == Status::OK {
                            self.time = now;
                        }
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
                let s = unsafe { (f.serialize_fmu_state)(c, state, bytes.as_mut_ptr(), size) };
                if s != Status::OK {
                    return s;
                }
                let intact = damage.apply(&mut bytes);
                let mut restored: FmuStatePtr = ptr::null_mut();
                let s = unsafe { (f.deserialize_fmu_state)(c, bytes.as_ptr(), bytes.len(), &mut restored) };
                if !intact && s != Status::ERROR {
                    return Status(-1);
                }
                if s == Status::OK && !restored.is_null() {
                    self.states.push(restored);
                }
                s
            }
            Call::DirectionalDerivative { unknowns, knowns, seeds } | Call::AdjointDerivative { unknowns, knowns, seeds } => {
                let (unknowns, knowns) = (t.vrs(unknowns), t.vrs(knowns));
                let adjoint = matches!(call, Call::AdjointDerivative { .. });
                // The seed has one value per known (per unknown for the adjoint), the
                // sensitivity one per unknown (per known): counts that disagree must be refused.
                let (n_seed, n_sensitivity) = if adjoint { (unknowns.len(), knowns.len()) } else { (knowns.len(), unknowns.len()) };
                let n_seed = n_seed.min(seeds.len());
                let mut seed = seeds.clone();
                seed.resize(n_seed.max(seeds.len()), 0.0);
                let mut out = vec![0.0; n_sensitivity];
                let function = if adjoint { f.get_adjoint_derivative } else { f.get_directional_derivative };
                unsafe { function(c, unknowns.as_ptr(), unknowns.len(), knowns.as_ptr(), knowns.len(), seed.as_ptr(), n_seed, out.as_mut_ptr(), n_sensitivity) }
            }
            Call::GetOutputDerivatives { vrs, orders } => {
                let vrs = t.vrs(vrs);
                let n = vrs.len().min(orders.len());
                let mut out = vec![0.0; n];
                unsafe { (f.get_output_derivatives)(c, vrs.as_ptr(), n, orders.as_ptr(), out.as_mut_ptr(), n) }
            }
            Call::EnterEventMode => unsafe { (f.enter_event_mode)(c) },
            Call::NewDiscreteStates => {
                let mut flags = [0u8; 5];
                let mut next = 0.0;
                let [a, b2, c2, d, e] = &mut flags;
                unsafe { (f.update_discrete_states)(c, a, b2, c2, d, e, &mut next) }
            }
            Call::EnterContinuousTimeMode => unsafe { (f.enter_continuous_time_mode.expect("ME function"))(c) },
            Call::SetTime(time) => unsafe { (f.set_time.expect("ME function"))(c, *time) },
            Call::SetContinuousStates { values, null } => {
                let p = if *null && !values.is_empty() { ptr::null() } else { values.as_ptr() };
                unsafe { (f.set_continuous_states.expect("ME function"))(c, p, values.len()) }
            }
            Call::GetRealArray { which, len_offset } => {
                let (function, n) = match which {
                    0 => (f.get_continuous_state_derivatives, t.n_states),
                    1 => (f.get_event_indicators, t.n_event_indicators),
                    2 => (f.get_continuous_states, t.n_states),
                    _ => (f.get_nominals_of_continuous_states, t.n_states),
                };
                let n = (n as i64 + *len_offset as i64).max(0) as usize;
                let mut out = vec![0.0; n];
                unsafe { (function.expect("ME function"))(c, out.as_mut_ptr(), n) }
            }
            Call::GetNumberOf(which) => {
                let (function, expected) = if *which == 0 {
                    (f.get_number_of_continuous_states, t.n_states)
                } else {
                    (f.get_number_of_event_indicators, t.n_event_indicators)
                };
                let mut n = usize::MAX;
                let s = unsafe { (function.expect("ME function"))(c, &mut n) };
                if s == Status::OK && n != expected {
                    return Status(-3);
                }
                s
            }
            Call::CompletedIntegratorStep { no_set_prior } => {
                let (mut enter, mut terminate) = (0u8, 0u8);
                unsafe { (f.completed_integrator_step.expect("ME function"))(c, b(*no_set_prior), &mut enter, &mut terminate) }
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
            Call::CancelStep | Call::GetStatus { .. } | Call::SetInputDerivatives { .. } => {
                unreachable!("FMI 2.0 calls are not generated for FMI 3.0: {call:?}")
            }
        }
    }
}

/// A state of FMI 3.0's state machine (sections 3.2 and 4.2 of the standard) these FMUs can be
/// in: no clocks, no structural parameters, no event mode in Co-Simulation (eventModeUsed =
/// false), so no Configuration, Reconfiguration, Clock Activation, Intermediate Update or
/// Co-Simulation Event Mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum State3 {
    Instantiated,
    InitializationMode,
    StepMode,
    EventMode,
    ContinuousTimeMode,
    Terminated,
}

/// What the FMI 3.0 standard says about the next call: the instance's state, followed through
/// the calls and their statuses, and the calls the standard does not allow there. `state` is
/// `None` where the standard leaves the state to the FMU: after fmi3Error or fmi3Discard of an
/// allowed call (only fmi3Get*, fmi3Reset and fmi3FreeInstance are defined then) and after
/// fmi3SetFMUState. The rules are the standard's, not this FMU's table (fmu-runtime's
/// fmi3/states.rs); where the standard's tables leave room (fmi3GetNominalsOfContinuousStates
/// in Initialization Mode, fmi3SetContinuousStates in Event Mode, the FMU-state functions, ...)
/// no rule is checked.
struct Oracle {
    model_exchange: bool,
    /// The value references a pick lands on, and those of the Enumerations (structural choices),
    /// which FMI 3.0 reads and sets with fmi3GetInt64/fmi3SetInt64: the only variables of the
    /// "other" types.
    vrs: Vec<ValueReference>,
    enumerations: Vec<ValueReference>,
    /// The position of Int64 in `Fmi3Functions::other_types`.
    int64: u8,
    state: Option<State3>,
    /// How many calls it said must be refused (all were).
    refusals: u64,
}

impl Oracle {
    fn new(model_exchange: bool, target: &Target) -> Oracle {
        let md = target.fmu.model_description();
        let enumerations =
            md.model_variables.iter().filter(|v| v.variable_type == VariableType::Enumeration).map(|v| v.value_reference).collect();
        let f = target.fmu.fmi3_functions().expect("an FMI 3.0 FMU");
        let int64 = f.other_types.iter().position(|t| t.0 == "Int64").expect("Int64 among the other types") as u8;
        Oracle { model_exchange, vrs: target.vrs.clone(), enumerations, int64, state: Some(State3::Instantiated), refusals: 0 }
    }

    /// Whether every pick is an Enumeration's value reference.
    fn all_enumerations(&self, picks: &[VrPick]) -> bool {
        picks.iter().all(|p| match p {
            VrPick::Existing(i) => self.enumerations.contains(&self.vrs[i % self.vrs.len()]),
            _ => false,
        })
    }

    /// Why the standard does not allow `call` here (it must then return fmi3Error), if it does not.
    fn forbids(&self, call: &Call) -> Option<String> {
        use State3::*;
        let me = self.model_exchange;
        // Whatever the state: functions of an interface the instance was not made for, or of a
        // capability the description does not declare.
        let model_exchange_only = matches!(
            call,
            Call::EnterEventMode
                | Call::NewDiscreteStates
                | Call::EnterContinuousTimeMode
                | Call::SetTime(_)
                | Call::SetContinuousStates { .. }
                | Call::GetRealArray { .. }
                | Call::CompletedIntegratorStep { .. }
        );
        if !me && model_exchange_only {
            return Some("a Model Exchange function on a Co-Simulation instance (eventModeUsed = false)".into());
        }
        if me && matches!(call, Call::DoStep { .. } | Call::GetOutputDerivatives { .. }) {
            return Some("a Co-Simulation function on a Model Exchange instance".into());
        }
        if let Call::Unprovided(which) = call {
            return Some(format!("{}: a capability modelDescription.xml does not declare", UNPROVIDED[*which as usize]));
        }
        if let Call::OtherType { which, vrs, .. } = call {
            if !vrs.is_empty() && !(*which == self.int64 && self.all_enumerations(vrs)) {
                return Some(format!("type {which} (Float32..UInt64, Binary): no variable has it (Int64: only the Enumerations)"));
            }
        }
        if let Call::MismatchedCount { vrs, .. } = call {
            if vrs.iter().all(|v| matches!(v, VrPick::Existing(_))) && !vrs.is_empty() {
                return Some("nValues differs from nValueReferences for scalar variables".into());
            }
        }
        let state = self.state?;
        let not = |allowed: &[State3]| (!allowed.contains(&state)).then(|| format!("not allowed in {state:?}"));
        let not_in = |forbidden: &[State3]| forbidden.contains(&state).then(|| format!("not allowed in {state:?}"));
        match call {
            Call::EnterInitializationMode | Call::Initialize => not(&[Instantiated]),
            Call::ExitInitializationMode => not(&[InitializationMode]),
            Call::Terminate => not_in(&[Instantiated, InitializationMode, Terminated]),
            Call::DoStep { .. } => not(&[StepMode]),
            Call::GetReal { .. } | Call::GetInteger { .. } | Call::GetBoolean { .. } | Call::GetString { .. } => not_in(&[Instantiated]),
            Call::OtherType { set: false, .. } | Call::MismatchedCount { set: false, .. } => not_in(&[Instantiated]),
            Call::SetReal { .. } | Call::SetInteger { .. } | Call::SetBoolean { .. } | Call::SetString { .. } => not_in(&[Terminated]),
            Call::OtherType { set: true, .. } | Call::MismatchedCount { set: true, .. } => not_in(&[Terminated]),
            Call::DirectionalDerivative { .. } | Call::AdjointDerivative { .. } | Call::GetOutputDerivatives { .. } => not_in(&[Instantiated]),
            Call::EnterEventMode | Call::SetTime(_) | Call::SetContinuousStates { .. } => not_in(&[Instantiated, InitializationMode, Terminated]),
            Call::NewDiscreteStates | Call::EnterContinuousTimeMode => not(&[EventMode]),
            Call::CompletedIntegratorStep { .. } => not(&[ContinuousTimeMode]),
            Call::GetRealArray { which: 0..=2, .. } => not_in(&[Instantiated]),
            _ => None,
        }
    }

    /// The state after `call` returned `status` (`refused`: the oracle had forbidden it).
    fn after(&mut self, call: &Call, status: Status, refused: bool) {
        use State3::*;
        if refused {
            // An illegal call that was refused leaves the instance where it was.
            self.refusals += 1;
            return;
        }
        if matches!(call, Call::Reset) {
            self.state = (status == Status::OK || status == Status::WARNING).then_some(Instantiated);
            return;
        }
        if !(status == Status::OK || status == Status::WARNING) {
            // An error or discard of an allowed call leaves the state to the FMU.
            self.state = None;
            return;
        }
        let initialized = if self.model_exchange { EventMode } else { StepMode };
        match call {
            Call::EnterInitializationMode => self.state = Some(InitializationMode),
            Call::ExitInitializationMode | Call::Initialize => self.state = Some(initialized),
            Call::Terminate => self.state = Some(Terminated),
            Call::EnterEventMode => self.state = Some(EventMode),
            Call::EnterContinuousTimeMode => self.state = Some(ContinuousTimeMode),
            Call::SetFmuState(_) => self.state = None,
            _ => {}
        }
    }
}

/// FMI 2.0 for Co-Simulation: the table of the calls allowed in each state (FMI 2.0.5, section
/// 4.2.4 "State Machine of Calling Sequence from Master to Slave"; the same in FMI 2.0 to
/// 2.0.4). A row per function, a cell per state: start/end, instantiated, Initialization Mode,
/// stepComplete, stepInProgress, stepFailed, stepCanceled, terminated, error, fatal. `x`: allowed;
/// a digit: allowed under the table's numbered condition (on the variables: which ones may be set
/// or read; not checked, so taken as allowed); `.`: not allowed.
const FMI2_CS_TABLE: &[(&str, &str)] = & [
    ("fmi2GetTypesPlatform", "xxxxxxxxx."),
    ("fmi2GetVersion", "xxxxxxxxx."),
    ("fmi2SetDebugLogging", ".xxxxxxxx."),
    ("fmi2Instantiate", "x........."),
    ("fmi2FreeInstance", ".xxx.xxxx."),
    ("fmi2SetupExperiment", ".x........"),
    ("fmi2EnterInitializationMode", ".x........"),
    ("fmi2ExitInitializationMode", "..x......."),
    ("fmi2Terminate", "...x.x...."),
    ("fmi2Reset", ".xxx.xxxx."),
    ("fmi2GetReal", "..2x.87x7."),
    ("fmi2GetInteger", "..2x.87x7."),
    ("fmi2GetBoolean", "..2x.87x7."),
    ("fmi2GetString", "..2x.87x7."),
    ("fmi2SetReal", ".136......"),
    ("fmi2SetInteger", ".136......"),
    ("fmi2SetBoolean", ".136......"),
    ("fmi2SetString", ".136......"),
    ("fmi2GetFMUstate", ".xxx.87x7."),
    ("fmi2SetFMUstate", ".xxx.xxxx."),
    ("fmi2FreeFMUstate", ".xxx.xxxx."),
    ("fmi2SerializedFMUstateSize", ".xxx.xxxx."),
    ("fmi2SerializeFMUstate", ".xxx.xxxx."),
    ("fmi2DeSerializeFMUstate", ".xxx.xxxx."),
    ("fmi2GetDirectionalDerivative", "..xx.87x7."),
    ("fmi2SetRealInputDerivatives", ".xxx......"),
    ("fmi2GetRealOutputDerivatives", "...x.8xx7."),
    ("fmi2DoStep", "...x......"),
    ("fmi2CancelStep", "....x....."),
    ("fmi2GetStatus", "...xxx.x.."),
    ("fmi2GetRealStatus", "...xxx.x.."),
    ("fmi2GetIntegerStatus", "...xxx.x.."),
    ("fmi2GetBooleanStatus", "...xxx.x.."),
    ("fmi2GetStringStatus", "...xxx.x.."),
];

/// FMI 2.0 for Model Exchange: the table of section 3.2.3 "State Machine of Calling Sequence"
/// (FMI 2.0.5), read as [`FMI2_CS_TABLE`]; cells: start/end, instantiated, Initialization Mode,
/// Event Mode, Continuous-Time Mode, terminated, error, fatal. Where the versions of FMI 2.0
/// differ the cell is the allowing one: fmi2GetNominalsOfContinuousStates in Initialization Mode
/// (not allowed up to 2.0.2, allowed from 2.0.3), fmi2SetTime in Event Mode (allowed in 2.0,
/// from 2.0.1 only for a pure discrete-time FMU: condition 8), fmi2GetDerivatives in
/// Initialization Mode (allowed by the 2.0.1 bugfix note).
const FMI2_ME_TABLE: &[(&str, &str)] = & [
    ("fmi2GetTypesPlatform", "xxxxxxx."),
    ("fmi2GetVersion", "xxxxxxx."),
    ("fmi2SetDebugLogging", ".xxxxxx."),
    ("fmi2Instantiate", "x......."),
    ("fmi2FreeInstance", ".xxxxxx."),
    ("fmi2SetupExperiment", ".x......"),
    ("fmi2EnterInitializationMode", ".x......"),
    ("fmi2ExitInitializationMode", "..x....."),
    ("fmi2Terminate", "...xx..."),
    ("fmi2Reset", ".xxxxxx."),
    ("fmi2GetReal", "..2xxx7."),
    ("fmi2GetInteger", "..2xxx7."),
    ("fmi2GetBoolean", "..2xxx7."),
    ("fmi2GetString", "..2xxx7."),
    ("fmi2SetReal", ".1345..."),
    ("fmi2SetInteger", ".134...."),
    ("fmi2SetBoolean", ".134...."),
    ("fmi2SetString", ".134...."),
    ("fmi2GetFMUstate", ".xxxxx7."),
    ("fmi2SetFMUstate", ".xxxxxx."),
    ("fmi2FreeFMUstate", ".xxxxxx."),
    ("fmi2SerializedFMUstateSize", ".xxxxxx."),
    ("fmi2SerializeFMUstate", ".xxxxxx."),
    ("fmi2DeSerializeFMUstate", ".xxxxxx."),
    ("fmi2GetDirectionalDerivative", "..xxxx7."),
    ("fmi2EnterEventMode", "...xx..."),
    ("fmi2NewDiscreteStates", "...x...."),
    ("fmi2EnterContinuousTimeMode", "...x...."),
    ("fmi2CompletedIntegratorStep", "....x..."),
    ("fmi2SetTime", "...8x..."),
    ("fmi2SetContinuousStates", "....x..."),
    ("fmi2GetEventIndicators", "..xxxx7."),
    ("fmi2GetContinuousStates", "..xxxx7."),
    ("fmi2GetDerivatives", "..xxxx7."),
    ("fmi2GetNominalsOfContinuousStates", ".xxxxx7."),
];

/// Cells of the tables that say "not allowed" where these FMUs accept the call: reported as
/// findings (counted, with the shortest sequence), not asserted, until it is decided whether the
/// FMU or the test changes. None now: fmi2SetInteger, fmi2SetBoolean and fmi2SetString in
/// Continuous-Time Mode (section 3.2.3's table: only fmi2SetReal, condition 5), accepted with no
/// value references when the oracle was written, are refused since.
const FMI2_REPORTED_CELLS: &[(&str, State2)] = &[];

/// The fmi2 function a call makes (the first one, for the calls that make several: whether it
/// is allowed decides whether the call is).
fn fmi2_function(call: &Call) -> &'static str {
    match call {
        Call::SetDebugLogging { .. } => "fmi2SetDebugLogging",
        Call::SetupExperiment { .. } | Call::Initialize => "fmi2SetupExperiment",
        Call::EnterInitializationMode => "fmi2EnterInitializationMode",
        Call::ExitInitializationMode => "fmi2ExitInitializationMode",
        Call::Terminate => "fmi2Terminate",
        Call::Reset => "fmi2Reset",
        Call::GetReal { .. } => "fmi2GetReal",
        Call::SetReal { .. } => "fmi2SetReal",
        Call::GetInteger { .. } => "fmi2GetInteger",
        Call::SetInteger { .. } => "fmi2SetInteger",
        Call::GetBoolean { .. } => "fmi2GetBoolean",
        Call::SetBoolean { .. } => "fmi2SetBoolean",
        Call::GetString { .. } => "fmi2GetString",
        Call::SetString { .. } => "fmi2SetString",
        Call::DoStep { .. } => "fmi2DoStep",
        Call::CancelStep => "fmi2CancelStep",
        Call::GetStatus { which, .. } => {
            ["fmi2GetStatus", "fmi2GetRealStatus", "fmi2GetIntegerStatus", "fmi2GetBooleanStatus", "fmi2GetStringStatus"][(*which as usize).min(4)]
        }
        Call::GetFmuState { .. } => "fmi2GetFMUstate",
        Call::SetFmuState(_) => "fmi2SetFMUstate",
        Call::FreeFmuState(_) => "fmi2FreeFMUstate",
        Call::SerializeAndRestore { .. } => "fmi2SerializedFMUstateSize",
        Call::DirectionalDerivative { .. } => "fmi2GetDirectionalDerivative",
        Call::SetInputDerivatives { .. } => "fmi2SetRealInputDerivatives",
        Call::GetOutputDerivatives { .. } => "fmi2GetRealOutputDerivatives",
        Call::EnterEventMode => "fmi2EnterEventMode",
        Call::NewDiscreteStates => "fmi2NewDiscreteStates",
        Call::EnterContinuousTimeMode => "fmi2EnterContinuousTimeMode",
        Call::SetTime(_) => "fmi2SetTime",
        Call::SetContinuousStates { .. } => "fmi2SetContinuousStates",
        Call::GetRealArray { which, .. } => match which {
            0 => "fmi2GetDerivatives",
            1 => "fmi2GetEventIndicators",
            2 => "fmi2GetContinuousStates",
            _ => "fmi2GetNominalsOfContinuousStates",
        },
        Call::CompletedIntegratorStep { .. } => "fmi2CompletedIntegratorStep",
        Call::OtherType { .. } | Call::MismatchedCount { .. } | Call::Unprovided(_) | Call::AdjointDerivative { .. } | Call::GetNumberOf(_) => {
            unreachable!("FMI 3.0 calls are not generated for FMI 2.0: {call:?}")
        }
    }
}

/// A state of FMI 2.0's state machines (sections 3.2.3 and 4.2.4) these FMUs can reach: not
/// stepInProgress or stepCanceled (entered only after fmi2DoStep returned fmi2Pending, a status
/// the test refuses; so fmi2CancelStep is allowed nowhere they can be), not fatal (fmi2Fatal,
/// refused too). Co-Simulation's slaveInitialized is stepComplete or stepFailed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum State2 {
    Instantiated,
    InitializationMode,
    StepComplete,
    StepFailed,
    EventMode,
    ContinuousTimeMode,
    Terminated,
    Error,
}

impl State2 {
    const CO_SIMULATION: [State2; 6] =
        [State2::Instantiated, State2::InitializationMode, State2::StepComplete, State2::StepFailed, State2::Terminated, State2::Error];
    const MODEL_EXCHANGE: [State2; 6] =
        [State2::Instantiated, State2::InitializationMode, State2::EventMode, State2::ContinuousTimeMode, State2::Terminated, State2::Error];

    fn bit(self) -> u16 {
        1 << self as u16
    }

    /// Its cell in a row of its interface's table.
    fn column(self, model_exchange: bool) -> usize {
        match (self, model_exchange) {
            (State2::Instantiated, _) => 1,
            (State2::InitializationMode, _) => 2,
            (State2::StepComplete, false) | (State2::EventMode, true) => 3,
            (State2::ContinuousTimeMode, true) => 4,
            (State2::StepFailed, false) | (State2::Terminated, true) => 5,
            (State2::Terminated, false) => 7,
            (State2::Error, true) => 6,
            (State2::Error, false) => 8,
            (state, _) => unreachable!("{state:?} is no state of this interface"),
        }
    }
}

/// What the FMI 2.0 standard says about the next call, as [`Oracle`] for FMI 3.0, from the
/// standard's tables ([`FMI2_CS_TABLE`], [`FMI2_ME_TABLE`]) and state charts, not from this FMU's
/// (fmu-runtime's fmi2/states.rs). The instance's state is a set of the states it may be in; a
/// call is forbidden (must return fmi2Error) where no state of the set allows it, and a function
/// of the other interface (no row in the instance's table) is forbidden in every state. A call
/// that makes several (`Initialize`: setup, enter, exit; `SerializeAndRestore`) is judged by its
/// first. The set:
/// * after an allowed call returned fmi2OK or fmi2Warning: where the state chart goes from each
///   state of the set that allows the call (an accepted call shows that the instance was in one
///   of those);
/// * after fmi2DoStep returned fmi2Discard: stepFailed (section 4.2.4's state chart); after
///   fmi2Discard of any other call (fmi2Set*, fmi2Get*, fmi2Get*Status): where it was (no
///   transition of the state charts is labelled with it);
/// * after an allowed call returned fmi2Error: the standard's state is `error` (section 2.1.3:
///   "the simulation cannot be continued with this FMU instance"; the error column of the
///   tables). These FMUs refuse a call with wrong arguments (a value reference of no variable, a
///   NULL array) with fmi2Error and stay where they were, so the set gets `error` added and
///   keeps the states it had: only what both forbid is asserted. What the error state alone
///   forbids and the FMU accepted is a finding ([`Oracle2::reported`]), not asserted;
/// * after a forbidden call was refused: where it was (a refusal changes nothing, the convention
///   the FMI 3.0 oracle has too; by section 2.1.3 alone any fmi2Error leads to `error`, whose
///   column also allows the debug-only reads, cells 7, which this convention asserts refused
///   where the instance was, e.g. fmi2GetReal in instantiated);
/// * after fmi2SetFMUstate (any status), or fmi2Reset that failed: every state of the interface
///   (the standard does not say which state a restored FMU state is in).
///
/// Not checked, where the standard leaves room or conditions a cell on the variables: the
/// numbered cells (which variables may be set or read in which state), fmi2SetupExperiment
/// before fmi2EnterInitializationMode (required by section 2.1.6's text, not by the tables),
/// fmi2GetXXX after fmi2SetXXX without fmi2DoStep in between in slaveInitialized (section 4.2.4's
/// text), the kinds of status each fmi2Get*Status may be asked for (section 4.2.3), and the FMI
/// 2.0 cells the versions disagree on (see [`FMI2_ME_TABLE`]); the cells of
/// [`FMI2_REPORTED_CELLS`] are reported, not asserted.
struct Oracle2 {
    model_exchange: bool,
    /// The states the instance may be in, a bit per [`State2`].
    states: u16,
    /// An allowed call returned fmi2Error since the last successful fmi2Reset or fmi2SetFMUstate:
    /// the standard's state is `error`.
    in_error: bool,
    /// How many calls it said must be refused (all were).
    refusals: u64,
}

impl Oracle2 {
    fn new(model_exchange: bool) -> Oracle2 {
        Oracle2 { model_exchange, states: State2::Instantiated.bit(), in_error: false, refusals: 0 }
    }

    fn interface(&self) -> &'static [State2; 6] {
        if self.model_exchange { &State2::MODEL_EXCHANGE } else { &State2::CO_SIMULATION }
    }

    fn possible(&self) -> Vec<State2> {
        self.interface().iter().copied().filter(|s| self.states & s.bit() != 0).collect()
    }

    fn every_state(&self) -> u16 {
        self.interface().iter().fold(0, |bits, s| bits | s.bit())
    }

    /// The row of `function` in the instance's table (`None`: a function of the other interface).
    fn row(&self, function: &str) -> Option<&'static [u8]> {
        let table = if self.model_exchange { FMI2_ME_TABLE } else { FMI2_CS_TABLE };
        table.iter().find(|(name, _)| *name == function).map(|(_, cells)| cells.as_bytes())
    }

    /// Whether the table allows `function` (its `row`) in `state`.
    fn allows(&self, row: &[u8], state: State2) -> bool {
        row[state.column(self.model_exchange)] != b'.'
    }

    /// As [`Oracle2::allows`], but the cells that are only reported count as allowing.
    fn allows_asserted(&self, function: &str, row: &[u8], state: State2) -> bool {
        self.allows(row, state) || FMI2_REPORTED_CELLS.contains(&(function, state))
    }

    /// Why the standard does not allow `call` here (it must then return fmi2Error), if it does not.
    fn forbids(&self, call: &Call) -> Option<String> {
        let function = fmi2_function(call);
        let Some(row) = self.row(function) else {
            let interface = if self.model_exchange { "Model Exchange" } else { "Co-Simulation" };
            return Some(format!("{function} is no function of FMI 2.0 for {interface} (not in the table of section {})", if self.model_exchange { "3.2.3" } else { "4.2.4" }));
        };
        let states = self.possible();
        (!states.is_empty() && states.iter().all(|s| !self.allows_asserted(function, row, *s)))
            .then(|| format!("{function} is not allowed in {}", self.state_text()))
    }

    /// A rule of the standard that does not allow `call` here but is reported, not asserted
    /// (checked where [`Oracle2::forbids`] has nothing): its description, the same for every call
    /// it does not allow in the error state.
    fn reported(&self, call: &Call) -> Option<String> {
        let function = fmi2_function(call);
        let row = self.row(function)?;
        let states = self.possible();
        if !states.is_empty() && states.iter().all(|s| !self.allows(row, *s)) {
            // Named by its cells (the states but `error`, which a finding of its own covers).
            let cells: Vec<String> = states.iter().filter(|s| **s != State2::Error).map(|s| format!("{s:?}")).collect();
            return Some(format!("{function} in {} (section {}'s table)", cells.join(" or "), if self.model_exchange { "3.2.3" } else { "4.2.4" }));
        }
        (self.in_error && !self.allows(row, State2::Error)).then(|| {
            format!(
                "{} calls the error state does not allow, after an fmi2Error (sections 2.1.3 and {}: the error column)",
                if self.model_exchange { "Model Exchange" } else { "Co-Simulation" },
                if self.model_exchange { "3.2.3" } else { "4.2.4" }
            )
        })
    }

    fn state_text(&self) -> String {
        let names: Vec<String> = self.possible().iter().map(|s| format!("{s:?}")).collect();
        names.join(" or ")
    }

    /// Follows the instance through `call`, which returned `status` (`refused`: the oracle had
    /// forbidden it).
    fn after(&mut self, call: &Call, status: Status, refused: bool) {
        use State2::*;
        if refused {
            self.refusals += 1;
            return;
        }
        let function = fmi2_function(call);
        let row = self.row(function).expect("an allowed call has a row");
        let ok = status == Status::OK || status == Status::WARNING;
        let initialized = if self.model_exchange { EventMode } else { StepComplete };
        let mut next = 0u16;
        match call {
            Call::SetFmuState(_) => next = self.every_state(),
            Call::Reset if !ok => next = self.every_state(),
            _ if status == Status::ERROR => {
                self.in_error = true;
                next = self.states | Error.bit();
            }
            Call::Initialize if !ok => {
                // Which of setup, enter and exit did not return fmi2OK is not known.
                next = Instantiated.bit() | InitializationMode.bit() | initialized.bit() | Error.bit();
            }
            _ => {
                for state in self.possible().into_iter().filter(|s| self.allows_asserted(function, row, *s)) {
                    next |= match call {
                        Call::DoStep { .. } if status == Status::DISCARD => StepFailed.bit(),
                        _ if !ok => state.bit(),
                        Call::EnterInitializationMode => InitializationMode.bit(),
                        Call::ExitInitializationMode | Call::Initialize => initialized.bit(),
                        Call::Terminate => Terminated.bit(),
                        Call::Reset => Instantiated.bit(),
                        Call::DoStep { .. } => StepComplete.bit(),
                        Call::EnterEventMode => EventMode.bit(),
                        Call::EnterContinuousTimeMode => ContinuousTimeMode.bit(),
                        // Condition 8: a pure discrete-time FMU leaves Event Mode with it.
                        Call::SetTime(_) if state == EventMode => EventMode.bit() | ContinuousTimeMode.bit(),
                        _ => state.bit(),
                    };
                }
            }
        }
        if ok && matches!(call, Call::Reset | Call::SetFmuState(_)) {
            self.in_error = false;
        }
        self.states = if next == 0 { self.every_state() } else { next };
    }
}

/// The legality oracle of the FMU's FMI version.
enum Legality {
    Fmi2(Oracle2),
    Fmi3(Oracle),
}

impl Legality {
    fn forbids(&self, call: &Call) -> Option<String> {
        match self {
            Legality::Fmi2(o) => o.forbids(call),
            Legality::Fmi3(o) => o.forbids(call),
        }
    }

    fn state_text(&self) -> String {
        match self {
            Legality::Fmi2(o) => o.state_text(),
            Legality::Fmi3(o) => format!("{:?}", o.state),
        }
    }

    /// See [`Oracle2::reported`] (FMI 3.0: none).
    fn reported(&self, call: &Call) -> Option<String> {
        match self {
            Legality::Fmi2(o) => o.reported(call),
            Legality::Fmi3(_) => None,
        }
    }

    fn after(&mut self, call: &Call, status: Status, refused: bool) {
        match self {
            Legality::Fmi2(o) => o.after(call, status, refused),
            Legality::Fmi3(o) => o.after(call, status, refused),
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
    /// Calls the oracle said the standard forbids there (each refused).
    forbidden: u64,
    /// FMI 2.0: the calls accepted where a rule of the standard that is reported, not asserted,
    /// does not allow them ([`Oracle2::reported`]): per rule, how many, and the shortest sequence.
    findings: Findings,
}

/// Per rule of the standard reported, not asserted: how many calls it did not allow were
/// accepted, and the shortest sequence that shows one.
type Findings = std::collections::BTreeMap<String, (u64, String)>;

/// Adds `more` to `findings`, keeping the shorter example.
fn merge_findings(findings: &mut Findings, more: Findings) {
    for (rule, (count, example)) in more {
        let entry = findings.entry(rule).or_insert((0, example.clone()));
        entry.0 += count;
        if example.len() < entry.1.len() {
            entry.1 = example;
        }
    }
}

fn run_case(target: &Target, case: &Case, reference: &[Vec<u64>; 2], tally: &mut Tally) -> Result<(), TestCaseError> {
    let inst = target.instantiate("fuzzed", case.model_exchange, case.logging_on, case.memory_callbacks);
    let version = target.fmu.fmi_version();
    let mut run = Run { target, inst, time: 0.0, states: Vec::new(), experiment: (None, 0.0, None) };
    let mut oracle = match version {
        FmiVersion::Fmi2 => Legality::Fmi2(Oracle2::new(case.model_exchange)),
        FmiVersion::Fmi3 => Legality::Fmi3(Oracle::new(case.model_exchange, target)),
    };
    for (i, call) in case.calls.iter().enumerate() {
        let mark = run.inst.log().len();
        let forbidden = oracle.forbids(call);
        let reported = if forbidden.is_none() { oracle.reported(call) } else { None };
        let state_before = oracle.state_text();
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
        prop_assert!(status != Status(-2), "{}: fmi3DoStep returned OK with eventHandlingNeeded, terminateSimulation or earlyReturn set, or a lastSuccessfulTime that is not the step's end", context());
        prop_assert!(status != Status(-3), "{}: fmi3GetNumberOf* disagrees with modelDescription.xml", context());
        prop_assert!(matches!(status.0, 0..=3), "{}: status {status:?} (fmi2Fatal means a model panicked)", context());
        if let Some(why) = &forbidden {
            prop_assert!(
                status == Status::ERROR,
                "{}: returned {status:?} where FMI {} does not allow the call ({why}; state {state_before})",
                context(),
                version.text()
            );
            tally.forbidden += 1;
        }
        if let Some(rule) = reported.filter(|_| status != Status::ERROR) {
            let example = format!(
                "{}, {} instance, calls {:?}: the last one returned {status:?}",
                target.name(),
                if case.model_exchange { "Model Exchange" } else { "Co-Simulation" },
                &case.calls[..=i]
            );
            merge_findings(&mut tally.findings, Findings::from([(rule, (1, example))]));
        }
        oracle.after(call, status, forbidden.is_some());
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

/// One FMU's report line and findings, or its failure.
type FuzzResult = Result<(String, Findings), String>;

/// One FMU's share of the cases, with its own fixed seed (index `n` in dist/'s order, and its FMI
/// version): its report line and its findings (FMI 2.0: [`Oracle2::reported`]), or the failure.
fn fuzz_one(n: usize, fmu: &Arc<Fmu>, per_fmu: u32) -> FuzzResult {
    let version = fmu.fmi_version();
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
    // Other sequences through the other version (FMI 2.0 keeps the seeds it always had).
    seed[9] = if version == FmiVersion::Fmi3 { 3 } else { 0 };
    let mut runner = TestRunner::new_with_rng(config, TestRng::from_seed(RngAlgorithm::ChaCha, &seed));
    let tally = std::cell::RefCell::new(Tally::default());
    let started = Instant::now();
    let result = runner.run(&any_case(version), |case| run_case(&target, &case, &reference, &mut tally.borrow_mut()));
    if let Err(e) = result {
        return Err(format!("{}: {e}", target.name()));
    }
    let t = tally.into_inner();
    let forbidden = format!(" ({} forbidden by FMI {} where called)", t.forbidden, version.text());
    let finding = if version == FmiVersion::Fmi2 {
        format!(", {} accepted where FMI 2.0 does not allow them (findings, below)", t.findings.values().map(|(n, _)| n).sum::<u64>())
    } else {
        String::new()
    };
    let line = format!(
        "  {:<30} {per_fmu} sequences, {} calls: {} OK ({} doSteps), {} Error{forbidden}, {} Discard{finding}; {:.1} s",
        target.name(),
        t.calls,
        t.ok,
        t.steps_ok,
        t.errors,
        t.discards,
        started.elapsed().as_secs_f64()
    );
    Ok((line, t.findings))
}

#[test]
fn random_call_sequences_never_crash_hang_or_fail_silently() {
    // (index in its version's dist folder, FMU): FMI 2.0's, then FMI 3.0's.
    let fmus: Vec<(usize, Arc<Fmu>)> = versions().into_iter().flat_map(|v| every_fmu_for(v).into_iter().enumerate()).collect();
    let total: u32 = std::env::var("FUZZ_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(10_000);
    // The total is split between the two versions (half each, also when FMI_VERSIONS picks one),
    // so testing both APIs takes the time testing one did.
    let per_version = total.div_ceil(2);
    let fmus_per_version = fmus.iter().filter(|(_, f)| f.fmi_version() == fmus[0].1.fmi_version()).count() as u32;
    let per_fmu = per_version.div_ceil(fmus_per_version);
    // The FMUs are fuzzed side by side, one thread per core taking the next FMU (instances share
    // nothing: tests/tests/threads.rs); each FMU's cases and seed are the same as one at a time.
    // FUZZ_THREADS overrides the count (tests/valgrind.sh, under which threads only interleave, sets 1).
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let workers = std::env::var("FUZZ_THREADS").ok().and_then(|v| v.parse().ok()).unwrap_or(cores).clamp(1, fmus.len());
    let next = std::sync::atomic::AtomicUsize::new(0);
    let mut results: Vec<(usize, FuzzResult)> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..workers)
            .map(|_| {
                s.spawn(|| {
                    let mut done = Vec::new();
                    loop {
                        let n = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                        let Some((index, fmu)) = fmus.get(n) else { break };
                        done.push((n, fuzz_one(*index, fmu, per_fmu)));
                    }
                    done
                })
            })
            .collect();
        handles.into_iter().flat_map(|h| h.join().expect("a fuzzing thread panicked")).collect()
    });
    results.sort_by_key(|(n, _)| *n);
    let mut report = Vec::new();
    let mut findings = Findings::new();
    for (_, result) in results {
        match result {
            Ok((line, more)) => {
                report.push(line);
                merge_findings(&mut findings, more);
            }
            Err(failure) => panic!("{failure}"),
        }
    }
    println!("random FMI call sequences (crashes 0, hangs 0, illegal statuses 0, silent errors 0):\n{}", report.join("\n"));
    // Rules of FMI 2.0 these FMUs do not follow, reported, not asserted (see `Oracle2`).
    for (rule, (count, example)) in &findings {
        println!("FMI 2.0 finding, not asserted: {count} calls accepted against \"{rule}\"; the shortest:\n    {example}");
    }
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
    for fmu in versions().into_iter().flat_map(every_fmu_for) {
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
            // FMI 2.0 keeps its seed; FMI 3.0 gets other damages.
            TestRng::from_seed(RngAlgorithm::ChaCha, &[if fmu.fmi_version() == FmiVersion::Fmi3 { 8u8 } else { 7u8 }; 32]),
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
        report.push(format!("  {:<30} {CASES} damaged copies of a {}-byte state refused", target.name(), valid.len()));
    }
    println!("corrupted serialized states:\n{}", report.join("\n"));
}
