//! Measurements of what a run made, as plain arithmetic on its results
//! (pixels, series): no GPU, no files. The commands feed them and the
//! report writes what they return; the tests import them from here.
//!
//! It uses `interface` only (the data view's constants).

pub mod light_waves;
pub mod stats;
pub mod trace;
