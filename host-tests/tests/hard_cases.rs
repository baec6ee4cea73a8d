//! Hard cases for the fixed-point core, each its own test: the longest documented run at
//! full scale, saturation beyond it, a stuck ADC, alternating extremes at Nyquist, the
//! cut-off ratio's ends, and the shortest runs. (Sub-LSB noise is a Monte Carlo row in
//! `monte_carlo.rs`.)

use host_tests::oracle::twin;
use imu_core::{AdcCode, Axis, Config, IntegratorState, Scheme, Settings, Tracker};

fn settings(fs_hz: u32, lowpass_fc_hz: Option<f64>, scheme: Scheme, adc_bits: u8) -> Settings {
    Config {
        fs_hz,
        lowpass_fc_hz,
        scheme,
        adc_bits,
        drift: None, // these cases drive the integrator directly
        ..Config::default()
    }
    .validate()
    .expect("valid hard-case settings")
}

/// Euler after `n` samples of constant `c` (Q16): `W = 2 c n`, `Z = 2 c n (n + 1)`.
fn euler_constant(c: i64, n: u64) -> (i64, i128) {
    let (c, n) = (i128::from(c), i128::from(n));
    ((2 * c * n) as i64, 2 * c * n * (n + 1))
}

#[test]
fn full_scale_for_24_hours_at_10_khz_is_exact_without_wrapping() {
    // The documented range: a 12-bit code at a rail relative to the opposite rail's bias
    // (|c| = 4095 LSB, 5 g on an ADXL335) for 24 h at 10 kHz, N = 8.64e8.
    let s = settings(10_000, None, Scheme::Euler, 12);
    let n: u64 = 864_000_000;
    for (code, bias) in [(4095u16, 0i64), (0, 4095 << 16)] {
        let mut axis = Axis::new(bias);
        for _ in 0..n {
            axis.update(&s, AdcCode(code));
        }
        let c = (i64::from(code) << 16) - bias;
        let (w, z) = euler_constant(c, n);
        assert_eq!(axis.integrator().velocity(), w);
        assert_eq!(axis.integrator().position(), z);
        // Headroom left: W uses 58.7 of 63 bits, Z 88.4 of 127.
        assert!(w.unsigned_abs() < 1 << 59 && z.unsigned_abs() < 1 << 89);
    }
}

#[test]
#[ignore = "8.64e9 samples, about 25 s: run by .ci/run with --ignored"]
fn full_scale_for_24_hours_at_100_khz_is_exact_without_wrapping() {
    // The top of the documented range: W reaches 2^62.0 of i64's 2^63.
    let s = settings(100_000, None, Scheme::Euler, 12);
    let n: u64 = 8_640_000_000;
    let mut axis = Axis::new(0);
    for _ in 0..n {
        axis.update(&s, AdcCode(4095));
    }
    let (w, z) = euler_constant(4095 << 16, n);
    assert_eq!(axis.integrator().velocity(), w);
    assert_eq!(axis.integrator().position(), z);
}

#[test]
fn sixteen_bit_full_scale_saturates_instead_of_wrapping() {
    // 16-bit codes at full scale (|c| = 65535 LSB) fill i64's W after 2^30 samples
    // (2^63 / (2 * 65535 * 2^16) = 1.0737e9). Beyond that W holds at the limit and Z keeps
    // growing monotonically: the cursor keeps going the same way instead of jumping back.
    let s = settings(100_000, None, Scheme::Euler, 16);
    let mut axis = Axis::new(0);
    let limit = 1_073_758_208u64; // ceil(2^63 / (2 * 65535 * 2^16))
    for _ in 0..limit - 1 {
        axis.update(&s, AdcCode(65_535));
    }
    assert!(axis.integrator().velocity() < i64::MAX);
    let mut last_z = axis.integrator().position();
    for _ in 0..1000 {
        axis.update(&s, AdcCode(65_535));
        assert!(axis.integrator().position() > last_z);
        last_z = axis.integrator().position();
    }
    assert_eq!(axis.integrator().velocity(), i64::MAX);
}

#[test]
fn adc_stuck_at_a_rail_integrates_exactly_and_reads_out_every_count() {
    // After calibrating at mid-scale the ADC sticks at 0 (or 4095) for 1 h at 3 kHz: a
    // constant -2048 (+2047) LSB, i.e. 5 g. Position and every count read at 1 kHz are exact:
    // 3.2e8 m, 1e13 counts, far beyond one i32 read-out, carried without loss.
    for rail in [0u16, 4095] {
        // Pure integration (drift control would call a stuck, constant code still).
        let config = Config {
            drift: None,
            ..Config::default()
        };
        let mut t = Tracker::new(&config).expect("valid");
        t.feed(&[[2048; 3]; 3000]);
        let n: u64 = 3000 * 3600;
        let mut total: i128 = 0;
        let block = [[rail, 2048, 2048]; 3];
        for _ in 0..n / 3 {
            t.feed(&block);
            total += i128::from(t.take_counts()[0]);
        }
        let c = (i64::from(rail) - 2048) << 16;
        let (_, z) = euler_constant(c, n);
        let r = t.settings().readout();
        // The rounded exact displacement in counts: round(Z M / 2^P).
        let want = (z * i128::from(r.mult()) + (1 << (r.shift() - 1))) >> r.shift();
        assert_eq!(total, want, "rail {rail}");
        assert!(want.unsigned_abs() > 10_000_000_000_000);
    }
}

