//! Shared by the steady_steps_* tests (one model per test binary: each model exports the FMI
//! functions): a global allocator that counts allocations per thread (the test harness runs
//! tests on several threads) and a driver of an `Instance` directly.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use fmu_runtime::instance::Instance;
use fmu_runtime::Model;

struct Counting;

thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

// SAFETY: forwards every call to the system allocator unchanged; it only counts (a const
// thread-local Cell never allocates, and `try_with` does nothing during thread teardown).
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
        System.alloc(layout)
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
        System.alloc_zeroed(layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
        System.realloc(ptr, layout, new_size)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

pub fn allocations() -> usize {
    ALLOCATIONS.with(Cell::get)
}

/// An initialized Co-Simulation instance, with the given integer parameters set first.
#[allow(dead_code)] // not every test binary drives an Instance directly
pub fn initialized<M: Model>(integers: &[(&str, i32)]) -> Instance<M> {
    initialized_with(integers, &[])
}

#[allow(unused_imports)] // not every test binary drives an Instance directly
pub use fmu_runtime::testing::initialized_with;

/// Allocations in `steps` doSteps of `h` after `warm_up` of them.
#[allow(dead_code)] // not every test binary drives an Instance directly
pub fn allocations_in_steady_steps<M: Model>(i: &mut Instance<M>, h: f64, warm_up: usize, steps: usize) -> usize {
    let mut t = i.time();
    for _ in 0..warm_up {
        i.do_step(t, h).unwrap();
        t += h;
    }
    let before = allocations();
    for _ in 0..steps {
        i.do_step(t, h).unwrap();
        t += h;
    }
    allocations() - before
}

#[allow(dead_code)] // not every test binary reads an integer
pub fn integer<M: Model>(i: &mut Instance<M>, name: &str) -> i32 {
    let vr = i.table().by_name(name).unwrap_or_else(|| panic!("{name}")).value_reference;
    let mut n = [0];
    i.get(&[vr], &mut n).unwrap();
    n[0]
}
