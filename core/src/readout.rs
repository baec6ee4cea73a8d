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
//!
//! # Cost on a 32-bit core
//! The definition is 128-bit arithmetic with shifts by a variable `P`: about 125
//! instructions on a Cortex-M4. The read-outs a device makes (`33 <= P <= 93`, a position
//! below `2^62` and a carry below `2^93` in magnitude, a count that fits `i32`; every rate and
//! scale the configuration accepts gives `P` in 34..=81) take a path of 64-bit pieces
//! instead ([`Readout::take`] shows why it is the same arithmetic); the rest take the
//! definition.

/// Position-to-counts scale `K = M / 2^P` (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Readout {
    mult: u32,
    shift: u32,
    /// Whether `33 <= P <= 93`, the shifts the 64-bit pieces serve (otherwise every
    /// read-out takes the definition).
    split: bool,
    /// `P - 32`, the shift of the carry's upper part (0 unless `split`).
    shift_hi: u32,
    /// `2^(P-33)`: the rounding offset `2^(P-1)` over `2^32` (0 unless `split`).
    half_hi: i64,
    /// `2^(P-32) - 1`: the mask of the upper part of a remainder below `2^P`.
    mask_hi: i64,
    /// `2^(P-1)` and `2^P` when `split`, else 0 and 0: a carry `c` is idle when `c + 2^(P-1)`
    /// lies in `[0, 2^P)` ([`Self::is_idle`]).
    idle_half: i128,
    idle_span: u128,
}

