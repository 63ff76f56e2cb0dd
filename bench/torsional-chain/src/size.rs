//! The chain's size: the benchmark and the tests write this file before each build.

/// Number of inertias N (2N - 1 states).
pub const INERTIAS: usize = 10;
