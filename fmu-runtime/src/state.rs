//! FMU state: get/set/free and serialize/deserialize (FMI 2.0, section 2.1.8; FMI 3.0, 3.2.4).
//!
//! A saved state is a [`Snapshot`] of values only (never pointers), held by the instance that
//! made it in a [`SnapshotStore`]: a clone of the instance's [`Situation`] (the part of an
//! instance that is saved, kept as one field of it) and the solver's own step size and
//! lookahead. Restoring is an assignment of the situation and a solver made afresh. The FMU state the master receives is an opaque handle
//! (slot and generation), not an address: a handle used after it was freed, freed twice, or
//! made up is recognised and refused with an error instead of touching freed memory.
//!
//! Serialized bytes: `MAGIC`, format version, the FMU's guid, the payload, and an FNV-1a 64
//! checksum of everything before it. Bytes from another FMU (guid), another format version, a
//! truncated or corrupted buffer are refused with a message saying which.

use crate::phase::Phase;
use crate::integrate::{parameters_len, Lookahead};
use crate::rk::{StepRecord, STAGES};
use crate::stepper::JacobianPoint;
use crate::values::Values;

pub const MAGIC: &[u8; 8] = b"FMURSST\0";
/// 4: the explicit solver's step reaching past the communication point (`lookahead`).
/// 5: the phase is the runtime's own (`Phase`), not an FMI 2.0 mode bit.
/// 6: the known reals no longer hold the states (`Values::states` is their one home), so the
/// known reals, input slopes, curvatures, previous inputs and the solver's parameter vector are
/// shorter by the number of states.
/// 7: the point the implicit solver's kept Jacobian was evaluated at (`jacobian`), and the time
/// event the solver last ended at (`after_time_event`).
/// 8: the implicit solver's step reaching past the communication point too (`lookahead`, the
/// same record with its stages), and Newton's contraction estimate with its Jacobian point.
pub const FORMAT_VERSION: u32 = 8;

/// The experiment the master set up (fmi2SetupExperiment; fmi3EnterInitializationMode).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Experiment {
    pub tolerance: Option<f64>,
    pub start_time: f64,
    pub stop_time: Option<f64>,
}

impl Default for Experiment {
    fn default() -> Self {
        Experiment { tolerance: None, start_time: 0.0, stop_time: None }
    }
}

/// The saved part of an instance: everything an FMU state restores but the solver's own step
/// size and lookahead. An instance keeps it as one field, so that saving it is a clone and
/// restoring it an assignment; what is not in it (the model, the variable table, the logger,
/// the interface and the master's event-mode flags, the saved FMU states, caches and buffers)
/// survives a restore.
#[derive(Clone, Debug, PartialEq)]
pub struct Situation {
    pub phase: Phase,
    pub time: f64,
    pub experiment: Experiment,
    /// Parameters, inputs, states, calculated values, derivatives, integers, booleans.
    pub values: Values,
    /// First and second time derivatives of the inputs for the next step (by known index;
    /// fmi2SetRealInputDerivatives), cleared after each step and when the input is set.
    pub input_slopes: Vec<f64>,
    pub input_curvatures: Vec<f64>,
    /// The known reals at the previous communication point and its time (input extrapolation).
    pub previous_inputs: Option<(f64, Vec<f64>)>,
}

/// Everything an instance needs to continue exactly from a saved point.
#[derive(Clone, Debug, PartialEq)]
pub struct Snapshot {
    pub situation: Situation,
    /// The solver's step size at this point (None before the first step).
    pub step_size: Option<f64>,
    /// The explicit solver's last step when it reaches past this point and the next doStep
    /// would continue it (the state here was interpolated in it).
    pub lookahead: Option<Lookahead>,
    /// Where the implicit solver's kept Jacobian was evaluated and the h gamma of its Newton
    /// matrix: a restored instance makes both again, bit for bit, and steps as the live one.
    pub jacobian: Option<JacobianPoint>,
    /// The time event the solver's last advance ended at (just below it): a step from there
    /// starts just past it.
    pub after_time_event: Option<f64>,
}

