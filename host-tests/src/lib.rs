//! imu-mouse host side: what judges the core, the world it is tested in, the device run on
//! the host, and the `cargo lab` commands.
//!
//! # Layout and dependency rules
//! Each folder is one role. An arrow is "may use"; nothing else is allowed, and
//! `tests/layout.rs` checks the rules that keep the judge independent of what it judges.
//!
//! | module | role | may use |
//! |---|---|---|
//! | [`oracle`] | the formulas of REFERENCE.md, the f64 twins of the core's stages, the error predictor: the judge | std, `libm` only: nothing of `imu_core`, nothing else of this crate |
//! | [`stats`] | mean squares and z-scores, quantiles, Allan deviation | std only |
//! | [`formats`] | recordings (CSV in), SVG charts (out) | std only |
//! | [`world`] | sensor noise, ADC quantisation, scenes, the hand on a desk: ADC codes, never the core | `stats` |
//! | [`device`] | the device on the host: the core and `imu_app` driven as the firmware drives them, the USB/IP bus | `imu_core`, `imu_app`, `world`, `stats` |
//! | [`commands`] | one module per `cargo lab` subcommand: its arguments, its run, its table | everything above; never another command |
//!
//! `src/bin/lab.rs` only parses the command line and dispatches to [`commands`].

pub mod commands;
pub mod device;
pub mod formats;
pub mod oracle;
pub mod stats;
pub mod world;
