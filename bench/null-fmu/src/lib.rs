//! NullStep: the benchmark's floor without any runtime. Hand-written `extern "C"` FMI 2.0
//! Co-Simulation functions: `fmi2Instantiate` hands out a pointer to a static byte,
//! `fmi2DoStep` returns fmi2OK at once, `fmi2GetReal` writes zeros. What a call from the host
//! into an FMU's shared library costs, with nothing behind it. Every other function returns
//! fmi2OK (or fmi2Error where it would have to produce something it does not have). Its
//! modelDescription.xml is written by the bench harness (`bench/harness`), which packages it.
#![allow(non_snake_case, clippy::missing_safety_doc)]

use std::os::raw::{c_char, c_int, c_void};

type Status = c_int;
const OK: Status = 0;
const ERROR: Status = 3;
type Component = *mut c_void;
type Vr = *const u32;

static INSTANCE: u8 = 0;

#[no_mangle]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    c"default".as_ptr()
}
#[no_mangle]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    c"2.0".as_ptr()
}
#[no_mangle]
pub extern "C" fn fmi2SetDebugLogging(_c: Component, _on: c_int, _n: usize, _cat: *const *const c_char) -> Status {
    OK
}
#[no_mangle]
pub extern "C" fn fmi2Instantiate(_name: *const c_char, _ty: c_int, _guid: *const c_char, _res: *const c_char, _cb: *const c_void, _visible: c_int, _logging: c_int) -> Component {
    &INSTANCE as *const u8 as Component
}
#[no_mangle]
pub extern "C" fn fmi2FreeInstance(_c: Component) {}
#[no_mangle]
pub extern "C" fn fmi2SetupExperiment(_c: Component, _tol_defined: c_int, _tol: f64, _start: f64, _stop_defined: c_int, _stop: f64) -> Status {
    OK
}
#[no_mangle]
pub extern "C" fn fmi2EnterInitializationMode(_c: Component) -> Status {
    OK
}
#[no_mangle]
pub extern "C" fn fmi2ExitInitializationMode(_c: Component) -> Status {
    OK
}
#[no_mangle]
pub extern "C" fn fmi2Terminate(_c: Component) -> Status {
    OK
}
#[no_mangle]
pub extern "C" fn fmi2Reset(_c: Component) -> Status {
    OK
}
#[no_mangle]
pub unsafe extern "C" fn fmi2GetReal(_c: Component, _vr: Vr, n: usize, values: *mut f64) -> Status {
    if n > 0 && !values.is_null() {
        std::slice::from_raw_parts_mut(values, n).fill(0.0);
    }
    OK
}
#[no_mangle]
pub extern "C" fn fmi2GetInteger(_c: Component, _vr: Vr, _n: usize, _v: *mut c_int) -> Status {
    ERROR
}
#[no_mangle]
pub extern "C" fn fmi2GetBoolean(_c: Component, _vr: Vr, _n: usize, _v: *mut c_int) -> Status {
    ERROR
}
#[no_mangle]
pub extern "C" fn fmi2GetString(_c: Component, _vr: Vr, _n: usize, _v: *mut *const c_char) -> Status {
    ERROR
}
#[no_mangle]
pub extern "C" fn fmi2SetReal(_c: Component, _vr: Vr, _n: usize, _v: *const f64) -> Status {
    OK
}
#[no_mangle]
pub extern "C" fn fmi2SetInteger(_c: Component, _vr: Vr, _n: usize, _v: *const c_int) -> Status {
    ERROR
}
#[no_mangle]
pub extern "C" fn fmi2SetBoolean(_c: Component, _vr: Vr, _n: usize, _v: *const c_int) -> Status {
    ERROR
}
#[no_mangle]
pub extern "C" fn fmi2SetString(_c: Component, _vr: Vr, _n: usize, _v: *const *const c_char) -> Status {
    ERROR
}
#[no_mangle]
pub extern "C" fn fmi2GetFMUstate(_c: Component, _s: *mut *mut c_void) -> Status {
    ERROR
}
#[no_mangle]
pub extern "C" fn fmi2SetFMUstate(_c: Component, _s: *mut c_void) -> Status {
    ERROR
}
#[no_mangle]
pub extern "C" fn fmi2FreeFMUstate(_c: Component, _s: *mut *mut c_void) -> Status {
    ERROR
}
#[no_mangle]
pub extern "C" fn fmi2SerializedFMUstateSize(_c: Component, _s: *mut c_void, _size: *mut usize) -> Status {
    ERROR
}
#[no_mangle]
pub extern "C" fn fmi2SerializeFMUstate(_c: Component, _s: *mut c_void, _b: *mut c_char, _size: usize) -> Status {
    ERROR
}
#[no_mangle]
pub extern "C" fn fmi2DeSerializeFMUstate(_c: Component, _b: *const c_char, _size: usize, _s: *mut *mut c_void) -> Status {
    ERROR
}
#[no_mangle]
pub extern "C" fn fmi2GetDirectionalDerivative(_c: Component, _u: Vr, _nu: usize, _z: Vr, _nz: usize, _dv: *const f64, _dz: *mut f64) -> Status {
    ERROR
}
#[no_mangle]
pub extern "C" fn fmi2SetRealInputDerivatives(_c: Component, _vr: Vr, _n: usize, _o: *const c_int, _v: *const f64) -> Status {
    ERROR
}
#[no_mangle]
pub extern "C" fn fmi2GetRealOutputDerivatives(_c: Component, _vr: Vr, _n: usize, _o: *const c_int, _v: *mut f64) -> Status {
    ERROR
}
/// The floor: returns at once.
#[no_mangle]
pub extern "C" fn fmi2DoStep(_c: Component, _t: f64, _h: f64, _no_prior: c_int) -> Status {
    OK
}
#[no_mangle]
pub extern "C" fn fmi2CancelStep(_c: Component) -> Status {
    ERROR
}
#[no_mangle]
pub extern "C" fn fmi2GetStatus(_c: Component, _k: c_int, _v: *mut c_int) -> Status {
    ERROR
}
#[no_mangle]
pub extern "C" fn fmi2GetRealStatus(_c: Component, _k: c_int, _v: *mut f64) -> Status {
    ERROR
}
#[no_mangle]
pub extern "C" fn fmi2GetIntegerStatus(_c: Component, _k: c_int, _v: *mut c_int) -> Status {
    ERROR
}
#[no_mangle]
pub extern "C" fn fmi2GetBooleanStatus(_c: Component, _k: c_int, _v: *mut c_int) -> Status {
    ERROR
}
#[no_mangle]
pub extern "C" fn fmi2GetStringStatus(_c: Component, _k: c_int, _v: *mut *const c_char) -> Status {
    ERROR
}
