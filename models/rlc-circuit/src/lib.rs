//! RlcCircuit (work in progress)
