//! Single-pole low-pass: the exact discretisation of the paper's filter `H = wc / (wc + j w)`.
//!
//! # Design
//! Sampling the continuous filter's impulse response gives the recursion
//! `y[n] = y[n-1] + k (x[n] - y[n-1])`, `k = 1 - q`, `q = exp(-alpha)`, `alpha = 2 pi fc / fs`
//! (REFERENCE (b): filtered white noise becomes AR(1) noise with `r[p] = r0 q^|p|`).
//!
//! Fixed point:
//! - input: an ADC code `x` [LSB], any `u16`;
//! - coefficient: `k` in Q0.32 (`k_q32 = round(k * 2^32)`, `1..=2^32-1`); the realised
//!   coefficient is `k_q32 / 2^32`, within `2^-33` of the ideal one;
//! - state: `y` in Q32 counts (`0..=65535 * 2^32`) plus a remainder `r` that holds the
//!   next 32 fractional bits, so the state is `y + r 2^-32` in Q32, i.e. 64 fractional bits.
//!
//! The update `y:r += k_q32 * (x 2^32 - y^)` is exact integer arithmetic in Q64, where
//! `y^ = y + (r >= 2^31)` is the state rounded (half up) to Q32. So the recursion is exact up
//! to using `y^` for `y`, an error in `(-2^-33, 2^-33]` LSB that is zero-mean (rounding, not
//! truncation: a floor here would be a small constant bias, and a bias is a parabola). There
//! is no dead band: with a constant input `x` the rounded state moves monotonically towards
//! `x 2^32`, never passes it, and reaches it exactly, after which every update adds zero.
//! The output is `y^` rounded half-up to Q16 counts, the integrator's input format; with a
//! settled state it equals the input exactly. Output error against the exact recursion:
//! `<= 2^-17 + 2^-32` LSB.
//!
//! # Stored form
//! [`LowpassState`] keeps `Y = y^` itself and `R = r XOR 2^31` (the remainder below the
//! rounded state, offset to be unsigned). In that form the update is
//! `Y 2^32 + R += k (x 2^32 - Y)`, with no rounding step, and it splits into unsigned
//! 32x32-bit products with `Y = H 2^32 + L` and `!k = 2^32 - 1 - k`:
//!
//! ```text
//! T  = L !k + L + R                   (< 2^64)     R' = T mod 2^32
//! Y' = H !k + H + floor(T / 2^32) + x k   (< 2^49)
//! ```
//!
//! (`L 2^32 - L k = L !k + L`, and likewise for `H`): three multiply-accumulates, no
//! signed or 128-bit arithmetic, about ten Cortex-M4 instructions a sample.

use crate::math;
use crate::AdcCode;

/// Lowest accepted cut-off as a fraction of the sampling rate, `fc / fs` (`k_q32` = 26 986
/// there).
pub const FC_OVER_FS_MIN: f64 = 1e-6;

/// Single-pole low-pass coefficient (see the module docs for the Q formats).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Lowpass {
    k_q32: u32,
}

impl Lowpass {
    /// The filter with cut-off ratio `fc / fs` in `[FC_OVER_FS_MIN, 0.5)`, or `None` outside
    /// that range (including NaN).
    pub fn from_ratio(fc_over_fs: f64) -> Option<Self> {
        if !(FC_OVER_FS_MIN..0.5).contains(&fc_over_fs) {
            return None;
        }
        let alpha = 2.0 * core::f64::consts::PI * fc_over_fs;
        let k = math::round_to_u64(math::ldexp(math::neg_expm1(alpha), 32));
        // alpha in [6.3e-6, pi): k_q32 in [26986, 0.957 * 2^32], always a valid u32.
        u32::try_from(k).ok().map(Self::from_k_q32)
    }

    /// The filter with the raw coefficient `k_q32 = (1 - exp(-alpha)) * 2^32`; `0` freezes
    /// the state.
    pub const fn from_k_q32(k_q32: u32) -> Self {
        Self { k_q32 }
    }

    /// The coefficient `k = 1 - exp(-alpha)` in Q0.32.
    pub const fn k_q32(&self) -> u32 {
        self.k_q32
    }

    /// Filters one sample and returns the output in Q16 counts (`0..=65535 * 2^16`).
    /// The arithmetic is the module docs' stored form (tested against the 128-bit product
    /// of the definition).
    #[inline]
    pub fn process(&self, state: &mut LowpassState, x: AdcCode) -> i64 {
        let k = u64::from(self.k_q32);
        let not_k = u64::from(!self.k_q32);
        let (h, l) = (state.y >> 32, state.y & 0xFFFF_FFFF); // h <= 65535
        let t = l * not_k + l + u64::from(state.r);
        state.r = t as u32;
        state.y = h * not_k + h + (t >> 32) + u64::from(x.0) * k;
        // Round half up to Q16: below 2^32 (Y <= 65535 2^32), so its low word is all of it.
        i64::from(((state.y + (1 << 15)) >> 16) as u32)
    }
}

