//! What `Config::validate` derives, checked from the definitions: every accessor of
//! `Settings`, the edges of each accepted range, and an axis's two halves.

use imu_core::{AdcCode, Axis, Config, ConfigError, Scheme};

fn cfg() -> Config {
    Config {
        drift: None,
        ..Config::default()
    }
}

#[test]
fn settings_carry_what_was_configured() {
    let (fs, fc, lsb) = (2000.0, 37.0, 0.011);
    let s = Config {
        fs_hz: fs as u32,
        lowpass_fc_hz: Some(fc),
        m_s2_per_lsb: lsb,
        scheme: Scheme::Trapezoid,
        ..cfg()
    }
    .validate()
    .expect("valid");
    assert_eq!(s.fs_hz(), 2000);
    assert_eq!(s.scheme(), Scheme::Trapezoid);
    assert_eq!(s.m_s2_per_lsb(), lsb);
    // k = 1 - exp(-2 pi fc / fs) in Q0.32, from its definition.
    let k = -(-2.0 * std::f64::consts::PI * fc / fs).exp_m1() * 2f64.powi(32);
    assert!(
        (f64::from(s.lowpass_k_q32()) - k).abs() <= 0.5,
        "{}",
        s.lowpass_k_q32()
    );
    assert_eq!(s.lowpass().map(|l| l.k_q32()), Some(s.lowpass_k_q32()));
    // s = Z LSB / (4 2^16 fs^2) (the integrator's units).
    let m = lsb / (4.0 * 65_536.0 * fs * fs);
    assert!((s.metres_per_position_unit() / m - 1.0).abs() < 1e-15);
    let plain = cfg().validate().expect("valid");
    assert!(plain.lowpass().is_none());
    assert_eq!((plain.lowpass_k_q32(), plain.scheme()), (0, Scheme::Euler));
}

#[test]
fn calibration_window_edges() {
    // The window holds at least 16 samples (16 / fs, a part in 1e12 of rounding allowed) and
    // lasts at most 60 s, which at the fastest rate is 6e6 samples, inside the calibrator's
    // 2^24.
    let window = |fs_hz: u32, calibration_s: f64| {
        Config {
            fs_hz,
            calibration_s,
            drift: None,
            ..cfg()
        }
        .validate()
        .map(|s| s.fs_hz())
    };
    assert!(window(1000, 0.016).is_ok());
    assert!(window(3000, 16.0 / 3000.0).is_ok());
    assert_eq!(
        window(1000, 0.016 * (1.0 - 1e-9)),
        Err(ConfigError::CalibrationWindow)
    );
    assert!(window(100_000, 60.0).is_ok());
    assert_eq!(window(1, 60.000_001), Err(ConfigError::CalibrationWindow));
    assert_eq!(window(1, 1000.0), Err(ConfigError::CalibrationWindow));
}

#[test]
fn rest_bound_is_a_variance_of_the_rms_squared() {
    // A bound of 0.5 LSB rms is a variance of 0.25 LSB^2. Windows of 16 samples, j of them
    // 1 LSB up: variance j (16 - j) / 240 LSB^2: 6 gives 0.25 (rest, at the edge), 7 gives
    // 0.2625 (motion).
    let s = Config {
        calibration_s: 16.0 / 3000.0,
        rest_noise_max_m_s2: 0.5 * cfg().m_s2_per_lsb,
        ..cfg()
    }
    .validate()
    .expect("valid");
    for (up, rest) in [(6, true), (7, false)] {
        let mut c = s.calibrator();
        for i in 0..16 {
            c.push(AdcCode(if i < up { 2001 } else { 2000 }));
        }
        assert_eq!(c.finish().is_ok(), rest, "{up} samples up");
    }
}

#[test]
fn rest_bound_is_at_most_one_g_and_fits_the_calibrator_on_the_finest_scale() {
    // A window whose noise is 1 g rms is no rest: refused above it. On the finest scale a
    // profile takes (2 g over 16 bits) 1 g is 2^15 LSB, whose Q16 variance fits the
    // calibrator's u64 with room (it overflows only from 2^23 LSB).
    let bound = |rest_noise_max_m_s2: f64, adc_bits: u8, m_s2_per_lsb: f64| {
        Config {
            rest_noise_max_m_s2,
            adc_bits,
            m_s2_per_lsb,
            ..cfg()
        }
        .validate()
        .map(|_| ())
    };
    let g = 9.806_65;
    let finest = 2.0 * g / 65_536.0;
    assert!(bound(g, 16, finest).is_ok());
    assert_eq!(
        bound(g * (1.0 + 1e-9), 16, finest),
        Err(ConfigError::RestNoise)
    );
    assert_eq!(
        bound(0.0, 12, cfg().m_s2_per_lsb),
        Err(ConfigError::RestNoise)
    );
    assert!(bound(1e-9, 12, cfg().m_s2_per_lsb).is_ok());
}

#[test]
fn an_axis_update_is_its_filter_then_its_integration() {
    // No filter, Euler, bias 2048: a constant code 2100 is c = 52 LSB = 52 2^16 in Q16; after
    // N samples W = 2 N c and Z = 2 sum W = 2 c N (N + 1).
    let s = cfg().validate().expect("valid");
    let mut axis = Axis::new(2048 << 16);
    let n = 10i64;
    for _ in 0..n {
        axis.update(&s, AdcCode(2100));
    }
    let c = 52i64 << 16;
    assert_eq!(axis.integrator().velocity(), 2 * n * c);
    assert_eq!(
        axis.integrator().position(),
        i128::from(2 * c * n * (n + 1))
    );
    assert_eq!(axis.last_code(), AdcCode(2100));
}

#[test]
fn a_primed_trapezoid_steps_from_the_primed_sample() {
    // Primed with y0, the first sample y1 steps W by (y0 - b) + (y1 - b), both bias-free.
    let s = Config {
        scheme: Scheme::Trapezoid,
        ..cfg()
    }
    .validate()
    .expect("valid");
    let b = 2048i64 << 16;
    let mut axis = Axis::new(b);
    axis.prime(2058 << 16);
    axis.integrate(&s, 2068 << 16);
    assert_eq!(axis.integrator().velocity(), (10 << 16) + (20 << 16));
}
