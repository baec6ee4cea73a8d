//! Small exact helpers: integer square root, rounding shifts, and the float functions that
//! configuration needs in a `no_std` crate (no `std`, no `libm`).
//!
//! Nothing here runs per sample except [`round_shr`]; drift control's ticks use the
//! divisions and roots.

/// `round(x / 2^s)`, rounding half up (towards +inf), for `s` in `1..=62`.
///
/// Arithmetic shift alone would floor, and a floor is a bias of half an output LSB, which
/// double integration turns into a parabola (REFERENCE (g)). Saturates instead of wrapping
/// when `x` is within `2^(s-1)` of `i64::MAX`.
#[inline(always)]
pub(crate) const fn round_shr(x: i64, s: u32) -> i64 {
    x.saturating_add(1 << (s - 1)) >> s
}

/// `d / n` rounded half away from zero, for `n > 0` and `|d| < 2^62`.
///
/// Drift control divides per tick by sample counts (a tick's, a window's, the zero's
/// averaging time) and mostly offsets of a few LSB: when `|d|` and `n` are below `2^29`,
/// `2 d + n` and `2 n` fit 32 bits and the Cortex-M4's one-instruction division gives the
/// same quotient as the 64-bit software routine (about 100 instructions).
#[inline]
pub(crate) fn div_round(d: i64, n: i64) -> i64 {
    const SMALL: u64 = 1 << 29;
    if d.unsigned_abs() < SMALL && n.unsigned_abs() < SMALL {
        let (d, n) = (d as i32, n as i32);
        return i64::from((2 * d + d.signum() * n) / (2 * n));
    }
    (2 * d + d.signum() * n) / (2 * n)
}

/// `floor(n / d)` for `d > 0`: in 32 bits when both fit (one instruction on the Cortex-M4
/// instead of a software routine), the same quotient.
#[inline]
pub(crate) fn div_u64(n: u64, d: u64) -> u64 {
    match (u32::try_from(n), u32::try_from(d)) {
        (Ok(n), Ok(d)) => u64::from(n / d),
        _ => n / d,
    }
}

/// Floor of the square root of `n`: core's integer square root, which needs no 128-bit
/// division (a software routine on a 32-bit core).
#[inline]
pub(crate) fn isqrt_u128(n: u128) -> u128 {
    n.isqrt()
}

/// `floor(e^2 / n)` for `n > 0`, without a 128-bit division: with `e = q n + r`,
/// `e^2 / n = q^2 n + 2 q r + r^2 / n`, where `r^2 < n^2` needs only a 64-bit one when
/// `n < 2^32`. Returns 0 for `n = 0`.
pub(crate) fn square_over(e: u64, n: u64) -> u128 {
    let (Some(q), Some(r)) = (e.checked_div(n), e.checked_rem(n)) else {
        return 0;
    };
    let tail = match u32::try_from(n) {
        Ok(_) => u128::from((r * r) / n), // r < n < 2^32
        Err(_) => u128::from(r) * u128::from(r) / u128::from(n),
    };
    let (q, r, n) = (u128::from(q), u128::from(r), u128::from(n));
    // Each term is at most e^2 / n: no overflow.
    q * q * n + 2 * q * r + tail
}

/// `1 - exp(-x)` for `0 <= x <= 4` (in this crate `x = 2 pi fc / fs < pi`), to a few ulp.
///
/// Computed without `1 - exp(-x)` cancellation: the alternating Taylor series for `x <= 1`
/// (terms fall by `x/n`, partial sums never cancel more than one digit), and
/// `1 - 1/exp(x)` from the positive series above that (where the result is `>= 0.63`).
pub(crate) fn neg_expm1(x: f64) -> f64 {
    if x <= 1.0 {
        // x - x^2/2! + x^3/3! - ..., Horner form from the 24th term down (x^25/25! < 1e-25).
        let mut acc = 0.0;
        for n in (1..=24u32).rev() {
            acc = x / f64::from(n) * (1.0 - acc);
        }
        acc
    } else {
        let mut term = 1.0;
        let mut sum = 1.0;
        for n in 1..=40u32 {
            term *= x / f64::from(n);
            sum += term;
        }
        1.0 - 1.0 / sum
    }
}

/// `x * 2^e` exactly, without `std`, for `e` in `-1022..=1023` (a normal power of two)
/// and a result in the normal range: the power is built from its exponent bits.
pub(crate) fn ldexp(x: f64, e: i32) -> f64 {
    debug_assert!((-1022..=1023).contains(&e));
    x * f64::from_bits(((e + 1023) as u64) << 52)
}

