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
    /// Whether the last read-out left its carry outside the usual range
    /// ([`crate::Readout::is_idle`] false), so that a read-out of nothing may still return
    /// counts. Decided once a read-out, for the settings it was read with (an axis serves one
    /// [`Settings`]: the tracker starts new axes when it is reconfigured), not on every poll
    /// at rest (128-bit arithmetic, about 24 instructions an axis on the Cortex-M4). A new
    /// axis's carry is 0, which every read-out leaves as it is.
    carry_busy: bool,
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

    /// Processes a block of samples exactly as [`Self::update`] on each, in one pass where
    /// it can: with the Euler scheme (the default) each sample only adds to two `i64` sums
    /// (`a = sum c`, `b = sum of its prefix sums`), and the integrator takes the block at
    /// once ([`IntegratorState::euler_block`]); the filter's state is a local. With
    /// the trapezoid, a velocity near saturation (`|W| >= 2^62`) or a block longer than
    /// `2^14`, it calls [`Self::update`] on each sample.
    ///
    /// # Ranges
    /// `|c| = |y - bias| < 2^32` for 16-bit codes in Q16 and `n <= 2^14`: `|a| < 2^46`,
    /// `|b| < 2^59`, exact in `i64`.
    pub fn update_block<I>(&mut self, settings: &Settings, codes: I)
    where
        I: ExactSizeIterator<Item = AdcCode>,
    {
        let n = codes.len();
        let euler = settings.scheme() == crate::Scheme::Euler;
        if euler
            && (1..=1 << 14).contains(&n)
            && self.integrator.velocity().unsigned_abs() < 1 << 62
        {
            self.euler_pass(settings.lowpass(), codes);
        } else {
            self.update_each(settings, codes);
        }
    }

    /// [`Self::update_block`]'s one pass: `1 <= n <= 2^14` samples, Euler, `|W| < 2^62`, so
    /// no step of the block would saturate and the integrator takes it whole.
    #[inline]
    fn euler_pass<I: ExactSizeIterator<Item = AdcCode>>(
        &mut self,
        lowpass: Option<&crate::Lowpass>,
        codes: I,
    ) {
        let n = codes.len() as u32;
        let bias = self.bias_q16;
        let (mut a, mut b) = (0i64, 0i64);
        let mut last = self.last;
        if let Some(lp) = lowpass {
            let mut state = self.lowpass;
            for x in codes {
                a += lp.process(&mut state, x) - bias;
                b += a;
                last = x;
            }
            self.lowpass = state;
        } else {
            for x in codes {
                a += (i64::from(x.0) << 16) - bias;
                b += a;
                last = x;
            }
        }
        self.last = last;
        self.integrator.euler_block(n, a, b);
    }

    /// [`Self::update`] on each sample: the trapezoid, and the cases the one pass does not
    /// serve.
    #[cold]
    #[inline(never)]
    fn update_each<I: Iterator<Item = AdcCode>>(&mut self, settings: &Settings, codes: I) {
        codes.for_each(|x| self.update(settings, x));
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

    /// Replaces the integrator's state (a motion integrated elsewhere, against this axis's
    /// new zero); bias, filter and read-out are kept.
    pub fn set_integrator(&mut self, state: IntegratorState) {
        self.integrator = state;
    }

    /// Moves the position not yet read out by `dz` (`Z = 4 S` units, see
    /// [`IntegratorState::correct`]).
    pub fn correct(&mut self, dz: i128) {
        self.integrator.correct(dz);
    }

    /// Sets the velocity (`W = 2 V`, Q16 counts times samples) at the start of a motion
    /// that carries one on; position, bias and filter are kept.
    pub fn set_velocity(&mut self, w: i64) {
        self.integrator.set_velocity(w);
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

    /// Whether [`Self::take_counts`] would return 0 and change nothing: no position since
    /// the last read-out, and a carry that read-out left in its usual range
    /// ([`crate::Readout::is_idle`], with the settings it was read with) or none yet.
    #[inline]
    pub fn is_idle(&self) -> bool {
        self.integrator.position() == 0 && !self.carry_busy
    }

    /// Drains the position accumulated since the last call into whole mouse counts, carrying
    /// the remainder.
    pub fn take_counts(&mut self, settings: &Settings) -> i32 {
        let z = self.integrator.take_position();
        let (n, idle) = settings.readout().take_and_idle(&mut self.readout, z);
        self.carry_busy = !idle;
        n
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Config;

    /// The default settings with drift control off: the axis alone.
    fn without_drift() -> Settings {
        Config {
            drift: None,
            ..Config::default()
        }
        .validate()
        .expect("valid")
    }

    #[test]
    fn an_axis_is_idle_until_it_moves_and_again_once_read() {
        let settings = without_drift();
        let mut axis = Axis::new(2048 << 16);
        assert!(axis.is_idle());
        axis.update(&settings, AdcCode(2060));
        assert!(!axis.is_idle());
        let _ = axis.take_counts(&settings);
        assert!(
            axis.is_idle(),
            "drained: nothing to read until the next sample"
        );
    }

    #[test]
    fn idle_after_a_read_out_is_the_read_outs_own_idle_test() {
        // Positions from one sample to past what a read-out can return at once (the carry
        // then holds the clamped excess): after each read-out the axis is idle exactly when
        // the read-out calls its carry idle, and then reading nothing returns 0 and changes
        // nothing.
        let settings = without_drift();
        let readout = settings.readout();
        let (mut idle, mut busy) = (0, 0);
        // The last: full scale for 2000 s (6 M samples at 3 kHz) moves 1e8 m, past the
        // 2^31 counts a read-out returns at most.
        for (code, samples) in [
            (2049u16, 2000),
            (2060, 2000),
            (3000, 2000),
            (65_535, 6_000_000),
        ] {
            let mut axis = Axis::new(2048 << 16);
            for _ in 0..samples {
                axis.update(&settings, AdcCode(code));
            }
            for _ in 0..3 {
                let _ = axis.take_counts(&settings);
                assert_eq!(
                    axis.is_idle(),
                    readout.is_idle(&axis.readout),
                    "code {code}"
                );
                if axis.is_idle() {
                    let before = axis;
                    assert_eq!(axis.take_counts(&settings), 0);
                    assert_eq!(
                        axis, before,
                        "code {code}: a read-out of nothing changed it"
                    );
                    idle += 1;
                } else {
                    busy += 1;
                }
            }
        }
        assert!(idle > 0 && busy > 0, "{idle} idle, {busy} busy");
    }

    #[test]
    fn a_block_near_saturation_is_taken_sample_by_sample() {
        // A velocity just below the limit, a block that rails up then down: per sample the
        // velocity saturates at the first step and comes back down; summed over the block
        // it would not have moved. The block must do what the samples do.
        let settings = Config {
            drift: None,
            lowpass_fc_hz: None,
            ..Config::default()
        }
        .validate()
        .expect("valid");
        let codes = [65_535u16, 65_535, 0, 0].map(AdcCode);
        for w in [i64::MAX - 10, (1 << 62) - 1, 1 << 62, i64::MIN + 10] {
            let mut by_sample = Axis::new(32_768 << 16);
            by_sample.integrator = IntegratorState::with_velocity(w);
            let mut by_block = by_sample;
            codes.iter().for_each(|&x| by_sample.update(&settings, x));
            by_block.update_block(&settings, codes.iter().copied());
            assert_eq!(by_block, by_sample, "W = {w}");
        }
    }

    #[test]
    fn a_motion_integrated_elsewhere_and_a_carried_velocity_replace_only_the_integrator() {
        // Drift control replays a motion's onset against a new zero and hands the axis the
        // result, or starts a motion with the velocity a glide carried: the integrator is
        // replaced, the bias and the filter stay.
        let settings = Config::default().validate().expect("valid");
        let mut axis = Axis::new(2048 << 16);
        for x in [2050, 2047, 2049] {
            axis.update(&settings, AdcCode(x));
        }
        let (bias, last) = (axis.bias_q16(), axis.last_code());
        let state = IntegratorState::with_velocity(12_345 << 16);
        axis.set_integrator(state);
        assert_eq!(*axis.integrator(), state);
        assert_eq!((axis.bias_q16(), axis.last_code()), (bias, last));
        axis.set_velocity(-(7 << 16));
        assert_eq!(axis.integrator().velocity(), -(7 << 16));
        assert_eq!(axis.integrator().position(), state.position());
        assert_eq!((axis.bias_q16(), axis.last_code()), (bias, last));
    }
}
