//! The oracle: what judges the core. The paper's formulas and their exact finite-N forms
//! (REFERENCE.md), the same algorithms as the core's stages in f64, and the error predictor.
//!
//! It imports nothing of `imu_core` and nothing else of this crate (`tests/layout.rs`), so a
//! defect in the core cannot also be a defect in its yardstick.

pub mod predict;
pub mod reference;
pub mod twin;
