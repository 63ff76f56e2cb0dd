//! Subnormal numbers flushed to zero inside the FMU's calls; the master's floating-point mode
//! untouched outside them.
//!
//! Why: a model at rest behind a travelling disturbance (the torsional chain of bench/, a shaft
//! line, a thermal network heated at one end) carries values that decay through the subnormal
//! range (below `f64::MIN_POSITIVE`, 2.2e-308), and x86 processors compute with subnormal operands
//! or results tens of times slower than with normal ones. On the stiff chain at 1 000 inertias
//! (1 999 states) a 1 ms doStep took 614 us with them and 518 us without; at 10 000 inertias
//! 46.7 ms against 8.9 ms (bench/run.sh --chain, 2026-12-04, BENCHMARKS.md). A subnormal is more
//! than 290 orders of magnitude below the absolute tolerance of a state of unit nominal even at a
//! relative tolerance of 1e-15, so reading it as zero changes no result at any tolerance.
//!
//! How: on x86_64, [`FlushSubnormals::enter`] sets the SSE control register's flush-to-zero (FTZ:
//! a subnormal result becomes zero) and denormals-are-zero (DAZ: a subnormal operand is read as
//! zero, in comparisons too) bits, and its drop puts the register back as the master had it, on
//! return and on unwinding alike (its exception flags too: those our arithmetic raised stay ours).
//! Every call on an instance enters it once (`boundary::guarded`); a callback into the master
//! inside such a call (the logger) runs in the master's own mode ([`MasterMode::run`]). The
//! control register belongs to the calling thread, so instances on other threads are not
//! affected. A guard costs two writes of the register and a read, about 7 ns.
//! On other architectures nothing changes. valgrind does not emulate the two bits: under it the
//! arithmetic keeps gradual underflow (it prints an emulation warning, no error).

/// FTZ (bit 15) and DAZ (bit 6) of MXCSR.
#[cfg(target_arch = "x86_64")]
const FTZ_DAZ: u32 = 1 << 15 | 1 << 6;

#[cfg(target_arch = "x86_64")]
fn read() -> u32 {
    let mut value: u32 = 0;
    // SAFETY: stmxcsr stores the 32-bit control register at the given address, a live u32.
    unsafe { std::arch::asm!("stmxcsr [{}]", in(reg) &mut value, options(nostack, preserves_flags)) };
    value
}

#[cfg(target_arch = "x86_64")]
fn write(value: u32) {
    // SAFETY: ldmxcsr loads the control register from a live u32; every value written here is
    // one read from the register, with at most the FTZ and DAZ bits added (no reserved bit set).
    unsafe { std::arch::asm!("ldmxcsr [{}]", in(reg) &value, options(nostack, preserves_flags)) };
}

#[cfg(target_arch = "x86_64")]
fn flushing(value: u32) -> u32 {
    value | FTZ_DAZ
}

#[cfg(not(target_arch = "x86_64"))]
fn read() -> u32 {
    0
}

#[cfg(not(target_arch = "x86_64"))]
fn write(_: u32) {}

#[cfg(not(target_arch = "x86_64"))]
fn flushing(value: u32) -> u32 {
    value
}

/// While alive: subnormals flushed to zero on this thread. Dropping it puts the register back as
/// it found it.
pub struct FlushSubnormals {
    found: u32,
}

impl FlushSubnormals {
    /// Flushes subnormals from now until the guard is dropped.
    pub fn enter() -> FlushSubnormals {
        let found = read();
        let flushed = flushing(found);
        if flushed != found {
            write(flushed);
        }
        FlushSubnormals { found }
    }

    /// The mode the master called in, for a callback into it.
    pub fn master_mode(&self) -> MasterMode {
        MasterMode(self.found)
    }
}

impl Drop for FlushSubnormals {
    fn drop(&mut self) {
        if flushing(self.found) != self.found {
            write(self.found);
        }
    }
}

/// The master's floating-point mode, as found when its call entered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MasterMode(u32);

impl MasterMode {
    /// Runs `f` (a callback into the master) in the master's mode, and returns to ours after it
    /// (also when `f` unwinds).
    pub fn run<T>(self, f: impl FnOnce() -> T) -> T {
        let ours = read();
        if ours == self.0 {
            return f();
        }
        write(self.0);
        let back = Restore(ours);
        let result = f();
        drop(back);
        result
    }
}

/// Puts the control register back on drop.
struct Restore(u32);

impl Drop for Restore {
    fn drop(&mut self) {
        write(self.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The smallest positive subnormal times one and a product that underflows into the
    /// subnormal range, as bits, computed at run time where they are written (black_box on the
    /// way in: not folded by the compiler; on the way out: not moved past a change of the mode,
    /// which the compiler orders only against memory, as the runtime's results are written).
    /// Compared as bits: inside a guard a comparison reads a subnormal operand as zero too (DAZ).
    fn tiny_bits() -> (u64, u64) {
        let black_box = std::hint::black_box;
        let sub = black_box(black_box(f64::from_bits(1)) * black_box(1.0));
        let product = black_box(black_box(1e-300) * black_box(1e-10));
        (sub.to_bits(), product.to_bits())
    }

    #[test]
    #[cfg(target_arch = "x86_64")]
    fn subnormals_flush_inside_and_the_mode_returns_after() {
        assert_eq!(read() & FTZ_DAZ, 0, "a test thread starts in IEEE mode");
        let ieee = tiny_bits();
        assert_eq!(ieee, (1, 1e-310f64.to_bits()), "gradual underflow outside");
        let before = read();
        {
            let guard = FlushSubnormals::enter();
            assert_eq!(tiny_bits(), (0, 0), "flushed inside");
            // The master's logger sees the master's mode, then ours again.
            assert_eq!(guard.master_mode().run(tiny_bits), ieee);
            assert_eq!(tiny_bits(), (0, 0));
            {
                let inner = FlushSubnormals::enter();
                assert_eq!(tiny_bits(), (0, 0));
                assert_eq!(guard.master_mode().run(tiny_bits), ieee);
                drop(inner);
            }
            assert_eq!(tiny_bits(), (0, 0), "the inner guard left the outer one's mode");
        }
        assert_eq!(read(), before, "the register as the master had it, flags included");
        assert_eq!(tiny_bits(), ieee);
    }

    #[test]
    #[cfg(target_arch = "x86_64")]
    fn a_panic_inside_restores_the_masters_mode() {
        let before = read();
        let caught = std::panic::catch_unwind(|| {
            let guard = FlushSubnormals::enter();
            guard.master_mode().run(|| panic!("inside the master's callback"));
        });
        assert!(caught.is_err());
        assert_eq!(read(), before);
    }
}
