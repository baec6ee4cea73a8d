//! Host tests of the composed pipeline: configuration, axis, tracker.

use imu_core::{
    AdcCode, Axis, CalibrationError, Config, ConfigError, Event, Lowpass, LowpassState, Phase,
    Scheme, Tracker,
};

/// The pure double integrator (drift control off): these tests check integration itself.
/// Drift control has its own tests (`drift.rs`).
fn cfg() -> Config {
    Config {
        drift: None,
        ..Config::default()
    }
}

#[track_caller]
fn rejects(config: Config, want: ConfigError) {
    assert_eq!(config.validate().err(), Some(want));
}

/// Mouse counts for a constant acceleration of `lsb` m/s^2 integrated by Euler for `n`
/// samples at `fs`, at 800 counts per inch: `lsb n (n + 1) / (2 fs^2) / 0.0254 * 800`.
fn euler_counts(lsb: f64, n: f64, fs: f64) -> f64 {
    lsb * n * (n + 1.0) / 2.0 / (fs * fs) / 0.0254 * 800.0
}

#[test]
fn default_config_is_valid() {
    let s = cfg().validate().expect("default is valid");
    assert_eq!(s.fs_hz(), 3000);
    assert_eq!(s.lowpass_k_q32(), 0);
}

#[test]
fn each_bad_field_is_named() {
    rejects(
        Config { fs_hz: 0, ..cfg() },
        ConfigError::SampleRate { fs_hz: 0 },
    );
    rejects(
        Config {
            fs_hz: 100_001,
            ..cfg()
        },
        ConfigError::SampleRate { fs_hz: 100_001 },
    );
    for fc in [1500.0, 2000.0, 0.0, -1.0, 0.002, f64::NAN, f64::INFINITY] {
        rejects(
            Config {
                lowpass_fc_hz: Some(fc),
                ..cfg()
            },
            ConfigError::LowpassCutoff,
        );
    }
    for s in [0.0, -0.02, f64::NAN, f64::INFINITY] {
        rejects(
            Config {
                m_s2_per_lsb: s,
                ..cfg()
            },
            ConfigError::Scale,
        );
    }
    // At 1 bit every code is a rail: no calibration could succeed. 2 bits is the least
    // (with a scale that spans at least 2 g in its 4 codes).
    assert!(Config {
        adc_bits: 2,
        m_s2_per_lsb: 5.0,
        ..cfg()
    }
    .validate()
    .is_ok());
    for b in [0, 1, 17] {
        rejects(
            Config {
                adc_bits: b,
                ..cfg()
            },
            ConfigError::AdcBits { adc_bits: b },
        );
    }
    rejects(
        Config {
            counts_per_inch: 0,
            ..cfg()
        },
        ConfigError::CountsPerInch { counts_per_inch: 0 },
    );
    for t in [0.0, 0.005, 1e5, f64::NAN, -1.0] {
        rejects(
            Config {
                calibration_s: t,
                ..cfg()
            },
            ConfigError::CalibrationWindow,
        );
    }
    for r in [0.0, -1.0, f64::NAN, 1e9] {
        rejects(
            Config {
                rest_noise_max_m_s2: r,
                ..cfg()
            },
            ConfigError::RestNoise,
        );
    }
}

#[test]
fn errors_say_which_parameter() {
    let msg = format!("{}", ConfigError::SampleRate { fs_hz: 0 });
    assert!(msg.starts_with("fs_hz = 0"), "{msg}");
    let msg = format!("{}", ConfigError::LowpassCutoff);
    assert!(msg.starts_with("lowpass_fc_hz"), "{msg}");
}

#[test]
fn cutoff_range_edges_are_accepted() {
    for fc in [0.003, 1499.99] {
        assert!(
            Config {
                lowpass_fc_hz: Some(fc),
                ..cfg()
            }
            .validate()
            .is_ok(),
            "{fc}"
        );
    }
}

