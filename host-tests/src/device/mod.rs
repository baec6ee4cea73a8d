//! The device on the host: the core (and the firmware's application, `imu_app`) driven
//! exactly as the firmware drives them.
//!
//! - [`bridge`]: the settings page's frames between its WebSocket and a device;
//! - [`check`]: a board judged from what it recorded at rest and moved;
//! - [`track`]: samples through `Tracker` and a 1 ms USB poll through `Reporter`;
//! - [`trial`]: one axis through the real fixed-point pipeline, the Monte Carlo's unit;
//! - [`usbip`] and [`twin`]: `imu_app` as a USB/IP device, in real time, with its profile
//!   in [`flash`];
//! - [`usbip_host`] and [`client`]: the host's side of the configuration interface, over
//!   USB/IP (the twin) or `hidapi` (a board);
//! - [`profile`]: a profile's keys as text, as `config` and a recording's `profile,` line
//!   carry them.

pub mod bridge;
pub mod check;
pub mod client;
pub mod flash;
pub mod profile;
pub mod track;
pub mod trial;
pub mod twin;
pub mod usbip;
pub mod usbip_host;
