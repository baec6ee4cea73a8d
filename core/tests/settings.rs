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
    // The window is round(calibration_s fs) samples, 16 to 2^24: 15.5 rounds up to 16 and
    // is accepted, 15.49 is not; at fs = 1 Hz, 2^24 + 0.49 is accepted, 2^24 + 0.5 is not.
    let window = |fs_hz: u32, calibration_s: f64| {
        Config {
            fs_hz,
            calibration_s,
            ..cfg()
        }
        .validate()
        .map(|s| s.fs_hz())
    };
    assert!(window(1000, 0.0155).is_ok());
    assert_eq!(window(1000, 0.01549), Err(ConfigError::CalibrationWindow));
    let top = f64::from(1u32 << 24);
    assert!(window(1, top + 0.49).is_ok());
    assert_eq!(window(1, top + 0.5), Err(ConfigError::CalibrationWindow));
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
fn rest_bound_beyond_16_bit_codes_is_refused() {
    // 2^23 LSB rms is meaningless for codes of at most 16 bits, and its Q16 variance would
    // not fit the calibrator: refused at the edge, accepted just below.
    let lsb = cfg().m_s2_per_lsb;
    let bound = |lsbs: f64| {
        Config {
            rest_noise_max_m_s2: lsbs * lsb,
            ..cfg()
        }
        .validate()
        .map(|_| ())
    };
    assert_eq!(bound(8_388_608.0), Err(ConfigError::RestNoise));
    assert!(bound(8_388_607.0).is_ok());
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