/// FNV-1a, 64 bit. Any change of a single byte changes the hash (each step is a bijection).
pub fn fnv1a64(seed: u64, bytes: &[u8]) -> u64 {
    let mut h = seed;
    for b in bytes {
        h ^= *b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

pub const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;

struct Writer(Vec<u8>);

impl Writer {
    fn u8(&mut self, v: u8) {
        self.0.push(v);
    }
    fn u32(&mut self, v: u32) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn f64(&mut self, v: f64) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn opt(&mut self, v: Option<f64>) {
        self.u8(v.is_some() as u8);
        self.f64(v.unwrap_or(0.0));
    }
    fn reals(&mut self, v: &[f64]) {
        self.u32(v.len() as u32);
        v.iter().for_each(|x| self.f64(*x));
    }
}

struct Reader<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl Reader<'_> {
    fn take(&mut self, n: usize) -> Result<&[u8], String> {
        let end = self.pos.checked_add(n).filter(|e| *e <= self.bytes.len()).ok_or_else(|| {
            format!("the serialized FMU state is truncated (needed {} bytes at offset {}, {} in all)", n, self.pos, self.bytes.len())
        })?;
        let s = &self.bytes[self.pos..end];
        self.pos = end;
        Ok(s)
    }
    fn u8(&mut self) -> Result<u8, String> {
        Ok(self.take(1)?[0])
    }
    fn u32(&mut self) -> Result<u32, String> {
        Ok(u32::from_le_bytes(self.take(4)?.try_into().unwrap()))
    }
    fn f64(&mut self) -> Result<f64, String> {
        Ok(f64::from_le_bytes(self.take(8)?.try_into().unwrap()))
    }
    fn opt(&mut self) -> Result<Option<f64>, String> {
        let some = self.u8()?;
        let v = self.f64()?;
        Ok((some != 0).then_some(v))
    }
    fn reals(&mut self, what: &str, expected: usize) -> Result<Vec<f64>, String> {
        let n = self.u32()? as usize;
        if n != expected {
            return Err(format!("the serialized FMU state has {n} {what}, this FMU has {expected}"));
        }
        (0..n).map(|_| self.f64()).collect()
    }
}

/// The sizes a state must have to fit this FMU.
pub struct Shape {
    pub known: usize,
    pub calculated: usize,
    pub states: usize,
    pub integers: usize,
    pub booleans: usize,
}

impl Snapshot {
    /// The bytes of this state, for an FMU with this guid.
    pub fn serialize(&self, guid: &str) -> Vec<u8> {
        let s = &self.situation;
        let mut w = Writer(Vec::with_capacity(64 + 8 * (s.values.known.len() + s.values.calculated.len())));
        w.0.extend_from_slice(MAGIC);
        w.u32(FORMAT_VERSION);
        w.u32(guid.len() as u32);
        w.0.extend_from_slice(guid.as_bytes());
        w.u32(s.phase as u32);
        w.f64(s.time);
        w.opt(s.experiment.tolerance);
        w.f64(s.experiment.start_time);
        w.opt(s.experiment.stop_time);
        w.opt(self.step_size);
        w.u8(self.lookahead.is_some() as u8);
        if let Some(la) = &self.lookahead {
            let r = &la.step;
            w.f64(r.t_start);
            w.f64(r.t_end);
            w.reals(&r.y_start);
            w.reals(&r.y_end);
            w.reals(&r.stages);
            w.reals(&la.parameters);
        }
        w.u8(self.jacobian.is_some() as u8);
        if let Some(j) = &self.jacobian {
            w.f64(j.t);
            w.f64(j.h_gamma);
            w.f64(j.contraction);
            w.reals(&j.x);
            w.reals(&j.parameters);
        }
        w.opt(self.after_time_event);
        w.reals(&s.values.known);
        w.reals(&s.values.calculated);
        w.reals(&s.values.derivatives);
        w.reals(&s.values.states);
        w.reals(&s.input_slopes);
        w.reals(&s.input_curvatures);
        w.opt(s.previous_inputs.as_ref().map(|(t, _)| *t));
        w.reals(s.previous_inputs.as_ref().map(|(_, v)| v.as_slice()).unwrap_or(&[]));
        w.u32(s.values.integers.len() as u32);
        s.values.integers.iter().for_each(|i| w.u32(*i as u32));
        w.u32(s.values.booleans.len() as u32);
        s.values.booleans.iter().for_each(|b| w.u8(*b as u8));
        let sum = fnv1a64(FNV_OFFSET, &w.0);
        w.0.extend_from_slice(&sum.to_le_bytes());
        w.0
    }

    /// Reads bytes made by `serialize` of an FMU with this guid and shape.
    pub fn deserialize(bytes: &[u8], guid: &str, shape: &Shape) -> Result<Snapshot, String> {
        if bytes.len() < MAGIC.len() + 8 + 8 || &bytes[..MAGIC.len()] != MAGIC {
            return Err("these bytes are not a serialized FMU state of this runtime (wrong magic number or too short)".into());
        }
        let (body, sum) = bytes.split_at(bytes.len() - 8);
        let mut r = Reader { bytes: body, pos: MAGIC.len() };
        let version = r.u32()?;
        if version != FORMAT_VERSION {
            return Err(format!("serialized FMU state format version {version}, this FMU reads version {FORMAT_VERSION}"));
        }
        let guid_len = r.u32()? as usize;
        let their_guid = r.take(guid_len)?;
        if their_guid != guid.as_bytes() {
            return Err(format!(
                "the serialized FMU state belongs to another FMU (guid {}, this FMU is {guid})",
                String::from_utf8_lossy(their_guid)
            ));
        }
        if fnv1a64(FNV_OFFSET, body).to_le_bytes() != sum {
            return Err("the serialized FMU state is corrupted (checksum mismatch)".into());
        }
        let phase_number = r.u32()?;
        let phase = Phase::from_number(phase_number)
            .filter(|p| *p != Phase::Fatal)
            .ok_or_else(|| format!("the serialized FMU state has an invalid phase {phase_number}"))?;
        let time = r.f64()?;
        let tolerance = r.opt()?;
        let start_time = r.f64()?;
        let stop_time = r.opt()?;
        let step_size = r.opt()?;
        let lookahead = match r.u8()? {
            0 => None,
            1 => Some(Lookahead {
                step: StepRecord {
                    t_start: r.f64()?,
                    t_end: r.f64()?,
                    y_start: r.reals("states at the solver step's start", shape.states)?,
                    y_end: r.reals("states at the solver step's end", shape.states)?,
                    stages: r.reals("solver stages", STAGES * shape.states)?,
                },
                parameters: r.reals("solver parameters", parameters_len(shape.known))?,
            }),
            other => return Err(format!("the serialized FMU state has an invalid solver-step flag {other}")),
        };
        if let Some(Lookahead { step: la, parameters }) = &lookahead {
            // The state was interpolated inside the step, which needs a step size to continue.
            let finite = [la.t_start, la.t_end].iter().chain(&la.y_start).chain(&la.y_end).chain(&la.stages).chain(parameters).all(|v| v.is_finite());
            if !(finite && la.t_start < la.t_end && la.t_start <= time && time <= la.t_end && step_size.is_some_and(|h| h > 0.0)) {
                return Err(format!(
                    "the serialized FMU state's solver step [{}, {}] s does not fit its time {time} s and step size {step_size:?}",
                    la.t_start, la.t_end
                ));
            }
        }
        let jacobian = match r.u8()? {
            0 => None,
            1 => Some(JacobianPoint {
                t: r.f64()?,
                h_gamma: r.f64()?,
                contraction: r.f64()?,
                x: r.reals("states at the solver's Jacobian point", shape.states)?,
                parameters: r.reals("solver parameters of its Jacobian", parameters_len(shape.known))?,
            }),
            other => return Err(format!("the serialized FMU state has an invalid Jacobian flag {other}")),
        };
        if let Some(j) = &jacobian {
            let finite = [j.t].iter().chain(&j.x).chain(&j.parameters).all(|v| v.is_finite());
            if !(finite && j.h_gamma.is_finite() && j.h_gamma > 0.0 && j.contraction.is_finite() && j.contraction >= 0.0) {
                return Err(format!(
                    "the serialized FMU state's Jacobian point (t = {} s, h gamma = {}, contraction {}) is not usable: \
                     its time, states and parameters must be finite, h gamma finite and positive, the contraction finite and not negative",
                    j.t, j.h_gamma, j.contraction
                ));
            }
        }
        let after_time_event = r.opt()?;
        if after_time_event.is_some_and(|e| !e.is_finite()) {
            return Err(format!("the serialized FMU state's time event {after_time_event:?} is not finite"));
        }
        let known = r.reals("known reals", shape.known)?;
        let calculated = r.reals("calculated reals", shape.calculated)?;
        let derivatives = r.reals("derivatives", shape.states)?;
        let states = r.reals("states", shape.states)?;
        let input_slopes = r.reals("input slopes", shape.known)?;
        let input_curvatures = r.reals("input curvatures", shape.known)?;
        let previous_time = r.opt()?;
        let previous_inputs = match previous_time {
            Some(t) => Some((t, r.reals("previous inputs", shape.known)?)),
            None => {
                r.reals("previous inputs", 0)?;
                None
            }
        };
        let n_int = r.u32()? as usize;
        if n_int != shape.integers {
            return Err(format!("the serialized FMU state has {n_int} integers, this FMU has {}", shape.integers));
        }
        let integers = (0..n_int).map(|_| r.u32().map(|v| v as i32)).collect::<Result<Vec<_>, _>>()?;
        let n_bool = r.u32()? as usize;
        if n_bool != shape.booleans {
            return Err(format!("the serialized FMU state has {n_bool} booleans, this FMU has {}", shape.booleans));
        }
        let booleans = (0..n_bool).map(|_| r.u8().map(|v| v != 0)).collect::<Result<Vec<_>, _>>()?;
        if r.pos != body.len() {
            return Err(format!("the serialized FMU state has {} unexpected trailing bytes", body.len() - r.pos));
        }
        Ok(Snapshot {
            situation: Situation {
                phase,
                time,
                experiment: Experiment { tolerance, start_time, stop_time },
                values: Values { known, states, calculated, derivatives, integers, booleans },
                input_slopes,
                input_curvatures,
                previous_inputs,
            },
            step_size,
            lookahead,
            jacobian,
            after_time_event,
        })
    }
}

/// The saved states of one instance, addressed by opaque handles.
#[derive(Default)]
pub struct SnapshotStore {
    slots: Vec<(u32, Option<Snapshot>)>,
    next_generation: u32,
}

const SLOT_BITS: u32 = 20;

impl SnapshotStore {
    fn decode(&self, handle: usize) -> Option<usize> {
        let slot = (handle & ((1 << SLOT_BITS) - 1)).checked_sub(1)?;
        let generation = (handle >> SLOT_BITS) as u64;
        match self.slots.get(slot) {
            Some((g, Some(_))) if *g as u64 == generation => Some(slot),
            _ => None,
        }
    }

    /// Stores a new snapshot; returns its handle (never 0).
    pub fn insert(&mut self, s: Snapshot) -> Result<usize, String> {
        self.next_generation = self.next_generation.wrapping_add(1);
        let generation = self.next_generation;
        let slot = match self.slots.iter().position(|(_, v)| v.is_none()) {
            Some(i) => i,
            None if self.slots.len() < (1 << SLOT_BITS) - 1 => {
                self.slots.push((0, None));
                self.slots.len() - 1
            }
            None => return Err("too many FMU states are alive in this instance; free some".into()),
        };
        self.slots[slot] = (generation, Some(s));
        Ok(((generation as usize) << SLOT_BITS) | (slot + 1))
    }

    pub fn get(&self, handle: usize) -> Option<&Snapshot> {
        self.decode(handle).and_then(|i| self.slots[i].1.as_ref())
    }

    /// Overwrites the snapshot behind a live handle.
    pub fn replace(&mut self, handle: usize, s: Snapshot) -> bool {
        match self.decode(handle) {
            Some(i) => {
                self.slots[i].1 = Some(s);
                true
            }
            None => false,
        }
    }

    pub fn remove(&mut self, handle: usize) -> bool {
        match self.decode(handle) {
            Some(i) => {
                self.slots[i].1 = None;
                true
            }
            None => false,
        }
    }

    pub fn live(&self) -> usize {
        self.slots.iter().filter(|(_, s)| s.is_some()).count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Snapshot {
        Snapshot {
            situation: Situation {
                phase: Phase::Stepping,
                time: 0.05,
                experiment: Experiment { tolerance: Some(1e-7), start_time: 0.0, stop_time: None },
                values: Values {
                    known: vec![1.0, 2.0, -3.5],
                    states: vec![4.0],
                    calculated: vec![0.25],
                    derivatives: vec![9.0],
                    integers: vec![3],
                    booleans: vec![true],
                },
                input_slopes: vec![0.0, 0.5, 0.0],
                input_curvatures: vec![0.0, 0.0, -1.0],
                previous_inputs: Some((0.04, vec![1.0, 2.0, -3.0])),
            },
            step_size: Some(1e-5),
            lookahead: Some(Lookahead {
                step: StepRecord {
                    t_start: 0.045,
                    t_end: 0.0501,
                    y_start: vec![3.9],
                    y_end: vec![4.01],
                    stages: vec![0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.1],
                },
                parameters: vec![1.0, 2.0, -3.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            }),
            jacobian: Some(JacobianPoint { t: 0.049, x: vec![3.95], parameters: vec![1.0, 2.0, -3.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0], h_gamma: 2.1e-6, contraction: 3.2e-7 }),
            after_time_event: Some(0.05),
        }
    }

    fn shape() -> Shape {
        Shape { known: 3, calculated: 1, states: 1, integers: 1, booleans: 1 }
    }

    #[test]
    fn round_trip_is_exact() {
        let s = sample();
        let bytes = s.serialize("{guid}");
        assert_eq!(Snapshot::deserialize(&bytes, "{guid}", &shape()).unwrap(), s);
    }

    #[test]
    fn every_single_bit_flip_and_every_truncation_is_refused() {
        let bytes = sample().serialize("{guid}");
        for i in 0..bytes.len() * 8 {
            let mut b = bytes.clone();
            b[i / 8] ^= 1 << (i % 8);
            assert!(Snapshot::deserialize(&b, "{guid}", &shape()).is_err(), "bit {i}");
        }
        for n in 0..bytes.len() {
            assert!(Snapshot::deserialize(&bytes[..n], "{guid}", &shape()).is_err(), "length {n}");
        }
    }

    #[test]
    fn a_state_without_a_solver_step_round_trips() {
        let s = Snapshot { lookahead: None, ..sample() };
        let bytes = s.serialize("{guid}");
        assert_eq!(Snapshot::deserialize(&bytes, "{guid}", &shape()).unwrap(), s);
        let s = Snapshot { lookahead: None, jacobian: None, ..sample() };
        let bytes = s.serialize("{guid}");
        assert_eq!(Snapshot::deserialize(&bytes, "{guid}", &shape()).unwrap(), s);
    }

    #[test]
    fn a_jacobian_point_that_is_not_usable_is_refused() {
        let mut s = sample();
        s.jacobian.as_mut().unwrap().h_gamma = 0.0;
        let err = Snapshot::deserialize(&s.serialize("{guid}"), "{guid}", &shape()).unwrap_err();
        assert!(err.contains("Jacobian point") && err.contains("h gamma = 0,") && err.contains("not usable"), "{err}");
        for bad in [f64::NAN, -0.5] {
            let mut s = sample();
            s.jacobian.as_mut().unwrap().contraction = bad;
            let err = Snapshot::deserialize(&s.serialize("{guid}"), "{guid}", &shape()).unwrap_err();
            assert!(err.contains(&format!("contraction {bad})")) && err.contains("not negative"), "{err}");
        }
    }

    #[test]
    fn a_solver_step_that_does_not_contain_the_time_is_refused() {
        let mut s = sample();
        s.lookahead.as_mut().unwrap().step.t_end = 0.049;
        let err = Snapshot::deserialize(&s.serialize("{guid}"), "{guid}", &shape()).unwrap_err();
        assert!(err.contains("does not fit"), "{err}");
    }

    #[test]
    fn another_fmus_state_is_refused_by_guid() {
        let bytes = sample().serialize("{other}");
        let err = Snapshot::deserialize(&bytes, "{guid}", &shape()).unwrap_err();
        assert!(err.contains("another FMU"), "{err}");
    }

    #[test]
    fn handles_are_not_reusable_after_free() {
        let mut store = SnapshotStore::default();
        let a = store.insert(sample()).unwrap();
        assert!(store.remove(a));
        assert!(!store.remove(a), "double free must be detected");
        let b = store.insert(sample()).unwrap();
        assert_ne!(a, b, "a reused slot gets a new generation");
        assert!(store.get(a).is_none());
        assert!(store.get(b).is_some());
        assert!(store.get(12345).is_none());
        assert!(store.get(0).is_none());
        assert_eq!(store.live(), 1);
    }
}