/// State of one [`Lowpass`]: the output rounded to Q32 counts, and the 32 bits below it (in
/// the module docs' stored form).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LowpassState {
    /// `Y`, the state rounded half up to Q32 counts, `0..=65535 * 2^32`.
    y: u64,
    /// `R`, the next 32 bits, offset by `2^31`.
    r: u32,
}

impl Default for LowpassState {
    /// Settled at 0.
    fn default() -> Self {
        Self::settled_q16(0)
    }
}

impl LowpassState {
    /// A state settled at `value_q16` (Q16 counts, clamped to `0..=65535 * 2^16`, the codes'
    /// range), e.g. the calibrated bias, so that the filter starts without a transient.
    pub fn settled_q16(value_q16: i64) -> Self {
        Self {
            y: (value_q16.clamp(0, 65_535 << 16) as u64) << 16,
            r: 1 << 31,
        }
    }

    /// The state rounded half-up to Q32 counts.
    #[inline(always)]
    pub const fn y_q32(&self) -> i64 {
        self.y as i64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_ratios_outside_range() {
        for r in [0.0, 9.9e-7, 0.5, 0.7, -0.1, f64::NAN, f64::INFINITY] {
            assert!(Lowpass::from_ratio(r).is_none(), "{r}");
        }
        assert!(Lowpass::from_ratio(1e-6).is_some());
        assert!(Lowpass::from_ratio(0.499_999).is_some());
    }

    #[test]
    fn coefficient_is_exp_discretisation_rounded_to_q32() {
        // fc/fs = 1/(2 pi): alpha = 1, k = 1 - 1/e = 0.63212055882855767.
        let lp = Lowpass::from_ratio(1.0 / (2.0 * core::f64::consts::PI)).expect("in range");
        assert_eq!(lp.k_q32(), 2_714_937_127); // round(0.632120558828557 * 2^32)
    }

    /// The definition's state: `y` in Q32 counts and the remainder `r` below it.
    #[derive(Clone, Copy)]
    struct Exact {
        y: i64,
        r: u32,
    }

    impl Exact {
        fn y_hat(&self) -> i64 {
            self.y + i64::from(self.r >> 31)
        }

        /// The stored form of this state (module docs).
        fn stored(&self) -> LowpassState {
            LowpassState {
                y: self.y_hat() as u64,
                r: self.r ^ (1 << 31),
            }
        }
    }

    /// The update as one 128-bit product: the definition the stored form must match.
    fn reference(lp: &Lowpass, st: &mut Exact, x: u16) -> i64 {
        let e = (i64::from(x) << 32) - st.y_hat();
        let p = i128::from(e) * i128::from(lp.k_q32) + i128::from(st.r);
        st.y += (p >> 32) as i64;
        st.r = p as u32;
        math::round_shr(st.y_hat(), 16)
    }

    #[test]
    fn the_stored_form_equals_the_128_bit_definition() {
        let mut g: u64 = 1;
        let mut next = || {
            g ^= g << 13;
            g ^= g >> 7;
            g ^= g << 17;
            g
        };
        for k in [0u32, 1, 26_986, 1 << 31, 0xFFFF_FFFF, 0x9E37_79B9] {
            let lp = Lowpass::from_k_q32(k);
            let (mut a, mut b) = (LowpassState::settled_q16(0), Exact { y: 0, r: 0 });
            assert_eq!(a, b.stored());
            for _ in 0..200_000 {
                let x = match next() % 4 {
                    0 => 0,
                    1 => 65_535,
                    _ => (next() % 65_536) as u16,
                };
                assert_eq!(lp.process(&mut a, AdcCode(x)), reference(&lp, &mut b, x));
                assert_eq!(a, b.stored());
            }
        }
    }

    #[test]
    fn a_settled_state_is_clamped_to_the_codes_range() {
        assert_eq!(LowpassState::settled_q16(-5).y_q32(), 0);
        assert_eq!(
            LowpassState::settled_q16(70_000 << 16).y_q32(),
            65_535 << 32
        );
        assert_eq!(LowpassState::settled_q16(123 << 16).y_q32(), 123 << 32);
        assert_eq!(LowpassState::default(), LowpassState::settled_q16(0));
        // Settled at full scale, full-scale input: the output stays exactly there.
        let lp = Lowpass::from_k_q32(0xFFFF_FFFF);
        let mut s = LowpassState::settled_q16(65_535 << 16);
        assert_eq!(lp.process(&mut s, AdcCode(65_535)), 65_535 << 16);
    }

    #[test]
    fn step_response_is_monotone_and_exact() {
        let lp = Lowpass::from_ratio(0.01).expect("in range");
        let mut s = LowpassState::settled_q16(0);
        let mut last = 0;
        for _ in 0..20_000 {
            let y = lp.process(&mut s, AdcCode(4095));
            assert!(y >= last && y <= 4095 << 16);
            last = y;
        }
        assert_eq!(last, 4095 << 16);
        assert_eq!(s.y_q32(), 4095 << 32);
    }
}
