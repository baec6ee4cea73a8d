//! imu-mouse core: fixed-point filtering, bias calibration and exact double integration of an
//! analog accelerometer's ADC codes into mouse counts.
//!
//! `#![no_std]`, no allocation, and no floating point on the sample path: floats appear only
//! when a [`Config`] in physical units is validated into [`Settings`], and in accessors meant
//! for host-side analysis.
//!
//! The data flow, one module per stage:
//!
//! ```text
//! AdcCode -> lowpass (optional) -> minus calibrated bias -> integrator -> readout -> counts
//!            lowpass.rs            calibration.rs           integrator.rs  readout.rs
//! ```
//!
//! [`Axis`] composes the stages for one axis, [`Tracker`] runs three axes through calibration
//! and tracking. The device's other logic lives here too, so that it is tested on the host:
//! [`hid`] (report descriptor, packing and scheduling), [`button`] (debounce, long press),
//! [`ledger`] (lost-sample accounting), [`indicator`] (LED patterns) and [`power`] (USB
//! suspend and remote wake-up). [`bench`] holds what `cargo lab speed` measures and is not
//! part of the device. The physics and every error formula are in the project's REFERENCE.md
//! (Thong et al., Meas. Sci. Technol. 13 (2002) 1163).
//!
//! # Fixed-point formats
//! - [`AdcCode`]: raw ADC code [LSB], any `u16`.
//! - Bias-free acceleration `c`: Q16 counts (`i64`, units of `2^-16` LSB).
//! - Integrator: `W = 2 V`, `Z = 4 S` in Q16 counts times samples (squared); see
//!   [`integrator`].
#![no_std]
#![forbid(unsafe_code)]

pub mod axis;
pub mod bench;
pub mod button;
pub mod calibration;
pub mod config;
pub mod drift;
pub mod hid;
pub mod indicator;
pub mod integrator;
pub mod ledger;
pub mod lowpass;
mod math;
pub mod power;
pub mod profile;
pub mod protocol;
pub mod readout;
pub mod tracker;

pub use axis::Axis;
pub use button::{ButtonEvent, Debouncer};
pub use calibration::{Calibration, CalibrationError, Calibrator};
pub use config::{Config, ConfigError, Settings};
pub use drift::{Drift, DriftError, State as DriftState};
pub use hid::{MouseReport, Reporter};
pub use indicator::{Indicator, LastCalibration, Link};
pub use integrator::{BlockSums, IntegratorState, Scheme};
pub use ledger::{Delivery, LedgerCounters, LedgerError, SampleLedger};
pub use lowpass::{Lowpass, LowpassState};
pub use power::{Power, PowerAction};
pub use profile::{AxisMap, Key, Profile, ProfileError};
pub use readout::{Readout, ReadoutState};
pub use tracker::{Counters, Event, Phase, Tracker, AXES};

/// Number of fractional bits of the bias-free acceleration `c` fed to the integrator
/// (Q16 counts). The bias is rounded to this grid: at most `2^-17` LSB of residual bias.
pub const FRAC_BITS: u32 = 16;

/// A raw ADC code [LSB]; for a 12-bit ADC `0..=4095`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(transparent)]
pub struct AdcCode(pub u16);