#[test]
fn bad_reconfigure_leaves_tracker_untouched() {
    let mut t = Tracker::new(&cfg()).expect("valid");
    t.feed(&[[2048, 2048, 2048]; 3000]);
    assert_eq!(t.phase(), Phase::Tracking);
    // Motion in progress, counts owed: a refused configuration must leave every bit of it.
    t.feed(&[[2100, 2000, 2048]; 300]);
    let before = t;
    let err = t.reconfigure(&Config { fs_hz: 0, ..cfg() });
    assert_eq!(err, Err(ConfigError::SampleRate { fs_hz: 0 }));
    assert_eq!(t, before, "the whole state, not only settings and phase");
    let err = t.reconfigure(&Config {
        lowpass_fc_hz: Some(2000.0),
        ..cfg()
    });
    assert!(err.is_err());
    assert_eq!(t, before);
    t.reconfigure(&Config {
        fs_hz: 1000,
        ..cfg()
    })
    .expect("valid");
    assert_eq!(
        (t.settings().fs_hz(), t.phase()),
        (1000, Phase::Calibrating)
    );
}

/// A sample at rest with a symmetric +-1 LSB dither (0, +1, 0, -1) around `mid`.
fn rest(i: usize, mid: u16) -> [u16; 3] {
    let v = match i % 4 {
        1 => mid + 1,
        3 => mid - 1,
        _ => mid,
    };
    [v, v, v]
}

#[test]
fn tracker_calibrates_then_tracks() {
    let mut t = Tracker::new(&cfg()).expect("valid");
    let window: Vec<[u16; 3]> = (0..3000).map(|i| rest(i, 2048)).collect();
    assert_eq!(t.feed(&window[..2999]), None);
    assert_eq!(t.take_counts(), [0; 3]);
    match t.feed(&window[2999..]) {
        Some(Event::Calibrated(c)) => {
            for axis in c {
                assert_eq!(axis.bias_q16, 2048 << 16);
                assert_eq!(axis.samples, 3000);
                // Sample variance of 0, 1, 0, -1 repeated: 1500 / 2999 LSB^2, rms 0.70722.
                let rms = axis.noise_rms_q16 as f64 / 65_536.0;
                assert!((rms - (1500.0f64 / 2999.0).sqrt()).abs() < 2e-5, "{rms}");
            }
        }
        other => panic!("expected calibration, got {other:?}"),
    }
    assert_eq!(t.phase(), Phase::Tracking);
    // At rest the symmetric dither integrates to a bounded wobble: no counts.
    t.feed(&window);
    assert_eq!(t.take_counts(), [0; 3]);
    assert_eq!(t.counters().samples, 6000);
}

#[test]
fn a_window_noisier_than_the_rms_bound_restarts_calibration() {
    let cfg = Config {
        rest_noise_max_m_s2: 0.1,
        ..cfg()
    };
    let mut t = Tracker::new(&cfg).expect("valid");
    let mut window: Vec<[u16; 3]> = (0..3000).map(|i| rest(i, 2048)).collect();
    window[1500][1] = 2400; // a knock on Y: rms 6.4 LSB = 0.15 m/s^2 > 0.1 m/s^2
    match t.feed(&window) {
        Some(Event::Rejected {
            axis: 1,
            error: CalibrationError::Motion { .. },
        }) => {}
        other => panic!("expected rejection on Y, got {other:?}"),
    }
    assert_eq!(t.phase(), Phase::Calibrating);
    assert_eq!(t.counters().rejected_windows, 1);
    let window: Vec<[u16; 3]> = (0..3000).map(|i| rest(i, 2048)).collect();
    assert!(matches!(t.feed(&window), Some(Event::Calibrated(_))));
}

