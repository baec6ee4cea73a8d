//! One axis's pipeline: ADC code -> optional low-pass -> minus bias -> double integration ->
//! read-out in mouse counts.
//!
//! # Design
//! Coefficients live in [`Settings`] (shared by every axis), state in [`Axis`]. Per sample:
//!
//! ```text
//! y = lowpass(x) in Q16 counts  (or x << 16 without a filter; exact)
//! c = y - bias_q16              (Q16 counts, exact)
//! integrate c                   (exact, see crate::integrator)
//! ```
//!
//! The only roundings on the whole path are the low-pass output to Q16 (half up, at most
//! `2^-17` LSB) and the bias to Q16 (at calibration); read-out rounding is carried.

use crate::config::Settings;
use crate::integrator::IntegratorState;
use crate::lowpass::LowpassState;
use crate::readout::ReadoutState;
use crate::AdcCode;

/// State of one axis of the tracker.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Axis {
    bias_q16: i64,
    last: AdcCode,
    lowpass: LowpassState,
    integrator: IntegratorState,
    readout: ReadoutState,
}

impl Axis {
    /// An axis at rest with bias `bias_q16` (Q16 counts, `0..=65535 * 2^16`), its filter
    /// settled there and its last code the nearest code to it.
    pub fn new(bias_q16: i64) -> Self {
        let mut axis = Self::default();
        axis.set_bias_q16(bias_q16);
        axis
    }

    /// Sets the bias (Q16 counts, clamped to `0..=65535 * 2^16`, the codes' range) and settles
    /// the filter at it; motion and read-out remainder are kept.
    pub fn set_bias_q16(&mut self, bias_q16: i64) {
        let bias_q16 = bias_q16.clamp(0, 65_535 << 16);
        self.bias_q16 = bias_q16;
        self.lowpass = LowpassState::settled_q16(bias_q16);
        self.last = AdcCode(crate::math::round_shr(bias_q16, 16) as u16);
    }

    /// The bias subtracted from every sample [Q16 counts].
    pub const fn bias_q16(&self) -> i64 {
        self.bias_q16
    }

    /// The double integrator's state (velocity and position since the last read-out).
    pub const fn integrator(&self) -> &IntegratorState {
        &self.integrator
    }

    /// Stops the motion (zero velocity and undelivered position); bias and filter are kept.
    pub fn stop(&mut self) {
        self.integrator.reset();
    }

    /// Processes one sample: [`Self::filter`] then [`Self::integrate`].
    #[inline]
    pub fn update(&mut self, settings: &Settings, x: AdcCode) {
        let y = self.filter(settings, x);
        self.integrate(settings, y);
    }

    /// The first half of [`Self::update`]: records the code and returns it filtered (or
    /// as is), in Q16 counts.
    #[inline]
    pub fn filter(&mut self, settings: &Settings, x: AdcCode) -> i64 {
        self.last = x;
        match settings.lowpass() {
            Some(lp) => lp.process(&mut self.lowpass, x),
            None => i64::from(x.0) << 16,
        }
    }

    /// The second half of [`Self::update`]: integrates a filtered sample `y` (Q16 counts)
    /// minus the bias.
    #[inline]
    pub fn integrate(&mut self, settings: &Settings, y: i64) {
        settings
            .scheme()
            .step(&mut self.integrator, y - self.bias_q16);
    }

    /// Integrates a whole block of filtered samples minus the bias, exactly as
    /// [`Self::integrate`] on each (see [`crate::Scheme::step_block`]).
    pub fn integrate_block(&mut self, settings: &Settings, b: &crate::integrator::BlockSums) {
        settings
            .scheme()
            .step_block(&mut self.integrator, b, self.bias_q16);
    }

    /// Primes the trapezoid with the filtered sample `y` (Q16 counts) before the next one,
    /// as if it had been integrated; the Euler scheme ignores it.
    pub fn prime(&mut self, y: i64) {
        self.integrator.prime(y - self.bias_q16);
    }

    /// Zero-velocity update (see [`IntegratorState::zero_velocity`]).
    pub fn zero_velocity(&mut self) {
        self.integrator.zero_velocity();
    }

    /// Moves the bias (Q16 counts, clamped to the codes' range) without touching the filter:
    /// bias tracking at rest.
    pub fn track_bias_q16(&mut self, bias_q16: i64) {
        self.bias_q16 = bias_q16.clamp(0, 65_535 << 16);
    }

    /// The last code processed.
    pub const fn last_code(&self) -> AdcCode {
        self.last
    }

    /// Drains the position accumulated since the last call into whole mouse counts, carrying
    /// the remainder.
    pub fn take_counts(&mut self, settings: &Settings) -> i32 {
        let z = self.integrator.take_position();
        settings.readout().take(&mut self.readout, z)
    }
}
