//! Read-out of the integrator's position into whole mouse counts, with the remainder carried.
//!
//! # Design
//! One integrator position unit is `K` mouse counts,
//! `K = LSB * cpi / (0.0254 * 4 * 2^16 * fs^2)` (see [`crate::integrator`] for the units of
//! `Z`). `K` is held as `M / 2^P` with `M` normalised to `[2^31, 2^32)`, so the only scale
//! error is `M`'s rounding, below `2^-32` relative. Each read-out adds `Z * M` to a carry in
//! Q`P` counts, takes the nearest whole count (half up) and keeps the rest:
//!
//! ```text
//! X = carry + Z M;   n = round(X / 2^P);   carry = X - n 2^P   (|carry| <= 2^(P-1))
//! ```
//!
//! All of it is exact integer arithmetic, so the sum of every count ever taken is the true
//! displacement `sum Z * M / 2^P` rounded to the nearest count: the cursor never drifts from
//! the integrator by even one count, however often it is read. `n` is clamped to `i32`; what
//! the clamp leaves stays in the carry and comes out in later read-outs.

/// Position-to-counts scale `K = M / 2^P` (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Readout {
    mult: u32,
    shift: u32,
    /// `2^(P-1)`: the rounding offset, precomputed (a variable 128-bit shift is tens of
    /// instructions on a 32-bit core).
    half: i128,
    /// `2^P - 1`: the remainder's mask, precomputed likewise.
    mask: i128,
}

/// The carried remainder of one axis's read-out, in Q`P` counts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReadoutState {
    carry: i128,
}

impl Readout {
    /// Integrator position units per (m/s^2 per LSB) per s^2: `4 * 2^16`. Position in metres
    /// is `Z * LSB / (POSITION_UNITS_PER_LSB_S2 * fs^2)`.
    pub const POSITION_UNITS_PER_LSB_S2: f64 = 4.0 * 65_536.0;

    /// The read-out for `counts_per_unit` mouse counts per integrator position unit, or `None`
    /// unless `2^-63 <= counts_per_unit < 2^31`.
    pub fn from_ratio(counts_per_unit: f64) -> Option<Self> {
        const TWO_31: f64 = 2_147_483_648.0;
        if !(counts_per_unit >= crate::math::ldexp(1.0, -63) && counts_per_unit < TWO_31) {
            return None;
        }
        // floor(log2(ratio)) from the exponent bits (the ratio is a normal float), so that
        // m = ratio 2^shift lies in [2^31, 2^32) with shift in 1..=94.
        let exponent = ((counts_per_unit.to_bits() >> 52) & 0x7ff) as i32 - 1023;
        let mut shift = (31 - exponent) as u32;
        let m = crate::math::ldexp(counts_per_unit, 31 - exponent);
        // Rounding may reach 2^32: renormalise, and
        // refuse the one ratio (within 2^-2 of 2^31) that would then need shift 0.
        let mut mult = crate::math::round_to_u64(m);
        if mult == 1 << 32 {
            mult = 1 << 31;
            shift -= 1;
        }
        if shift == 0 {
            return None;
        }
        Some(Self {
            mult: mult as u32,
            shift,
            half: 1 << (shift - 1),
            mask: (1 << shift) - 1,
        })
    }

    /// The multiplier `M`, in `[2^31, 2^32)`.
    pub const fn mult(&self) -> u32 {
        self.mult
    }

    /// The shift `P`, in `1..=94`.
    pub const fn shift(&self) -> u32 {
        self.shift
    }

    /// The realised counts per position unit, `M / 2^P` (for host-side analysis).
    pub fn counts_per_unit(&self) -> f64 {
        crate::math::ldexp(f64::from(self.mult), -(self.shift as i32))
    }