#[test]
fn the_motion_test_counts_the_windows_20_ms_blocks() {
    // At 3 kHz a 1 s window is 50 blocks of 60 samples (4 ticks of 15): their bound is
    // 0.485. X one code up in 8 runs of 25 blocks in all, 16 changes among 50 blocks: a von
    // Neumann ratio of 2 * 16 / 50 = 0.64, above the bound: rest, whatever the 25 ms blocks
    // find. (Counted in other blocks, the window's ratio and bound would be other numbers.)
    let high = [3usize, 3, 3, 3, 3, 3, 3, 4];
    let low = [3usize, 3, 3, 3, 3, 3, 3, 2, 2];
    let mut up = Vec::new();
    for (r, &l) in low.iter().enumerate() {
        up.extend(core::iter::repeat_n(false, l * 60));
        if let Some(&h) = high.get(r) {
            up.extend(core::iter::repeat_n(true, h * 60));
        }
    }
    assert_eq!(up.len(), 3000);
    let mut t = Tracker::new(&cfg()).expect("valid");
    let window: Vec<[u16; 3]> = (0..3000)
        .map(|i| {
            let [x, y, z] = rest(i, 2048);
            [x + u16::from(up[i]), y, z]
        })
        .collect();
    assert!(
        matches!(t.feed(&window), Some(Event::Calibrated(_))),
        "a ratio of 0.64 in 50 blocks is rest"
    );
    let settings = cfg().validate().expect("valid");
    let mut c = settings.calibrator();
    window.iter().for_each(|s| c.push(AdcCode(s[0])));
    assert!(c.finish().is_ok());
}

#[test]
fn a_tilt_during_calibration_restarts_it() {
    // X steps by 2 codes (0.05 m/s^2, 0.3 degrees) half-way: 1 LSB rms, far under the rms
    // bound, and a zero a code off; the motion test refuses the window.
    let mut t = Tracker::new(&cfg()).expect("valid");
    let window: Vec<[u16; 3]> = (0..3000)
        .map(|i| {
            let [x, y, z] = rest(i, 2048);
            [x + if i >= 1500 { 2 } else { 0 }, y, z]
        })
        .collect();
    match t.feed(&window) {
        Some(Event::Rejected {
            axis: 0,
            error: e @ CalibrationError::Unsteady { .. },
        }) => {
            let text = e.to_string();
            let lengths = [
                "over 20 ms blocks",
                "over 25 ms blocks",
                "over 30 ms blocks",
            ];
            assert!(lengths.iter().all(|l| text.contains(l)), "{text}");
        }
        other => panic!("expected rejection on X, got {other:?}"),
    }
    assert_eq!(t.phase(), Phase::Calibrating);
    let window: Vec<[u16; 3]> = (0..3000).map(|i| rest(i, 2048)).collect();
    assert!(matches!(t.feed(&window), Some(Event::Calibrated(_))));
}

#[test]
fn constant_acceleration_moves_the_cursor_by_the_exact_count() {
    // 1 LSB of constant acceleration on X for 1 s at 3 kHz, Euler: 11.975 mm = 471.5 counts.
    let config = cfg();
    let mut t = Tracker::new(&config).expect("valid");
    t.feed(&[[2048; 3]; 3000]);
    t.feed(&[[2049, 2048, 2048]; 3000]);
    let exact = euler_counts(config.m_s2_per_lsb, 3000.0, 3000.0);
    let [x, y, z] = t.take_counts();
    assert_eq!((y, z), (0, 0));
    assert_eq!(f64::from(x), exact.round(), "exact {exact}");
}

#[test]
fn counts_taken_in_pieces_sum_to_the_rounded_total() {
    let config = cfg();
    let mut t = Tracker::new(&config).expect("valid");
    t.feed(&[[2048; 3]; 3000]);
    let mut total = [0i64; 2];
    for _ in 0..3000 {
        t.feed(&[[2049, 2047, 2048]]);
        let [x, y, _] = t.take_counts();
        total[0] += i64::from(x);
        total[1] += i64::from(y);
    }
    let exact = euler_counts(config.m_s2_per_lsb, 3000.0, 3000.0);
    assert_eq!(total[0] as f64, exact.round());
    assert_eq!(total[1] as f64, (-exact).round());
}

#[test]
fn lost_samples_are_held_so_time_stays_right() {
    let config = cfg();
    let mut a = Tracker::new(&config).expect("valid");
    let mut b = Tracker::new(&config).expect("valid");
    for t in [&mut a, &mut b] {
        t.feed(&[[2048; 3]; 3000]);
    }
    a.feed(&[[2050, 2048, 2048]; 100]);
    b.feed(&[[2050, 2048, 2048]; 40]);
    b.lost(60);
    assert_eq!(a.axes()[0].integrator(), b.axes()[0].integrator());
    assert_eq!(b.counters().lost, 60);
}

