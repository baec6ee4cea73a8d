//! The quantizer's bound (`imu_core::drift::noise::quantizer_bound_q16`) against an
//! independent computation: the rounded codes' moments by numerical integration of the
//! Gaussian over each code's interval (not the error function), the gains by direct sums of
//! the density at the codes' boundaries (not the Fourier series), and every secant gain of a
//! grid of zeros and excursions.

use imu_core::drift::noise::quantizer_bound_q16;

/// The Gaussian density of sd `s` at `x`.
fn phi(x: f64, s: f64) -> f64 {
    (-0.5 * (x / s).powi(2)).exp() / (s * (2.0 * std::f64::consts::PI).sqrt())
}

/// The probability of `[a, b]` under the Gaussian of sd `s` (Simpson's rule, 400 panels).
fn prob(a: f64, b: f64, s: f64) -> f64 {
    let n = 400;
    let h = (b - a) / f64::from(n);
    let mut sum = phi(a, s) + phi(b, s);
    for i in 1..n {
        sum += phi(a + f64::from(i) * h, s) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    sum * h / 3.0
}

/// The codes' mean and rms for input noise `s` at `u` from a code's centre, around code 2048.
fn moments(s: f64, u: f64) -> (f64, f64) {
    let (mut m1, mut m2) = (0.0, 0.0);
    for j in -12..=12 {
        let j = f64::from(j);
        let p = prob(j - 0.5 - u, j + 0.5 - u, s);
        m1 += j * p;
        m2 += j * j * p;
    }
    (2048.0 + m1, (m2 - m1 * m1).sqrt())
}

/// The mean code's gain at `u`: the density at every code boundary.
fn gain(s: f64, u: f64) -> f64 {
    (-12..=12).map(|j| phi(f64::from(j) + 0.5 - u, s)).sum()
}

fn bound(s: f64, u: f64) -> f64 {
    let (mean, rms) = moments(s, u);
    let q16 = |x: f64| (x * 65_536.0).round();
    f64::from(quantizer_bound_q16(q16(rms) as u64, q16(mean) as i64)) / 65_536.0
}

#[test]
fn the_bound_is_the_largest_gain_over_the_least_wherever_the_calibration_found_the_zero() {
    for s in [0.3, 0.36, 0.45, 0.6] {
        let want = gain(s, 0.5) / gain(s, 0.0);
        for u in [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, -0.25] {
            let got = bound(s, u);
            assert!(
                (got / want - 1.0).abs() < 2e-3,
                "sigma {s} LSB, zero {u} LSB from a centre: bound {got}, gains' ratio {want}"
            );
        }
    }
    // The quiet sensor of the hand model: 100 ug/sqrt(Hz) through a 50 Hz pole on 12 bits.
    assert!(
        (bound(0.36, 0.0) - 1.367).abs() < 2e-3,
        "{}",
        bound(0.36, 0.0)
    );
}

#[test]
fn no_excursion_of_the_input_moves_the_mean_code_further_than_the_bound_allows() {
    for s in [0.3, 0.36, 0.45] {
        let r = bound(s, 0.0);
        let mut worst: f64 = 0.0;
        for iu in 0..=20 {
            let u = f64::from(iu) / 40.0;
            let m0 = moments(s, u).0;
            for im in 1..=60 {
                let x = f64::from(im) / 20.0;
                for x in [x, -x] {
                    let secant = (moments(s, u + x).0 - m0) / x;
                    worst = worst.max(secant / gain(s, u));
                }
            }
        }
        assert!(
            worst <= r,
            "sigma {s}: a secant over the local gain {worst} > {r}"
        );
        // And the bound is not slack by more than the secant's own reach (1.23 at 0.36).
        assert!(
            worst > 1.0 + (r - 1.0) * 0.5,
            "sigma {s}: {worst} against {r}"
        );
    }
}

#[test]
fn a_sensor_whose_noise_dithers_the_codes_keeps_its_tests_bit_for_bit() {
    // The ADXL335 on the Black Pill: 1.1 LSB rms at 12 bits, anywhere between two codes.
    for u in [0.0, 0.25, 0.5] {
        assert_eq!(bound(1.09, u), 1.0);
    }
    // From 0.82 LSB of input noise the ratio rounds to 1 in Q16.
    assert_eq!(bound(0.82, 0.0), 1.0);
    assert!(bound(0.8, 0.0) > 1.0);
}

#[test]
fn any_mean_code_gives_a_bound_without_overflow() {
    // Only the mean's place between codes is used; the function is public, so its whole
    // domain is safe.
    for bias in [
        i64::MIN,
        -1,
        0,
        (2048 << 16) + 32_768,
        65_535 << 16,
        i64::MAX,
    ] {
        let r = quantizer_bound_q16(26_608, bias);
        assert!(r >= 1 << 16, "bias {bias}: {r}");
    }
    assert_eq!(
        quantizer_bound_q16(26_608, 2048 << 16),
        quantizer_bound_q16(26_608, 5 << 16)
    );
}

#[test]
fn codes_that_barely_move_take_the_bound_at_a_quarter_lsb() {
    // 0.1 LSB of noise at a centre: the codes sit on one value; the bound is the one for
    // 0.25 LSB, finite.
    let at_floor = bound(0.25, 0.0);
    assert!((bound(0.1, 0.0) / at_floor - 1.0).abs() < 1e-3);
    // There the series' third term is 3.0e-5 of the gains, the second 1.4e-2: the bound is
    // still the gains' ratio (3.697).
    let want = gain(0.25, 0.5) / gain(0.25, 0.0);
    assert!(
        (at_floor / want - 1.0).abs() < 2e-3,
        "{at_floor} against {want}"
    );
}
