//! Exact double integration of integer samples (REFERENCE (g), architecture A).
//!
//! # Design
//! Input: `c[n]`, bias-free acceleration in Q16 counts (`i64`, `|c| <= 65535 * 2^16`).
//! The integrator keeps twice the velocity and four times the position, so that both schemes
//! are exact integer recursions with no division:
//!
//! ```text
//! Euler      W[n] = W[n-1] + 2 c[n]               Z[n] = Z[n-1] + 2 W[n]
//! Trapezoid  W[n] = W[n-1] + c[n-1] + c[n]        Z[n] = Z[n-1] + W[n-1] + W[n]
//! ```
//!
//! `W = 2 V` and `Z = 4 S`, where `V = sum c` and `S = sum V` are REFERENCE (c)'s velocity and
//! position times `fs` and `fs^2`. In SI units:
//! `v = W * LSB / (2 * 2^16 * fs)` [m/s] and `s = Z * LSB / (4 * 2^16 * fs^2)` [m], with
//! `LSB` in m/s^2 ([`crate::Settings::metres_per_position_unit`]).
//!
//! Euler integrates samples `c[1..N]` (every sample is a step); the trapezoid integrates
//! `c[0..N]`, so its first sample only primes `c[-1]` and each later sample is a step.
//! Integer sums are exact: the integrator adds no error at all.
//!
//! # Ranges
//! `W` is `i64`, `Z` is `i128`, both saturating (a wrap would be a cursor jump to the other
//! side of the screen). With a full-scale 12-bit input held constant (`|c| < 2^28`), `W`
//! stays below `2^29 N` and `Z` below `2^29 N^2`: at 100 kHz for 24 h (`N = 8.64e9`) that is
//! `2^62.0` and `2^95.1`, so nothing saturates in any documented run. 16-bit codes at full
//! scale (`|c| < 2^32`) reach the `i64` limit of `W` after `N = 2^30` samples.

/// Double-integration scheme.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Scheme {
    /// Rectangle rule on both stages, REFERENCE (c)(i): `v += a/fs`, `s += v/fs`.
    #[default]
    Euler,
    /// Trapezoid rule on both stages, REFERENCE (c)(ii): exact for a constant bias.
    Trapezoid,
}

/// State of the double integrator of one axis.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct IntegratorState {
    w: i64,
    z: i128,
    prev: i64,
    primed: bool,
}

impl IntegratorState {
    /// Twice the velocity, `W = 2 V`, in Q16 counts times samples.
    pub const fn velocity(&self) -> i64 {
        self.w
    }

    /// Four times the position, `Z = 4 S`, in Q16 counts times samples squared, since the last
    /// drain ([`Self::take_position`]).
    pub const fn position(&self) -> i128 {
        self.z
    }

    /// Returns the position accumulated since the last call and clears it. Velocity is kept,
    /// so the motion carries on; the caller moves the position into a read-out.
    #[inline]
    pub fn take_position(&mut self) -> i128 {
        core::mem::take(&mut self.z)
    }

    /// Zero-velocity update: velocity to zero (the trapezoid waits for a new first sample);
    /// the position not yet drained is kept, so nothing already moved is lost.
    pub fn zero_velocity(&mut self) {
        self.w = 0;
        self.primed = false;
    }

    /// Stops the motion: zero velocity and position, and the trapezoid waits for a new first
    /// sample.
    pub fn reset(&mut self) {
        *self = Self::default();
    }
}

impl Scheme {
    /// Integrates one sample `c` (Q16 counts).
    #[inline]
    pub fn step(self, state: &mut IntegratorState, c: i64) {
        match self {
            Self::Euler => {
                state.w = state.w.saturating_add(2 * c);
                state.z = state.z.saturating_add(2 * i128::from(state.w));
            }
            Self::Trapezoid => {
                if state.primed {
                    let w = state.w.saturating_add(state.prev + c);
                    state.z = state.z.saturating_add(i128::from(state.w) + i128::from(w));
                    state.w = w;
                } else {
                    state.primed = true;
                }
                state.prev = c;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn euler_constant_is_n_n_plus_one_over_two() {
        let mut s = IntegratorState::default();
        for _ in 0..10 {
            Scheme::Euler.step(&mut s, 3);
        }
        assert_eq!(s.velocity(), 2 * 3 * 10);
        assert_eq!(s.position(), 4 * 3 * 10 * 11 / 2);
    }

    #[test]
    fn trapezoid_constant_is_exactly_n_squared_over_two() {
        let mut s = IntegratorState::default();
        for _ in 0..=10 {
            Scheme::Trapezoid.step(&mut s, 3); // 11 samples = 10 steps
        }
        assert_eq!(s.velocity(), 2 * 3 * 10);
        assert_eq!(s.position(), 4 * 3 * 100 / 2);
    }

    #[test]
    fn take_position_drains_and_keeps_velocity() {
        let mut s = IntegratorState::default();
        Scheme::Euler.step(&mut s, 1);
        Scheme::Euler.step(&mut s, 1);
        assert_eq!(s.take_position(), 2 * (2 + 4));
        assert_eq!(s.position(), 0);
        assert_eq!(s.velocity(), 4);
    }

    #[test]
    fn saturates_instead_of_wrapping() {
        let mut s = IntegratorState {
            w: i64::MAX - 1,
            z: i128::MAX - 1,
            ..Default::default()
        };
        Scheme::Euler.step(&mut s, 1 << 32);
        assert_eq!((s.velocity(), s.position()), (i64::MAX, i128::MAX));
        let mut s = IntegratorState {
            w: i64::MIN + 1,
            z: i128::MIN + 1,
            ..Default::default()
        };
        Scheme::Euler.step(&mut s, -(1 << 32));
        assert_eq!((s.velocity(), s.position()), (i64::MIN, i128::MIN));
    }
}