#[test]
fn recalibrate_stops_motion() {
    let mut t = Tracker::new(&cfg()).expect("valid");
    t.feed(&[[2048; 3]; 3000]);
    t.feed(&[[2060, 2048, 2048]; 10]);
    t.recalibrate();
    assert_eq!(t.phase(), Phase::Calibrating);
    assert_eq!(t.axes()[0].integrator().velocity(), 0);
    assert_eq!(t.take_counts()[0], 0);
}

#[test]
fn stuck_adc_rail_is_reported_as_clipping() {
    for rail in [0u16, 4095] {
        let mut t = Tracker::new(&cfg()).expect("valid");
        let event = t.feed(&[[2048, rail, 2048]; 3000]);
        assert_eq!(
            event,
            Some(Event::Rejected {
                axis: 1,
                error: CalibrationError::Clipped { code: rail }
            })
        );
    }
}

#[test]
fn lowpass_settles_exactly_for_every_allowed_ratio() {
    // From rail to rail, and by one code, at cut-off ratios across the whole allowed range.
    // Settling takes about ln(2^80 / 2^32) / k samples to the last Q32 unit plus at most
    // 1 / k to creep through it: 60 / k is enough.
    for ratio in [1e-6, 1e-5, 1e-3, 0.01, 0.1, 0.25, 0.4, 0.499_999] {
        let lp = Lowpass::from_ratio(ratio).expect("in range");
        let k = f64::from(lp.k_q32()) / 4_294_967_296.0;
        let steps = (60.0 / k) as usize;
        for (from, to) in [(0u16, 4095u16), (4095, 0), (65_535, 1), (1000, 1001)] {
            let mut s = LowpassState::settled_q16(i64::from(from) << 16);
            let mut y = 0;
            for _ in 0..steps {
                y = lp.process(&mut s, AdcCode(to));
            }
            assert_eq!(y, i64::from(to) << 16, "ratio {ratio}, {from} -> {to}");
            assert_eq!(
                s.y_q32(),
                i64::from(to) << 32,
                "ratio {ratio}, {from} -> {to}"
            );
        }
    }
}

#[test]
fn filtered_axis_at_its_bias_stays_exactly_still() {
    let s = Config {
        lowpass_fc_hz: Some(50.0),
        ..cfg()
    }
    .validate()
    .expect("valid");
    let mut axis = Axis::new(2048 << 16);
    for _ in 0..100_000 {
        axis.update(&s, AdcCode(2048));
    }
    assert_eq!(axis.integrator().velocity(), 0);
    assert_eq!(axis.integrator().position(), 0);
}

#[test]
fn trapezoid_tracker_integrates_a_step_exactly() {
    // The first tracked sample only primes the trapezoid; the next 3000 are steps with a
    // constant 1 LSB: s = LSB (N^2 / 2) / fs^2 exactly.
    let trap = Config {
        scheme: Scheme::Trapezoid,
        ..cfg()
    };
    let mut t = Tracker::new(&trap).expect("valid");
    t.feed(&[[2048; 3]; 3000]);
    t.feed(&[[2049, 2048, 2048]; 3001]);
    let exact = trap.m_s2_per_lsb * 3000.0 * 3000.0 / 2.0 / 9e6 / 0.0254 * 800.0;
    assert_eq!(
        f64::from(t.take_counts()[0]),
        exact.round(),
        "exact {exact}"
    );
}

#[test]
fn out_of_range_bias_is_clamped_not_wrapped() {
    let s = cfg().validate().expect("valid");
    for (bias, held) in [(i64::MAX, 65_535u16), (-5, 0)] {
        let mut axis = Axis::new(bias);
        assert_eq!(axis.bias_q16(), i64::from(held) << 16);
        axis.update(&s, AdcCode(held));
        assert_eq!(axis.integrator().velocity(), 0);
    }
}

