//! The estimator: when a motion ends.
//!
//! A motion is integrated from its onset (where the start test says its run began, at zero
//! velocity, [`super::rest`]), every sample, exactly. It ends when two things hold on both
//! horizontal axes at a tick's end:
//!
//! - **quiet**: the last 20 ms of raw ticks have a mean within `K_QUIET` sd of the zero, plus
//!   what the measured disturbance can put into a 20 ms mean (`G_quiet A` per tick,
//!   [`super::noise`]). 20 ms is the stop latency this test costs (a stroke's deceleration
//!   tapers to zero at its end); a hand's deceleration is not over while it fails;
//! - **the velocity explained**: the integrated velocity `V` within `K_VELOCITY` of its own
//!   sd, `sd(V)^2 = q n + q n^2 / N_b` (`n` samples since the onset, the zero averaged over
//!   `N_b` samples; REFERENCE (i)), plus twice the velocity amplitude the disturbance
//!   measured now could give (a vibration's velocity at the onset's arbitrary phase: `A fs /
//!   (2 pi f D)` at `f >= knock_hz`).
//!
//! Mid-stroke the acceleration passes through zero while the hand moves fastest: the velocity
//! keeps the motion going. A drag's glide has no acceleration at all, but its velocity is
//! many sd from zero (the accelerometer saw the ramp that made it: `sd(V)` grows as
//! `sqrt(ND^2 t / 2 + sd(b)^2 t^2)`, 5 mm/s 2 s after a ramp): it goes on. A velocity that
//! no acceleration explains and that is within `K_VELOCITY` sd is stopped, however long it
//! has lasted: there is no timeout.
//!
//! # Error rates
//! `K_QUIET = 3`: a window at rest passes with probability 0.997 (a false "not quiet" only
//! delays a stop by a tick). `K_VELOCITY = 3`: the end of a stroke at rest is taken for a
//! glide with probability 0.27 % per axis; that glide then stops as `sd(V)` grows past it.

use super::click::Click;
use super::noise::within;
use super::ticks::offset;
use super::{Action, Detector, DriftSettings};

/// The quiet test's bound [sd], squared, Q8.
const K_QUIET2_Q8: u64 = 9 * 256;
/// The velocity test's bound [sd], squared, Q8.
const K_VELOCITY2_Q8: u64 = 9 * 256;

/// A motion under way.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Motion {
    /// Samples integrated since the onset.
    pub(crate) samples: u64,
}

impl Motion {
    /// A motion whose onset was `samples` samples ago.
    pub(crate) fn begin(&mut self, samples: u64) {
        self.samples = samples;
    }

    /// One more sample integrated.
    #[inline(always)]
    pub(crate) fn sample(&mut self, click: &mut Click) {
        self.samples += 1;
        click.motion_sample();
    }
}

impl Detector {
    /// Whether the last 20 ms are quiet on both horizontal axes.
    pub(crate) fn quiet(&self, s: &DriftSettings, bias: [i64; 3]) -> bool {
        let k = s.quiet_ticks;
        let w = self.stream.window(k);
        let n = u64::from(k) * u64::from(s.tick);
        (0..2).all(|a| {
            let allow = (u128::from(s.quiet_gain_q16)
                * u128::from(self.disturbance[a].amp_q16)
                * u128::from(k))
                >> 16;
            within(
                offset(w[a], n, bias[a]),
                self.noise[a].var(n, self.bias_samples),
                K_QUIET2_Q8,
                allow as u64,
            )
        })
    }

    /// Whether the velocities `W = 2 V` are explained by their uncertainty on both
    /// horizontal axes.
    pub(crate) fn velocity_explained(&self, s: &DriftSettings, velocity: [i64; 3]) -> bool {
        (0..2).all(|a| {
            let allow = (2 * u128::from(s.vib_velocity_q16)
                * u128::from(self.disturbance[a].amp_q16))
                >> 16;
            within(
                velocity[a] / 2,
                self.noise[a].var(self.motion.samples, self.bias_samples),
                K_VELOCITY2_Q8,
                allow.min(u128::from(u64::MAX)) as u64,
            )
        })
    }

    /// Decisions while moving at a tick's end: the stop, then the tilt tests.
    pub(crate) fn moving_tick(
        &mut self,
        s: &DriftSettings,
        bias: [i64; 3],
        velocity: [i64; 3],
    ) -> Action {
        if self.quiet(s, bias) && self.velocity_explained(s, velocity) {
            // A motion that ends younger than its hold was a jolt, not a stroke; a tilt
            // suspicion that ends in a stop was refuted: deliver.
            let held = self.click.hold_left > 0;
            self.enter_still();
            return if held { Action::Discard } else { Action::Stop };
        }
        if self.stream.block_closed() {
            return self.tilt_block(s, bias);
        }
        Action::None
    }
}
