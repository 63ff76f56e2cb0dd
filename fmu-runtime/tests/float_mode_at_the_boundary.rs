//! Subnormal numbers are flushed to zero inside the FMU's calls and only there
//! (fmu_runtime::float_mode): a model's output that underflows into the subnormal range reads
//! zero through fmi2GetReal and fmi3GetFloat64, while the master's own arithmetic before and after
//! each call, and inside the logger callback the FMU calls, keeps gradual underflow.
//!
//! The reference values are IEEE 754's: 1e-300 x 1e-10 = 1e-310 is subnormal (below
//! f64::MIN_POSITIVE = 2.2e-308) and exact in binary64 as the nearest subnormal to 1e-310; with
//! flush-to-zero the product is +0.

use std::sync::atomic::{AtomicU64, Ordering};

use fmu_runtime::exported::Exported;
use fmu_runtime::prelude::*;
use fmu_runtime::standards::Standard;

/// y = scale x 1e-10 with scale = 1e-300: a subnormal output.
pub struct Underflow {
    scale: Parameter,
    x: State,
    y: Output,
}

impl Model for Underflow {
    fn info() -> ModelInfo {
        ModelInfo {
            name: "Underflow",
            description: "An output in the subnormal range",
            default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 1.0, step_size: 0.1 },
            solver: Solver::ExplicitRungeKutta,
            documentation: "<p>y = scale 1e-10</p>",
        }
    }
    fn declare(d: &mut Declarations) -> Self {
        Underflow {
            scale: d.parameter("scale", 1e-300, "1").positive().describe("a tiny factor"),
            x: d.state("x", 1.0, "1").describe("a state, so that the model steps"),
            y: d.output("y", "1").describe("scale times 1e-10"),
        }
    }
    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        der[self.x] = -k[self.x];
    }
    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        out[self.y] = k[self.scale] * 1e-10;
    }
}

/// The master's own product, computed where it is stored (black_box: neither folded by the
/// compiler nor moved across the FMU's call).
fn masters_product_bits() -> u64 {
    let bb = std::hint::black_box;
    bb(bb(1e-300f64) * bb(1e-10f64)).to_bits()
}

fn subnormal_bits() -> u64 {
    1e-310f64.to_bits()
}

fn exported() -> &'static Exported<Underflow> {
    Box::leak(Box::new(Exported::of()))
}

fn vr(e: &Exported<Underflow>, name: &str) -> u32 {
    e.declared.table.by_name(name).expect("declared").value_reference
}

/// What the master computed inside its logger callback (the product's bits), and how often.
static LOGGED_PRODUCT: AtomicU64 = AtomicU64::new(u64::MAX);

unsafe extern "C" fn fmi3_logger(_: *mut std::ffi::c_void, _: fmu_runtime::fmi3::types::fmi3Status, _: *const std::os::raw::c_char, _: *const std::os::raw::c_char) {
    LOGGED_PRODUCT.store(masters_product_bits(), Ordering::SeqCst);
}

#[test]
fn fmi3_flushes_inside_its_calls_and_the_master_keeps_its_mode() {
    use fmu_runtime::fmi3::functions as f;
    use fmu_runtime::fmi3::types::*;
    use fmu_runtime::instance::Interface;
    assert_eq!(masters_product_bits(), subnormal_bits(), "the test thread starts with gradual underflow");
    let e = exported();
    let token = std::ffi::CString::new(e.of_standard(Standard::Fmi3).token.clone()).unwrap();
    let y = vr(e, "y");
    unsafe {
        let c = f::instantiate::<Underflow>(e, Interface::CoSimulation, c"u".as_ptr(), token.as_ptr(), std::ptr::null_mut(), false, Some(fmi3_logger), (false, false));
        assert!(!c.is_null());
        assert_eq!(f::enter_initialization_mode::<Underflow>(c, 0, 0.0, 0.0, 0, 0.0), fmi3OK);
        assert_eq!(f::exit_initialization_mode::<Underflow>(c), fmi3OK);
        let mut value = f64::NAN;
        assert_eq!(f::get_float64::<Underflow>(c, &y, 1, &mut value, 1), fmi3OK);
        assert_eq!(value.to_bits(), 0, "y = 1e-300 x 1e-10 flushed to +0 inside the FMU");
        assert_eq!(masters_product_bits(), subnormal_bits(), "the master's mode is back after the call");
        // An error inside a call reaches the logger, which runs in the master's mode.
        let unknown = 9999u32;
        assert_eq!(f::set_float64::<Underflow>(c, &unknown, 1, &1.0, 1), fmi3Error);
        assert_eq!(LOGGED_PRODUCT.load(Ordering::SeqCst), subnormal_bits(), "the logger callback ran with gradual underflow");
        assert_eq!(masters_product_bits(), subnormal_bits());
        let (mut event, mut terminate, mut early, mut last) = (false, false, false, 0.0);
        assert_eq!(f::do_step::<Underflow>(c, 0.0, 0.1, 1, &mut event, &mut terminate, &mut early, &mut last), fmi3OK);
        assert_eq!(masters_product_bits(), subnormal_bits(), "and after a doStep");
        f::free_instance::<Underflow>(c);
    }
}

#[test]
fn fmi2_flushes_inside_its_calls_and_the_master_keeps_its_mode() {
    use fmu_runtime::fmi2::functions as f;
    use fmu_runtime::fmi2::types::*;
    assert_eq!(masters_product_bits(), subnormal_bits());
    let e = exported();
    let guid = std::ffi::CString::new(e.of_standard(Standard::Fmi2).token.clone()).unwrap();
    let y = vr(e, "y");
    let callbacks = fmi2CallbackFunctions { logger: None, allocateMemory: None, freeMemory: None, stepFinished: None, componentEnvironment: std::ptr::null_mut() };
    unsafe {
        let c = f::instantiate::<Underflow>(e, c"u".as_ptr(), fmi2CoSimulation, guid.as_ptr(), std::ptr::null(), &callbacks, 0, 0);
        assert!(!c.is_null());
        assert_eq!(f::setup_experiment::<Underflow>(c, 0, 0.0, 0.0, 0, 0.0), fmi2OK);
        assert_eq!(f::enter_initialization_mode::<Underflow>(c), fmi2OK);
        assert_eq!(f::exit_initialization_mode::<Underflow>(c), fmi2OK);
        assert_eq!(f::do_step::<Underflow>(c, 0.0, 0.1, 1), fmi2OK);
        assert_eq!(masters_product_bits(), subnormal_bits(), "the master's mode is back after fmi2DoStep");
        let mut value = f64::NAN;
        assert_eq!(f::get_real::<Underflow>(c, &y, 1, &mut value), fmi2OK);
        assert_eq!(value.to_bits(), 0, "flushed to +0 inside the FMU");
        assert_eq!(masters_product_bits(), subnormal_bits(), "and after fmi2GetReal");
        f::free_instance::<Underflow>(c);
    }
}