#[test]
fn the_readout_ratio_fits_at_every_corner_of_the_keys_ranges() {
    // Counts per position unit = m_s2_per_lsb / (2^18 fs^2) * counts_per_inch / 0.0254. Within
    // the ranges of the rate, the full scale and the resolution it stays inside the read-out's
    // [2^-63, 2^31): from 4.5e-18 (2 g over 16 bits at 100 kHz, 1 count per inch) to 9.4e3
    // (1000 g over 2 bits at 1 Hz, 25 400 counts per inch). So the resolution's own range is
    // the whole of its limit, and the read-out's refusal (its unit tests) is never reached
    // from a profile.
    let g = 9.806_65;
    for (fs_hz, adc_bits, full_scale_g, counts_per_inch) in [
        (100_000, 16, 2.0, 1),
        (1, 2, 1000.0, 25_400),
        (100_000, 2, 1000.0, 25_400),
        (1, 16, 2.0, 1),
    ] {
        let c = Config {
            fs_hz,
            adc_bits,
            m_s2_per_lsb: full_scale_g * g / f64::from(1u32 << adc_bits),
            counts_per_inch,
            calibration_s: 16.0,
            drift: None,
            ..cfg()
        };
        assert!(c.validate().is_ok(), "{c:?}: {:?}", c.validate());
    }
}

#[test]
fn a_new_configuration_leaves_no_phantom_counts() {
    // The read-out's remainder at 800 cpi is in units of its shift; kept across the change to
    // 12 800 cpi and read with the new shift, it came out of a still device as 6 phantom
    // counts. The axes now start afresh.
    let mut t = Tracker::new(&Config {
        drift: None,
        ..cfg()
    })
    .expect("valid");
    t.feed(&[[2048, 2048, 2048]; 3000]);
    assert_eq!(t.phase(), Phase::Tracking);
    // A short push, drained at 1 kHz, leaves a remainder in the read-out.
    for i in 0..300 {
        t.feed(&[[if i < 150 { 2051 } else { 2045 }, 2048, 2048]]);
        if i % 3 == 2 {
            t.take_counts();
        }
    }
    t.reconfigure(&Config {
        counts_per_inch: 12_800,
        drift: None,
        ..cfg()
    })
    .expect("valid");
    let mut moved = [0i64; 3];
    for i in 0..6000 {
        t.feed(&[[2048, 2048, 2048]]);
        if i % 3 == 2 {
            for (m, c) in moved.iter_mut().zip(t.take_counts()) {
                *m += i64::from(c);
            }
        }
    }
    assert_eq!(t.phase(), Phase::Tracking);
    assert_eq!(moved, [0, 0, 0], "a still device after the change");
}

/// Deterministic codes around 2048 with the occasional rail, for block tests.
fn wander(n: usize, seed: u64) -> Vec<u16> {
    let mut t = imu_core::bench::testsignal::Trace::new(seed);
    (0..n)
        .map(|_| match t.next_u64() % 50 {
            0 => 0,
            1 => 4095,
            _ => t.next_code(),
        })
        .collect()
}

#[test]
fn a_block_is_processed_exactly_as_its_samples_are() {
    // Blocks of every length from 0 to 40 (and one of 2^14 + 1, past the one pass's bound),
    // with and without the low-pass, both schemes: the block-wise axis equals the
    // per-sample one after every block, counts included.
    for (filter, scheme) in [
        (true, Scheme::Euler),
        (false, Scheme::Euler),
        (true, Scheme::Trapezoid),
    ] {
        let settings = Config {
            lowpass_fc_hz: filter.then_some(50.0),
            scheme,
            ..cfg()
        }
        .validate()
        .expect("valid");
        let codes = wander(40 * 41 / 2 + (1 << 14) + 1, 0xB10C);
        let (mut by_sample, mut by_block) = (Axis::new(2040 << 16), Axis::new(2040 << 16));
        let mut rest = &codes[..];
        for len in (0..=40).chain([(1 << 14) + 1]) {
            let (now, later) = rest.split_at(len);
            for &c in now {
                by_sample.update(&settings, AdcCode(c));
            }
            by_block.update_block(&settings, now.iter().map(|&c| AdcCode(c)));
            assert_eq!(
                by_block, by_sample,
                "filter {filter}, {scheme:?}, block {len}"
            );
            assert_eq!(
                by_block.take_counts(&settings),
                by_sample.take_counts(&settings)
            );
            rest = later;
        }
        assert!(rest.is_empty());
    }
}