/// Nearest integer to a finite `x` with `0 <= x < 2^63`, ties rounded up.
pub(crate) fn round_to_u64(x: f64) -> u64 {
    // `as` truncates; the fractional part of a float below 2^63 is exact in f64.
    let t = x as u64;
    if x - t as f64 >= 0.5 {
        t + 1
    } else {
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn isqrt_is_floor_of_sqrt_at_squares_and_neighbours() {
        for r in [
            0u128,
            1,
            2,
            3,
            255,
            65_535,
            1 << 40,
            (1 << 63) - 1,
            u128::from(u64::MAX),
        ] {
            let sq = r * r;
            assert_eq!(isqrt_u128(sq), r);
            if sq > 0 {
                assert_eq!(isqrt_u128(sq - 1), r - 1);
            }
            assert_eq!(isqrt_u128(sq + 2 * r), r); // (r+1)^2 - 1
        }
        assert_eq!(isqrt_u128(u128::MAX), u128::from(u64::MAX));
    }

    #[test]
    fn square_over_is_the_floor_of_the_exact_quotient() {
        let mut trace = crate::bench::testsignal::Trace::new(0x5A);
        for _ in 0..100_000 {
            let e = trace.next_u64() >> (trace.next_u64() % 64);
            let n = (trace.next_u64() >> (trace.next_u64() % 64)).max(1);
            assert_eq!(
                square_over(e, n),
                (u128::from(e) * u128::from(e)) / u128::from(n)
            );
        }
        assert_eq!(
            square_over(u64::MAX, 1),
            u128::from(u64::MAX) * u128::from(u64::MAX)
        );
        assert_eq!(square_over(u64::MAX, u64::MAX), u128::from(u64::MAX));
        assert_eq!(square_over(7, 0), 0);
    }

    #[test]
    fn the_32_bit_divisions_are_the_64_bit_ones() {
        // Both sides of the 32-bit paths' bounds, every sign, and random operands.
        let edges = [
            0i64,
            1,
            2,
            3,
            (1 << 29) - 1,
            1 << 29,
            (1 << 32) - 1,
            1 << 32,
            1 << 60,
        ];
        let wide =
            |d: i64, n: i64| (2 * i128::from(d) + i128::from(d.signum() * n)) / (2 * i128::from(n));
        let mut trace = crate::bench::testsignal::Trace::new(0xD1);
        let random = (0..20_000).map(|_| {
            let d = (trace.next_u64() >> (4 + trace.next_u64() % 60)) as i64;
            let n = ((trace.next_u64() >> (4 + trace.next_u64() % 60)) as i64).max(1);
            (
                if trace.next_u64().is_multiple_of(2) {
                    d
                } else {
                    -d
                },
                n,
            )
        });
        let grid = edges.iter().flat_map(|&d| {
            edges
                .iter()
                .filter(|&&n| n > 0)
                .flat_map(move |&n| [(d, n), (-d, n), (d - 1, n), (1 - d, n)])
        });
        for (d, n) in grid.chain(random) {
            assert_eq!(i128::from(div_round(d, n)), wide(d, n), "{d} / {n}");
            let (u, v) = (d.unsigned_abs(), n.unsigned_abs());
            assert_eq!(div_u64(u, v), u / v, "{u} / {v}");
        }
        // Half away from zero: 5 / 2 is 3, -5 / 2 is -3, 7 / 14 is 1, 6 / 14 is 0.
        assert_eq!(
            [
                div_round(5, 2),
                div_round(-5, 2),
                div_round(7, 14),
                div_round(6, 14)
            ],
            [3, -3, 1, 0]
        );
    }

    #[test]
    fn isqrt_of_two_is_one() {
        assert_eq!(isqrt_u128(2), 1);
    }

    #[test]
    fn div_round_rounds_half_away_from_zero() {
        for (d, n, q) in [
            (7, 2, 4),
            (-7, 2, -4),
            (5, 3, 2),
            (-5, 3, -2),
            (1, 3, 0),
            (-1, 3, 0),
        ] {
            assert_eq!(div_round(d, n), q, "{d} / {n}");
        }
        assert_eq!(div_round(0, 5), 0);
    }

    #[test]
    fn round_shr_rounds_half_up_not_down() {
        assert_eq!(round_shr(3, 1), 2); // 1.5 -> 2
        assert_eq!(round_shr(-3, 1), -1); // -1.5 -> -1 (half up)
        assert_eq!(round_shr(-5, 2), -1); // -1.25 -> -1
        assert_eq!(round_shr(5, 2), 1); // 1.25 -> 1
        assert_eq!(round_shr(i64::MAX, 16), i64::MAX >> 16); // saturates, no wrap
    }

    #[test]
    fn neg_expm1_matches_its_series_at_tiny_x_and_known_values() {
        // At x = 1e-9, 1 - e^-x = x - x^2/2 to far below f64 resolution.
        let x = 1e-9;
        assert!((neg_expm1(x) - (x - x * x / 2.0)).abs() <= 1e-24);
        // 1 - e^-1 and 1 - e^-pi to 1e-15 (values from the exponential's definition).
        assert!((neg_expm1(1.0) - 0.632_120_558_828_557_7).abs() < 1e-15);
        assert!((neg_expm1(core::f64::consts::PI) - 0.956_786_081_736_227_6).abs() < 1e-15);
    }

    #[test]
    fn ldexp_and_rounding_are_exact() {
        assert_eq!(ldexp(3.0, 40), 3.0 * (1u64 << 40) as f64);
        assert_eq!(ldexp(3.0, -2), 0.75);
        assert_eq!(ldexp(3.0, 0), 3.0);
        assert_eq!(ldexp(1.0, -1022), f64::MIN_POSITIVE);
        assert_eq!(ldexp(1.0, 1023), 2f64.powi(1023));
        assert_eq!(round_to_u64(2.5), 3);
        assert_eq!(round_to_u64(2.499_999_999_999_999_6), 2);
        assert_eq!(round_to_u64(0.0), 0);
    }
}
