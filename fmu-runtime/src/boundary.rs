//! What both C adapters (`fmi2`, `fmi3`) do alike at the C boundary: the instance behind the
//! opaque pointer, the guard every call passes through (a live instance, a call legal in its
//! phase, a panic caught and turned into a fatal status), C arrays as slices, and the FMU-state
//! calls, which the two standards shape alike.
#![allow(clippy::missing_safety_doc)]

use std::ffi::CStr;
use std::os::raw::c_char;
use std::panic::{catch_unwind, AssertUnwindSafe};

use crate::instance::Instance;
use crate::model::Model;
use crate::phase::Phase;
use crate::status::{CallResult, Failure, Status};

/// Marks live instances; cleared on free so that a stale pointer to a still-mapped instance
/// is recognised rather than used.
const MAGIC: u64 = 0x464d_5552_5349_4e53;

/// What the master's instance pointer (`fmi2Component`, `fmi3Instance`) points at.
#[repr(C)]
pub struct Component<M: Model> {
    magic: u64,
    pub instance: Instance<M>,
    /// Bytes of the last serialized-size call, reused by the serialize call that follows.
    serialized: Option<(usize, Vec<u8>)>,
}

impl<M: Model> Component<M> {
    /// The pointer a master receives for a new instance.
    pub fn into_raw(instance: Instance<M>) -> *mut std::ffi::c_void {
        Box::into_raw(Box::new(Component { magic: MAGIC, instance, serialized: None })) as *mut std::ffi::c_void
    }

    /// The instance behind a master's pointer, if it is a live one of this model.
    pub unsafe fn from_raw<'a>(c: *mut std::ffi::c_void) -> Option<&'a mut Component<M>> {
        let comp = (c as *mut Component<M>).as_mut()?;
        (comp.magic == MAGIC).then_some(comp)
    }

    /// Frees an instance (a null or stale pointer is ignored).
    pub unsafe fn free(c: *mut std::ffi::c_void) {
        if Self::from_raw(c).is_none() {
            return;
        }
        let mut comp = Box::from_raw(c as *mut Component<M>);
        comp.magic = 0;
        let _ = catch_unwind(AssertUnwindSafe(move || drop(comp)));
    }

    /// A new FMU state (`existing` = none) or an overwritten live one: its handle.
    pub fn get_fmu_state(&mut self, existing: Option<usize>) -> CallResult<usize> {
        self.instance.get_fmu_state(existing)
    }

    /// The size of a state's serialized bytes (kept for the serialize call that follows).
    pub fn serialized_size(&mut self, handle: usize) -> CallResult<usize> {
        let bytes = self.instance.serialize_fmu_state(handle)?;
        let size = bytes.len();
        self.serialized = Some((handle, bytes));
        Ok(size)
    }

    /// Writes a state's serialized bytes into the master's buffer of `out.len()` bytes.
    pub fn serialize_into(&mut self, handle: usize, out: Option<&mut [u8]>, size: usize) -> CallResult {
        let bytes = match self.serialized.take() {
            Some((cached, bytes)) if cached == handle => bytes,
            _ => self.instance.serialize_fmu_state(handle)?,
        };
        if size != bytes.len() {
            return Err(Failure::error(format!(
                "the buffer holds {size} bytes, the serialized state has {} (ask for the serialized size first)",
                bytes.len()
            )));
        }
        out.ok_or_else(|| null("the byte buffer"))?.copy_from_slice(&bytes);
        Ok(())
    }
}

/// An FMU-state pointer as the instance's store knows it: a handle, 0 for none.
pub fn handle(state: *mut std::ffi::c_void) -> Option<usize> {
    let h = state as usize;
    (h != 0).then_some(h)
}

pub fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".to_string())
}

/// An adapter's table of which of its functions may be called in which phase.
pub trait CallTable: Copy {
    /// The phases (`Phase::bit`s) in which the function may be called.
    fn allowed(self) -> u16;
    fn is_model_exchange_only(self) -> bool;
    fn is_co_simulation_only(self) -> bool;
    /// The standard's name of a phase.
    fn phase_name(phase: Phase) -> &'static str;
    /// What comes before a phase's name in a message ("in mode " in FMI 2.0, "in " in FMI 3.0).
    const IN: &'static str;

    fn is_allowed_in(self, phase: Phase) -> bool {
        self.allowed() & phase.bit() != 0
    }

