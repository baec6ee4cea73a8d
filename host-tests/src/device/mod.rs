//! The device on the host: the core (and the firmware's application, `imu_app`) driven
//! exactly as the firmware drives them.
//!
//! - [`track`]: samples through `Tracker` and a 1 ms USB poll through `Reporter`;
//! - [`trial`]: one axis through the real fixed-point pipeline, the Monte Carlo's unit;
//! - [`usbip`] and [`twin`]: `imu_app` as a USB/IP device, in real time.

pub mod track;
pub mod trial;
pub mod twin;
pub mod usbip;
