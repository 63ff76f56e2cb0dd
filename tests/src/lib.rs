//! FMI 2.0 host (work in progress)
