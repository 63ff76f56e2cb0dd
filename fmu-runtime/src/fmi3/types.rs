//! The C types of FMI 3.0 (`fmi3PlatformTypes.h`, `fmi3FunctionTypes.h`) that this FMU uses, as
//! Rust sees them.
#![allow(non_camel_case_types, non_upper_case_globals, non_snake_case)]

use std::os::raw::{c_char, c_void};

pub type fmi3Instance = *mut c_void;
pub type fmi3InstanceEnvironment = *mut c_void;
pub type fmi3FMUState = *mut c_void;
pub type fmi3ValueReference = u32;
pub type fmi3Float32 = f32;
pub type fmi3Float64 = f64;
pub type fmi3Int8 = i8;
pub type fmi3UInt8 = u8;
pub type fmi3Int16 = i16;
pub type fmi3UInt16 = u16;
pub type fmi3Int32 = i32;
pub type fmi3UInt32 = u32;
pub type fmi3Int64 = i64;
pub type fmi3UInt64 = u64;
/// C `bool`. Read from the master as a byte (any non-zero byte is true): a Rust `bool` holding
/// another value than 0 or 1 would be undefined behaviour.
pub type fmi3Boolean = bool;
pub type fmi3BooleanIn = u8;
pub type fmi3Char = c_char;
pub type fmi3String = *const c_char;
pub type fmi3Byte = u8;
pub type fmi3Binary = *const u8;
pub type fmi3Clock = bool;

/// fmi3Status, passed as a plain int so that no value is an invalid enum.
pub type fmi3Status = i32;
pub const fmi3OK: fmi3Status = 0;
pub const fmi3Warning: fmi3Status = 1;
pub const fmi3Discard: fmi3Status = 2;
pub const fmi3Error: fmi3Status = 3;
pub const fmi3Fatal: fmi3Status = 4;

pub type fmi3DependencyKind = i32;
pub type fmi3IntervalQualifier = i32;

pub type fmi3LogMessageCallback = unsafe extern "C" fn(fmi3InstanceEnvironment, fmi3Status, fmi3String, fmi3String);
pub type fmi3IntermediateUpdateCallback =
    unsafe extern "C" fn(fmi3InstanceEnvironment, fmi3Float64, fmi3Boolean, fmi3Boolean, fmi3Boolean, fmi3Boolean, *mut fmi3Boolean, *mut fmi3Float64);
pub type fmi3ClockUpdateCallback = unsafe extern "C" fn(fmi3InstanceEnvironment);
pub type fmi3LockPreemptionCallback = unsafe extern "C" fn();
pub type fmi3UnlockPreemptionCallback = unsafe extern "C" fn();

pub const VERSION: &std::ffi::CStr = c"3.0";

/// Opaque data the master never reads (the `void*` arguments of unsupported functions).
pub type Opaque = c_void;