/// Whether `-2^bits <= v < 2^bits`: the bounds of the read-out's 64-bit pieces.
#[inline(always)]
fn below(v: i128, bits: u32) -> bool {
    (v >> bits) == (v >> 127)
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
        let split = (33..=93).contains(&shift);
        let shift_hi = if split { shift - 32 } else { 0 };
        Some(Self {
            mult: mult as u32,
            shift,
            split,
            shift_hi,
            half_hi: if split { 1 << (shift_hi - 1) } else { 0 },
            mask_hi: (1 << shift_hi) - 1,
            idle_half: if split { 1 << (shift - 1) } else { 0 },
            idle_span: if split { 1 << shift } else { 0 },
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
    ///
    /// The usual read-out, with `33 <= P <= 93`, `|z| < 2^62` and `|carry| < 2^93`, is
    /// computed in 64-bit pieces. Split `z = h 2^32 + l` (`|h| <= 2^30`, `l < 2^32`) and the
    /// carry `c = c_hi 2^32 + c_lo` (`c_lo < 2^32`). Then
    /// `u = c + z M + 2^(P-1) = u_hi 2^32 + u_lo` with
    ///
    /// ```text
    /// a = l M (< 2^64),  u_lo = (c_lo + a) mod 2^32,
    /// u_hi = c_hi + h M + floor((c_lo + a) / 2^32) + 2^(P-33)
    /// ```
    ///
    /// where `|c_hi| <= 2^61`, `|h M| < 2^62` and the other two terms are below `2^61`, so
    /// `u_hi` is exact in `i64`. The count is `n = floor(u / 2^P) = u_hi >> (P - 32)` and the
    /// new carry `u mod 2^P - 2^(P-1) = ((u_hi & (2^(P-32) - 1)) - 2^(P-33)) 2^32 + u_lo`:
    /// one 64-bit variable shift where the definition needs several 128-bit ones. If `n`
    /// does not fit `i32` (the clamp), the definition takes over. Tested against the
    /// definition on both sides of every bound.
    #[inline]
    pub fn take(&self, state: &mut ReadoutState, z: i128) -> i32 {
        self.take_and_idle(state, z).0
    }

    /// [`Self::take`], and whether the carry it leaves is idle ([`Self::is_idle`]): by
    /// construction on the 64-bit pieces' path (its new carry is `u mod 2^P - 2^(P-1)`, in
    /// the usual range), tested only after the definition's (a clamp may leave more).
    #[inline]
    pub fn take_and_idle(&self, state: &mut ReadoutState, z: i128) -> (i32, bool) {
        if self.split && below(z, 62) && below(state.carry, 93) {
            let c = state.carry;
            let m = u64::from(self.mult);
            let a = u64::from(z as u32) * m;
            let (lo, over) = (c as u32).overflowing_add(a as u32);
            // h = z >> 32 fits i32 (|z| < 2^62).
            let u_hi = (c >> 32) as i64
                + i64::from((z >> 32) as i32) * m as i64
                + (a >> 32) as i64
                + i64::from(over)
                + self.half_hi;
            if let Ok(n) = i32::try_from(u_hi >> self.shift_hi) {
                let hi = (u_hi & self.mask_hi) - self.half_hi;
                state.carry = (i128::from(hi) << 32) + i128::from(lo);
                return (n, true);
            }
        }
        self.take_exactly_and_idle(state, z)
    }

    /// The definition's path of [`Self::take_and_idle`], out of line with its idle test.
    #[cold]
    #[inline(never)]
    fn take_exactly_and_idle(&self, state: &mut ReadoutState, z: i128) -> (i32, bool) {
        let n = self.take_exactly(state, z);
        (n, self.is_idle(state))
    }

    /// Whether a read-out of nothing (`z = 0`) would return 0 and leave the carry as it is:
    /// true for a carry in its usual range `[-2^(P-1), 2^(P-1))` (`33 <= P <= 93`), false
    /// after a clamp left more in it, and for the shifts the 64-bit pieces do not serve. A
    /// device at rest asks this instead of reading out (about a fifth of the cost).
    #[inline]
    pub fn is_idle(&self, state: &ReadoutState) -> bool {
        // As in `take` with z = 0: u_hi = c_hi + 2^(P-33), and the count u_hi >> (P - 32) is 0
        // exactly when -2^(P-1) <= c < 2^(P-1) (which also keeps c below 2^93): one add and
        // one compare, no variable 128-bit shift. A carry that wraps in the add is far
        // outside and lands at or above 2^127. Never idle unless `split` (the span is 0).
        (state.carry.wrapping_add(self.idle_half) as u128) < self.idle_span
    }

    /// [`Self::take`] by its definition, in saturating 128-bit arithmetic.
    #[cold]
    #[inline(never)]
    fn take_exactly(&self, state: &mut ReadoutState, z: i128) -> i32 {
        let zm = z.saturating_mul(i128::from(self.mult));
        let x = state.carry.saturating_add(zm);
        let n_full = x.saturating_add(1 << (self.shift - 1)) >> self.shift;
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
            let (got, idle) = r.take_and_idle(&mut st, z);
            let want = reference(&r, carry, z);
            assert_eq!((got, st.carry), want, "P {} carry {carry} z {z}", r.shift());
            // The idle flag a read-out returns is the idle test on the carry it left.
            assert_eq!(idle, r.is_idle(&st), "P {} carry {carry} z {z}", r.shift());
            let zm = z.saturating_mul(i128::from(r.mult()));
            let fits = |v: i128| (i128::from(i32::MIN)..=i128::from(i32::MAX)).contains(&v);
            if (33..=93).contains(&r.shift())
                && below(carry, 93)
                && below(z, 62)
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
    fn idle_means_a_zero_read_out_changes_nothing() {
        // Carries inside, at and beyond the usual range, at shifts inside and outside the
        // 64-bit pieces' 33..=93: idle exactly when reading out nothing gives 0 and keeps
        // the carry.
        let mut rng = Rng(crate::bench::testsignal::Trace::new(0x1D1E));
        let (mut idle, mut busy) = (0, 0);
        let mut shifts = [false; 96];
        for exponent in [-1, -2, -3, -30, -32, -33, -34, -35, -62, -63] {
            let r = Readout::from_ratio(crate::math::ldexp(1.5, exponent)).expect("in range");
            shifts[r.shift() as usize] = true;
            let half = 1i128 << (r.shift() - 1);
            let edges = [
                0,
                half - 1,
                -half,
                half,
                -half - 1,
                1 << 93,
                1 << 100,
                -(1 << 100),
                i128::MAX,
                i128::MIN,
                i128::MAX - half + 1,
                1 << 64,
                (1 << 64) - 1,
                -(1 << 64),
                -(1 << 64) - 1,
                1 - half,
            ];
            for i in 0..2000 + edges.len() {
                let carry = match edges.get(i) {
                    Some(&c) => c,
                    None => {
                        let bits = (rng.next() % 100) as u32;
                        rng.wide(bits)
                    }
                };
                let st = ReadoutState { carry };
                let mut read = st;
                let unchanged = r.take(&mut read, 0) == 0 && read == st;
                if r.is_idle(&st) {
                    assert!(unchanged, "P {} carry {carry}", r.shift());
                    idle += 1;
                } else {
                    // Not idle: either a zero read-out gives something, or P is outside
                    // 33..=93 (where idle is never claimed).
                    assert!(
                        !unchanged || !(33..=93).contains(&r.shift()),
                        "P {} carry {carry}",
                        r.shift()
                    );
                    busy += 1;
                }
            }
        }
        assert!(idle > 1000 && busy > 1000, "{idle} idle, {busy} busy");
        // Shifts at both ends of 33..=93, outside it, and about 64 (the carry's halves).
        for p in [32, 33, 34, 61, 63, 64, 65, 66, 93, 94] {
            assert!(shifts[p], "P {p} not covered");
        }
    }

    #[test]
    fn the_fast_path_bounds_hold_at_their_edges() {
        // P = 32 and 33 (below and at the fast path's smallest shift), P = 93 and 94 (at and
        // beyond its largest), with carries just inside and outside 2^93, positions just
        // inside and outside 2^62, and counts at and beyond the ends of i32.
        for exponent in [-2, -1, -62, -63] {
            let r = Readout::from_ratio(crate::math::ldexp(1.5, exponent)).expect("in range");
            for carry in [
                (1i128 << 93) - 1,
                -(1i128 << 93),
                1i128 << 93,
                -(1i128 << 93) - 1,
                (1i128 << (r.shift() - 1)) - 1,
                -(1i128 << (r.shift() - 1)),
                0,
                1 << 100,
                -(1 << 97),
            ] {
                // Positions and carries far beyond the bounds whose low bits are all zero:
                // a bound tested on the wrong bits would let them in.
                for z in [
                    0i128,
                    1,
                    -1,
                    1 << 66,
                    -(1 << 100),
                    (1 << 62) - 1,
                    -(1 << 62),
                    1 << 62,
                    -(1 << 62) - 1,
                    i128::from(i32::MAX) << r.shift().saturating_sub(31).min(60),
                    i128::from(i32::MIN) << r.shift().saturating_sub(31).min(60),
                ] {
                    let mut st = ReadoutState { carry };
                    let got = r.take(&mut st, z);
                    let want = reference(&r, carry, z);
                    assert_eq!((got, st.carry), want, "P {} carry {carry} z {z}", r.shift());
                }
            }
        }
    }
}