#[test]
fn alternating_extremes_at_nyquist() {
    // 0, 4095, 0, 4095, ... around a bias of 2047.5 LSB: -+2047.5 LSB at fs / 2.
    // Euler's velocity alternates between -2047.5 and 0 LSB*samples, so its position drifts
    // linearly, -2047.5 N / 2 (the rectangle rule's known response at Nyquist). Every
    // trapezoid step adds (c[n-1] + c[n]) / 2 = 0: velocity and position stay exactly 0.
    // Both match their f64 twins exactly (the inputs are integers in Q16).
    let bias = 2047 * 65_536 + 32_768;
    for (scheme, rule) in [
        (Scheme::Euler, twin::Scheme::Euler),
        (Scheme::Trapezoid, twin::Scheme::Trapezoid),
    ] {
        let s = settings(3000, None, scheme, 12);
        let mut axis = Axis::new(bias);
        let mut f = twin::Integrator::new(rule);
        for i in 0..1_000_000u32 {
            let code = if i % 2 == 0 { 0 } else { 4095 };
            axis.update(&s, AdcCode(code));
            f.step(f64::from(code) - 2047.5);
        }
        let z = axis.integrator().position() as f64 / 4.0 / 65_536.0;
        assert_eq!(z, f.s, "{scheme:?}");
        let n = 1e6;
        let want = match scheme {
            Scheme::Euler => -2047.5 * n / 2.0,
            Scheme::Trapezoid => 0.0,
        };
        assert_eq!(z, want, "{scheme:?}");
    }
}

#[test]
fn alternating_extremes_through_the_filter_at_both_ends_of_its_range() {
    // The same Nyquist input through the low-pass at fc/fs = 1e-6 and just under 0.5: the
    // output stays within the input range and within the twin's budget (2^-17 + 2^-32 LSB
    // plus the twin's own error, bounded by 2 ulp(4096) / k).
    for fc in [0.003, 1499.997] {
        let s = settings(3000, Some(fc), Scheme::Euler, 12);
        let lp = *s.lowpass().expect("filter configured");
        let mut state = imu_core::LowpassState::settled_q16(2047 << 16);
        let mut f = twin::Lowpass::realised(lp.k_q32(), 2047.0);
        let bound = 2f64.powi(-17) + 2f64.powi(-32) + 2.0 * f64::EPSILON * 4096.0 / f.k;
        for i in 0..1_000_000u32 {
            let code = if i % 2 == 0 { 0 } else { 4095 };
            let y = lp.process(&mut state, AdcCode(code));
            assert!(
                (0..=4095 << 16).contains(&y),
                "fc {fc}: output {y} out of range"
            );
            let err = (y as f64 / 65_536.0 - f.process(f64::from(code))).abs();
            assert!(
                err <= bound,
                "fc {fc}, sample {i}: error {err:e} > {bound:e}"
            );
        }
    }
}

#[test]
fn one_and_two_samples_are_exact() {
    // REFERENCE (c) weights. Euler, fs^2 s[N] = sum (N - k + 1) a[k]: N = 1 gives a1,
    // N = 2 gives 2 a1 + a2. Trapezoid, fs^2 s[N] = (N/2 - 1/4) a0 + sum (N - k) a[k]
    // + a[N] / 4: N = 1 (2 samples) gives a0/4 + a1/4, N = 2 (3 samples) 3 a0/4 + a1 + a2/4.
    let cases: [(Scheme, &[i64], f64); 4] = [
        (Scheme::Euler, &[3], 3.0),
        (Scheme::Euler, &[3, -5], 1.0),
        (Scheme::Trapezoid, &[3, -5], 0.25 * 3.0 + 0.25 * -5.0),
        (
            Scheme::Trapezoid,
            &[3, -5, 7],
            0.75 * 3.0 - 5.0 + 0.25 * 7.0,
        ),
    ];
    for (scheme, cs, want) in cases {
        let mut st = IntegratorState::default();
        for &c in cs {
            scheme.step(&mut st, c << 16);
        }
        assert_eq!(
            st.position() as f64 / 4.0 / 65_536.0,
            want,
            "{scheme:?} {cs:?}"
        );
    }
}
