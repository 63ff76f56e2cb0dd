//! FMU state helpers: `fmi2GetFMUstate`, `fmi2SetFMUstate`, `fmi2FreeFMUstate` and
//! (de)serialization (FMI 3.0: `fmi3GetFMUState`, ...), as methods of [`Instance`].

use std::ffi::c_char;
use std::ptr;

use crate::ffi::{Api, FmuStatePtr, Status};
use crate::instance::Instance;

/// A handle to an FMU state (`fmi2FMUstate`) owned by the instance that made it.
///
/// It is not freed on drop (that needs the instance): free it with
/// [`Instance::free_fmu_state`]; states still alive are the FMU's to release in
/// `fmi2FreeInstance`. Use a handle only with the instance that created it.
#[derive(Debug, PartialEq, Eq)]
pub struct FmuState {
    ptr: FmuStatePtr,
}

// SAFETY: a handle is an opaque pointer only dereferenced by the FMU, through its instance.
unsafe impl Send for FmuState {}

impl FmuState {
    /// ESCAPE HATCH: the raw `fmi2FMUstate` pointer.
    pub fn as_raw(&self) -> FmuStatePtr {
        self.ptr
    }

    /// ESCAPE HATCH (misuse tests): a handle from a raw pointer, e.g. a second handle to the same
    /// state (`FmuState::from_raw(state.as_raw())`) to free it twice, or a handle kept after
    /// its state was freed.
    ///
    /// # Safety
    /// Handing such a handle to the FMU is exactly the misuse being tested: the FMU must detect
    /// it, or it may crash.
    pub unsafe fn from_raw(ptr: FmuStatePtr) -> FmuState {
        FmuState { ptr }
    }
}

impl Instance {
    /// `fmi2GetFMUstate` into a new state (`*FMUstate == NULL` on entry).
    pub fn get_fmu_state(&mut self) -> (Status, Option<FmuState>) {
        let mut raw: FmuStatePtr = ptr::null_mut();
        // SAFETY: valid out pointer.
        let status = unsafe { self.raw_get_fmu_state(&mut raw) };
        (status, (!raw.is_null()).then_some(FmuState { ptr: raw }))
    }

    /// `fmi2GetFMUstate` overwriting an existing state (`*FMUstate != NULL` on entry).
    pub fn update_fmu_state(&mut self, state: &mut FmuState) -> Status {
        // SAFETY: valid in/out pointer.
        unsafe { self.raw_get_fmu_state(&mut state.ptr) }
    }

    /// # Safety
    /// `state` is a valid in/out pointer.
    unsafe fn raw_get_fmu_state(&mut self, state: *mut FmuStatePtr) -> Status {
        match self.api() {
            Api::Fmi2(f) => (f.get_fmu_state)(self.c(), state),
            Api::Fmi3(f) => (f.get_fmu_state)(self.c(), state),
        }
    }

    /// `fmi2SetFMUstate`.
    pub fn set_fmu_state(&mut self, state: &FmuState) -> Status {
        // SAFETY: the handle was produced by this FMU (or is a deliberate misuse, see from_raw).
        unsafe {
            match self.api() {
                Api::Fmi2(f) => (f.set_fmu_state)(self.c(), state.ptr),
                Api::Fmi3(f) => (f.set_fmu_state)(self.c(), state.ptr),
            }
        }
    }

    /// `fmi2FreeFMUstate` (consumes the handle).
    pub fn free_fmu_state(&mut self, state: FmuState) -> Status {
        let mut raw = state.ptr;
        // SAFETY: valid in/out pointer.
        unsafe {
            match self.api() {
                Api::Fmi2(f) => (f.free_fmu_state)(self.c(), &mut raw),
                Api::Fmi3(f) => (f.free_fmu_state)(self.c(), &mut raw),
            }
        }
    }

    /// `fmi2SerializedFMUstateSize`.
    pub fn serialized_fmu_state_size(&mut self, state: &FmuState) -> (Status, usize) {
        let mut size = 0usize;
        // SAFETY: valid out pointer.
        let status = unsafe {
            match self.api() {
                Api::Fmi2(f) => (f.serialized_fmu_state_size)(self.c(), state.ptr, &mut size),
                Api::Fmi3(f) => (f.serialized_fmu_state_size)(self.c(), state.ptr, &mut size),
            }
        };
        (status, size)
    }

    /// `fmi2SerializedFMUstateSize` then `fmi2SerializeFMUstate` into a new buffer. On a
    /// non-OK status of the size query that status is returned with an empty buffer.
    pub fn serialize_fmu_state(&mut self, state: &FmuState) -> (Status, Vec<u8>) {
        let (status, size) = self.serialized_fmu_state_size(state);
        if !status.is_ok_or_warning() {
            return (status, Vec::new());
        }
        let mut bytes = vec![0u8; size];
        // SAFETY: the buffer holds `size` bytes.
        let status = unsafe {
            match self.api() {
                Api::Fmi2(f) => (f.serialize_fmu_state)(
                    self.c(),
                    state.ptr,
                    bytes.as_mut_ptr().cast::<c_char>(),
                    size,
                ),
                Api::Fmi3(f) => (f.serialize_fmu_state)(self.c(), state.ptr, bytes.as_mut_ptr(), size),
            }
        };
        (status, bytes)
    }

    /// `fmi2DeSerializeFMUstate` into a new state.
    pub fn deserialize_fmu_state(&mut self, bytes: &[u8]) -> (Status, Option<FmuState>) {
        let mut raw: FmuStatePtr = ptr::null_mut();
        // SAFETY: the buffer holds bytes.len() bytes; valid out pointer.
        let status = unsafe {
            match self.api() {
                Api::Fmi2(f) => (f.de_serialize_fmu_state)(
                    self.c(),
                    bytes.as_ptr().cast::<c_char>(),
                    bytes.len(),
                    &mut raw,
                ),
                Api::Fmi3(f) => (f.deserialize_fmu_state)(self.c(), bytes.as_ptr(), bytes.len(), &mut raw),
            }
        };
        (status, (!raw.is_null()).then_some(FmuState { ptr: raw }))
    }
}
