//! imu-mouse host side: the f64 reference formulas, f64 twins of the core's stages,
//! simulated sensors, Monte Carlo statistics, and the `lab` CLI's commands.

pub mod allan;
pub mod budget;
pub mod columns;
pub mod device_twin;
pub mod drift;
pub mod hid;
pub mod montecarlo;
pub mod mouse;
pub mod plot;
pub mod pointing;
pub mod predict;
pub mod recording;
pub mod reference;
pub mod reproduce;
pub mod scene;
pub mod sim;
pub mod speed;
pub mod stats;
pub mod track;
pub mod twin;
pub mod usbip;
