//! Whether the solvers' vector loops take their AVX versions.
//!
//! The FMUs are built for x86_64's baseline (SSE2: two numbers per instruction), so that they
//! load on any 64-bit x86 processor. The loops over the states that take most of a large
//! model's explicit doStep (the stage sums `rk::combine` and the error norm, from 64 states on)
//! are compiled a second time for AVX (four per instruction) and chosen here, at run time. AVX
//! adds no fused multiply-add: each version does the same multiplications and additions in the
//! same order, so both give the same bits (`tests/avx_same_bits.rs` steps a chain both ways).
//! The implicit method stays on the baseline: its time goes to the band solves, and AVX in its
//! loops measured no faster (`rk::combine_baseline`).

use std::sync::atomic::{AtomicBool, Ordering};

static BASELINE_ONLY: AtomicBool = AtomicBool::new(false);

/// Whether the AVX versions may run: the processor and the operating system support AVX, and
/// [`baseline_only`] is off.
#[inline(always)]
pub(crate) fn avx() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        !BASELINE_ONLY.load(Ordering::Relaxed) && std::arch::is_x86_feature_detected!("avx")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// For tests: with `true`, every vector loop runs its baseline version (SSE2) in this process;
/// with `false`, the AVX versions again where the processor has them.
pub fn baseline_only(on: bool) {
    BASELINE_ONLY.store(on, Ordering::Relaxed);
}
