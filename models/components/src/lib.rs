//! Lumped-parameter elements (work in progress)
