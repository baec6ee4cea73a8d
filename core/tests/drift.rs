//! Drift control through the tracker: at rest nothing moves, motion arrives whole, the bias
//! follows slow drift, and a click does not drag the cursor. Each has a control with drift
//! control off (or the freeze off) that does move.

use imu_core::testsignal::Trace;
use imu_core::{Config, ConfigError, Drift, DriftError, Tracker};

/// Deterministic noise from the core's SplitMix64 trace generator.
struct Noise(Trace);
impl Noise {
    fn next(&mut self) -> u64 {
        self.0.next_u64()
    }
    /// A code around `mid` with zero-mean noise in -2..=2 LSB (variance 1 LSB^2).
    fn code(&mut self, mid: u16) -> u16 {
        let r = self.next();
        let t = |k: u64| [-1i32, 0, 0, 1][(k & 3) as usize];
        (i32::from(mid) + t(r) + t(r >> 2)) as u16
    }
}

fn tracker(drift: Option<Drift>) -> Tracker {
    let mut t = Tracker::new(&Config {
        drift,
        ..Config::default()
    })
    .expect("valid");
    let mut n = Noise(Trace::new(1));
    let cal: Vec<[u16; 3]> = (0..3000)
        .map(|_| [n.code(2048), n.code(2048), n.code(2048)])
        .collect();
    t.feed(&cal);
    t
}

/// Feeds `f(i)` for `n` samples, draining counts every 3 samples (1 kHz); returns the sum.
fn run(t: &mut Tracker, n: usize, mut f: impl FnMut(usize) -> [u16; 3]) -> [i64; 3] {
    let mut total = [0i64; 3];
    for i in 0..n {
        t.feed(&[f(i)]);
        if i % 3 == 2 {
            for (s, c) in total.iter_mut().zip(t.take_counts()) {
                *s += i64::from(c);
            }
        }
    }
    total
}

#[test]
fn ten_minutes_at_rest_send_no_count() {
    let mut on = tracker(Some(Drift::default()));
    let mut off = tracker(None);
    let mut n1 = Noise(Trace::new(7));
    let mut n2 = Noise(Trace::new(7));
    let minutes10 = 10 * 60 * 3000;
    let a = run(&mut on, minutes10, |_| {
        [n1.code(2048), n1.code(2048), n1.code(2048)]
    });
    let b = run(&mut off, minutes10, |_| {
        [n2.code(2048), n2.code(2048), n2.code(2048)]
    });
    assert_eq!(a, [0, 0, 0]);
    assert!(on.counters().still_samples > minutes10 as u64 * 99 / 100);
    // Control: the pure integrator wanders (noise T^1.5 and the calibration's bias T^2).
    assert!(b.iter().any(|c| c.abs() > 100), "{b:?}");
}

#[test]
fn a_stroke_arrives_whole_despite_the_detector_window() {
    // Rest without noise, then +20 LSB for 0.1 s and -20 LSB for 0.1 s: velocity returns to
    // exactly zero, so the pure integrator's count is the stroke's. The detector sees the
    // step only after part of its window, and integrates that window from the start.
    let stroke = |i: usize| {
        let v = match i {
            0..=2999 => 2048,
            3000..=3299 => 2068,
            3300..=3599 => 2028,
            _ => 2048,
        };
        [v, 2048, 2048]
    };
    let mut on = tracker(Some(Drift::default()));
    let mut off = tracker(None);
    // Calibration saw +-2 LSB noise; this rest is quiet: both start from the same bias.
    let a = run(&mut on, 9000, stroke);
    let b = run(&mut off, 9000, stroke);
    assert_eq!(on.counters().motions, 1);
    // The bias the calibration left (a fraction of an LSB) integrates in the pure run during
    // the rests; drift control does not integrate the rests. Compare with that removed: the
    // pure run over the stroke's 600 samples only.
    let mut pure = tracker(None);
    let c = run(&mut pure, 600, |i| stroke(i + 3000));
    assert!(
        (a[0] - c[0]).abs() <= 1,
        "drift control {a:?}, stroke alone {c:?}"
    );
    // The stroke: A t1^2 with A = 20 LSB = 0.479 m/s^2 and t1 = 0.1 s: 4.79 mm = 150.8 counts
    // (the calibration's sub-LSB bias and the Euler rectangle rule move it by < 1 count).
    let lsb = Config::default().m_s2_per_lsb;
    let want = 20.0 * lsb * 0.01 / 0.0254 * 800.0;
    assert!((c[0] as f64 - want).abs() <= 1.0, "{c:?} vs {want}");
    assert_ne!(a, b);
}

#[test]
fn the_bias_follows_slow_drift_at_rest() {
    // The zero-g output creeps up by 1 LSB over a minute (temperature).
    let mut on = tracker(Some(Drift::default()));
    let mut off = tracker(None);
    let drift = |i: usize, n: &mut Noise| {
        let mid = if i * 2 > 60 * 3000 { 2049 } else { 2048 };
        [n.code(mid), n.code(2048), n.code(2048)]
    };
    let (mut n1, mut n2) = (Noise(Trace::new(3)), Noise(Trace::new(3)));
    let a = run(&mut on, 120 * 3000, |i| drift(i, &mut n1));
    let b = run(&mut off, 120 * 3000, |i| drift(i, &mut n2));
    assert_eq!(a, [0, 0, 0]);
    let bias = on.axes()[0].bias_q16() as f64 / 65_536.0;
    assert!((bias - 2049.0).abs() < 0.05, "bias {bias}");
    assert!(b[0].abs() > 1000, "{b:?}");
}

#[test]
fn a_click_does_not_drag_the_cursor() {
    let jolt = |i: usize| {
        let v = if (3000..3090).contains(&i) {
            if i % 10 < 5 {
                2090
            } else {
                2006
            }
        } else {
            2048
        };
        [v, v, 2048]
    };
    for (freeze, drags) in [(0.15, false), (0.0, true)] {
        let mut t = tracker(Some(Drift {
            click_freeze_s: freeze,
            ..Drift::default()
        }));
        let mut total = [0i64; 3];
        for i in 0..9000 {
            if i == 2995 {
                t.button_edge();
            }
            t.feed(&[jolt(i)]);
            for (s, c) in total.iter_mut().zip(t.take_counts()) {
                *s += i64::from(c);
            }
        }
        assert_eq!(total != [0, 0, 0], drags, "freeze {freeze}: {total:?}");
    }
}

#[test]
fn lost_samples_at_rest_do_not_move() {
    let mut t = tracker(Some(Drift::default()));
    t.feed(&[[2048; 3]; 300]);
    t.lost(500);
    assert_eq!(t.take_counts(), [0; 3]);
    assert!(t.is_still());
}

#[test]
fn drift_errors_are_named() {
    let bad = Config {
        drift: Some(Drift {
            window_s: 1.0,
            ..Drift::default()
        }),
        ..Config::default()
    };
    assert_eq!(
        bad.validate().err(),
        Some(ConfigError::Drift(DriftError::Window))
    );
    let msg = format!("{}", ConfigError::Drift(DriftError::Window));
    assert!(msg.starts_with("drift.window_s"), "{msg}");
}