#[test]
fn a_tracker_without_drift_control_takes_blocks_exactly_as_samples() {
    // Calibration ends inside a block; the rest of it and every later block go through the
    // axes at once. Fed one sample at a time, the same tracker ends in the same state.
    let config = cfg();
    let (mut by_sample, mut by_block) = (
        Tracker::new(&config).expect("valid"),
        Tracker::new(&config).expect("valid"),
    );
    let quiet: Vec<[u16; 3]> = (0..3000 + 7).map(|i| rest(i, 2048)).collect();
    let moving: Vec<[u16; 3]> = wander(3 * 5000, 0x7EAC)
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    let samples: Vec<[u16; 3]> = quiet.into_iter().chain(moving).collect();
    let mut moved = [0i64; 3];
    for block in samples.chunks(20) {
        for s in block {
            by_sample.feed(core::slice::from_ref(s));
        }
        by_block.feed(block);
        let counts = by_block.take_counts();
        assert_eq!(counts, by_sample.take_counts());
        for (m, n) in moved.iter_mut().zip(counts) {
            *m += i64::from(n).abs();
        }
        assert_eq!(by_block.axes(), by_sample.axes());
    }
    assert_eq!(by_block.phase(), Phase::Tracking);
    assert_eq!(by_block.counters(), by_sample.counters());
    assert!(
        moved.iter().all(|&m| m > 0),
        "the wander moved every axis: {moved:?}"
    );
}

#[test]
fn every_sample_fed_is_counted_with_and_without_drift_control() {
    // Calibration ends inside a block of 20; the rest of the samples are tracked, one by one
    // with drift control, a block at a time without: every one is counted.
    for config in [Config::default(), cfg()] {
        let mut tracker = Tracker::new(&config).expect("valid");
        let samples: Vec<[u16; 3]> = (0..3000 + 1007).map(|i| rest(i, 2048)).collect();
        for block in samples.chunks(20) {
            tracker.feed(block);
        }
        assert_eq!(tracker.phase(), Phase::Tracking);
        assert_eq!(tracker.counters().samples, samples.len() as u64);
    }
}

#[test]
fn the_motion_test_is_sized_to_the_windows_blocks_at_every_rate() {
    // 1 s at 3 kHz: ticks of 15 samples, 50, 40 and 33 blocks of 4, 5 and 6 ticks; at 100 Hz
    // ticks of one sample (10 ms), 25, 20 and 16 blocks; 0.2 s at 3 kHz, 10 blocks of 4
    // ticks and fewer: too few to test.
    let bounds = |fs_hz: u32, calibration_s: f64| {
        Config {
            fs_hz,
            calibration_s,
            ..cfg()
        }
        .validate()
        .expect("valid")
        .calibrator()
        .steady_bounds_q16()
    };
    let min = imu_core::calibration::steady_min_q16;
    assert_eq!(bounds(3000, 1.0), [min(50), min(40), min(33)]);
    assert_eq!(bounds(100, 1.0), [min(25), min(20), min(16)]);
    assert_eq!(bounds(3000, 0.2), [0, 0, 0]);
    // The message names the blocks' lengths at the rate: 40, 50 and 60 ms at 100 Hz.
    let mut t = Tracker::new(&Config {
        fs_hz: 100,
        ..cfg()
    })
    .expect("valid");
    let window: Vec<[u16; 3]> = (0..100)
        .map(|i| [2048 + if i >= 50 { 4 } else { 0 }, 2048, 2048])
        .collect();
    match t.feed(&window) {
        Some(Event::Rejected { error, .. }) => {
            let text = error.to_string();
            let lengths = [
                "over 40 ms blocks",
                "over 50 ms blocks",
                "over 60 ms blocks",
            ];
            assert!(lengths.iter().all(|l| text.contains(l)), "{text}");
        }
        other => panic!("a step at 100 Hz: {other:?}"),
    }
}