    /// Where the function may be called, for an error message.
    fn allowed_names(self) -> String {
        let mask = self.allowed();
        if mask == 0 {
            return "none (this FMU never enters the state where it would be allowed)".into();
        }
        Phase::ALL.into_iter().filter(|p| mask & p.bit() != 0).map(Self::phase_name).collect::<Vec<_>>().join(", ")
    }
}

/// Runs `body` if the adapter's table allows `function` for the instance's interface and phase.
pub unsafe fn checked<M: Model, F: CallTable>(c: *mut std::ffi::c_void, function: F, name: &str, body: impl FnOnce(&mut Component<M>) -> CallResult) -> Option<Status> {
    let legal = |instance: &Instance<M>| {
        let (phase, interface) = (instance.phase(), instance.interface);
        if (function.is_model_exchange_only() && interface == crate::instance::Interface::CoSimulation)
            || (function.is_co_simulation_only() && interface == crate::instance::Interface::ModelExchange)
        {
            return Err(Refusal { status: Status::Error, message: format!("is not available: this instance was instantiated for {interface:?}") });
        }
        if !function.is_allowed_in(phase) {
            let status = if phase == Phase::Fatal { Status::Fatal } else { Status::Error };
            return Err(Refusal { status, message: format!("is not allowed {}{}; it is allowed in: {}", F::IN, F::phase_name(phase), function.allowed_names()) });
        }
        Ok(())
    };
    guarded::<M>(c, name, legal, body)
}

/// Why a call is refused before it runs: not legal in this phase or for this interface. The
/// adapter's state table says it, in its standard's words.
pub struct Refusal {
    pub status: Status,
    pub message: String,
}

/// Runs `body` on the instance behind `c` if `legal` lets it (`None`: no live instance there).
/// A failure is reported through the logger with the function's name; a panic moves the
/// instance to the Fatal phase. Inside, subnormal numbers are flushed to zero
/// ([`crate::float_mode`]); the master's mode is back on return.
pub unsafe fn guarded<M: Model>(
    c: *mut std::ffi::c_void,
    name: &str,
    legal: impl FnOnce(&Instance<M>) -> Result<(), Refusal>,
    body: impl FnOnce(&mut Component<M>) -> CallResult,
) -> Option<Status> {
    let comp = Component::<M>::from_raw(c)?;
    let flushing = crate::float_mode::FlushSubnormals::enter();
    comp.instance.logger.set_master_mode(Some(flushing.master_mode()));
    let status = if let Err(refusal) = legal(&comp.instance) {
        comp.instance.logger.log(refusal.status, &format!("{name} {}", refusal.message));
        refusal.status
    } else {
        match catch_unwind(AssertUnwindSafe(|| body(comp))) {
            Ok(Ok(())) => Status::Ok,
            Ok(Err(failure)) => {
                let status = failure.status;
                comp.instance.report(&Failure { message: format!("{name}: {}", failure.message), ..failure });
                status
            }
            Err(payload) => {
                comp.instance.enter_fatal();
                let msg = format!("{name}: internal error (panic): {}; the instance can only be freed", panic_message(&*payload));
                comp.instance.logger.log(Status::Fatal, &msg);
                Status::Fatal
            }
        }
    };
    comp.instance.logger.set_master_mode(None);
    Some(status)
}

/// A C array as a slice; `None` (an error) when it is null but should hold `n` > 0 items.
pub unsafe fn slice<'a, T>(p: *const T, n: usize) -> Option<&'a [T]> {
    if n == 0 {
        Some(&[])
    } else if p.is_null() {
        None
    } else {
        Some(std::slice::from_raw_parts(p, n))
    }
}

pub unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> Option<&'a mut [T]> {
    if n == 0 {
        Some(&mut [])
    } else if p.is_null() {
        None
    } else {
        Some(std::slice::from_raw_parts_mut(p, n))
    }
}

pub fn null(what: &str) -> Failure {
    Failure::error(format!("{what} is a null pointer"))
}

pub unsafe fn c_str<'a>(p: *const c_char) -> Option<&'a str> {
    if p.is_null() {
        None
    } else {
        CStr::from_ptr(p).to_str().ok()
    }
}

/// Why a value reference is no String variable (neither FMU version has String variables).
pub fn no_string(table: &crate::variables::VariableTable, vr: u32) -> String {
    match table.get(vr) {
        Some(v) => format!("value reference {vr} is the {} variable '{}', not a String (this FMU has no String variables)", v.base_type().name(), v.name),
        None => format!("unknown value reference {vr} (this FMU has no String variables)"),
    }
}
