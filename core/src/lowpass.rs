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
//! - state: `y` in Q32 counts (`i64`, `0..=65535 * 2^32`) plus a remainder `r` that holds the
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
    ///
    /// The Q64 update `p = k (x 2^32 - y^) + r` is computed in 64-bit pieces (a Cortex-M4
    /// has 32x32->64 multiplies but no 64x64->128): with `y^ = hi 2^32 + lo`,
    /// `p = (x - hi) k 2^32 - lo k + r`, where `|(x - hi) k| < 2^48` and `lo k < 2^64`. The
    /// result is identical to the 128-bit product (tested against it).
    #[inline]
    pub fn process(&self, state: &mut LowpassState, x: AdcCode) -> i64 {
        let yh = state.y_q32();
        let hi = (yh >> 32) as i32; // 0..=65536
        let lo = yh as u32;
        let a = i64::from(i32::from(x.0) - hi) * i64::from(self.k_q32);
        let b = u64::from(lo) * u64::from(self.k_q32);
        // p = (a - b_hi) 2^32 + t, t = r - b_lo in (-2^32, 2^32): floor(t / 2^32) is t >> 32.
        let t = i64::from(state.r) - i64::from(b as u32);
        state.y += a - (b >> 32) as i64 + (t >> 32);
        state.r = t as u32;
        // Round half up to Q16; |y^| < 2^49, so the addition cannot overflow.
        (state.y_q32() + (1 << 15)) >> 16
    }
}

/// State of one [`Lowpass`]: the output in Q32 counts with a 32-bit remainder below it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LowpassState {
    y: i64,
    r: u32,
}

impl LowpassState {
    /// A state settled at `value_q16` (Q16 counts, `0..=65535 * 2^16`), e.g. the calibrated
    /// bias, so that the filter starts without a transient.
    pub const fn settled_q16(value_q16: i64) -> Self {
        Self {
            y: value_q16 << 16,
            r: 0,
        }
    }

    /// The state rounded half-up to Q32 counts.
    #[inline(always)]
    pub const fn y_q32(&self) -> i64 {
        self.y + (self.r >> 31) as i64
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

    /// The update as one 128-bit product: the definition the 64-bit pieces must match.
    fn reference(lp: &Lowpass, st: &mut LowpassState, x: u16) -> i64 {
        let e = (i64::from(x) << 32) - st.y_q32();
        let p = i128::from(e) * i128::from(lp.k_q32) + i128::from(st.r);
        st.y += (p >> 32) as i64;
        st.r = p as u32;
        math::round_shr(st.y_q32(), 16)
    }

    #[test]
    fn sixty_four_bit_pieces_equal_the_128_bit_product() {
        let mut g: u64 = 1;
        let mut next = || {
            g ^= g << 13;
            g ^= g >> 7;
            g ^= g << 17;
            g
        };
        for k in [1u32, 26_986, 1 << 31, 0xFFFF_FFFF, 0x9E37_79B9] {
            let lp = Lowpass::from_k_q32(k);
            let (mut a, mut b) = (LowpassState::settled_q16(0), LowpassState::settled_q16(0));
            for _ in 0..200_000 {
                let x = match next() % 4 {
                    0 => 0,
                    1 => 65_535,
                    _ => (next() % 65_536) as u16,
                };
                assert_eq!(lp.process(&mut a, AdcCode(x)), reference(&lp, &mut b, x));
                assert_eq!(a, b);
            }
        }
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
