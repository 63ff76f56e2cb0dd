//! FMI 2.0 runtime (work in progress)
