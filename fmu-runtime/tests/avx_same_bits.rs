//! The explicit method's AVX loops give the bits of their baseline (SSE2) versions
//! (`fmu_runtime::simd`): the torsional chain of `fmu_runtime::testing::chains`, large enough for
//! the vector loops (100 inertias, 199 states; they take blocks from 64 states on), stepped 1 ms
//! at a time through its torque step once with AVX and once without, with an FMU state saved
//! and restored halfway; every state after every doStep must agree bit for bit. On a processor
//! without AVX both runs take the baseline and agree trivially (the test says so on stderr).

use fmu_runtime::instance::Instance;
use fmu_runtime::prelude::*;
use fmu_runtime::testing::chains::Chain;
use fmu_runtime::testing::initialized_with;

const N: usize = 100;
const STEP: f64 = 1e-3;

fn vr<M: Model>(i: &Instance<M>, name: &str) -> u32 {
    i.table().by_name(name).unwrap_or_else(|| panic!("{name}")).value_reference
}

/// The bits of every state after each doStep over 0.2 s (the torque steps on at 0.01 s), the
/// instance's FMU state saved at 0.1 s and restored into a fresh instance that goes on.
fn run<M: Model>(parameters: &[(&str, f64)]) -> Vec<u64> {
    let make = || initialized_with::<M>(&[], parameters);
    let mut i = make();
    let vrs: Vec<u32> = (1..=N).map(|k| vr(&i, &format!("w_{k}"))).chain((1..N).map(|k| vr(&i, &format!("theta_{k}")))).collect();
    let mut bits = Vec::new();
    for s in 0..200 {
        if s == 100 {
            let saved = i.get_fmu_state(None).unwrap();
            let bytes = i.serialize_fmu_state(saved).unwrap();
            i.free_fmu_state(saved).unwrap();
            let mut twin = make();
            let restored = twin.deserialize_fmu_state(&bytes, None).unwrap();
            twin.set_fmu_state(restored).unwrap();
            twin.free_fmu_state(restored).unwrap();
            i = twin;
        }
        let t = s as f64 * STEP;
        i.do_step(t, STEP).unwrap_or_else(|e| panic!("doStep from {t} s: {}", e.message));
        let mut x = vec![0.0; vrs.len()];
        i.get(&vrs, &mut x).unwrap();
        bits.extend(x.iter().map(|v| v.to_bits()));
    }
    bits
}

fn both_ways<M: Model>(what: &str, parameters: &[(&str, f64)]) {
    fmu_runtime::simd::baseline_only(false);
    let with_avx = run::<M>(parameters);
    fmu_runtime::simd::baseline_only(true);
    let baseline = run::<M>(parameters);
    fmu_runtime::simd::baseline_only(false);
    #[cfg(target_arch = "x86_64")]
    if !std::arch::is_x86_feature_detected!("avx") {
        eprintln!("{what}: this processor has no AVX; both runs took the baseline");
    }
    let differ = with_avx.iter().zip(&baseline).filter(|(a, b)| a != b).count();
    assert_eq!(with_avx.len(), baseline.len());
    assert_eq!(differ, 0, "{what}: {differ} of {} state values differ between AVX and the baseline", with_avx.len());
    // The run went somewhere: the first inertia turns.
    assert!(f64::from_bits(with_avx[with_avx.len() - 2 * N + 1]) > 0.0, "{what}: the chain did not move");
}

#[test]
fn the_explicit_chain_steps_bit_for_bit_with_avx_and_without() {
    both_ways::<Chain<N, true, false>>("explicit chain", &[("step_time", 0.01)]);
}