    /// Converts the position `z` drained from an integrator into whole counts, carrying the
    /// remainder in `state`. Saturates (never wraps) if `carry + z M` leaves `i128`, which no
    /// documented run reaches.
    pub fn take(&self, state: &mut ReadoutState, z: i128) -> i32 {
        let zm = match i64::try_from(z) {
            // The usual case (a read-out every millisecond drains small positions): two
            // 32x32->64 products instead of a checked 128-bit multiply. With z = h 2^32 + l,
            // |h| < 2^31 and l < 2^32: |h M| < 2^63 and l M < 2^64, so both are exact.
            Ok(z) => {
                let hi = (z >> 32) * i64::from(self.mult);
                let lo = u64::from(z as u32) * u64::from(self.mult);
                (i128::from(hi) << 32) + i128::from(lo)
            }
            Err(_) => z.saturating_mul(i128::from(self.mult)),
        };
        // The usual case: carry and product below 2^94 in magnitude (so `u = x + 2^(P-1)`,
        // with `2^(P-1) <= 2^93`, is below 2^96: no saturation), `P > 32`, and a count that
        // fits `i32` (no clamp). Then `n = floor(u / 2^P) = floor(floor(u / 2^33) / 2^(P-33))`,
        // where `u >> 33` fits `i64` (below 2^63): a fixed 128-bit shift and a 64-bit one
        // instead of variable 128-bit shifts; and
        // `carry' = x - n 2^P = u - 2^(P-1) - (u - (u mod 2^P)) = (u & (2^P - 1)) - 2^(P-1)`.
        // The same values as the general path below.
        let below_2_94 = |v: i128| (v >> 94) == (v >> 127);
        if self.shift > 32 && below_2_94(state.carry) && below_2_94(zm) {
            let u = state.carry + zm + self.half;
            let n = ((u >> 33) as i64) >> (self.shift - 33);
            if let Ok(n) = i32::try_from(n) {
                state.carry = (u & self.mask) - self.half;
                return n;
            }
        }
        let x = state.carry.saturating_add(zm);
        let n_full = x.saturating_add(self.half) >> self.shift;
        let n = n_full.clamp(i128::from(i32::MIN), i128::from(i32::MAX));
        // |n 2^P| <= 2^125 and n has the sign of x with |n 2^P| <= |x| + 2^(P-1): exact.
        state.carry = x - (n << self.shift);
        n as i32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ratio_is_normalised() {
        let r = Readout::from_ratio(0.75).expect("in range");
        assert_eq!((r.mult(), r.shift()), (3 << 30, 32));
        assert_eq!(r.counts_per_unit(), 0.75);
        assert!(Readout::from_ratio(2_147_483_648.0).is_none());
        assert!(Readout::from_ratio(0.0).is_none());
        assert!(Readout::from_ratio(f64::NAN).is_none());
        assert!(Readout::from_ratio(crate::math::ldexp(1.0, -63)).is_some());
        // Just below 2^31 rounds up to M = 2^32 with shift 1, i.e. 2^31 with shift 0: refused.
        assert!(Readout::from_ratio(2_147_483_647.9).is_none());
        assert_eq!(
            Readout::from_ratio(2_147_483_647.0).map(|r| r.shift()),
            Some(1)
        );
        // Just below 1 rounds up to M = 2^32: renormalised to exactly 1 (2^31 / 2^31).
        let r = Readout::from_ratio(1.0 - crate::math::ldexp(1.0, -34)).expect("in range");
        assert_eq!((r.mult(), r.shift()), (1 << 31, 31));
        // Exactly a power of two, at both ends of the range.
        let r = Readout::from_ratio(1.0).expect("in range");
        assert_eq!((r.mult(), r.shift()), (1 << 31, 31));
        let r = Readout::from_ratio(crate::math::ldexp(1.0, -63)).expect("in range");
        assert_eq!((r.mult(), r.shift()), (1 << 31, 94));
    }

    #[test]
    fn remainder_is_carried_so_sums_never_drift() {
        // 1/3 count per unit: three reads of one unit give 0, 1, 0 (0.33, 0.67 -> 1, 1.0).
        let r = Readout::from_ratio(1.0 / 3.0).expect("in range");
        let mut s = ReadoutState::default();
        let got: [i32; 3] = core::array::from_fn(|_| r.take(&mut s, 1));
        assert_eq!(got, [0, 1, 0]);
        // A million reads of one unit sum to round(1e6 * M / 2^P).
        let mut total = i64::from(got.iter().sum::<i32>());
        for _ in 3..1_000_000 {
            total += i64::from(r.take(&mut s, 1));
        }
        let exact = 1_000_000 * i128::from(r.mult());
        let half = 1i128 << (r.shift() - 1);
        assert_eq!(i128::from(total), (exact + half) >> r.shift());
    }

    #[test]
    fn split_product_equals_the_128_bit_product() {
        let r = Readout::from_ratio(0.3e-9).expect("in range");
        for z in [
            0i128,
            1,
            -1,
            1 << 40,
            -(1 << 40) - 7,
            i128::from(i64::MAX),
            i128::from(i64::MIN),
            123_456_789_012_345,
        ] {
            let (mut a, mut b) = (ReadoutState::default(), ReadoutState::default());
            let got = r.take(&mut a, z);
            // The definition: carry + z M, rounded at P.
            let x = b.carry + z * i128::from(r.mult());
            let n = ((x + (1 << (r.shift() - 1))) >> r.shift())
                .clamp(i128::from(i32::MIN), i128::from(i32::MAX));
            b.carry = x - (n << r.shift());
            assert_eq!((got, a), (n as i32, b), "z = {z}");
        }
    }

    #[test]
    fn a_position_beyond_the_product_range_saturates_by_its_sign() {
        // |z M| beyond i128 (z near 2^126): the largest count of the right sign, never a
        // wrap to the other side of the screen.
        let r = Readout::from_ratio(1.0).expect("in range");
        for (z, n) in [(i128::MAX / 2, i32::MAX), (i128::MIN / 2, i32::MIN)] {
            let mut s = ReadoutState::default();
            assert_eq!(r.take(&mut s, z), n);
        }
    }

    #[test]
    fn clamped_counts_stay_in_the_carry() {
        let r = Readout::from_ratio(1.0).expect("in range");
        let mut s = ReadoutState::default();
        let big = 3 * i128::from(i32::MAX);
        assert_eq!(r.take(&mut s, big), i32::MAX);
        assert_eq!(r.take(&mut s, 0), i32::MAX);
        assert_eq!(r.take(&mut s, 0), i32::MAX);
        assert_eq!(r.take(&mut s, 0), 0);
    }

    /// The definition, in plain saturating 128-bit arithmetic: what `take` must compute.
    fn reference(r: &Readout, carry: i128, z: i128) -> (i32, i128) {
        let x = carry.saturating_add(z.saturating_mul(i128::from(r.mult())));
        let n = (x.saturating_add(1 << (r.shift() - 1)) >> r.shift())
            .clamp(i128::from(i32::MIN), i128::from(i32::MAX));
        (n as i32, x - (n << r.shift()))
    }

    /// The benchmark trace's SplitMix64, with wide signed draws.
    struct Rng(crate::bench::testsignal::Trace);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0.next_u64()
        }
        /// A signed value of about `bits` bits (`0..=126`).
        fn wide(&mut self, bits: u32) -> i128 {
            let m = (i128::from(self.next() >> 1) << 64 | i128::from(self.next()))
                >> (126 - bits.min(126));
            if self.next() & 1 == 0 {
                m
            } else {
                -m
            }
        }
    }

    #[test]
    fn every_path_equals_the_definition_at_every_shift() {
        // Shifts from 1 to 94 (both sides of the fast path's P > 32), carries and positions
        // of every magnitude (both sides of its 2^94 bound), counts in and beyond i32.
        let mut rng = Rng(crate::bench::testsignal::Trace::new(0x5EED));
        let (mut fast, mut slow) = (0, 0);
        for i in 0..200_000u32 {
            let mantissa = 1.0 + (rng.next() % 1000) as f64 / 1000.0;
            let exponent = (rng.next() % 94) as i32 - 63;
            let Some(r) = Readout::from_ratio(crate::math::ldexp(mantissa, exponent)) else {
                continue;
            };
            let carry_bits = if i % 4 == 0 {
                (rng.next() % 127) as u32
            } else {
                r.shift() - 1
            };
            let carry = rng.wide(carry_bits);
            let z_bits = (rng.next() % 100) as u32;
            let z = rng.wide(z_bits);
            let mut st = ReadoutState { carry };
            let got = r.take(&mut st, z);
            let want = reference(&r, carry, z);
            assert_eq!((got, st.carry), want, "P {} carry {carry} z {z}", r.shift());
            let small = |v: i128| (v >> 94) == (v >> 127);
            let zm = z.saturating_mul(i128::from(r.mult()));
            let fits = |v: i128| (i128::from(i32::MIN)..=i128::from(i32::MAX)).contains(&v);
            if r.shift() > 32
                && small(carry)
                && small(zm)
                && fits((carry + zm + (1 << (r.shift() - 1))) >> r.shift())
            {
                fast += 1;
            } else {
                slow += 1;
            }
        }
        // Both paths ran many times.
        assert!(fast > 10_000 && slow > 10_000, "{fast} fast, {slow} slow");
    }

    #[test]
    fn the_fast_path_bounds_hold_at_their_edges() {
        // P = 33 (the fast path's smallest shift) and P = 32 (the general path's largest),
        // with carries and products just inside and outside 2^94.
        for shift_ratio in [-2, -1, 0, 1] {
            let r = Readout::from_ratio(crate::math::ldexp(1.5, shift_ratio)).expect("in range");
            for carry in [
                (1i128 << 94) - 1,
                -(1i128 << 94),
                1i128 << 94,
                -(1i128 << 94) - 1,
                0,
            ] {
                for z in [0i128, 1, -1, 1 << 62, -(1 << 62), i128::from(i64::MAX)] {
                    let mut st = ReadoutState { carry };
                    let got = r.take(&mut st, z);
                    assert_eq!((got, st.carry), reference(&r, carry, z), "P {}", r.shift());
                }
            }
        }
    }
}
