//! Drift control through the tracker: at rest nothing moves, motion arrives whole, the bias
//! follows slow drift, and a click does not drag the cursor. Each has a control with drift
//! control off (or the freeze off) that does move.

use imu_core::bench::testsignal::Trace;
use imu_core::drift::Tuning;
use imu_core::{Config, ConfigError, Drift, DriftError, DriftState, Tracker};

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
    calibrated(&Config {
        drift,
        ..Config::default()
    })
}

/// A tracker of `config`, calibrated on 1 s of the noisy rest at mid-scale.
fn calibrated(config: &Config) -> Tracker {
    let mut t = Tracker::new(config).expect("valid");
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
    // The zero-g output creeps up by 1 LSB over a minute (temperature): dithered, so the
    // mean moves smoothly.
    let mut on = tracker(Some(Drift::default()));
    let mut off = tracker(None);
    let drift = |i: usize, n: &mut Noise| {
        let frac = (i as f64 / (60.0 * 3000.0)).min(1.0);
        let up = (n.next() % 1_000_000) as f64 / 1e6 < frac;
        [n.code(2048) + u16::from(up), n.code(2048), n.code(2048)]
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
fn a_stroke_that_coasts_in_the_middle_is_not_cut_there() {
    // +20 LSB for 0.2 s, nothing for 0.3 s (the hand glides at 0.096 m/s), -20 LSB for
    // 0.2 s. The window is quiet in the middle, but the velocity is 100 times its noise:
    // the stroke goes on. Control: with every velocity "explained" it stops mid-glide.
    let stroke = |i: usize| {
        let v = match i {
            0..=2999 => 2048,
            3000..=3599 => 2068,
            3600..=4499 => 2048,
            4500..=5099 => 2028,
            _ => 2048,
        };
        [v, 2048, 2048]
    };
    let lsb = Config::default().m_s2_per_lsb;
    // a t1^2 + a t1 t_glide = 20 LSB (0.04 + 0.06) s^2 -> counts at 800 cpi.
    let want = 20.0 * lsb * (0.04 + 0.06) / 0.0254 * 800.0;
    // The pure integrator over the stroke's samples alone: the same calibrated bias.
    let mut pure = tracker(None);
    let p = run(&mut pure, 2100, |i| stroke(i + 3000));
    // The calibration's bias is off by sd 1 / sqrt(3000) = 0.018 LSB; 3 sd over 0.7 s is
    // 0.055 LSB * 0.0239 m/s^2 * 0.7^2 / 2 = 0.32 mm = 10 counts.
    assert!((p[0] as f64 - want).abs() <= 10.0, "{p:?} vs {want}");
    let mut on = tracker(Some(Drift::default()));
    let a = run(&mut on, 9000, stroke);
    // Drift control has tracked the bias during the second of quiet rest before the stroke
    // (the pure run keeps the calibration's): the same 10-count bound.
    assert!((a[0] - p[0]).abs() <= 10, "{a:?} vs {p:?}");
    assert_eq!(on.counters().motions, 1);
    let mut cut = tracker(Some(Drift {
        tuning: Tuning {
            chi2: 1e6,
            ..Tuning::default()
        },
        ..Drift::default()
    }));
    let c = run(&mut cut, 9000, stroke);
    assert!((c[0] - p[0]).abs() > 100, "{c:?} vs {p:?}");
}

#[test]
fn a_glide_goes_on_while_its_velocity_is_known_and_its_ramp_down_does_not_run_it_back() {
    // +20 LSB for 0.1 s (a ramp to 48 mm/s), a glide with no acceleration at all, then -20
    // LSB for 0.1 s (the ramp down) 2 s later. The glide's velocity is hundreds of sd from
    // zero: the cursor glides on, and the ramp down ends it where the hand stopped.
    let glide = |i: usize| {
        let v = match i {
            3000..=3299 => 2068,
            9300..=9599 => 2028,
            _ => 2048,
        };
        [v, 2048, 2048]
    };
    let lsb = Config::default().m_s2_per_lsb;
    // 0.1 s of ramp (v t / 2 each) and 2 s of glide at v = 20 LSB * 0.1 s.
    let v = 20.0 * lsb * 0.1;
    let want = (v * 0.1 + v * 2.0) / 0.0254 * 800.0;
    let mut t = tracker(Some(Drift::default()));
    let a = run(&mut t, 9000, glide);
    assert_eq!(t.drift_state(), Some(DriftState::Moving), "mid-glide");
    let b = run(&mut t, 6000, |i| glide(i + 9000));
    let total = a[0] + b[0];
    assert!(
        (total as f64 - want).abs() < 0.02 * want,
        "{total} vs {want}"
    );
    assert!(t.is_still(), "{:?}", t.drift_state());
    // Control: a stop that takes every velocity for zero cuts the glide at its start.
    let mut cut = tracker(Some(Drift {
        tuning: Tuning {
            chi2: 1e6,
            ..Tuning::default()
        },
        ..Drift::default()
    }));
    let c = run(&mut cut, 15_000, glide);
    assert!((c[0] as f64) < 0.2 * want, "{c:?} vs {want}");
}

/// Sample `i` of a noiseless glide no hand makes: +20 LSB on X for 0.1 s from 1 s, then no
/// acceleration at all, but for a jolt of +1 LSB on X for `jolt` samples from 4 s.
fn ramp_glide(i: usize, jolt: usize) -> [u16; 3] {
    let x = if (3000..3300).contains(&i) {
        2068
    } else if (12_000..12_000 + jolt).contains(&i) {
        2049
    } else {
        2048
    };
    [x, 2048, 2048]
}

#[test]
fn a_glide_no_hand_makes_stops_after_the_longest_glide_and_stroke() {
    // +20 LSB for 0.1 s (a ramp to 48 mm/s), then a glide with no acceleration at all and no
    // ramp down: hundreds of sd from zero, its velocity is explained only after tens of
    // seconds. No hand glides longer than glide_max_s (4 s), its ramps' calm ends adding at
    // most the longest stroke (2 s): after 6 s of calm it stops, the velocity dropped, and
    // nothing moves after. Control: without the bound it is still gliding 10 s later.
    let glide = |i: usize| ramp_glide(i, 0);
    let mut t = tracker(Some(Drift::default()));
    // 5.9 s of calm after the ramp: gliding.
    let a = run(&mut t, 3300 + 17_700, glide);
    assert_eq!(t.drift_state(), Some(DriftState::Moving), "{a:?}");
    // 6.1 s: stopped.
    run(&mut t, 600, |i| glide(i + 21_000));
    assert!(t.is_still(), "{:?}", t.drift_state());
    let after = run(&mut t, 30_000, |i| glide(i + 21_600));
    assert_eq!(after, [0, 0, 0]);
    // Delivered as it went (nothing held it), it is stopped, not dropped.
    assert_eq!(t.counters().discarded, 0);
}

#[test]
fn a_faded_glide_carries_its_velocity_into_the_ramp_down() {
    // A glide so slow that its own uncertainty catches it up: +1 LSB for 0.2 s on a noisy
    // rest (the calibration's noise, variance 1 LSB^2), a glide of 4.8 mm/s, and its ramp
    // down 3 s later. The glide fades (the cursor stops) and its velocity waits: the ramp
    // down brings it to zero, it does not start a motion backwards. Control: with no wait
    // (glide_max_s 0) the ramp down runs the cursor back.
    let scene = |i: usize, n: &mut Noise| {
        let v = match i {
            3000..=3599 => 2049,
            12_600..=13_199 => 2047,
            _ => 2048,
        };
        [n.code(v), n.code(2048), n.code(2048)]
    };
    for (glide_max_s, backwards) in [(4.0, false), (0.0, true)] {
        let mut t = tracker(Some(Drift {
            glide_max_s,
            ..Drift::default()
        }));
        let mut n = Noise(Trace::new(21));
        let retreat = max_retreat(&mut t, 20_000, |i| scene(i, &mut n));
        // At most 2 mm (63 counts) back, with the wait.
        assert_eq!(
            retreat > 63,
            backwards,
            "glide_max_s {glide_max_s}: retreat {retreat}"
        );
    }
}

#[test]
fn a_glide_fades_through_small_jolts_that_are_no_deceleration() {
    // The glide of `a_faded_glide_carries_its_velocity_into_the_ramp_down`, noiseless after
    // the calibration, with a small jolt on Y every 0.2 s (2 LSB for 5 ms, the sign
    // alternating: a hand's tremor, a desk's tick). Each fails the quiet test of its 20 ms
    // window (chi-square about 15 against 11.83: the velocity cannot stop there), none the
    // bound over the fade's span (16.9, the same tail for its 12.5 windows), so the glide
    // still fades and its velocity waits for the ramp down. Control: with a jolt taken for a
    // deceleration (the one-window bound) the glide never fades, its velocity is dropped at
    // the stop, and the ramp down runs the cursor back 12 mm.
    let scene = |i: usize| {
        let x = match i {
            3000..=3599 => 2049,
            12_600..=13_199 => 2047,
            _ => 2048,
        };
        let y = match i.checked_sub(3600).map(|k| (k / 600, k % 600)) {
            Some((j, 0..=14)) if j % 2 == 0 => 2050,
            Some((_, 0..=14)) => 2046,
            _ => 2048,
        };
        [x, y, 2048]
    };
    let mut t = tracker(Some(Drift::default()));
    let retreat = max_retreat(&mut t, 20_000, scene);
    // At most 2 mm (63 counts) back.
    assert!(retreat <= 63, "retreat {retreat}");
}

/// The largest retreat of the cursor's X below its running maximum over `n` samples.
fn max_retreat(t: &mut Tracker, n: usize, f: impl FnMut(usize) -> [u16; 3]) -> i64 {
    drag_run(t, n, (0, n, 1), f).0
}

/// Over `n` samples of `f`, the counts along `dir` X (+1 or -1) delivered from sample `from`
/// on: their largest pull-back below their running maximum, and their sum by sample `at`.
fn drag_run(
    t: &mut Tracker,
    n: usize,
    (from, at, dir): (usize, usize, i64),
    mut f: impl FnMut(usize) -> [u16; 3],
) -> (i64, i64) {
    let (mut pos, mut best, mut retreat, mut then) = (0i64, 0i64, 0i64, 0i64);
    for i in 0..n {
        t.feed(&[f(i)]);
        if i % 3 == 2 {
            let c = dir * i64::from(t.take_counts()[0]);
            if i >= from {
                pos += c;
                best = best.max(pos);
                retreat = retreat.max(best - pos);
            }
        }
        if i == at {
            then = pos;
        }
    }
    (retreat, then)
}

#[test]
fn a_tilt_stops_within_half_a_second_and_becomes_the_new_zero() {
    // Rest, then the desk tilts by 2 degrees within 0.1 s (X reads 14 LSB more) and stays.
    // The cursor runs while the tilt builds and for rest_s after; then it stops (held), and
    // rest_s later the tilt is the new zero.
    let tilt = |i: usize, n: &mut Noise| {
        let f = ((i as f64 - 3000.0) / 300.0).clamp(0.0, 1.0);
        [
            n.code(2048 + (14.0 * f).round() as u16),
            n.code(2048),
            n.code(2048),
        ]
    };
    let mut t = tracker(Some(Drift::default()));
    let mut n = Noise(Trace::new(5));
    let runaway = run(&mut t, 3300 + 1500, |i| tilt(i, &mut n));
    assert!(runaway[0] > 0, "{runaway:?}");
    assert!(t.is_holding(), "0.5 s after the tilt its motion is held");
    let after = run(&mut t, 30_000, |i| tilt(i + 4800, &mut n));
    assert_eq!(after, [0, 0, 0]);
    assert!(t.is_still(), "{:?}", t.drift_state());
    assert!(!t.is_holding(), "at rest nothing is held");
    assert_eq!(t.counters().rebiases, 1);
    let bias = t.axes()[0].bias_q16() as f64 / 65_536.0;
    assert!((bias - 2062.0).abs() < 0.1, "bias {bias}");
}

#[test]
fn a_lift_and_a_tilted_landing_do_not_move_the_cursor() {
    // Lifted 2 cm in 0.3 s (Z: +54, -54 LSB), tilted by 3 degrees while in the air, set
    // down: X reads +21 LSB from then on. Control: without lift detection it moves.
    let lift = |i: usize, n: &mut Noise| {
        let (x, z) = match i {
            0..=2999 => (2048, 2048),
            3000..=3449 => (2048 + ((i - 3000) / 20) as u16, 2102),
            3450..=3899 => (2069, 1994),
            _ => (2069, 2048),
        };
        [n.code(x), n.code(2048), n.code(z)]
    };
    for (detect, moves) in [(Some(0.5), false), (None, true)] {
        let mut t = tracker(Some(Drift {
            lift_rise_s: detect,
            ..Drift::default()
        }));
        let mut n = Noise(Trace::new(9));
        let a = run(&mut t, 15_000, |i| lift(i, &mut n));
        let moved = a[0].abs() + a[1].abs();
        // 160 counts = 5 mm, issue 22's bound per re-placement. The tilt in the air begins
        // with the rise: what X integrates before the lift is seen (its persistence, 25 ms)
        // is a few counts.
        assert_eq!(moved > 160, moves, "lift {detect:?}: {a:?}");
        if !moves {
            assert!(moved <= 5, "{a:?}");
            assert_eq!((t.counters().lifts, t.counters().rebiases), (1, 1));
            assert!(t.is_still());
        }
    }
}

/// A lift (Z +54 then -54 LSB over 0.3 s), 0.2 s in the air, a fall begun (Z -54 LSB for
/// 0.15 s), then Z `level` LSB off its zero for `hold` samples with X and Y at theirs, then
/// the fall's end that brings the device to rest (+54 LSB for 0.15 s, plus what undoes the
/// level's velocity), and rest at the old zeros; and the offset's samples' span.
fn falling_at(level: i32, hold: usize) -> impl Fn(usize, &mut Noise) -> [u16; 3] {
    let end = 4950 + hold;
    let back = -level * hold as i32 / 450;
    move |i: usize, n: &mut Noise| {
        let z = match i {
            3000..=3449 => 54,
            3450..=3899 | 4500..=4949 => -54,
            _ if (4950..end).contains(&i) => level,
            _ if (end..end + 450).contains(&i) => 54 + back,
            _ => 0,
        };
        [n.code(2048), n.code(2048), n.code((2048 + z) as u16)]
    }
}

#[test]
fn a_fall_whose_thirds_agree_is_not_a_rest_unless_it_lasts() {
    // A fall's accelerations can average alike over the landing window's thirds (the lab's
    // lifts:50, seed 1: 8 LSB below the zero on Z, 56 ms before the fall ended); here Z
    // holds 8 LSB below its zero for 0.4 s with X and Y at theirs. At rest gravity gives
    // Z = -|delta|^2 / (2 g) = 0 for that: not a rest, so the device lands only after the
    // fall's end, at the old zeros. Control: without the gravity test it lands at the
    // offset (a new zero 8 LSB off), is lifted again by the fall's end and lands again.
    let mut t = tracker(Some(Drift::default()));
    let mut n = Noise(Trace::new(17));
    let f = falling_at(-8, 1200);
    let a = run(&mut t, 15_000, |i| f(i, &mut n));
    let c = t.counters();
    assert_eq!((c.lifts, c.rebiases), (1, 0), "{c:?}");
    assert_eq!(a, [0, 0, 0]);
    assert!(t.is_still());
    // Held at such a level for longer than the longest stroke since the lift (the fall's
    // end 4 s later), it is taken as a rest (a pad steeper than the test allows for, a
    // scale configured wrong): a landing at 2 s since the lift, then the fall's end is a
    // new lift.
    let mut t = tracker(Some(Drift::default()));
    let f = falling_at(-8, 12_000);
    run(&mut t, 3000 + 3 * 2000, |i| f(i, &mut n));
    assert!(!t.is_still(), "{:?}", t.drift_state());
    run(&mut t, 3000, |i| f(i + 9000, &mut n));
    assert!(t.is_still(), "{:?}", t.drift_state());
    assert_eq!(t.counters().rebiases, 1);
}

#[test]
fn a_hand_that_moves_a_falling_device_does_not_land_it() {
    // The fall of `a_fall_whose_thirds_agree_is_not_a_rest_unless_it_lasts`, Z 8 LSB below
    // its zero for 0.5 s, and within it a stroke on X (+20 LSB for 0.1 s, -20 for 0.1 s,
    // from 0.25 s into the offset): the window's first two thirds agree, its last differs on
    // X only, as when a hand moves the device just after a set-down. But Z's level is not
    // one gravity gives at rest: the device is still in the air, and neither lands nor
    // starts a motion until the fall ends. Control: without the gravity test it lands at the
    // offset (a new zero) and starts the stroke.
    let fall = falling_at(-8, 1500);
    let scene = |i: usize, n: &mut Noise| {
        let mut c = fall(i, n);
        c[0] = match i {
            5700..=5999 => n.code(2068),
            6000..=6299 => n.code(2028),
            _ => c[0],
        };
        c
    };
    let mut t = tracker(Some(Drift::default()));
    let mut n = Noise(Trace::new(23));
    run(&mut t, 15_000, |i| scene(i, &mut n));
    let c = t.counters();
    assert_eq!((c.lifts, c.rebiases, c.motions), (1, 0, 0), "{c:?}");
    assert!(t.is_still());
}

#[test]
fn a_device_held_still_in_the_air_lands_only_after_a_fall_or_the_longest_stroke() {
    // Lifted 2 cm in 0.3 s (Z: +54, -54 LSB) and held still in the air for `hover` samples,
    // then set down in 0.3 s (-54, +54). Held still, the device reads what it read on the
    // desk: only the fall tells the two apart, so it stays lifted through a 1 s hover and
    // lands 0.26 s after the fall (the landing window). Held 3 s, it lands at the longest
    // stroke's time since the lift (2 s: a set-down too gentle to be seen), and the fall
    // that follows is a new lift. Controls: landing without the fall lands in the hover;
    // the fall's velocity integrated with the wrong sign, or tested against the rise's
    // direction, never sees it.
    let scene = |hover: usize| {
        move |i: usize, n: &mut Noise| {
            let fall = 3900 + hover;
            let z = match i {
                3000..=3449 => 2102,
                3450..=3899 => 1994,
                _ if (fall..fall + 450).contains(&i) => 1994,
                _ if (fall + 450..fall + 900).contains(&i) => 2102,
                _ => 2048,
            };
            [n.code(2048), n.code(2048), n.code(z)]
        }
    };
    let lifted = |t: &Tracker| t.drift_state() == Some(DriftState::Lifted);
    let mut t = tracker(Some(Drift::default()));
    let mut n = Noise(Trace::new(29));
    let f = scene(3000);
    run(&mut t, 6900, |i| f(i, &mut n));
    assert!(lifted(&t), "{:?}", t.drift_state());
    // The fall ends at 7800; the window is steady 0.26 s later.
    run(&mut t, 1800, |i| f(i + 6900, &mut n));
    assert!(t.is_still(), "{:?}", t.drift_state());
    assert_eq!((t.counters().lifts, t.counters().rebiases), (1, 0));
    let mut t = tracker(Some(Drift::default()));
    let f = scene(9000);
    // The lift is seen about 0.1 s after it began (3000): 2 s later is about 9300.
    run(&mut t, 9000, |i| f(i, &mut n));
    assert!(lifted(&t), "{:?}", t.drift_state());
    run(&mut t, 1500, |i| f(i + 9000, &mut n));
    assert!(t.is_still(), "{:?}", t.drift_state());
    // The fall, 3 s after the lift's end (12 900 to 13 800).
    run(&mut t, 3900, |i| f(i + 10_500, &mut n));
    assert_eq!(t.counters().lifts, 2);
}

#[test]
fn a_set_down_on_a_steep_slope_lands_at_once() {
    // Lifted 2 cm in 0.3 s (Z: +54, -54 LSB), 0.2 s in the air, set down in 0.3 s onto a
    // 15 degree slope about Y: X reads g sin 15 = +106 LSB and Z g (cos 15 - 1) = -14 LSB
    // from then on (g = 409.6 LSB). Gravity gives that rest, Z = -|delta|^2 / (2 g), so the
    // device lands as soon as the landing window is steady (0.26 s), at the new zeros.
    // Control: taking Z's curvature for zero leaves it 14 LSB off, more than the mounting's
    // allowance (sin 5 degrees of 106 LSB, 9.2) and the noise allow: the landing waits for
    // the longest stroke's time since the lift (2 s).
    let scene = |i: usize, n: &mut Noise| {
        let (x, z) = match i {
            3000..=3449 | 4950..=5399 => (2048, 2102),
            3450..=3899 | 4500..=4949 => (2048, 1994),
            5400.. => (2154, 2034),
            _ => (2048, 2048),
        };
        [n.code(x), n.code(2048), n.code(z)]
    };
    let mut t = tracker(Some(Drift::default()));
    let mut n = Noise(Trace::new(19));
    let a = run(&mut t, 5400 + 1500, |i| scene(i, &mut n));
    assert!(t.is_still(), "{:?}", t.drift_state());
    assert_eq!((t.counters().lifts, t.counters().rebiases), (1, 1));
    assert_eq!(a, [0, 0, 0]);
    let bias = t.axes()[2].bias_q16() as f64 / 65_536.0;
    assert!((bias - 2034.0).abs() < 0.2, "Z's zero {bias}");
}

/// A minimum-jerk step's acceleration at `u` of its span (`60 u - 180 u^2 + 120 u^3`, zero
/// outside `[0, 1)`), per metre over the span squared.
fn step_accel(u: f64) -> f64 {
    if (0.0..1.0).contains(&u) {
        60.0 * u - 180.0 * u * u + 120.0 * u * u * u
    } else {
        0.0
    }
}

/// The vertical acceleration [m/s^2] at `time` [s] of `lifts`, each `(start, height, rise,
/// air, fall)` [s, m]: minimum-jerk up and down.
fn lifts_accel(lifts: &[(f64, f64, f64, f64, f64)], time: f64) -> f64 {
    lifts
        .iter()
        .map(|&(t0, h, up, air, down)| {
            h / (up * up) * step_accel((time - t0) / up)
                - h / (down * down) * step_accel((time - t0 - up - air) / down)
        })
        .sum()
}

/// A tilt of `deg` degrees about the horizontal axis at `az` degrees [rad, about Y and X].
fn tilt_deg(deg: f64, az: f64) -> [f64; 2] {
    let (d, az) = (deg.to_radians(), az.to_radians());
    [d * az.cos(), d * az.sin()]
}

/// The tilt [rad, about Y and X] at `time` [s] of a lift `(start, rise, air, fall)` [s] that
/// the hand tilts from level to `wobble` over the rise and the first half of the air, and
/// from there to `slope` over the rest of the air and the set-down.
fn wobble_tilt(
    time: f64,
    lift: (f64, f64, f64, f64),
    wobble: [f64; 2],
    slope: [f64; 2],
) -> [f64; 2] {
    let (t0, up, air, down) = lift;
    let (turn, touch) = (t0 + up + air / 2.0, t0 + up + air + down);
    core::array::from_fn(|j| {
        wobble[j] * ramp((time - t0) / (turn - t0))
            + (slope[j] - wobble[j]) * ramp((time - turn) / (touch - turn))
    })
}

/// What gravity adds to each axis [m/s^2] with the device tilted by `tilt` [rad, about Y and
/// X] from level: `g sin` into X and Y, `g (cos cos - 1)` on Z.
fn gravity(tilt: [f64; 2]) -> [f64; 3] {
    const G: f64 = 9.80665;
    let [x, y] = tilt;
    [G * x.sin(), G * y.sin(), G * (x.cos() * y.cos() - 1.0)]
}

/// The cursor's counts on X and Y, polled every third sample (1 kHz at 3 kHz), and where it
/// was before a stroke.
#[derive(Default)]
struct Cursor {
    pos: [i64; 2],
    before: [i64; 2],
}

impl Cursor {
    /// After sample `i`: takes the counts on a poll, and keeps the position while `before`
    /// the stroke.
    fn poll(&mut self, t: &mut Tracker, i: usize, before: bool) {
        if i % 3 == 2 {
            let c = t.take_counts();
            self.pos = [self.pos[0] + i64::from(c[0]), self.pos[1] + i64::from(c[1])];
        }
        if before {
            self.before = self.pos;
        }
    }

    /// How far the cursor moved before the stroke, and how far the stroke's own counts end
    /// from a stroke of `d` m at `dir` rad [mm] (800 counts per inch).
    fn judge(&self, d: f64, dir: f64) -> (f64, f64) {
        let mm = |p: i64| p as f64 * 25.4 / 800.0;
        let [x, y] = [0, 1].map(|a| mm(self.pos[a] - self.before[a]));
        let error = (x - d * 1000.0 * dir.cos()).hypot(y - d * 1000.0 * dir.sin());
        (mm(self.before[0]).hypot(mm(self.before[1])), error)
    }
}

/// A lift of `h` m from 1.5 s into tracking, rising over `up` s, `air` s in the air, set
/// down over `down` s, then a stroke of `d` m over `dur` s at `deg` degrees `gap` s later
/// (minimum-jerk steps), on [`noisy_code`]`(.., k)`'s noise, noise draw `seed`: how far the
/// cursor moved before the stroke, and how far the stroke's own counts end from it [mm].
/// The hand tilts the device (about Y and X [rad]: `g sin` into X and Y, `g cos cos` on Z)
/// from level to `wobble` over the rise and the first half of the air, and from there to
/// `slope` over the rest of the air and the set-down.
struct LiftThenStroke {
    h: f64,
    up: f64,
    air: f64,
    down: f64,
    gap: f64,
    d: f64,
    dur: f64,
    deg: f64,
    k: usize,
    wobble: [f64; 2],
    slope: [f64; 2],
}

/// A new user's gentle flat set-down (`liftflat_312`): 14.2 mm up over 0.161 s, 0.244 s in
/// the air, down over 0.49 s, and a 47.6 mm stroke over 0.533 s at 55 degrees 1.94 s later,
/// with 4.8 LSB of noise a sample (303 ug/sqrt(Hz)).
const GENTLE_SET_DOWN: LiftThenStroke = LiftThenStroke {
    h: 0.0142,
    up: 0.161,
    air: 0.244,
    down: 0.49,
    gap: 1.94,
    d: 0.0476,
    dur: 0.533,
    deg: 55.0,
    k: 2,
    wobble: [0.0; 2],
    slope: [0.0; 2],
};

impl LiftThenStroke {
    fn run(&self, seed: u64) -> (f64, f64) {
        let Self {
            h,
            up,
            air,
            down,
            gap,
            d,
            dur,
            deg,
            k,
            wobble,
            slope,
        } = *self;
        let lsb = Config::default().m_s2_per_lsb;
        let (mut n, mut t) = noisy_calibrated(seed, k);
        let (t0, dir) = (1.5, deg.to_radians());
        let t1 = t0 + up + air;
        let s0 = t1 + down + gap;
        let mut cursor = Cursor::default();
        for i in 0..((s0 + dur + 1.5) * 3000.0) as usize {
            let time = i as f64 / 3000.0;
            let z = lifts_accel(&[(t0, h, up, air, down)], time);
            let a = d / (dur * dur) * step_accel((time - s0) / dur) / lsb;
            let g = gravity(wobble_tilt(time, (t0, up, air, down), wobble, slope));
            t.feed(&[[
                noisy_code(&mut n, 2048.0 + a * dir.cos() + g[0] / lsb, k),
                noisy_code(&mut n, 2048.0 + a * dir.sin() + g[1] / lsb, k),
                noisy_code(&mut n, 2048.0 + (z + g[2]) / lsb, k),
            ]]);
            cursor.poll(&mut t, i, time < s0);
        }
        cursor.judge(d, dir)
    }
}

#[test]
fn a_gentle_flat_set_down_lands_at_its_zero_and_the_next_stroke_arrives() {
    // The landing allows for the disturbance measured as it decides, not at the lift, where
    // the rise's own motion counted as one. Eight noise draws: each re-placement moves nothing and each
    // stroke ends within max(5 %, 3 floors) = 2.4 mm (the floor `ND T^1.5 / sqrt 6` = 0.25
    // mm). Control: with the disturbance measured at the lift allowed for (the rise read as
    // 17 LSB a sample on Z), the descent's tail passed as steady, the Z zero was taken 5.7
    // LSB off, a false lift followed 0.3 s later, and all eight strokes were lost (47.6 mm
    // off).
    for seed in 0..8 {
        let (moved, error) = GENTLE_SET_DOWN.run(seed);
        assert!(
            moved <= 5.0,
            "draw {seed}: the re-placement moved {moved:.1} mm"
        );
        assert!(
            error <= 0.05 * 47.6,
            "draw {seed}: the stroke ended {error:.1} mm off"
        );
    }
}

#[test]
fn a_set_down_seen_without_its_lift_is_its_own_fall() {
    // A rise over 1.2 s moves the device 5 mm up too slowly for the lift test (its window
    // is sized for rises up to 0.5 s); the set-down over 0.15 s is seen, as a displacement
    // down. A device can go down only from above the desk: that is the fall, and the
    // landing follows as soon as its window is steady. Four noise draws: the device moves
    // nothing and the stroke 0.5 s after the set-down ends within max(5 %, 3 floors) = 2.4
    // mm. Control: waiting for a fall after the set-down (the device would have to rise
    // again), the device stayed lifted for the longest stroke's time and the strokes were
    // lost (47.6 mm off).
    for seed in 0..4 {
        // 5 mm up over 1.2 s, 0.3 s in the air, down over 0.15 s; the stroke 0.5 s later.
        let scene = LiftThenStroke {
            h: 0.005,
            up: 1.2,
            air: 0.3,
            down: 0.15,
            gap: 0.5,
            ..GENTLE_SET_DOWN
        };
        let (moved, error) = scene.run(seed);
        assert!(moved <= 5.0, "draw {seed}: moved {moved:.1} mm");
        assert!(
            error <= 0.05 * 47.6,
            "draw {seed}: the stroke ended {error:.1} mm off"
        );
    }
}

#[test]
fn a_tilt_in_the_air_undone_at_the_set_down_leaves_the_next_stroke_whole() {
    // A new user's lifts (`tiltair_08`, `tiltair_07`): the hand tilts the device by 8 degrees
    // in the air and back onto a 3.5 degree slope as it sets it down. The tilt takes
    // `g (1 - cos 8 deg)` = 0.095 m/s^2 off Z, which the fall test reads as a fall (it is
    // not sure: a rotation can give it), and the device, held still, lands in the air at the
    // tilted level. The set-down then turns it back: its descent's window reads as a rise
    // (08) or a descent (07), and the gravity test, which allows `r` for the old rest's
    // orientation, is asked about a level 8 degrees off the desk's. Four noise draws each:
    // nothing moves, and the stroke 1.3-1.8 s after the touch ends within max(5 %, 3 floors)
    // = 2.5 mm. Controls: waiting for a fall after the rise the set-down reads as (08), or
    // allowing only `r` for the landing in doubt (07), the device stayed lifted for the
    // longest stroke's time and every stroke was lost (50 mm off).
    for (name, scene) in [
        (
            "08",
            LiftThenStroke {
                h: 0.0051,
                up: 0.248,
                air: 0.725,
                down: 0.251,
                gap: 1.83,
                d: 0.05,
                dur: 0.5,
                deg: 20.0,
                k: 2,
                wobble: tilt_deg(8.0, 200.0),
                slope: tilt_deg(3.46, 75.7),
            },
        ),
        (
            "07",
            LiftThenStroke {
                h: 0.0115,
                up: 0.42,
                air: 0.68,
                down: 0.207,
                gap: 1.29,
                d: 0.05,
                dur: 0.5,
                deg: 20.0,
                k: 2,
                wobble: tilt_deg(8.2, 300.0),
                slope: tilt_deg(3.75, 47.8),
            },
        ),
    ] {
        for seed in 0..4 {
            let (moved, error) = scene.run(seed);
            assert!(moved <= 5.0, "{name}, draw {seed}: moved {moved:.1} mm");
            assert!(
                error <= 2.5,
                "{name}, draw {seed}: the stroke ended {error:.1} mm off"
            );
        }
    }
}

#[test]
fn a_lift_without_a_turn_soon_after_a_landing_in_doubt_waits_for_its_fall() {
    // The lab's `lifts` trial 108, seed 6: a 5 mm lift wobbling to 8.9 degrees in the air and
    // set down gently on a 3.6 degree slope (its fall not sure: a landing in doubt), then, 2 s
    // after the touch, an 8.8 mm lift straight up that tilts back to level only as it lands.
    // Its rise is no set-down: nothing turns in its window, so it waits for its fall, and the
    // device lands on the desk. Four noise draws: the cursor stays within 5 mm (target 3).
    // Control: taking any rise in the doubt as its own fall, the device landed in the air
    // 0.25 s later, and the tilt as it set down went out as motion (8.9 mm; 7.4 in the lab's
    // trial).
    let lsb = Config::default().m_s2_per_lsb;
    let rad = |d: [f64; 2]| d.map(f64::to_radians);
    // (start, height, rise, air, fall), both lifts.
    let lifts = [
        (1.5, 0.005, 0.317, 0.164, 0.348),
        (4.329, 0.0088, 0.19, 0.294, 0.167),
    ];
    let (wobble, slope) = (rad([-4.6, -7.61]), rad([-3.17, 1.75]));
    let tilt = |t: f64| -> [f64; 2] {
        let (t0, _, up, air, down) = lifts[0];
        if t < lifts[1].0 {
            wobble_tilt(t, (t0, up, air, down), wobble, slope)
        } else {
            let (t0, _, up, air, down) = lifts[1];
            let u = ramp((t - (t0 + up + air + down / 2.0)) / (down / 2.0));
            slope.map(|a| a * (1.0 - u))
        }
    };
    for seed in 0..4 {
        let (mut n, mut t) = noisy_calibrated(seed, 2);
        let mut cursor = Cursor::default();
        for i in 0..(7.0 * 3000.0) as usize {
            let time = i as f64 / 3000.0;
            let z = lifts_accel(&lifts, time);
            let g = gravity(tilt(time));
            t.feed(&[[
                noisy_code(&mut n, 2048.0 + g[0] / lsb, 2),
                noisy_code(&mut n, 2048.0 + g[1] / lsb, 2),
                noisy_code(&mut n, 2048.0 + (z + g[2]) / lsb, 2),
            ]]);
            cursor.poll(&mut t, i, true);
        }
        let (moved, _) = cursor.judge(0.0, 0.0);
        assert!(moved <= 5.0, "draw {seed}: moved {moved:.1} mm");
    }
}

/// A re-placement from 1.5 s into tracking (`first`: height [m], rise, air and fall [s]),
/// the hand tilting the device to `wobble` [rad, about Y and X] over the rise and the first
/// half of the air and onto `slope` over the rest and the fall; then, `gap` s after the touch,
/// a hesitant one: 10 mm up over 0.25 s while the hand starts to carry the device 30 mm to the
/// right over 0.4 s, 0.5 s still in the air, 30 mm more over 0.4 s, down over 0.25 s; 1 s at
/// rest. [`noisy_code`]`(.., 2)`'s noise, draw `seed`. How far the cursor moved [mm].
fn replacement_then_carry(
    first: (f64, f64, f64, f64),
    wobble: [f64; 2],
    slope: [f64; 2],
    gap: f64,
    seed: u64,
) -> f64 {
    let lsb = Config::default().m_s2_per_lsb;
    let (h, up, air, down) = first;
    let t0 = 1.5;
    let t2 = t0 + up + air + down + gap;
    // (start, height, rise, air, fall) and (start, distance, duration) [s, m].
    let lifts = [(t0, h, up, air, down), (t2, 0.01, 0.25, 1.3, 0.25)];
    let carries = [(t2, 0.03, 0.4), (t2 + 0.9, 0.03, 0.4)];
    let (mut n, mut t) = noisy_calibrated(seed, 2);
    let mut cursor = Cursor::default();
    for i in 0..((t2 + 2.8) * 3000.0) as usize {
        let time = i as f64 / 3000.0;
        let z = lifts_accel(&lifts, time);
        let x: f64 = carries
            .iter()
            .map(|&(t0, d, dur)| d / (dur * dur) * step_accel((time - t0) / dur))
            .sum();
        let g = gravity(wobble_tilt(time, (t0, up, air, down), wobble, slope));
        t.feed(&[[
            noisy_code(&mut n, 2048.0 + (x + g[0]) / lsb, 2),
            noisy_code(&mut n, 2048.0 + g[1] / lsb, 2),
            noisy_code(&mut n, 2048.0 + (z + g[2]) / lsb, 2),
        ]]);
        cursor.poll(&mut t, i, true);
    }
    cursor.judge(0.0, 0.0).0
}

#[test]
fn a_lift_waits_for_its_own_fall_unless_the_last_landing_is_in_doubt() {
    // A hand that lifts while carrying sideways turns the lift window's X (the carry's
    // acceleration) as a set-down after a landing in the air turns it (its rotation); pausing
    // in the air, it would land there and the rest of the carry would go out. So only a
    // landing in doubt (a new zero after a fall a rotation could have given) makes such a
    // rise its own fall, and only while the motions after it are wary (the longest stroke's
    // time). Two scenes, the hesitant carry after (a) a quick re-placement onto a 3 degree
    // slope (2 cm up over 0.15 s, 0.1 s in the air, down over 0.15 s: its fall is sure),
    // 1 s later, and (b) a gentle one that wobbles to 6 degrees in the air onto the same
    // slope (5 mm over 0.3 s, 0.3 s in the air, down over 0.35 s: in doubt), 3 s later.
    // Four noise draws each: the cursor stays within 5 mm (target 3). Controls: with every
    // landing in doubt, (a) landed in the air as the hand paused and the second carry went
    // out; with the doubt kept after the wary time, (b) did.
    let slope = tilt_deg(3.0, 40.0);
    for (name, first, wobble, gap) in [
        ("sure", (0.02, 0.15, 0.1, 0.15), slope, 1.0),
        (
            "in doubt",
            (0.005, 0.3, 0.3, 0.35),
            tilt_deg(6.0, 250.0),
            3.0,
        ),
    ] {
        for seed in 0..4 {
            let moved = replacement_then_carry(first, wobble, slope, gap, seed);
            assert!(moved <= 5.0, "{name}, draw {seed}: moved {moved:.1} mm");
        }
    }
}

/// A re-placement with a carry in the air, then a stroke: calibrated at rest on a desk
/// sloping by `from` [rad, about Y and X]; from 1.5 s into tracking, `h` m up over 0.25 s
/// while the hand tilts the device from there to `tilt`,
/// still there for `hover` s, carried `carry` m along X over `carry_s` s (a world-horizontal
/// acceleration: `a cos` on X, `-a sin` on Z), set down over `down` s from `pause` s after
/// the carry's end (negative: while it ends) while the hand turns the device to `slope`; then,
/// 1 s after the touch, a 40 mm stroke over 0.6 s at 60 degrees; 1.5 s at rest.
/// [`noisy_code`]`(.., 2)`'s noise.
struct CarryThenStroke {
    from: [f64; 2],
    h: f64,
    tilt: [f64; 2],
    hover: f64,
    carry: f64,
    carry_s: f64,
    pause: f64,
    down: f64,
    slope: [f64; 2],
}

/// The nineteenth tester's `hover` family: 10 mm up, tilted by 8 degrees and held 0.6 s, a
/// 50 mm carry over 0.4 s, set down level over 0.25 s as it ends.
const HOVER: CarryThenStroke = CarryThenStroke {
    from: [0.0; 2],
    h: 0.01,
    tilt: [0.1209, 0.0698],
    hover: 0.6,
    carry: 0.05,
    carry_s: 0.4,
    pause: -0.1,
    down: 0.25,
    slope: [0.0; 2],
};

impl CarryThenStroke {
    /// Noise draw `seed`: how far the cursor moved before the stroke, how far the stroke's
    /// counts end from it, and how far they were from it 0.4 s after its end [mm].
    fn run(&self, seed: u64) -> (f64, f64, f64) {
        let lsb = Config::default().m_s2_per_lsb;
        let (t0, up) = (1.5, 0.25);
        let c0 = t0 + up + self.hover;
        let fall = c0 + self.carry_s + self.pause;
        let touch = fall + self.down;
        let (s0, d, dur, dir) = (touch + 1.0, 0.04, 0.6, 60f64.to_radians());
        let lift = [(t0, self.h, up, fall - t0 - up, self.down)];
        let mut n = Noise(Trace::new(seed));
        let mut t = Tracker::new(&Config::default()).expect("valid");
        let desk = gravity(self.from);
        let cal: Vec<[u16; 3]> = (0..3000)
            .map(|_| core::array::from_fn(|a| noisy_code(&mut n, 2048.0 + desk[a] / lsb, 2)))
            .collect();
        t.feed(&cal);
        let mut cursor = Cursor::default();
        let mut late = f64::NAN;
        for i in 0..((s0 + dur + 1.5) * 3000.0) as usize {
            let time = i as f64 / 3000.0;
            if i == ((s0 + dur + 0.4) * 3000.0) as usize {
                late = cursor.judge(d, dir).1;
            }
            let (u, v) = (ramp((time - t0) / up), ramp((time - fall) / self.down));
            let [tx, ty]: [f64; 2] = core::array::from_fn(|j| {
                self.from[j]
                    + (self.tilt[j] - self.from[j]) * u
                    + (self.slope[j] - self.tilt[j]) * v
            });
            let c =
                self.carry / (self.carry_s * self.carry_s) * step_accel((time - c0) / self.carry_s);
            let a = d / (dur * dur) * step_accel((time - s0) / dur);
            let g = gravity([tx, ty]);
            let z = lifts_accel(&lift, time) - c * tx.sin();
            t.feed(&[[
                noisy_code(
                    &mut n,
                    2048.0 + (c * tx.cos() + a * dir.cos() + g[0]) / lsb,
                    2,
                ),
                noisy_code(&mut n, 2048.0 + (a * dir.sin() + g[1]) / lsb, 2),
                noisy_code(&mut n, 2048.0 + (z + g[2]) / lsb, 2),
            ]]);
            cursor.poll(&mut t, i, time < s0);
        }
        let (moved, error) = cursor.judge(d, dir);
        (moved, error, late)
    }
}

#[test]
fn a_carry_after_a_tilted_pause_in_the_air_is_dropped_at_its_set_down() {
    // Held still in the air tilted by 8 degrees, the device lands there: the tilt's
    // `g (1 - cos)` reads as a fall a rotation could give (a landing in doubt), and at rest
    // the sensor cannot tell the air from a gentle set-down on a slope. What follows can: the
    // carry is held until it stops, and the set-down, seen as its own fall, drops it; had
    // the device been on the desk the carry would have been a stroke, delivered at its stop.
    // Three re-placements: set down as the carry ends, 0.15 s after it stopped in the air
    // (what a motion after a landing in doubt moved is held until the slowest rise plus `P`
    // after its stop, 0.53 s), and lifted from a 4 degree slope, tilted on to 10 degrees and
    // set back on the slope (there the old rest's orientation, 4 degrees off Z, puts `u0 .
    // delta` into Z beyond the curvature: 0.075 m/s^2). Four noise draws each: the cursor
    // stays within 5 mm, and after the level set-downs the stroke 1 s after the touch ends
    // within max(5 %, 3 floors) = 2 mm (after the one on a slope it is the after-tilt
    // family's, 90 % within: draws 0 and 2 end 2.2 and 2.5 mm off, 2.04 allowed). Controls:
    // releasing the carry when its acceleration reverses, as after a tilt, it went out (51
    // mm); without the hold after the stop, the one set down after the pause did (51 mm);
    // without `r (|v_x| + |v_y|)` in the rotation's share, from the slope one draw's carry
    // went out (40.7 mm) and two lost the stroke after it (40 mm off).
    let slope = tilt_deg(4.0, 30.0);
    let from_a_slope = CarryThenStroke {
        from: slope,
        tilt: tilt_deg(10.0, 30.0),
        slope,
        ..HOVER
    };
    for (name, scene, level) in [
        ("as it ends", HOVER, true),
        (
            "after a pause",
            CarryThenStroke {
                pause: 0.15,
                ..HOVER
            },
            true,
        ),
        ("from a slope", from_a_slope, false),
    ] {
        for seed in 0..4 {
            let (moved, error, _) = scene.run(seed);
            assert!(moved <= 5.0, "{name}, draw {seed}: moved {moved:.1} mm");
            assert!(
                !level || error <= 0.05 * 40.0,
                "{name}, draw {seed}: the stroke ended {error:.1} mm off"
            );
        }
    }
}

#[test]
fn a_carry_in_the_air_leaves_its_set_down_on_a_slope_sure() {
    // A re-placement onto a 3 degree slope that the hand tilts to as it lifts: 20 mm up over
    // 0.25 s, carried 50 mm over 0.3 s at once, set down over 0.25 s as the carry ends. The
    // old rest's orientation within `mount_tilt_deg` of Z puts up to `r` of the horizontal
    // velocity into Z's (`u0 . v`), not `r` of every tick's acceleration summed: the carry's
    // ends cancel. So its fall is sure, and the stroke 1 s after the touch goes out as it is
    // made. Four noise draws: the re-placement moves nothing, and 0.4 s after its end the
    // stroke has arrived as it ends (its stop is within 30 ms of the end, the speed a
    // minimum-jerk stroke ends with is zero, and a late bridge comes 0.32 s after the stop):
    // within 0.1 mm, three counts. Control: with `r (|o_x| + |o_y|)` summed over the
    // ticks, the landing was in doubt, the stroke was held until 0.53 s after its stop, and
    // 0.4 s after its end the cursor had not moved (40 mm off) on each draw.
    let slope = tilt_deg(3.0, 45.0);
    let scene = CarryThenStroke {
        h: 0.02,
        tilt: slope,
        hover: 0.0,
        carry_s: 0.3,
        pause: -0.15,
        slope,
        ..HOVER
    };
    for seed in 0..4 {
        let (moved, error, late) = scene.run(seed);
        assert!(moved <= 5.0, "draw {seed}: moved {moved:.1} mm");
        assert!(
            (late - error).abs() <= 0.1,
            "draw {seed}: 0.4 s after its end {late:.1} mm off, at last {error:.1}"
        );
    }
}

/// A lift of 2 cm in 0.3 s (Z +54 then -54 LSB) at 2 s into tracking, 0.2 s in the air, set
/// down over 0.3 s (at 2.8 s), on a desk a machine shakes with 48 mg at 30 Hz on every axis
/// from `machine` s (ramped in over 0.2 s), [`noisy_code`]`(.., 1)`'s noise (3.4 LSB a
/// sample), noise draw `seed`; a 20 mm stroke over 1 s at 311 degrees at 5 s. When the
/// device landed [s], how far the cursor moved before the stroke and how far the stroke's
/// counts end from it [mm].
fn lift_on_a_shaking_desk(machine: f64, seed: u64) -> (Option<f64>, f64, f64) {
    let desk = Shaking {
        mg: 48.0,
        hz: 30.0,
        k: 1,
        machine,
    };
    let k = desk.k;
    let lsb = Config::default().m_s2_per_lsb;
    let (mut n, mut t) = noisy_calibrated(seed, k);
    let (d, dur, s0, dir) = (0.02, 1.0, 5.0, 311f64.to_radians());
    let mut cursor = Cursor::default();
    let (mut landed, mut lifted) = (None, false);
    for i in 0..((s0 + dur + 1.5) * 3000.0) as usize {
        let time = i as f64 / 3000.0;
        let z = match time {
            x if (2.0..2.15).contains(&x) || (2.65..2.8).contains(&x) => 54.0,
            x if (2.15..2.3).contains(&x) || (2.5..2.65).contains(&x) => -54.0,
            _ => 0.0,
        };
        let a = d / (dur * dur) * step_accel((time - s0) / dur) / lsb;
        let v = desk.at(time, lsb);
        t.feed(&[[
            noisy_code(&mut n, 2048.0 + a * dir.cos() + v[0], k),
            noisy_code(&mut n, 2048.0 + a * dir.sin() + v[1], k),
            noisy_code(&mut n, 2048.0 + z + v[2], k),
        ]]);
        let up = t.drift_state().is_some_and(DriftState::is_lifted);
        if lifted && !up && landed.is_none() {
            landed = Some(time);
        }
        lifted |= up;
        cursor.poll(&mut t, i, time < s0);
    }
    let (moved, error) = cursor.judge(d, dir);
    (landed, moved, error)
}

#[test]
fn a_lift_on_a_shaking_desk_lands_as_on_a_quiet_one_whenever_the_machine_started() {
    // The machine starts before the lift (0 s), as the device rises (1.85 s, inside the lift
    // window), in the air (2.4 s) or just after the set-down (2.9 s), two noise draws each:
    // the landing allows for the disturbance measured as it decides, so the device lands
    // within the landing window's 0.26 s of the set-down (at 2.8 s) each time, having moved
    // at most 5 mm, and the stroke at 5 s ends within max(5 %, 3 floors) = 2.8 mm. Controls:
    // with the disturbance measured at the lift allowed for instead (until the eighteenth
    // stop), a machine started in the air held the landing back to 3.4-4.3 s; with none
    // allowed for, the device on the shaking desk never landed (to the scene's end, 7.5 s).
    for machine in [0.0, 1.85, 2.4, 2.9] {
        for seed in 0..2 {
            let (landed, moved, error) = lift_on_a_shaking_desk(machine, seed);
            let at = format!("machine at {machine} s, draw {seed}");
            let landed = landed.expect("lands");
            assert!(landed <= 2.8 + 0.3, "{at}: landed at {landed:.3} s");
            assert!(moved <= 5.0, "{at}: the re-placement moved {moved:.1} mm");
            assert!(error <= 2.8, "{at}: the stroke ended {error:.1} mm off");
        }
    }
}

#[test]
fn a_stroke_begun_just_after_a_set_down_arrives() {
    // Lifted 2 cm in 0.3 s (Z: +54, -54 LSB), held 0.2 s, set down in 0.3 s (-54, +54) flat
    // or on a 3 degree slope (X +21 LSB from the set-down on), then at rest for `gap` and a
    // stroke on X: +20 LSB for 0.1 s, -20 for 0.1 s, 4.79 mm = 150.8 counts (see
    // `a_stroke_arrives_whole_despite_the_detector_window`). At 0.2 s the stroke begins
    // inside the landing's window (0.26 s), after its first two thirds; at 1 s (the control)
    // after the landing. Each arrives whole. Without the rule the first is lost.
    let scene = |gap: usize, slope: u16| {
        move |i: usize, n: &mut Noise| {
            let z = match i {
                3000..=3449 | 4950..=5399 => 2102,
                3450..=3899 | 4500..=4949 => 1994,
                _ => 2048,
            };
            let level = if i >= 5400 { 2048 + slope } else { 2048 };
            let x = match i.checked_sub(5400 + gap) {
                Some(0..=299) => level + 20,
                Some(300..=599) => level - 20,
                _ => level,
            };
            [n.code(x), n.code(2048), n.code(z)]
        }
    };
    // Over the motion's 0.3 s (the stroke and its stop), the noise (1 LSB^2 a sample) moves
    // each axis by 1.3 counts sd and the zero by 0.6 (the calibration's, 1 / sqrt(3000) LSB)
    // or 1.45 (a new one from the 0.18 s of rest, 1 / sqrt(540) LSB): 3 sd of the sum is 4.5
    // or 5.9 counts.
    for (gap, slope, rebiases, tol) in [(600, 0, 0, 4), (3000, 0, 0, 4), (600, 21, 1, 6)] {
        let mut t = tracker(Some(Drift::default()));
        let mut n = Noise(Trace::new(11));
        let f = scene(gap, slope);
        let a = run(&mut t, 5400 + gap + 3000, |i| f(i, &mut n));
        let c = t.counters();
        let case = format!("gap {gap}, slope {slope}: {a:?} {c:?}");
        assert_eq!((c.lifts, c.rebiases, c.motions), (1, rebiases, 1), "{case}");
        assert!((a[0] - 151).abs() <= tol, "{case}");
        assert!(a[1].abs() <= tol, "{case}");
        assert!(t.is_still(), "{case}");
    }
}

#[test]
fn a_stroke_on_a_pad_that_tilted_and_settled_arrives() {
    // The pad tilts 3 degrees at once (X +21 LSB), settles, and 0.5 s later, while the tilt
    // is still held (it is confirmed only after 1 s one-sided), a stroke on X: +20 LSB for
    // 0.1 s, -20 for 0.1 s, 150.8 counts. The change from the settled level begins a shadow
    // from that level; the stroke goes both ways against it, so the shadow wins at its end
    // and the stroke arrives. Without the change's shadow the stroke is lost with the tilt's
    // held runaway when the tilt is confirmed.
    let scene = |i: usize, n: &mut Noise| {
        let x = match i {
            0..=2999 => 2048,
            4500..=4799 => 2089,
            4800..=5099 => 2049,
            _ => 2069,
        };
        [n.code(x), n.code(2048), n.code(2048)]
    };
    let mut t = tracker(Some(Drift::default()));
    let mut n = Noise(Trace::new(13));
    // The tilt's runaway before the hold is delivered; what counts is what comes after.
    run(&mut t, 4500, |i| scene(i, &mut n));
    assert!(t.is_holding(), "{:?}", t.drift_state());
    let a = run(&mut t, 9000, |i| scene(i + 4500, &mut n));
    // The shadow integrates at most 0.4 s (its replayed sub-window, the stroke, its stop):
    // the noise (1 LSB^2 a sample) moves it by 2.0 counts sd, its level's error (0.3 s of
    // rest: 1 / sqrt(900) LSB) by 2.0: 3 sd of the sum is 8.5 counts on each axis.
    assert!((a[0] - 151).abs() <= 8, "{a:?}");
    assert!(a[1].abs() <= 8, "{a:?}");
    assert_eq!((t.counters().discarded, t.counters().rebiases), (1, 1));
    assert!(t.is_still(), "{:?}", t.drift_state());
    assert!(!t.is_holding());
}

/// A pad rocked (pressed and let go, or the device tipped on its base and back): tilted by
/// `deg` degrees about the horizontal axis at `az` degrees from 1.5 s into tracking over
/// `down` s, held there `hold` s, back to level over `back` s; then a stroke of `d` m over
/// `dur` s at `dir` degrees `gap` s after the rock ended (minimum-jerk steps), on
/// [`noisy_code`]`(.., 2)`'s noise (4.8 LSB a sample, 303 ug/sqrt(Hz)), noise draw `seed`.
struct RockThenStroke {
    deg: f64,
    az: f64,
    down: f64,
    hold: f64,
    back: f64,
    gap: f64,
    d: f64,
    dur: f64,
    dir: f64,
}

/// A 2 degree rock over 1.2 s and a 40 mm stroke over 0.6 s 1 s after it.
const ROCK: RockThenStroke = RockThenStroke {
    deg: 2.0,
    az: 200.0,
    down: 0.4,
    hold: 0.4,
    back: 0.4,
    gap: 1.0,
    d: 0.04,
    dur: 0.6,
    dir: 150.0,
};

impl RockThenStroke {
    /// How far the cursor moved before the stroke and how far the stroke's own counts end
    /// from it [mm], how long after the stroke's start the cursor first moved 0.5 mm [s],
    /// whether drift control rests 1.5 s after the stroke, and how far the cursor moved
    /// from 0.5 s after the rock's return to the stroke [mm] (target 3: nothing).
    fn run(&self, seed: u64) -> (f64, f64, f64, bool, f64) {
        let lsb = Config::default().m_s2_per_lsb;
        let (mut n, mut t) = noisy_calibrated(seed, 2);
        let (t0, dir) = (1.5, self.dir.to_radians());
        let up = t0 + self.down + self.hold;
        let s0 = up + self.back + self.gap;
        let tilt = tilt_deg(self.deg, self.az);
        let mut cursor = Cursor::default();
        let mut latency = f64::INFINITY;
        let mut rested = None;
        for i in 0..((s0 + self.dur + 1.5) * 3000.0) as usize {
            let time = i as f64 / 3000.0;
            if rested.is_none() && time >= up + self.back + 0.5 {
                rested = Some(cursor.pos);
            }
            let share = ramp((time - t0) / self.down) - ramp((time - up) / self.back);
            let g = gravity(tilt.map(|x| x * share));
            let a = self.d / (self.dur * self.dur) * step_accel((time - s0) / self.dur) / lsb;
            t.feed(&[[
                noisy_code(&mut n, 2048.0 + a * dir.cos() + g[0] / lsb, 2),
                noisy_code(&mut n, 2048.0 + a * dir.sin() + g[1] / lsb, 2),
                noisy_code(&mut n, 2048.0 + g[2] / lsb, 2),
            ]]);
            cursor.poll(&mut t, i, time < s0);
            let away = [0, 1].map(|a| (cursor.pos[a] - cursor.before[a]) as f64 * 25.4 / 800.0);
            if latency.is_infinite() && away[0].hypot(away[1]) >= 0.5 {
                latency = time - s0;
            }
        }
        let (moved, error) = cursor.judge(self.d, dir);
        let late = rested.map_or(0.0, |p| {
            let mm = |a: usize| (cursor.before[a] - p[a]) as f64 * 25.4 / 800.0;
            mm(0).hypot(mm(1))
        });
        (moved, error, latency, t.is_still(), late)
    }

    /// Target 3 for the stroke [mm]: max(5 %, 3 bias floors), T_rest the gap since the
    /// rock (the noise density of [`noisy_code`]`(.., 2)`: 23 LSB^2 a sample at 3 kHz).
    fn allowed(&self) -> f64 {
        let nd = 23f64.sqrt() * Config::default().m_s2_per_lsb / 1500f64.sqrt();
        let sd_b = nd / (2.0 * self.gap).sqrt();
        let floor =
            (nd * nd * self.dur.powi(3) / 6.0 + sd_b * sd_b * self.dur.powi(4) / 4.0).sqrt();
        (0.05 * self.d).max(3.0 * floor) * 1000.0
    }
}

#[test]
fn a_stroke_after_a_rock_arrives() {
    // The pad rocks 2 degrees (X -20 LSB, Y -7) and back; the held motion carries the rock's
    // runaway and the velocity its pulse gave (0.2 m/s), against a zero the device is back
    // at. Once the last three short sub-windows are steady there, an undone shadow from rest
    // carries what comes next; a stroke's two lobes make it win at their end, the rock
    // dropped. Strokes begun 0.3 s (while the hold waits), 1.0 and 1.6 s (spanning the
    // wait's end) and 2.0 s (after it) after the rock, and a steeper rock's (the twentieth
    // tester's `f3_rock_02`: 5.8 degrees, 0.64 s down, 0.46 s held, 0.56 s back, a 40 mm
    // stroke over 0.75 s 1.0 s later), 8 noise draws each. Target 3: within
    // max(5 %, 3 bias floors), T_rest the gap; the 2 degree rock's own runaway before its
    // hold within the pad tilt's 25 mm; a stroke in the wait arrives by its end (the stop's
    // 30 ms), one after it at its reversal (wary after a tilt: half the stroke and a short
    // sub-window).
    // Controls: without the undone shadow the strokes at 0.3 and 1.0 s were lost (40.0 mm
    // off; both axes asked to go both ways, the stroke along X alone was lost); begun once
    // and not again at rest, the noise it integrated at rest ran on (2.20
    // mm off at 1.0 s, 2.03 allowed); ended at the wait's end while moving, the strokes at
    // 1.6 s were found again from rest mid-stroke and glided 129-163 mm; not dropped at rest
    // before twice the longest stroke, or waiting from its own start rather than the
    // shadow's it replaced, the stroke at 2.0 s arrived only at its end (0.6 s); with the
    // tilt's runs not begun again at the undone shadow's start, the steep rock's were still
    // long enough to confirm it a tilt there, and the stroke after was lost (40 mm off).
    let steep = RockThenStroke {
        deg: 5.8,
        az: 60.0,
        down: 0.64,
        hold: 0.46,
        back: 0.56,
        gap: 1.0,
        d: 0.04,
        dur: 0.75,
        dir: 60.0,
    };
    // (The first along X alone: one axis's two lobes are a stroke's.)
    let scenes = [(0.3f64, 0.0), (1.0, 150.0), (1.6, 150.0), (2.0, 150.0)]
        .map(|(gap, dir)| RockThenStroke { gap, dir, ..ROCK });
    for (k, scene) in scenes.iter().chain([&steep]).enumerate() {
        let (dur, gap, allowed) = (scene.dur, scene.gap, scene.allowed());
        let by = if gap < 2.0 {
            dur + 0.03
        } else {
            dur / 2.0 + 0.1
        };
        for seed in 0..8 {
            let (moved, error, latency, still, _) = scene.run(seed);
            let case = format!("scene {k} ({gap} s after), draw {seed}");
            // (The pad tilt's 25 mm is asked of 0.5-5 degrees; the steep rock is steeper.)
            assert!(
                moved <= 25.0 || scene.deg > 5.0,
                "{case}: the rock moved {moved:.1} mm"
            );
            assert!(
                error <= allowed,
                "{case}: {error:.2} mm off, allowed {allowed:.2}"
            );
            assert!(
                latency <= by,
                "{case}: arrived {latency:.3} s after its start"
            );
            assert!(still, "{case}");
        }
    }
}

#[test]
fn a_rock_released_at_rest_is_dropped_not_delivered() {
    // The device rocked 3 degrees on its base and straight back (down over 0.15-0.6 s, back
    // over 0.3-0.7 s, no pause): one lobe of 0.8-0.9 s, shorter than a tilt is confirmed
    // in, so it is held as a stroke's slow first lobe. Its runs break once the device is
    // back at the zeros, with the velocity the rock's pulse gave (about 0.2 m/s) and nothing
    // to take it back: released and delivered there, it glided on (16 of 24 noise draws,
    // 101-116 mm in the 0.5 s before the stroke, the stroke up to 0.49 m off). Held on until
    // the device rests on the zeros, an undone shadow takes over from rest, as when a
    // shadow's rock is undone, and a 40 mm stroke 1 s later arrives at its end. 8 noise
    // draws each. Target 3 for the rock: nothing from 0.5 s after its return, and its own
    // runaway before its hold within the pad tilt's 25 mm (asked of tilts over 0.3-2 s: the
    // 0.15 s one is faster, 27.1 mm at most); the stroke within target 3.
    let scenes = [
        (3.0, 0.3, 0.5, 30.0),
        (3.0, 0.15, 0.7, 200.0),
        (3.0, 0.6, 0.3, 110.0),
    ]
    .map(|(deg, down, back, az)| RockThenStroke {
        deg,
        az,
        down,
        hold: 0.0,
        back,
        ..ROCK
    });
    for (k, scene) in scenes.iter().enumerate() {
        let allowed = scene.allowed();
        for seed in 0..8 {
            let (moved, error, _, still, late) = scene.run(seed);
            let case = format!("scene {k}, draw {seed}");
            // (The pad tilt's 25 mm is asked of tilts over 0.3-2 s; the sudden one is faster.)
            assert!(
                moved <= 25.0 || scene.down < 0.3,
                "{case}: the rock moved {moved:.1} mm"
            );
            assert!(late == 0.0, "{case}: {late:.1} mm after the rock");
            assert!(
                error <= allowed,
                "{case}: {error:.2} mm off, allowed {allowed:.2}"
            );
            assert!(still, "{case}");
        }
    }
}

#[test]
fn a_stroke_after_a_pad_let_go_arrives() {
    // The lab's after-tilt trial 41 of seed 1: the pad tilts 1.38 degrees over 0.42 s, held
    // 0.66 s, back over 0.82 s, and a 72.5 mm stroke over 1.95 s 0.12 s after the return.
    // The tilt is confirmed and its zeros taken; the return is a new motion, held against
    // them, and the slow stroke after it is part of that motion. Back at rest on the zeros
    // from before the tilt and off the tilted ones, the pad was let go: the held return is
    // dropped, those zeros come back, and the stroke starts from rest. 8 noise draws; target
    // 3 (within max(5 %, 3 bias floors), T_rest the gap) asks 90 % of strokes: at most one
    // of 8 outside (8 x 10 %, rounded up). Control: without the rule all 8 were lost, 72.5
    // mm off.
    let scene = RockThenStroke {
        deg: 1.38,
        az: 40.0,
        down: 0.419,
        hold: 0.656,
        back: 0.823,
        gap: 0.118,
        d: 0.0725,
        dur: 1.95,
        dir: 200.0,
    };
    let allowed = scene.allowed();
    let outside: Vec<(u64, f64)> = (0..8)
        .map(|seed| (seed, scene.run(seed).1))
        .filter(|&(_, error)| error > allowed)
        .collect();
    assert!(
        outside.len() <= 1,
        "(draw, mm off) outside {allowed:.1} mm: {outside:?}"
    );
}

#[test]
fn a_slow_rock_back_past_the_level_it_settled_at_is_a_tilt() {
    // The lab's after-tilt trial 71 of seed 14: the pad tilts 4.9 degrees over 1.48 s (its
    // tilt confirmed, the zeros its level; what it tilts after is a new motion, held), then
    // back over 1.73 s, passing slowly through the level it had settled at, and a 218.9 mm
    // stroke 1.71 s later. There the held motion reads as undone; the return goes on,
    // one-sided against those zeros for longer than a hand's lobe, and is confirmed as a
    // tilt, its runs counted from the undone shadow's start. 8 noise draws, target 3:
    // within max(5 %, 3 bias floors), T_rest the gap. Control: waited on to twice the
    // longest stroke, the stroke then begun was found again from rest mid-way (up to 367
    // mm off in the lab).
    let scene = RockThenStroke {
        deg: 4.9,
        az: -51.9,
        down: 1.477,
        hold: 0.853,
        back: 1.731,
        gap: 1.707,
        d: 0.2189,
        dur: 0.473,
        dir: 129.0,
    };
    let allowed = scene.allowed();
    for seed in 0..8 {
        let (_, error, _, still, _) = scene.run(seed);
        assert!(
            error <= allowed,
            "draw {seed}: {error:.2} mm off, allowed {allowed:.2}"
        );
        assert!(still, "draw {seed}");
    }
}

#[test]
fn a_stroke_after_presses_arrives() {
    // A new user's presses (`press_17`): the pad pressed 1.79 degrees at 17 degrees (down
    // over 0.11 s, held 0.2 s, up over 0.13 s), then 1.42 s later 0.90 degrees (0.28 s,
    // 0.03 s, 0.21 s), and a 63.7 mm stroke over 0.40 s at 79.5 degrees 1 s after the last.
    // The first press's undone shadow takes the second press's pulse into its velocity,
    // which no acceleration changes after it: calm for a glide's fade wait past the longest
    // stroke, nothing is under way and it is dropped, and the stroke after it, wary, arrives.
    // 8 noise draws, target 3: within max(5 %, 3 bias floors), T_rest the 1 s gap. Control:
    // waited on to twice the longest stroke, the stroke was held and lost (63.7 mm off).
    let lsb = Config::default().m_s2_per_lsb;
    let presses = [
        (1.5, 1.79, 0.114, 0.203, 0.128),
        (2.922, 0.90, 0.276, 0.025, 0.205),
    ];
    let stroke = RockThenStroke {
        deg: 0.0,
        az: 17.0,
        down: 0.0,
        hold: 0.0,
        back: 0.0,
        gap: 1.0,
        d: 0.0637,
        dur: 0.4,
        dir: 79.5,
    };
    let (s0, dir) = (4.428, stroke.dir.to_radians());
    for seed in 0..8 {
        let (mut n, mut t) = noisy_calibrated(seed, 2);
        let mut cursor = Cursor::default();
        for i in 0..((s0 + stroke.dur + 2.0) * 3000.0) as usize {
            let time = i as f64 / 3000.0;
            let deg: f64 = presses
                .iter()
                .map(|&(t0, deg, down, hold, back)| {
                    deg * (ramp((time - t0) / down) - ramp((time - t0 - down - hold) / back))
                })
                .sum();
            let g = gravity(tilt_deg(deg, stroke.az));
            let a =
                stroke.d / (stroke.dur * stroke.dur) * step_accel((time - s0) / stroke.dur) / lsb;
            t.feed(&[[
                noisy_code(&mut n, 2048.0 + a * dir.cos() + g[0] / lsb, 2),
                noisy_code(&mut n, 2048.0 + a * dir.sin() + g[1] / lsb, 2),
                noisy_code(&mut n, 2048.0 + g[2] / lsb, 2),
            ]]);
            cursor.poll(&mut t, i, time < s0);
        }
        let (_, error) = cursor.judge(stroke.d, dir);
        let allowed = stroke.allowed();
        assert!(
            error <= allowed,
            "draw {seed}: {error:.2} mm off, allowed {allowed:.2}"
        );
        assert!(t.is_still(), "draw {seed}");
    }
}

#[test]
fn a_drag_whose_ramp_is_held_arrives_at_its_ramp_down() {
    // A drag whose ramp up is a steady push (0.08-0.15 m/s^2 for 0.4-0.6 s) is held as a
    // tilt would be; its glide, at the zero, reads as the tilt undone, and the undone
    // shadow begins. The ramp down ends the held motion with its velocity explained: it
    // was a hand's, and arrives. 4 drags, 4 noise draws: target 2, within max(10 %, 3 bias
    // floors) (T_rest 1.5 s), and no retreat over 2 mm. One more glides 3 s, longer than
    // the wait: it is dropped (151 of 180 mm lost, as before the undone shadow), and its
    // ramp down, wary after the rock's drop, does not run the cursor back (drift control
    // rests once that wary motion is dropped, the longest stroke after it began). Controls: with
    // the undone shadow deciding first, the held motion was never let stop (5.3-9.2 mm of
    // 50-84 arrived); not wary after the drop, the long glide's ramp down ran it back 6.9 mm.
    let lsb = Config::default().m_s2_per_lsb;
    let nd = 23f64.sqrt() * lsb / 1500f64.sqrt();
    for (push, glide, acc) in [
        (0.5f64, 1.0, 0.1),
        (0.6, 0.8, 0.08),
        (0.4, 1.2, 0.15),
        (0.5, 0.6, 0.1),
        (0.5, 3.0, 0.1),
    ] {
        let edge = 0.05;
        let v = acc * (push - edge);
        let (length, dur) = (v * (push + glide), 2.0 * push + glide);
        let sd_b = nd / (2.0 * 1.5f64).sqrt();
        let floor = (nd * nd * dur.powi(3) / 6.0 + sd_b * sd_b * dur.powi(4) / 4.0).sqrt();
        let allowed = (0.1 * length).max(3.0 * floor) * 1000.0;
        for seed in 0..4 {
            let (mut n, mut t) = noisy_calibrated(seed, 2);
            let t0 = 1.5;
            let (mut pos, mut best, mut retreat) = ([0i64; 2], 0i64, 0i64);
            for i in 0..((t0 + dur + 2.5) * 3000.0) as usize {
                let time = i as f64 / 3000.0;
                let plateau = |t: f64| ramp(t / edge) - ramp((t - push + edge) / edge);
                let a = acc * (plateau(time - t0) - plateau(time - t0 - push - glide)) / lsb;
                feed_horizontal(&mut t, &mut n, [a, 0.0], 2, i, &mut pos);
                best = best.max(pos[0]);
                retreat = retreat.max(best - pos[0]);
            }
            let mm = |c: i64| c as f64 * 25.4 / 800.0;
            let error = (mm(pos[0]) - length * 1000.0).hypot(mm(pos[1]));
            let case = format!("a {push} s push at {acc} m/s^2, draw {seed}");
            // Gliding past the wait (the longest stroke from the hold's shadow), the glide is
            // dropped as a rock's would be: the data do not yet tell them apart.
            let lost = glide > 2.0;
            assert!(
                lost || error <= allowed,
                "{case}: {error:.1} mm off, allowed {allowed:.1}"
            );
            assert!(mm(retreat) <= 2.0, "{case}: ran back {:.1} mm", mm(retreat));
            assert!(
                t.is_still(),
                "{case}: {error:.1} mm off, {:?}",
                t.drift_state()
            );
        }
    }
}

#[test]
fn a_knock_moves_nothing_and_keeps_the_bias() {
    // A knock on the desk: Z rings at +-80 LSB for 30 ms, X at +-10 LSB (at 167 Hz: it moves
    // the device by micrometres). It is integrated, exactly, and returns: nothing is
    // delivered, it is not a lift, and the zero stays.
    let knock = |i: usize, n: &mut Noise| {
        let ring = (6000..6090).contains(&i);
        let s = if i % 6 < 3 { 1i32 } else { -1 };
        let x = if ring { 2048 + 10 * s } else { 2048 };
        let z = if ring { 2048 + 80 * s } else { 2048 };
        [n.code(x as u16), n.code(2048), n.code(z as u16)]
    };
    let mut t = tracker(Some(Drift::default()));
    let mut n = Noise(Trace::new(4));
    let bias = t.axes()[0].bias_q16();
    let a = run(&mut t, 12_000, |i| knock(i, &mut n));
    assert_eq!(a, [0, 0, 0]);
    assert_eq!((t.counters().lifts, t.counters().rebiases), (0, 0));
    assert!((t.axes()[0].bias_q16() - bias).abs() < 65_536 / 10);
}

#[test]
fn a_click_does_not_drag_the_cursor_even_when_its_edge_comes_late() {
    // The jolt (+42 LSB for 15 ms, then -42: the finger's push and the hand's recoil)
    // starts at sample 3000; the debounced edge arrives 0, 5 or 10 ms later.
    // Controls: no hold (the jolt is delivered before the edge), no freeze.
    let jolt = |i: usize| {
        let v = if (3000..3090).contains(&i) {
            if i - 3000 < 45 {
                2090
            } else {
                2006
            }
        } else {
            2048
        };
        [v, v, 2048]
    };
    let cases = [
        (0.012, 0.15, 0, false),
        (0.012, 0.15, 15, false),
        (0.012, 0.15, 30, false),
        (0.0, 0.15, 30, true),
        (0.012, 0.0, 0, true),
    ];
    for (hold, freeze, late, drags) in cases {
        let mut t = tracker(Some(Drift {
            hold_s: hold,
            click_freeze_s: freeze,
            ..Drift::default()
        }));
        let mut total = [0i64; 3];
        for i in 0..9000 {
            if i == 3000 + late {
                t.button_edge();
            }
            t.feed(&[jolt(i)]);
            for (s, c) in total.iter_mut().zip(t.take_counts()) {
                *s += i64::from(c).abs();
            }
        }
        assert_eq!(
            total != [0, 0, 0],
            drags,
            "hold {hold} freeze {freeze} late {late}: {total:?}"
        );
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
            stroke_max_s: 10.0,
            ..Drift::default()
        }),
        ..Config::default()
    };
    assert_eq!(
        bad.validate().err(),
        Some(ConfigError::Drift(DriftError::Stroke))
    );
    let msg = format!("{}", ConfigError::Drift(DriftError::Stroke));
    assert!(msg.starts_with("drift.stroke_max_s"), "{msg}");
    let tuned = Config {
        drift: Some(Drift {
            tuning: Tuning {
                k_sd: 0.0,
                ..Tuning::default()
            },
            ..Drift::default()
        }),
        ..Config::default()
    };
    let e = tuned.validate().err();
    assert_eq!(e, Some(ConfigError::Drift(DriftError::Tuning("k_sd"))));
    assert!(format!("{}", e.expect("an error")).contains("drift.tuning.k_sd"));
}

#[test]
fn the_trapezoid_replays_a_stroke_as_it_integrates_it() {
    // The replayed onset is primed with the sample before it: with the trapezoid the
    // stroke arrives as the pure trapezoid integrates the same samples. Noise-free rest, so
    // the calibration bias is exact; a 1 LSB stroke, so that the alarm comes ticks after
    // the onset and the replay runs over the ring.
    let stroke = |i: usize| {
        let v = match i {
            0..=2999 => 2048,
            3000..=3899 => 2049,
            3900..=4799 => 2047,
            _ => 2048,
        };
        [v, 2048, 2048]
    };
    let config = |drift| Config {
        scheme: imu_core::Scheme::Trapezoid,
        drift,
        ..Config::default()
    };
    let mut on = Tracker::new(&config(Some(Drift::default()))).expect("valid");
    let mut pure = Tracker::new(&config(None)).expect("valid");
    on.feed(&[[2048; 3]; 3000]);
    pure.feed(&[[2048; 3]; 3000]);
    let a = run(&mut on, 9000, stroke);
    let p = run(&mut pure, 1800, |i| stroke(i + 3000));
    assert_eq!(on.counters().motions, 1);
    // Exact bias: the only difference is where the two runs start and stop integrating
    // zeros, which adds nothing; the read-out rounding allows one count.
    assert!((a[0] - p[0]).abs() <= 1, "{a:?} vs {p:?}");
    // 1 LSB (0.0239 m/s^2) for 0.3 s each way: a t1^2 = 2.15 mm = 68 counts.
    assert!((p[0] - 68).abs() <= 1, "{p:?}");
}

#[test]
fn velocity_is_zero_whenever_drift_control_is_not_integrating() {
    // The invariant every stop keeps (end of a stroke, a click, a lift, a tilt, the end of a
    // freeze): outside a motion the velocity is zero, so nothing can creep and every
    // motion starts from rest. Strokes, a click in the middle of one, a tilt, a lift.
    let scene = |i: usize, n: &mut Noise| {
        let t = i as f64 / 3000.0;
        let x = match t {
            t if (1.0..1.1).contains(&t) => 2068,
            t if (1.1..1.2).contains(&t) => 2028,
            t if (2.0..2.2).contains(&t) => 2060,
            t if (2.2..2.4).contains(&t) => 2036,
            t if (3.0..6.0).contains(&t) => 2062, // a tilt
            _ => 2048,
        };
        let z = if (7.0..7.3).contains(&t) { 2110 } else { 2048 }; // a lift
        [n.code(x), n.code(2048), n.code(z)]
    };
    let mut t = tracker(Some(Drift::default()));
    let mut n = Noise(Trace::new(11));
    for i in 0..9 * 3000 {
        if i == 6300 {
            t.button_edge(); // in the middle of the second stroke
        }
        t.feed(&[scene(i, &mut n)]);
        t.take_counts();
        if t.drift_state() != Some(DriftState::Moving) {
            for a in t.axes() {
                assert_eq!(
                    a.integrator().velocity(),
                    0,
                    "sample {i}: {:?}",
                    t.drift_state()
                );
            }
        }
    }
    let c = t.counters();
    assert!(c.motions >= 2 && c.lifts >= 1 && c.rebiases >= 1, "{c:?}");
}

#[test]
fn a_brisk_stroke_that_a_tilted_mount_puts_on_z_is_not_a_lift() {
    // The sensor sits 10 degrees off level in the case: a sixth of X's acceleration shows on
    // Z. A brisk minimum-jerk stroke (0.2 s, peak 100 LSB = 2.4 m/s^2: 16.6 mm) puts 2.8 mm of
    // displacement on Z, a lift's on its own; the mounting allowance (a sin(12 degrees) share
    // of the horizontal displacement) keeps it a stroke. Control: with no allowance it is taken
    // for a lift and not tracked.
    let lsb = Config::default().m_s2_per_lsb;
    let (dur, peak) = (0.2, 100.0);
    let d = peak * lsb * dur * dur / 5.7735; // peak = 5.7735 D / T^2
    let stroke = |i: usize| {
        let u = (i as f64 - 3000.0) / 3000.0 / dur;
        let a = d / (dur * dur) * step_accel(u) / lsb;
        [
            (2048.0 + a).round() as u16,
            2048,
            (2048.0 + a / 6.0).round() as u16,
        ]
    };
    let want = d / 0.0254 * 800.0;
    for (ratio, tracked) in [(12.0, true), (0.0, false)] {
        let mut t = tracker(Some(Drift {
            mount_tilt_deg: ratio,
            ..Drift::default()
        }));
        let a = run(&mut t, 9000, stroke);
        // Rounding the codes to whole LSB: a few counts.
        assert_eq!(
            (a[0] as f64 - want).abs() < 0.02 * want,
            tracked,
            "ratio {ratio}: {a:?} vs {want}"
        );
    }
}

/// Sampling dies 0.2 s into a push and restarts 1 s later: the gap's acceleration is
/// unknown. `restarted` stops the motion there; `lost` (for a late block, where holding is
/// right) would hold the push for the whole second. The control shows what the hold costs
/// the pure integrator (drift control takes a second of one-sided push for a tilt).
#[test]
fn a_sampling_restart_mid_stroke_stops_the_motion_instead_of_holding_it() {
    for drift in [Some(Drift::default()), None] {
        let push = |i: usize| {
            if i < 600 {
                [2078, 2048, 2048]
            } else {
                [2048; 3]
            }
        };
        let mut cut = tracker(drift);
        let mut held = tracker(drift);
        let before = run(&mut cut, 600, push)[0];
        assert_eq!(run(&mut held, 600, push)[0], before);
        cut.restarted(3000);
        held.lost(3000);
        let after_cut = run(&mut cut, 300, |_| [2048; 3])[0];
        let after_held = run(&mut held, 300, |_| [2048; 3])[0];
        assert_eq!(cut.counters().lost, 3000);
        // 30 LSB for 0.2 s is 1.4 m/s^2 and 0.28 m/s: 9 counts so far, and a held second
        // would add 0.28 m/s x 1 s + 1.4 m/s^2 x 1 s^2 / 2 = 1 m, tens of thousands of counts.
        assert!(before > 5, "{drift:?}: the push moved {before}");
        assert!(
            after_cut.abs() <= 1,
            "{drift:?}: {after_cut} counts after the restart"
        );
        if drift.is_none() {
            assert!(
                after_held > 10_000,
                "{drift:?}: the hold moved only {after_held}"
            );
        }
    }
}

/// A tracker moving: a push of 30 LSB on X for `samples` samples.
fn moving(drift: Drift, samples: usize) -> Tracker {
    let mut t = tracker(Some(drift));
    run(&mut t, samples, |_| [2078, 2048, 2048]);
    assert_eq!(t.drift_state(), Some(DriftState::Moving));
    assert!(!t.is_still());
    t
}

#[test]
fn a_restart_leaves_the_detector_at_rest() {
    let mut t = moving(Drift::default(), 300);
    t.restarted(30);
    assert_eq!(t.drift_state(), Some(DriftState::Still));
}

#[test]
fn a_click_discards_a_held_motion_and_stops_a_delivered_one() {
    // A motion younger than the hold (16 ms) is the click's own jolt: discarded. An older
    // one was the hand's: it stops (zero velocity), and is not counted as discarded.
    let young = 30; // 10 ms of push: two detector ticks, the fast alarm after the first
    let mut t = tracker(Some(Drift::default()));
    run(&mut t, young, |_| [2078, 2048, 2048]);
    assert_eq!(t.drift_state(), Some(DriftState::Moving));
    t.button_edge();
    assert_eq!(t.counters().discarded, 1, "held motion discarded");
    let mut t = moving(Drift::default(), 300);
    t.button_edge();
    assert_eq!(t.counters().discarded, 0, "a delivered motion only stops");
    assert_eq!(t.drift_state(), Some(DriftState::Frozen));
    assert_eq!(t.axes()[0].integrator().velocity(), 0);
    run(&mut t, 30, |_| [2048; 3]);
    assert_eq!(
        t.counters().frozen_samples,
        30,
        "the freeze counts what it skipped"
    );
}

#[test]
fn without_a_click_freeze_a_click_stops_the_motion_at_once() {
    let drift = Drift {
        click_freeze_s: 0.0,
        ..Drift::default()
    };
    let mut t = moving(drift, 300);
    t.button_edge();
    assert_eq!(t.drift_state(), Some(DriftState::Still));
    let mut t = tracker(Some(drift));
    t.button_edge();
    assert_eq!(
        t.drift_state(),
        Some(DriftState::Still),
        "at rest it stays at rest"
    );
}

#[test]
fn a_stroke_during_a_tilts_hold_never_delivers_the_tilts_runaway() {
    // The desk tilts by 2 degrees within 0.1 s (X reads 14 LSB more) and stays; 0.3 to 1 s
    // later, while the tilt's motion is held, a hand strokes (two sine lobes of 20 or 40 LSB
    // over 0.5 s), its first lobe along the tilt. The tilt's runaway, many metres by the time
    // anything ends, must never be delivered: the cursor may be off the stroke by at most
    // the stroke itself and what the tilt alone runs before its hold. (The runs that decide
    // between the tilt and the stroke once went uncounted while the stroke's shadow ran, and
    // the held runaway was delivered: 55 000 counts.)
    let run_scheme = |scheme, tilted: bool, start: f64, amp: f64| {
        let scene = move |i: usize, n: &mut Noise| {
            let t = (i as f64 - start) / 3000.0;
            let stroke = if (0.0..0.5).contains(&t) {
                amp * (core::f64::consts::TAU * t / 0.5).sin()
            } else {
                0.0
            };
            let f = ((i as f64 - 3000.0) / 300.0).clamp(0.0, 1.0);
            let x = 2048.0 + if tilted { 14.0 * f } else { 0.0 } + stroke;
            [n.code(x.round() as u16), n.code(2048), n.code(2048)]
        };
        let mut t = calibrated(&Config {
            scheme,
            ..Config::default()
        });
        let mut n = Noise(Trace::new(5));
        let total = run(&mut t, 20_000, |i| scene(i, &mut n));
        assert!(t.is_still(), "{:?}", t.drift_state());
        (total[0], t.counters())
    };
    let run_scene = |tilted: bool, start: f64, amp: f64| {
        run_scheme(imu_core::Scheme::Euler, tilted, start, amp)
    };
    let alone = run_scene(true, 1e9, 0.0).0;
    assert!(alone > 0, "the tilt runs before its hold: {alone}");
    for start in [3900.0, 4200.0, 4500.0, 5100.0, 6000.0] {
        for amp in [20.0, 40.0] {
            let stroke = run_scene(false, start, amp).0;
            let both = run_scene(true, start, amp).0;
            assert!(
                (both - stroke).abs() <= stroke.abs() + alone,
                "start {start}, {amp} LSB: {both} counts, the stroke alone {stroke}, the tilt alone {alone}"
            );
        }
    }
    // A stroke 0.9 s after the tilt: its shadow (integrated against the tilt's level) comes
    // to rest first and replaces the held motion, so the cursor moves by the stroke plus the
    // tilt's run before its hold. The level is a mean of 0.3 s (900 samples of 1 LSB^2:
    // sd 0.033 LSB, 0.2 % of a 20 LSB stroke's peak); bound 1 % and 2 counts of rounding.
    // The same with the trapezoid, whose shadow is primed with the sample before it.
    let schemes = [imu_core::Scheme::Euler, imu_core::Scheme::Trapezoid];
    for (scheme, amp) in schemes.into_iter().flat_map(|s| [(s, 20.0), (s, 40.0)]) {
        let stroke = run_scheme(scheme, false, 6000.0, amp).0;
        let alone = run_scheme(scheme, true, 1e9, 0.0).0;
        let (both, counters) = run_scheme(scheme, true, 6000.0, amp);
        let want = stroke + alone;
        // The held motion dropped once, the tilt's level the new zero once.
        assert_eq!(
            (counters.discarded, counters.rebiases),
            (1, 1),
            "{scheme:?}, {amp} LSB"
        );
        assert!(
            (both - want).abs() <= stroke.abs() / 100 + 2,
            "{scheme:?}, {amp} LSB: {both} counts, want {want}"
        );
    }
}

#[test]
fn a_pad_settling_after_its_tilt_delivers_nothing_once_at_rest() {
    // The pad tilts slowly under the resting mouse: X rises by `lsb` (2 degrees is 14 LSB) in
    // a minimum-jerk profile over `secs`, then stays. Whatever the cursor runs before the
    // hold, nothing may arrive later than half a second after the pad is at rest: the held
    // run is dropped and the tilt is the new zero. (On these scenes the tilt is confirmed
    // at its end; the hand model's pads that go on settling after a shadow's level are
    // `lab_families.rs`'s.)
    for (lsb, secs) in [(9.0, 0.68), (6.0, 0.5), (9.0, 1.0), (14.0, 0.7), (4.0, 0.4)] {
        let len = secs * 3000.0;
        let scene = |i: usize, n: &mut Noise| {
            let u = ((i as f64 - 3000.0) / len).clamp(0.0, 1.0);
            let x = 2048.0 + lsb * u * u * u * (10.0 - 15.0 * u + 6.0 * u * u);
            [n.code(x.round() as u16), n.code(2048), n.code(2048)]
        };
        let mut t = tracker(Some(Drift::default()));
        let mut n = Noise(Trace::new(3));
        let rest_at = 3000 + len as usize;
        let before = run(&mut t, rest_at + 1500, |i| scene(i, &mut n));
        let after = run(&mut t, 30_000, |i| scene(i + rest_at + 1500, &mut n));
        assert_eq!(
            after,
            [0, 0, 0],
            "{lsb} LSB over {secs} s: {before:?} before"
        );
        assert!(t.is_still(), "{:?}", t.drift_state());
    }
}

#[test]
fn a_quick_stroke_across_a_tilts_hold_arrives_though_its_shadow_stops_at_once() {
    // The desk tilts by 2 degrees on X (14 LSB within 0.1 s, from 1 s on) and stays; 0.8 to
    // 0.94 s later, while the tilt's motion is held, a hand flicks Y (one sine period of 20
    // or 40 LSB over 0.15 s) and is still again before the tilt is confirmed. The shadow
    // taken at the confirmation replays the flick and is at rest at once: it is adopted
    // because its replayed sub-windows went against the tilt's direction (a stroke's lobes
    // have both signs), so the flick arrives whole: the cursor moves by the flick and the
    // tilt's run before its hold, each as alone, to 2 counts of rounding and 2 %: the hold a
    // tick earlier or later changes a run growing as t^2 by 2 tick / t, 2 % at 0.5 s (and
    // the level's own noise, 0.2 % of the flick's peak).
    let scene = |start: usize, amp: f64| {
        move |i: usize, n: &mut Noise| {
            let t = (i as f64 - start as f64) / 3000.0;
            let flick = if (0.0..0.15).contains(&t) {
                amp * (core::f64::consts::TAU * t / 0.15).sin()
            } else {
                0.0
            };
            let f = ((i as f64 - 3000.0) / 300.0).clamp(0.0, 1.0);
            let x = 2048.0 + if start > 0 { 14.0 * f } else { 0.0 };
            [
                n.code(x.round() as u16),
                n.code((2048.0 + flick).round() as u16),
                n.code(2048),
            ]
        }
    };
    let total = |f: &mut dyn FnMut(usize, &mut Noise) -> [u16; 3]| {
        let mut t = tracker(Some(Drift::default()));
        let mut n = Noise(Trace::new(5));
        let sum = run(&mut t, 20_000, |i| f(i, &mut n));
        assert!(t.is_still(), "{:?}", t.drift_state());
        (sum, t.counters())
    };
    let (tilt, _) = total(&mut scene(usize::MAX, 0.0));
    for start in [5400, 5600, 5800] {
        for amp in [20.0, 40.0] {
            let (flick, _) = {
                let alone = scene(start, amp);
                total(&mut |i, n| {
                    let [_, y, z] = alone(i, n);
                    [n.code(2048), y, z]
                })
            };
            let (both, counters) = total(&mut scene(start, amp));
            assert_eq!((counters.discarded, counters.rebiases), (1, 1), "adopted");
            let close = |a: usize| {
                let want = flick[a] + tilt[a];
                (both[a] - want).abs() <= (flick[a].abs() + tilt[a].abs()) / 50 + 2
            };
            assert!(
                close(0) && close(1),
                "start {start}, {amp} LSB: {both:?}, the flick alone {flick:?}, the tilt alone {tilt:?}"
            );
        }
    }
}

#[test]
fn a_brisk_start_is_found_within_a_usb_frame_not_at_the_ticks_end() {
    // A 0.7 g step (300 LSB) on X after rest: the fast CUSUM's check within a tick finds it
    // within one USB frame (1 ms: 3 samples at 3 kHz, 20 at 20 kHz), where the tick's end
    // (15 and 100 samples) would be 5 ms. The rest is a whole number of ticks, so the step
    // starts a tick.
    for fs_hz in [3000u32, 20_000] {
        let config = Config {
            fs_hz,
            drift: Some(Drift::default()),
            ..Config::default()
        };
        let mut t = Tracker::new(&config).expect("valid");
        let mut n = Noise(Trace::new(11));
        let mut feed = |t: &mut Tracker, x: u16| {
            let s = [n.code(x), n.code(2048), n.code(2048)];
            t.feed(&[s]);
        };
        for _ in 0..fs_hz + fs_hz / 2 {
            feed(&mut t, 2048);
        }
        assert_eq!(
            t.drift_state(),
            Some(DriftState::Still),
            "{fs_hz} Hz at rest"
        );
        let frame = (fs_hz / 1000) as usize;
        let found = (1..=200).find(|_| {
            feed(&mut t, 2348);
            t.drift_state() == Some(DriftState::Moving)
        });
        assert!(
            found.is_some_and(|k| k <= frame),
            "{fs_hz} Hz: found after {found:?} samples, a frame is {frame}"
        );
    }
}

/// One period of a sine along +X over `len` samples (6 LSB, rounded), starting at sample
/// 3000, whose samples carry a velocity error while the hand moves: `err` LSB on every 22nd
/// sample (a mean of `err / 22` LSB, 1.09 mm/s^2 for one LSB), on a noiseless rest after a
/// noisy calibration.
fn erring_wave(len: usize, err: i32) -> impl Fn(usize) -> [u16; 3] {
    move |i: usize| {
        let s = i.wrapping_sub(3000);
        let a = if s < len {
            (6.0 * (core::f64::consts::TAU * s as f64 / len as f64).sin()).round() as i32
        } else {
            0
        };
        let e = if s < len && s.is_multiple_of(22) {
            err
        } else {
            0
        };
        [(2048 + a + e) as u16, 2048, 2048]
    }
}

/// The 1 s stroke of [`erring_wave`] (23 mm).
fn erring_stroke(err: i32) -> impl Fn(usize) -> [u16; 3] {
    erring_wave(3000, err)
}

/// The double sum (Euler, the default scheme) of accelerations [LSB] at 3 kHz, in counts.
fn double_sum_counts(a: impl Iterator<Item = i64>) -> f64 {
    let (mut v, mut x) = (0i64, 0i64);
    for a in a {
        v += a;
        x += v;
    }
    let fs = 3000.0;
    x as f64 * Config::default().m_s2_per_lsb / (fs * fs) / 0.0254 * 800.0
}

/// The stroke of [`erring_stroke`] without its error [counts], against the exact zero.
fn erring_stroke_truth() -> f64 {
    double_sum_counts((3000..6000).map(|i| i64::from(erring_stroke(0)(i)[0]) - 2048))
}

/// The position error [counts] that `err` LSB on every 22nd sample of the stroke leaves at
/// its end, integrated alone.
fn erring_stroke_error(err: i32) -> f64 {
    double_sum_counts((0..3000u32).map(|s| {
        if s.is_multiple_of(22) {
            i64::from(err)
        } else {
            0
        }
    }))
}

#[test]
fn a_stroke_that_ends_short_is_finished_by_its_velocity_left() {
    // The error's mean, -1/22 LSB = -1.09 mm/s^2 over the 1 s stroke, leaves -1.09 mm/s at
    // the stop (2.5 sd of the velocity's uncertainty: explained, a stop) and the position
    // 0.545 mm = 17 counts short. The bridge moves the cursor on by V n / 2, onto the stroke
    // within a count. Control: without it the cursor stays 26 counts short (the error's 17
    // and the zero's own error, which the bridge removes as well).
    let truth = erring_stroke_truth();
    let short = erring_stroke_error(-1);
    assert!(short < -16.0, "{short}");
    // Without the zero's tracking at rest, no decision comes between the two strokes below.
    let mut t = tracker(Some(Drift {
        bias_tau_s: None,
        ..Drift::default()
    }));
    let got = run(&mut t, 12_000, erring_stroke(-1));
    assert_eq!(t.counters().motions, 1);
    assert!(
        (got[0] as f64 - truth).abs() <= 1.0,
        "{} against {truth}",
        got[0]
    );
    // The same stroke again 2 s later starts afresh: the first's correction stays.
    let again = run(&mut t, 12_000, erring_stroke(-1));
    assert_eq!(t.counters().motions, 2);
    let both = got[0] + again[0];
    assert!(
        (both as f64 - 2.0 * truth).abs() <= 2.0,
        "{both} against {}",
        2.0 * truth
    );
}

#[test]
fn a_stroke_that_overshoots_is_pulled_back_once_the_rest_after_it_shows_the_hand_stopped() {
    // The same error the other way: +1.09 mm/s left along the travel. It may be the hand
    // still moving (a slow deceleration within the velocity's uncertainty), so the stop does
    // not pull the cursor back at once: it stays over (by the error's 17 counts less the
    // zero's 9) until the tick ring holds only the rest after the stop (320 ms). Over the
    // stop's wait after it the acceleration is nil, not the rest of a deceleration: the
    // velocity was error, and the bridge is made then, late. Within a count of the stroke at
    // last, and still over 0.2 s after the stop. Control: never pulled back (the bridge's
    // forward test alone, before the late bridge), 723 counts against 723.7 -> 732.
    let truth = erring_stroke_truth();
    assert!(erring_stroke_error(1) > 16.0);
    let mut t = tracker(Some(Drift::default()));
    // The stroke ends at sample 6000 and stops within 30 ms; 0.2 s after, it has not moved
    // back.
    let early = run(&mut t, 6700, erring_stroke(1));
    assert!(
        early[0] as f64 - truth > 4.0,
        "{} against {truth}",
        early[0]
    );
    let got = run(&mut t, 5300, |i| erring_stroke(1)(i + 6700));
    let got = early[0] + got[0];
    assert!((got as f64 - truth).abs() <= 1.0, "{got} against {truth}");
}

#[test]
fn a_lift_after_a_stop_drops_its_late_bridge() {
    // The overshooting stroke above, lifted 0.1 s after its stop (Z +54 then -54 LSB over
    // 0.3 s, 0.15 s in the air, -54 then +54 over 0.3 s): the rest after the stop held a lift,
    // not a hand's rest, and the pending step is dropped: still over at last. Control: judged
    // anyway once the ring holds only the rest after the landing, the step is made there.
    let truth = erring_stroke_truth();
    let mut t = tracker(Some(Drift::default()));
    let mut n = Noise(Trace::new(9));
    let stroke = erring_stroke(1);
    let got = run(&mut t, 12_000, |i| {
        let z = match i {
            6400..=6849 | 8200..=8649 => 2102,
            6850..=7299 | 7750..=8199 => 1994,
            _ => 2048,
        };
        let [x, y, _] = stroke(i);
        [x, y, n.code(z)]
    });
    assert_eq!(t.counters().lifts, 1);
    assert!(got[0] as f64 - truth > 4.0, "{} against {truth}", got[0]);
}

#[test]
fn a_stroke_whose_hand_decelerates_after_its_stop_is_not_pulled_back() {
    // 30 mm over 1.2 s at 30 degrees with 6.8 LSB of white noise a sample (428
    // ug/sqrt(Hz)): the stop comes while the hand still decelerates, within the velocity's
    // uncertainty, the velocity left along the travel. The rest of the deceleration comes
    // over the stop's wait after it, taking that velocity nearer back to zero than not: the
    // hand was moving, and no late bridge pulls the cursor back. Draws 10 and 34 end 2.2
    // and 1.6 mm off (allowed 6.75) and never back by more than 2 mm; control: the late
    // bridge made without that test, they step back 5.8 and 3.3 mm and end 4.5 and 4.1 off.
    for seed in [10, 34] {
        let (case, error, allowed, retreat, _) = stroke_outcome(0.03, 1.2, 30.0, 1.0, seed, 4);
        assert!(error <= allowed, "{case}, allowed {allowed:.2}");
        assert!(retreat <= 2.0, "{case}");
    }
}

#[test]
fn a_stroke_resumed_after_its_stop_is_corrected_once() {
    // Two erring strokes, the second starting 0.1 s after the first's stop: it resumes the
    // first (carries its velocity), so the second's stop corrects the whole span less what
    // the first's corrected. That span counts the pause between them, which the cursor sat
    // out: the correction overshoots by V t / 2 for the pause t, 2.18 mm/s x 0.13 s / 2 =
    // 4.5 counts; within that and a count. Control: correcting the whole span on top of the
    // first's correction puts the cursor 26 counts further.
    let truth = erring_stroke_truth();
    let mut t = tracker(Some(Drift::default()));
    let first = run(&mut t, 6000, erring_stroke(-1));
    assert_eq!(t.counters().motions, 1);
    assert_eq!(t.drift_state(), Some(DriftState::Still));
    // The stop came within 30 ms of the stroke's end (sample 6000): start the next at 6300.
    let second = run(&mut t, 9000, |i| erring_stroke(-1)(i + 2700));
    assert_eq!(t.counters().motions, 2);
    let got = first[0] + second[0];
    assert!(
        (got as f64 - 2.0 * truth).abs() <= 5.5,
        "{got} against {}",
        2.0 * truth
    );
}

#[test]
fn a_resumed_motion_never_takes_its_correction_back() {
    // The 1 s stroke ends 26 counts short and is corrected forward. 0.1 s later a flick
    // along +X resumes it (0.45 s, one period of 6 LSB; its lobes shorter than a tilt's
    // hold, so it is delivered as it goes) with 3 LSB on every 22nd sample: the whole span
    // ends with about +0.4 mm/s along the travel (-1.09 carried, +1.47 the flick's), and
    // its correction, less the first's, would be a step back; so would taking the first's
    // back (26 counts). Neither is made: the cursor retreats only by what the carried
    // velocity (-1.09 mm/s, the first's error) runs before the flick turns it (tens of ms:
    // about a count; as before the bridge). Control: with the step back made, the cursor
    // retreats 16 counts.
    let truth = erring_stroke_truth();
    let flick = erring_wave(1350, 3);
    let mut t = tracker(Some(Drift::default()));
    // The first stroke runs forward only: its end is the furthest the cursor has been.
    let pos = run(&mut t, 6300, erring_stroke(-1))[0];
    assert!((pos as f64 - truth).abs() <= 1.0, "{pos} against {truth}");
    // The flick's samples start at 6300, 0.1 s after the first stroke's stop.
    let retreat = max_retreat(&mut t, 5700, |i| flick(i + 3000));
    assert_eq!(t.counters().motions, 2);
    assert!(retreat <= 3, "retreat {retreat}");
}

/// A code around `mid` with wide zero-mean noise: the sum of 46 draws of -1, 0, 0, 1
/// (variance 23 LSB^2, 4.8 LSB sd: 300 ug/sqrt(Hz) over the full 1.5 kHz band, no filter).
fn wide_code(n: &mut Noise, mid: f64) -> u16 {
    noisy_code(n, mid, 2)
}

/// A code around `mid` with the sum of `23 k` draws of -1, 0, 0, 1 (variance `11.5 k`
/// LSB^2).
fn noisy_code(n: &mut Noise, mid: f64, k: usize) -> u16 {
    let mut v = 0i32;
    for _ in 0..k {
        let mut r = n.next();
        for _ in 0..23 {
            v += [-1i32, 0, 0, 1][(r & 3) as usize];
            r >>= 2;
        }
    }
    (mid.round() as i32 + v) as u16
}

/// Feeds sample `i` of a scene: horizontal acceleration `acc` [LSB] on X and Y, none on Z,
/// with [`noisy_code`]`(.., k)`'s noise; the counts taken every third sample (a 1 kHz poll at
/// 3 kHz) are added to `pos`.
fn feed_horizontal(
    t: &mut Tracker,
    n: &mut Noise,
    acc: [f64; 2],
    k: usize,
    i: usize,
    pos: &mut [i64; 2],
) {
    let c = [
        noisy_code(n, 2048.0 + acc[0], k),
        noisy_code(n, 2048.0 + acc[1], k),
        noisy_code(n, 2048.0, k),
    ];
    t.feed(&[c]);
    if i % 3 == 2 {
        let c = t.take_counts();
        *pos = [pos[0] + i64::from(c[0]), pos[1] + i64::from(c[1])];
    }
}

/// Noise draw `seed` of [`wide_code`] and a default tracker calibrated on 1 s of it at
/// mid-scale.
fn wide_calibrated(seed: u64) -> (Noise, Tracker) {
    noisy_calibrated(seed, 2)
}

/// Noise draw `seed` of [`noisy_code`]`(.., k)` and a default tracker calibrated on 1 s of
/// it at mid-scale.
fn noisy_calibrated(seed: u64, k: usize) -> (Noise, Tracker) {
    let mut n = Noise(Trace::new(seed));
    let mut t = Tracker::new(&Config::default()).expect("valid");
    let cal: Vec<[u16; 3]> = (0..3000)
        .map(|_| core::array::from_fn(|_| noisy_code(&mut n, 2048.0, k)))
        .collect();
    t.feed(&cal);
    (n, t)
}

#[test]
fn a_slow_stroke_found_in_its_second_lobe_arrives_from_its_first() {
    // A new user's slow stroke: 15.5 mm over 1.571 s at 311 degrees (minimum jerk, its peak
    // 0.036 m/s^2 = 1.5 LSB), with 4.8 LSB of white noise a sample (a tick's mean: 1.2 LSB,
    // so the peak is 1.2 sd of a tick). Its first lobe's run stays under the alarm and its
    // second crosses it; between them the acceleration stays within kappa of zero for longer
    // than the hand-band filter's 85 ms, so the first lobe was not found, the motion began at
    // the second, and the cursor glided back at the stroke's peak speed. Bridging the lobes'
    // gap (a quarter of the longest stroke) finds it. Four noise draws in which the cursor
    // went back (by 38, 3.4, 4.0 and 64 mm): each now within max(5 %, 3 floors) = 7.2 mm
    // (the floor `ND T^1.5 / sqrt 6` = 2.4 mm, ND = 4.8 LSB / sqrt(1500 Hz)) and never back
    // by more than 2 mm. Control: with the filter's length alone, all four go back. (Of 24
    // draws, 7 went back by more than 2 mm before and 4 still do: those whose first lobe's
    // run is not the other side's last, or stays under 5 sd; and one draw's stroke is now
    // discarded whole instead of gliding back 419 mm.)
    let (d, dur) = (0.0155f64, 1.571f64);
    for seed in [102u64, 103, 109, 114] {
        slow_stroke_arrives(d, dur, seed);
    }
}

/// A minimum-jerk stroke of `d` m over `dur` s at 311 degrees, after 1 s of rest, with
/// [`wide_code`]'s 4.8 LSB of white noise a sample (noise draw `seed`, calibration
/// included): it ends within max(5 %, 3 floors) of its length (the floor `ND T^1.5 / sqrt
/// 6`, ND = 4.8 LSB / sqrt(1500 Hz)), never back against its direction by more than 2 mm or
/// 3 floors (what a stop's late bridge may step back for its velocity error), and the
/// tracker at rest 2.5 s after it.
fn slow_stroke_arrives(d: f64, dur: f64, seed: u64) {
    stroke_arrives(d, dur, 311.0, seed, 2);
}

/// A minimum-jerk stroke of `d` m over `dur` s at `deg` degrees, after 1 s of rest, with
/// [`noisy_code`]`(.., k)`'s white noise (`sqrt(11.5 k)` LSB a sample; noise draw `seed`,
/// calibration included): as [`slow_stroke_arrives`].
fn stroke_arrives(d: f64, dur: f64, deg: f64, seed: u64, k: usize) {
    let (case, error, allowed, retreat, still) = stroke_outcome(d, dur, deg, 1.0, seed, k);
    assert!(error <= allowed, "{case}, allowed {allowed:.1}");
    let floor = legs_nd(k) * dur.powf(1.5) / 6f64.sqrt() * 1000.0;
    assert!(retreat <= (3.0 * floor).max(2.0), "{case}");
    assert!(still, "{case}");
}

/// [`stroke_arrives`]'s scene with the stroke begun `lead` s after the calibration: its
/// description, the error and what is allowed [mm], the largest retreat [mm], and whether
/// the tracker ends still.
fn stroke_outcome(
    d: f64,
    dur: f64,
    deg: f64,
    lead: f64,
    seed: u64,
    k: usize,
) -> (String, f64, f64, f64, bool) {
    let dir = deg.to_radians();
    let lsb = Config::default().m_s2_per_lsb;
    let nd = (11.5 * k as f64).sqrt() * lsb / 1500f64.sqrt();
    let floor = nd * dur.powf(1.5) / 6f64.sqrt();
    let allowed = (0.05 * d).max(3.0 * floor) * 1000.0;
    let (end, retreat, still) = run_stroke(seed, k, 2.5 + lead + dur, dir, |time| {
        let a = d / (dur * dur) * step_accel((time - lead) / dur);
        [a * dir.cos(), a * dir.sin()]
    });
    let error = (end[0] - d * 1000.0 * dir.cos()).hypot(end[1] - d * 1000.0 * dir.sin());
    let case = format!(
        "{:.1} mm over {dur} s, draw {seed}: at {end:?} mm, error {error:.1} mm, back {retreat:.1} mm",
        d * 1000.0
    );
    (case, error, allowed, retreat, still)
}

/// `seconds` of horizontal acceleration `acc(time)` [m/s^2] after a calibration of 1 s, with
/// [`noisy_code`]`(.., k)`'s noise in noise draw `seed`: where the cursor ends [mm], how far
/// it went back against the direction `dir` [rad] from the farthest it reached along it [mm],
/// and whether the tracker rests at the end.
fn run_stroke(
    seed: u64,
    k: usize,
    seconds: f64,
    dir: f64,
    acc: impl Fn(f64) -> [f64; 2],
) -> ([f64; 2], f64, bool) {
    let lsb = Config::default().m_s2_per_lsb;
    let (mut n, mut t) = noisy_calibrated(seed, k);
    let (mut pos, mut best, mut retreat) = ([0i64; 2], 0f64, 0f64);
    let along = |p: [i64; 2]| (p[0] as f64 * dir.cos() + p[1] as f64 * dir.sin()) * 25.4 / 800.0;
    for i in 0..(seconds * 3000.0) as usize {
        let a = acc(i as f64 / 3000.0);
        let c = [
            noisy_code(&mut n, 2048.0 + a[0] / lsb, k),
            noisy_code(&mut n, 2048.0 + a[1] / lsb, k),
            noisy_code(&mut n, 2048.0, k),
        ];
        t.feed(&[c]);
        if i % 3 == 2 {
            let c = t.take_counts();
            pos = [pos[0] + i64::from(c[0]), pos[1] + i64::from(c[1])];
            best = best.max(along(pos));
            retreat = retreat.max(best - along(pos));
        }
    }
    let end = [pos[0] as f64, pos[1] as f64].map(|p| p * 25.4 / 800.0);
    (end, retreat, t.is_still())
}

/// Legs `(d m, dur s, deg)` of minimum-jerk strokes back to back after 1 s of rest, with
/// [`noisy_code`]`(.., k)`'s noise, in each noise draw of `seeds`: the cursor ends within
/// max(5 % of the path, 3 floors of the whole) of the legs' sum.
fn zigzag_arrives(legs: &[(f64, f64, f64)], seeds: impl IntoIterator<Item = u64>, k: usize) {
    for seed in seeds {
        let (error, allowed) = zigzag(legs, seed, k);
        assert!(
            error <= allowed,
            "draw {seed}: {error:.1} mm off, allowed {allowed:.1}"
        );
    }
}

/// The horizontal acceleration [m/s^2] at `time` [s] of minimum-jerk legs `(d m, dur s,
/// deg)` back to back from time 0.
fn legs_acc(legs: &[(f64, f64, f64)], time: f64) -> [f64; 2] {
    let mut acc = [0f64; 2];
    let mut t0 = 0.0;
    for &(d, dur, deg) in legs {
        let u = (time - t0) / dur;
        if (0.0..1.0).contains(&u) {
            let a = d / (dur * dur) * step_accel(u);
            let r = f64::to_radians(deg);
            acc = [acc[0] + a * r.cos(), acc[1] + a * r.sin()];
        }
        t0 += dur;
    }
    acc
}

/// [`zigzag_arrives`]'s one draw: how far the cursor ends from the legs' sum, and the error
/// allowed [mm].
fn zigzag(legs: &[(f64, f64, f64)], seed: u64, k: usize) -> (f64, f64) {
    let total: f64 = legs.iter().map(|l| l.1).sum();
    let path: f64 = legs.iter().map(|l| l.0).sum();
    let allowed = (0.05 * path).max(3.0 * legs_nd(k) * total.powf(1.5) / 6f64.sqrt()) * 1000.0;
    let mut truth = [0f64; 2];
    for &(d, _, deg) in legs {
        let r = f64::to_radians(deg);
        truth = [
            truth[0] + d * 1000.0 * r.cos(),
            truth[1] + d * 1000.0 * r.sin(),
        ];
    }
    let end = legs_moved(legs, seed, k, -1.0);
    ((end[0] - truth[0]).hypot(end[1] - truth[1]), allowed)
}

/// The noise density of [`noisy_code`]`(.., k)` at 3 kHz [m/s^2/sqrt(Hz)].
fn legs_nd(k: usize) -> f64 {
    (11.5 * k as f64).sqrt() * Config::default().m_s2_per_lsb / 1500f64.sqrt()
}

/// The cursor's motion [mm] from `from_s` [s] of minimum-jerk legs `(d m, dur s, deg)` (back
/// to back from time 0, after 1 s at rest) to 3.5 s after them, at 3 kHz with noise draw
/// `seed` of [`noisy_code`]`(.., k)`.
fn legs_moved(legs: &[(f64, f64, f64)], seed: u64, k: usize, from_s: f64) -> [f64; 2] {
    let lsb = Config::default().m_s2_per_lsb;
    let total: f64 = legs.iter().map(|l| l.1).sum();
    let (mut n, mut t) = noisy_calibrated(seed, k);
    let mut pos = [0i64; 2];
    let mut from = [0i64; 2];
    let start = ((1.0 + from_s) * 3000.0) as usize;
    for i in 0..((3.5 + total) * 3000.0) as usize {
        if i == start {
            from = pos;
        }
        let acc = legs_acc(legs, i as f64 / 3000.0 - 1.0);
        feed_horizontal(&mut t, &mut n, acc.map(|a| a / lsb), k, i, &mut pos);
    }
    [0, 1].map(|a| (pos[a] - from[a]) as f64 * 25.4 / 800.0)
}

#[test]
fn a_noisy_stroke_whose_hold_is_released_at_its_crest_is_not_taken_for_a_tilt() {
    // A 45.5 mm stroke over 1.68 s at 90 degrees with 11.7 LSB of white noise a sample
    // (741 ug/sqrt(Hz)): its first lobe peaks at 0.093 m/s^2, 5.8 sd of a 100 ms sub-window,
    // and is held as one-sided; near its crest one sub-window falls short, which releases the
    // hold while the level before was significant, so a shadow begins from that level. At the
    // crest the shadow is quiet and its velocity small: allowed to win before it has gone
    // both ways against the level, it won within 50 ms and took the stroke's first half for
    // a tilt. Draws 22 and 27 arrive within max(5 %, 3 floors) = 19.4 mm; control: with a
    // released shadow allowed to win one-sided, they end 38.5 and 37.6 mm off.
    for seed in [22, 27] {
        stroke_arrives(0.0455, 1.68, 90.0, seed, 12);
    }
}

#[test]
fn the_rest_of_a_deceleration_found_late_resumes_the_stroke_that_stopped() {
    // The same stroke and noise: mid-stroke the velocity's uncertainty (1.2 s of 741
    // ug/sqrt(Hz), the zero averaged over 1 s: 8.4 mm/s) explains 26 mm/s, and the motion
    // stops while the hand still moves. The rest of its deceleration starts a motion whose
    // run began at that stop, found 0.26 s later: past the stopped velocity's wait counted to
    // the alarm (0.25 s), within it counted to the onset. Draws 17 and 23 arrive (within 19.4
    // mm, never back by more than 2 mm); control: with the wait counted to the alarm, the
    // deceleration starts from zero velocity and they end 87.0 and 75.4 mm off, going back
    // 82.5 and 58.6 mm.
    for seed in [17, 23] {
        stroke_arrives(0.0455, 1.68, 90.0, seed, 12);
    }
}

#[test]
fn a_zigzag_leg_that_does_not_decelerate_the_stopped_one_starts_from_rest() {
    // A new user's zigzag: five legs back to back, each a minimum-jerk stroke (so each ends
    // at rest), alternating 166 and 94 degrees, with 6.8 LSB of white noise a sample (428
    // ug/sqrt(Hz)). Each leg's stop keeps its velocity for the next; a leg that resumed it
    // carried that motion's whole uncertainty, its stop test explained it within tens of
    // milliseconds, and the leg's rest glided. Only a motion that decelerates the stopped
    // velocity is its rest. Draws 4, 6, 7 and 8 end 7.0, 5.8, 29.7 and 3.7 mm off, within
    // max(5 % of the 83.7 mm path, 3 floors of the 3.73 s) = 37.0 mm; control: resuming
    // any motion that starts within the wait, 108.7, 185.8, 164.1 and 49.0 mm off. (Of 40
    // draws, 17 missed before and 6 still do.)
    let legs = [
        (0.0283, 0.59, 166.0),
        (0.0117, 0.72, 94.0),
        (0.0118, 0.81, 166.0),
        (0.0188, 0.97, 94.0),
        (0.0131, 0.64, 166.0),
    ];
    zigzag_arrives(&legs, [4, 6, 7, 8], 4);
}

/// A desk a machine shakes with `mg` milli-g at `hz` Hz on every axis (phases 0, 1 and 2
/// radians), starting `machine` s into tracking and ramped in over 0.2 s, and a sensor of
/// [`noisy_code`]`(.., k)`'s white noise.
#[derive(Clone, Copy)]
struct Shaking {
    mg: f64,
    hz: f64,
    k: usize,
    machine: f64,
}

impl Shaking {
    /// The machine's acceleration on X, Y and Z at `time` s into tracking [LSB, at `lsb`
    /// m/s^2 a code]: none before it starts, then ramped in over 0.2 s.
    fn at(&self, time: f64, lsb: f64) -> [f64; 3] {
        let amp = self.mg * 1e-3 * 9.80665 / lsb;
        let w = std::f64::consts::TAU * self.hz;
        let on = time - self.machine;
        [0.0, 1.0, 2.0].map(|ph| amp * (on / 0.2).clamp(0.0, 1.0) * (w * on + ph).sin())
    }
}

/// A minimum-jerk stroke of `d` m over `dur` s at 311 degrees, 1.5 s after the machine of
/// `desk` starts (noise draw `seed`, calibration on the quiet desk before): how far the
/// cursor ends from the stroke's end 2.5 s after it, and the error allowed, max(5 %, 3
/// floors) [mm]. With `d = 0`, how far it moved at all.
fn stroke_on_a_shaking_desk(desk: Shaking, d: f64, dur: f64, seed: u64) -> (f64, f64) {
    let Shaking { k, machine, .. } = desk;
    let deg = 311.0f64;
    let dir = deg.to_radians();
    let lsb = Config::default().m_s2_per_lsb;
    let nd = (11.5 * k as f64).sqrt() * lsb / 1500f64.sqrt();
    let allowed = (0.05 * d).max(3.0 * nd * dur.powf(1.5) / 6f64.sqrt()) * 1000.0;
    let (mut n, mut t) = noisy_calibrated(seed, k);
    let mut cursor = Cursor::default();
    // The machine starts 2 s into tracking, the stroke 1.5 s later.
    for i in 0..((machine + 1.5 + dur + 2.5) * 3000.0) as usize {
        let time = i as f64 / 3000.0;
        let a = d / (dur * dur) * step_accel((time - machine - 1.5) / dur) / lsb;
        let v = desk.at(time, lsb);
        let c = [
            noisy_code(&mut n, 2048.0 + a * dir.cos() + v[0], k),
            noisy_code(&mut n, 2048.0 + a * dir.sin() + v[1], k),
            noisy_code(&mut n, 2048.0 + v[2], k),
        ];
        t.feed(&[c]);
        cursor.poll(&mut t, i, false);
    }
    let (_, error) = cursor.judge(d, dir);
    (error, allowed)
}

#[test]
fn strokes_on_a_shaking_desk_arrive_as_on_a_quiet_one() {
    // A machine shakes the desk with 47.6 mg at 30 Hz on every axis, 4.8 LSB of white noise
    // a sample (303 ug/sqrt(Hz)); strokes of 15 mm over 1 s, 20 mm over 1.5 s and 30 mm over
    // 1.8 s, draws 0-7: all 24 within max(5 %, 3 floors). Two rules carry them; controls:
    // - the slow start test's kappa widened by what the vibration can put into a tick
    //   (`G_band A`) instead of its run judged net of what it can add to a run: 11 of the 16
    //   slower strokes outside (4 of the 20 mm ones never move);
    // - the noise learnt at rest from ticks the desk's disturbance shook: the learnt sd grows
    //   2.2-fold in 3 s, and 19 of the 24 are outside (every 20 and 30 mm stroke never
    //   moves).
    let desk = Shaking {
        mg: 47.6,
        hz: 30.0,
        k: 2,
        machine: 2.0,
    };
    for (d, dur) in [(0.015, 1.0), (0.02, 1.5), (0.03, 1.8)] {
        for seed in 0..8 {
            let (error, allowed) = stroke_on_a_shaking_desk(desk, d, dur, seed);
            assert!(
                error <= allowed,
                "{d} m over {dur} s, draw {seed}: {error:.1} mm off, allowed {allowed:.1}"
            );
        }
    }
}

#[test]
fn a_stroke_found_whole_after_it_ended_on_a_shaking_desk_is_not_taken_for_the_shaking() {
    // The machine starts as tracking does, and a weak stroke, 12 mm over 1.6 s, comes 1.5 s
    // later: in draws 2, 8 and 12 it is found after it ended (its first lobe's run with its
    // second), replayed whole, and at rest again at once. A motion started on a disturbed
    // desk is held until its velocity stands out of the disturbance's: at the replay's end
    // it does not, but at the replayed blocks' ends it did, so it is a hand's. They end 6.8,
    // 1.1 and 4.7 mm off (allowed 7.35); control: judged on the velocity at the replay's
    // end, each is discarded as the shaking and the cursor never moves (12 mm off).
    let desk = Shaking {
        mg: 47.6,
        hz: 30.0,
        k: 2,
        machine: 0.0,
    };
    for seed in [2, 8, 12] {
        let (error, allowed) = stroke_on_a_shaking_desk(desk, 0.012, 1.6, seed);
        assert!(
            error <= allowed,
            "draw {seed}: {error:.1} mm off, allowed {allowed:.1}"
        );
    }
}

#[test]
fn a_machine_starting_up_does_not_move_a_resting_cursor() {
    // A quieter sensor (3.4 LSB a sample, 214 ug/sqrt(Hz)); a machine of 48 mg starts on the
    // desk (ramped in over 0.2 s) and runs for a minute: at 30 Hz (draw 2) and at 35 Hz
    // (draw 0) the cursor moves by at most a count (0.032 mm). While it spins up the
    // disturbance is not measured yet: the hand-band residual shows a tick 40 ms after it
    // (the filter's centre), while the fast start test sees it within a millisecond. A
    // motion found within a tick is made unproven at a tick's end that shows the desk
    // disturbed, while none of it has been delivered; control: judged at its start alone,
    // 0.11 and 0.07 mm (3.5 and 2.2 counts).
    for (hz, seed) in [(30.0, 2), (35.0, 0)] {
        let desk = Shaking {
            mg: 48.0,
            hz,
            k: 1,
            machine: 2.0,
        };
        let (moved, _) = stroke_on_a_shaking_desk(desk, 0.0, 60.0, seed);
        assert!(moved <= 0.0318, "{hz} Hz, draw {seed}: {moved:.3} mm");
    }
}

#[test]
fn a_slow_stroke_whose_lobes_each_fall_short_of_the_alarm_arrives_from_the_two_together() {
    // The same noise as above (a tick's mean 1.2 LSB sd). An 8 mm stroke over 1 s peaks at
    // 0.046 m/s^2 = 1.6 tick sd and its lobes average 1.0 tick sd (0.7 on each axis at 311
    // degrees): each lobe's run of the slow CUSUM, about (0.7 - 1/2) sd over 100 ticks,
    // stays under its alarm (24.5 sd; 6 to 21 sd in draws 1000-1003), but the two together
    // can pass the two-lobe alarm (27.7 sd) at the second's end, and the whole stroke is
    // replayed from the first's onset. Draws 1000-1007 all
    // arrive; control: without the two-lobe test, draws 1000, 1001, 1003, 1006 and 1007
    // never move. A 12 mm stroke over 1.6 s is longer than the replay (1.24 s): its pair is
    // taken as the first lobe's onset is about to leave the blocks (draws 1000-1007 arrive;
    // without that check, or without the two-lobe test, 1000-1002 never move).
    for seed in 1000..1008 {
        slow_stroke_arrives(0.008, 1.0, seed);
        slow_stroke_arrives(0.012, 1.6, seed);
    }
}

#[test]
fn a_slow_stroke_whose_second_lobe_peaked_before_its_first_lobes_onset_leaves_the_blocks_arrives() {
    // The two-lobe sum is checked once more as the first lobe's onset is about to leave the
    // blocks (1.24 s of them), for a stroke whose second lobe's run ends later. A stroke of 1.2
    // to 1.3 s ends its second lobe's run just after that moment, while the run has already
    // peaked and is falling: the check must take the run's highest value, as the check at
    // its end does, not its value at that tick. The noise of the tests above (a tick's mean
    // 1.2 LSB sd). Of draws 1000-1023, with the run's value at that tick, 9 of 8 mm over 1.2 s
    // and 4 of 10 mm over 1.3 s missed; with its highest value, 5 and 2: the draws below
    // arrive within max(5 %, 3 floors) (control: each of them never moves).
    for seed in [1001, 1016, 1018, 1023] {
        slow_stroke_arrives(0.008, 1.2, seed);
    }
    for seed in [1000, 1022] {
        slow_stroke_arrives(0.010, 1.3, seed);
    }
}

#[test]
fn a_slow_stroke_found_on_the_axis_without_a_first_lobe_starts_from_the_other_axis_first_lobe() {
    // A stroke's lobes come on both axes at once, and noise may leave one axis's first lobe
    // under lobe_sd while the other's passes it. A new user's 14.9 mm stroke over 1.61 s,
    // 0.5 s after the calibration, alarmed on Y's second lobe with no first lobe of Y's own
    // and glided back 209 mm from zero velocity there, while X's second lobe's run, past
    // lobe_sd, was going on after a first lobe of 5.2 sd. The start now begins at the first
    // lobe of such a run on either axis. 15 mm over 1.6 s at 320 degrees 1 s after the
    // calibration, with 4.8 LSB of white noise a sample: of 48 draws, 2 miss (control: 3,
    // the draw below 7.8 mm off, 7.3 allowed). (The 20 mm strokes over 1.8 s this test also
    // asked of, three draws that glided back 87-107 mm without the rule, are found since the
    // twenty-third stop as their first lobe leaves the blocks, with the rule or without it:
    // [`a_long_slow_stroke_starts_as_its_first_lobe_leaves_the_blocks`].)
    let (case, error, allowed, retreat, still) = stroke_outcome(0.015, 1.6, 320.0, 1.0, 1042, 2);
    assert!(
        error <= allowed && retreat <= 2.0 && still,
        "{case}, allowed {allowed:.1}"
    );
}

#[test]
fn a_long_slow_stroke_starts_as_its_first_lobe_leaves_the_blocks() {
    // 20 mm along X over 2 s, 2 s after the calibration, with 4.8 LSB of white noise a
    // sample: each lobe's run stays under the slow alarm (its mean acceleration is about
    // 0.6 of a tick's sd, the CUSUM's kappa 0.5), and the pair's sum passes its own only
    // after the first lobe's onset has left the blocks a start replays (1.26 s), so it
    // started nothing: 14 of 48 draws were lost whole (the rest found late, from zero
    // velocity). As that onset is about to leave, a second lobe going on after a first lobe
    // past lobe_sd is a stroke no noise makes (a noise run does not last a second): the
    // motion starts there from the onset, unproven, and is delivered once its velocity
    // stands out. Every draw now moves the cursor toward the stroke's end and rests there.
    for seed in 0..48 {
        let (case, error, allowed, retreat, still) = stroke_outcome(0.02, 2.0, 0.0, 2.0, seed, 2);
        assert!(
            error < 20.0 && still,
            "{case}, allowed {allowed:.1}, back {retreat:.1} mm"
        );
    }
}

#[test]
fn a_long_slow_stroke_is_not_stopped_while_it_decelerates() {
    // The same strokes: found as the first lobe leaves the blocks, the motion's velocity is
    // short of the hand's by what that lobe gave before its run rose, and its deceleration,
    // 2 mg against a 20 ms mean's sd of 1.5 mg, is within the quiet test: its velocity was
    // explained mid-way through the deceleration, and the rest of it, found again from rest,
    // ran the cursor back. A motion started so is held on while the tilt tests' long
    // sub-window is significant against its travel. The first four draws that went back
    // more than 2 mm without it (3.3, 4.3, 3.4 and 2.6 mm) now go back less than that
    // (target 2's bound for a drag, asked here of a stroke).
    for seed in [5, 7, 9, 13] {
        let (case, error, allowed, retreat, still) = stroke_outcome(0.02, 2.0, 0.0, 2.0, seed, 2);
        assert!(
            retreat <= 2.0 && error < 20.0 && still,
            "{case}, allowed {allowed:.1}, back {retreat:.1} mm"
        );
    }
}

#[test]
fn a_long_slow_stroke_waits_out_a_deceleration_under_the_sub_window_test() {
    // The same 20 mm over 2 s along X as above. Near the floor its deceleration stays under
    // the long sub-window's significance for most of its length: released as soon as its
    // velocity was explained, the motion took the hand's velocity left for error and its
    // stop's bridge moved the cursor back (draws 0, 10, 15, 42 and 45: 5.0, 7.3, 5.7, 4.5
    // and 3.9 mm back, 12.3-13.5 mm off). While the tick ring's mean acceleration points
    // against its velocity it waits: each within max(5 %, 3 floors) = 10.3 mm and back by
    // 2 mm at most. Control: without the ring's sign, all five are back and outside.
    for seed in [0, 10, 15, 42, 45] {
        let (case, error, allowed, retreat, still) = stroke_outcome(0.02, 2.0, 0.0, 2.0, seed, 2);
        assert!(
            error <= allowed && retreat <= 2.0 && still,
            "{case}, allowed {allowed:.1}"
        );
    }
}

/// A minimum-jerk ramp from 0 to 1 over `u` in 0..1.
fn ramp(u: f64) -> f64 {
    let u = u.clamp(0.0, 1.0);
    u * u * u * (10.0 - 15.0 * u + 6.0 * u * u)
}

/// A new user's lift and stroke (noise draw `seed`, [`wide_code`]'s 4.8 LSB a sample): lifted
/// 5.6 mm over 0.406 s at 1 s, 0.651 s in the air wobbling (1.4 and 1.7 degrees at 2.05 Hz),
/// set down level over 0.476 s (too gently for the fall test: the landing waits for the
/// lift's timeout), then a 269.5 mm stroke over 0.95 s at 313 degrees begun `gap` s after the
/// touchdown. Returns how far the cursor ends from where the stroke should have taken it,
/// and the most one poll (3 samples) moved it [mm].
fn lift_then_stroke(seed: u64, gap: f64) -> (f64, f64) {
    const G: f64 = 9.80665;
    let fs = 3000.0;
    let lsb = Config::default().m_s2_per_lsb;
    let (h, rise, air, fall) = (0.0056, 0.406, 0.651, 0.476);
    let (roll, pitch, wf) = (-1.4f64.to_radians(), 1.7f64.to_radians(), 2.05);
    let (len, dur, dir) = (0.2695, 0.95, 313f64.to_radians());
    let t0 = 1.0 + rise + air + fall + gap;
    let pose = |t: f64| {
        let z = h * ramp((t - 1.0) / rise) - h * ramp((t - 1.0 - rise - air) / fall);
        let u = (t - 1.0 - rise) / air;
        let w = if (0.0..=1.0).contains(&u) {
            let pi = std::f64::consts::PI;
            (pi * u).sin().powi(2) * (2.0 * pi * wf * (t - 1.0 - rise) + 1.0).sin()
        } else {
            0.0
        };
        let m = len * ramp((t - t0) / dur);
        ([m * dir.cos(), m * dir.sin(), z], [roll * w, pitch * w])
    };
    let (mut n, mut t) = wide_calibrated(seed);
    let (mut pos, mut start, mut jump) = ([0i64; 2], [0i64; 2], 0f64);
    let mm = |c: i64| c as f64 * 25.4 / 800.0;
    for i in 0..((t0 + dur + 3.0) * fs) as usize {
        let time = i as f64 / fs;
        let (p0, p1, p2) = (pose(time - 1.0 / fs), pose(time), pose(time + 1.0 / fs));
        let a: [f64; 3] = core::array::from_fn(|k| (p2.0[k] - 2.0 * p1.0[k] + p0.0[k]) * fs * fs);
        // The specific force in the device's frame: (a + g) rotated back, less g.
        let ((sr, cr), (sp, cp)) = (p1.1[0].sin_cos(), p1.1[1].sin_cos());
        let r = [
            [cp, sp * sr, sp * cr],
            [0.0, cr, -sr],
            [-sp, cp * sr, cp * cr],
        ];
        let w = [a[0], a[1], a[2] + G];
        let f: [f64; 3] = core::array::from_fn(|k| {
            r[0][k] * w[0] + r[1][k] * w[1] + r[2][k] * w[2] - if k == 2 { G } else { 0.0 }
        });
        t.feed(&[core::array::from_fn(|k| {
            wide_code(&mut n, 2048.0 + f[k] / lsb)
        })]);
        if i % 3 == 2 {
            let c = t.take_counts();
            jump = jump.max(mm(i64::from(c[0])).hypot(mm(i64::from(c[1]))));
            pos = [pos[0] + i64::from(c[0]), pos[1] + i64::from(c[1])];
        }
        if i == (t0 * fs) as usize {
            start = pos;
        }
    }
    let moved = [mm(pos[0] - start[0]), mm(pos[1] - start[1])];
    let want = [len * 1e3 * dir.cos(), len * 1e3 * dir.sin()];
    ((moved[0] - want[0]).hypot(moved[1] - want[1]), jump)
}

#[test]
fn a_stroke_begun_as_a_lifted_device_lands_at_its_timeout_arrives() {
    // A new user's stroke begun about 10 ms before a lifted device's timeout lands it. No
    // start test runs while lifted; the stroke's first milliseconds leave the landing
    // window's thirds steady but move the last one's means by 1.2 LSB on X and Y. Taken as
    // the zero, the stroke never came to rest against it: held, then a shadow from its crest
    // adopted, 3.9 m in one poll, the cursor 4.1 m off. The zero is the middle third's. Draws
    // 1 to 3, the stroke begun 0.630 to 0.634 s after the touchdown (the landing and the
    // stroke's start overlap there): each arrives within max(5 %, 3 floors) (13.5 mm);
    // control: with the last third, draw 1 ends 198 mm, 4.1 m and 120 mm off at 0.630, 0.631
    // and 0.632 s. Begun sooner, the stroke is lost whole while the device is still lifted.
    for seed in [1u64, 2, 3] {
        for k in 0..5 {
            let gap = 0.630 + 0.001 * f64::from(k);
            let (off, jump) = lift_then_stroke(seed, gap);
            assert!(
                off <= 0.05 * 269.5,
                "draw {seed}, {gap:.3} s: {off:.0} mm off, {jump:.0} mm in one poll"
            );
        }
    }
}

#[test]
fn a_pair_whose_first_lobe_has_left_the_replay_starts_nothing() {
    // A new user's out-and-back: 21.8 mm over 1.16 s at 68 degrees, 20 ms still, 20.1 mm
    // back over 1.57 s, on a noisier sensor (92 draws a code: 6.8 LSB a sample, about 420
    // ug/sqrt(Hz) over the 1.5 kHz band). The out stroke's second lobe and the back stroke's
    // first have one sign and make one run; paired with the out stroke's first lobe at that
    // run's end, their onset had left the 1.26 s of blocks, and the replay from the oldest
    // block started the motion mid-way from zero velocity: it glided on for seconds. A pair
    // is now taken only while its first lobe's onset is in the blocks. Noise draw 36 ends
    // within max(5 % of the 41.9 mm path, 3 floors of the whole 2.75 s: 23.4 mm), 21 mm off;
    // control: started from the oldest block, 340 mm off. (Of 60 draws that one changed; 4
    // others end 300 to 400 mm off either way, a failure of this noise level that is not
    // the pair's: draws 10, 37, 50, 59.)
    let (d1, t1, gap, d2, t2) = (0.0218f64, 1.16f64, 0.02f64, 0.0201f64, 1.57f64);
    let dir = 68f64.to_radians();
    let lsb = Config::default().m_s2_per_lsb;
    let acc = |d: f64, dur: f64, t: f64| d / (dur * dur) * step_accel(t / dur);
    let mut n = Noise(Trace::new(36));
    let mut t = Tracker::new(&Config::default()).expect("valid");
    let cal: Vec<[u16; 3]> = (0..3000)
        .map(|_| core::array::from_fn(|_| noisy_code(&mut n, 2048.0, 4)))
        .collect();
    t.feed(&cal);
    let mut pos = [0i64; 2];
    for i in 0..((1.0 + t1 + gap + t2 + 6.0) * 3000.0) as usize {
        let time = i as f64 / 3000.0 - 1.0;
        let a = acc(d1, t1, time) - acc(d2, t2, time - t1 - gap);
        let c = [
            noisy_code(&mut n, 2048.0 + a * dir.cos() / lsb, 4),
            noisy_code(&mut n, 2048.0 + a * dir.sin() / lsb, 4),
            noisy_code(&mut n, 2048.0, 4),
        ];
        t.feed(&[c]);
        if i % 3 == 2 {
            let k = t.take_counts();
            pos = [pos[0] + i64::from(k[0]), pos[1] + i64::from(k[1])];
        }
    }
    let end = pos.map(|p| p as f64 * 25.4 / 800.0);
    let want = (d1 - d2) * 1000.0;
    let off = (end[0] - want * dir.cos()).hypot(end[1] - want * dir.sin());
    let nd = (46f64).sqrt() * lsb / 1500f64.sqrt();
    let floor = nd * (t1 + gap + t2).powf(1.5) / 6f64.sqrt() * 1000.0;
    let allowed = (0.05 * (d1 + d2) * 1000.0).max(3.0 * floor);
    assert!(off <= allowed, "{off:.0} mm off, allowed {allowed:.1}");
}

#[test]
fn a_zigzag_turning_at_rest_is_not_taken_for_a_shaking_desk() {
    // A new user's zigzag: six minimum-jerk legs back to back, the second 59 mm in 0.175 s
    // (11 m/s^2 at its peak), each turning back at rest, with 4.8 LSB of white noise a
    // sample (300 ug/sqrt(Hz)). A leg's start from rest (a jerk step) and a turn (two lobes
    // of one sign meeting at zero) pass the hand-band filter's residual as a knock's ring
    // does: counted as the desk's disturbance, they widened the quiet and velocity tests
    // until the motion stopped at a turn while the next leg was already under way (at 1 m/s^2),
    // and that leg started late, from zero velocity. A residual no larger than the hand's
    // band output (which dominates the residual's power) is the hand's. Draws 1-4 end 4.2,
    // 3.7, 6.4 and 1.8 mm off, within max(5 % of the 221.9 mm path, 3 floors) = 11.1 mm (16
    // of draws 1-16, 0.8 to 6.7 mm); control: with every residual the desk's, 66.1, 110.6,
    // 103.9 and 98.9 mm off (12 of 12 draws outside, 49-128 mm); with the band output
    // measured against the zero alone, not also against its own values over the filter's
    // span, draw 4 ends 50.7 mm off (3 of 16 draws outside).
    let legs = [
        (0.0585, 0.478, 27.0),
        (0.0590, 0.175, 233.1),
        (0.0229, 0.239, 56.5),
        (0.0155, 0.256, 204.6),
        (0.0483, 0.268, 44.0),
        (0.0177, 0.447, 226.7),
    ];
    zigzag_arrives(&legs, 1..=4, 2);
}

#[test]
fn a_long_zigzag_is_never_taken_for_a_tilt_at_its_shadows_timeout() {
    // A fourth new user's zigzag on a line: eight legs back to back over 3.18 s, 26 to 79 mm
    // each, with 4.8 LSB of white noise a sample (300 ug/sqrt(Hz)). A turn's two lobes of one
    // sign hold the motion; its release at the next leg begins a shadow from the turn's
    // level (about 3 m/s^2), and neither comes to rest while the legs go on. At the shadow's
    // timeout the tilt won because the acceleration was one-sided at that moment (as a leg's
    // is half the time): the shadow, integrated for 2 s against a hand's crest, arrived in
    // one read. Now the held motion goes on at the timeout. Draws 1-4 end 8.2, 8.4, 3.3 and
    // 4.5 mm off, within max(5 % of the 438 mm path, 3 floors) = 21.9 mm (15 of draws 1-16,
    // draw 7 22.0 mm); control: with the tilt winning at the timeout while one-sided, 5.17 to
    // 5.22 m off in all 16.
    let legs = [
        (0.026, 0.52, 316.0),
        (0.070, 0.23, 136.0),
        (0.046, 0.42, 316.0),
        (0.079, 0.56, 136.0),
        (0.053, 0.27, 316.0),
        (0.070, 0.57, 136.0),
        (0.029, 0.37, 316.0),
        (0.065, 0.24, 136.0),
    ];
    zigzag_arrives(&legs, 1..=4, 2);
}

/// Noise draw `seed` of [`noisy_code`]`(.., 2)`: the pad tilts by 2 degrees within 0.1 s (X
/// reads 14 LSB more) after 1 s of rest, and minimum-jerk legs `(d m, dur s, deg)` follow
/// back to back from 0.7 s after it; where the cursor ends on X [mm] 4 s after the last.
fn tilt_then_legs(legs: &[(f64, f64, f64)], seed: u64) -> f64 {
    let lsb = Config::default().m_s2_per_lsb;
    let (mut n, mut t) = noisy_calibrated(seed, 2);
    let total: f64 = legs.iter().map(|l| l.1).sum();
    let mut pos = [0i64; 2];
    for i in 0..((1.0 + 0.7 + total + 4.0) * 3000.0) as usize {
        let time = i as f64 / 3000.0 - 1.0;
        let acc = legs_acc(legs, time - 0.7).map(|a| a / lsb);
        let tilt = 14.0 * (time / 0.1).clamp(0.0, 1.0);
        feed_horizontal(&mut t, &mut n, [tilt + acc[0], acc[1]], 2, i, &mut pos);
    }
    assert!(t.is_still(), "draw {seed}: {:?}", t.drift_state());
    pos[0] as f64 * 25.4 / 800.0
}

#[test]
fn a_long_zigzag_begun_during_a_tilts_hold_never_delivers_the_tilts_runaway() {
    // While a 2 degree tilt's motion is held, a hand zigzags along X for 3.2 s, its first leg
    // against the tilt, then rests. The tilt's level begins a shadow at the change; neither
    // comes to rest within the longest stroke, and the shadow is dropped (its level may have
    // been a pad still tilting). The next release's shadow takes its level from the legs:
    // adopted at its timeout, it delivered the tilt's runaway with the legs' (2.7 m of 0.34
    // m/s^2 over 4 s less what a hand's level took off: 1.38 to 1.41 m in draws 1-8). Kept
    // held, the motion is confirmed as a tilt once the hand rests, and nothing of it arrives:
    // the cursor may be off the legs' sum by at most that sum and what the tilt alone runs
    // before its hold (18.0 to 18.9 mm in draws 1-8: the legs' 35 mm are lost with the tilt,
    // which no statistic can tell from them while they last).
    let legs = [
        (0.040, 0.40, 180.0),
        (0.060, 0.35, 0.0),
        (0.050, 0.45, 180.0),
        (0.070, 0.40, 0.0),
        (0.045, 0.50, 180.0),
        (0.060, 0.30, 0.0),
        (0.050, 0.45, 180.0),
        (0.030, 0.35, 0.0),
    ];
    let truth: f64 = legs
        .iter()
        .map(|&(d, _, deg)| d * 1000.0 * f64::to_radians(deg).cos())
        .sum();
    for seed in 1..=4 {
        let alone = tilt_then_legs(&[], seed);
        let end = tilt_then_legs(&legs, seed);
        assert!(
            (end - truth).abs() <= truth.abs() + alone.abs(),
            "draw {seed}: {end:.1} mm, the legs {truth:.1}, the tilt alone {alone:.1}"
        );
    }
}

/// Noise draw `seed` of [`noisy_code`]`(.., k)`: after 1 s of rest a circle of radius `r`
/// [m] turned `turns` times over `dur` [s] (the angle a minimum-jerk profile), starting at
/// angle `theta0` [rad] counter-clockwise; how far the cursor ends from the circle's end
/// and the error allowed, max(5 % of the path, 3 floors) [mm].
fn circle(r: f64, turns: f64, dur: f64, theta0: f64, seed: u64, k: usize) -> (f64, f64) {
    let lsb = Config::default().m_s2_per_lsb;
    let nd = (11.5 * k as f64).sqrt() * lsb / 1500f64.sqrt();
    let path = core::f64::consts::TAU * r * turns;
    let allowed = (0.05 * path).max(3.0 * nd * dur.powf(1.5) / 6f64.sqrt()) * 1000.0;
    let (mut n, mut t) = noisy_calibrated(seed, k);
    let sweep = core::f64::consts::TAU * turns;
    let mut pos = [0i64; 2];
    for i in 0..((1.0 + dur + 3.0) * 3000.0) as usize {
        let u = ((i as f64 / 3000.0 - 1.0) / dur).clamp(0.0, 1.0);
        let mut acc = [0.0; 2];
        if u > 0.0 && u < 1.0 {
            let phi = theta0 + sweep * u * u * u * (10.0 - 15.0 * u + 6.0 * u * u);
            let w = sweep * 30.0 * u * u * (1.0 - u) * (1.0 - u) / dur;
            let dw = sweep * step_accel(u) / (dur * dur);
            acc = [
                r * (-phi.sin() * dw - phi.cos() * w * w),
                r * (phi.cos() * dw - phi.sin() * w * w),
            ];
        }
        feed_horizontal(&mut t, &mut n, acc.map(|a| a / lsb), k, i, &mut pos);
    }
    let phi = theta0 + sweep;
    let truth = [
        r * (phi.cos() - theta0.cos()),
        r * (phi.sin() - theta0.sin()),
    ]
    .map(|v| v * 1000.0);
    let end = pos.map(|p| p as f64 * 25.4 / 800.0);
    ((end[0] - truth[0]).hypot(end[1] - truth[1]), allowed)
}

/// Asserts that each noise draw in `seeds` of [`circle`]`(r, turns, dur, theta0, .., k)`
/// ends within its allowance.
fn circles_arrive(
    (r, turns, dur, theta0): (f64, f64, f64, f64),
    seeds: impl IntoIterator<Item = u64>,
    k: usize,
) {
    for seed in seeds {
        let (error, allowed) = circle(r, turns, dur, theta0, seed, k);
        assert!(
            error <= allowed,
            "draw {seed}: {error:.1} mm off, allowed {allowed:.1}"
        );
    }
}

#[test]
fn a_circle_is_never_taken_for_a_tilt() {
    // A fourth new user's circle: radius 36 mm, 1.17 turns over 3.18 s, with 4.8 LSB of
    // white noise a sample (300 ug/sqrt(Hz)). Its acceleration rotates, so each axis keeps its
    // sign for half a turn (1.4 s here, longer at the slow start and end): one-sided for
    // longer than any stroke's lobe, it was confirmed as a tilt and dropped (the cursor stopped
    // a third of the way round and never went on) and the zeros became the hand's level. A
    // tilt leaks gravity along one fixed direction; while one axis is one-sided the other
    // sweeps through both signs. Draws 1-8 end 5.4, 14.1, 11.0, 8.5, 13.7, 13.7, 4.1 and 5.5
    // mm off, within max(5 % of the 265 mm path, 3 floors) = 20.6 mm (16 of draws 1-16, at
    // most 14.5 mm); control: a tilt confirmed however the other axis turned, draws 1, 4, 6
    // and 8 end 28.3 to 31.9 mm off (9 of 16 outside).
    circles_arrive((0.036, 1.17, 3.18, 1.0), 1..=8, 2);
}

#[test]
fn a_slow_circle_held_past_the_longest_stroke_is_dropped_not_delivered() {
    // A slow circle, a fifth new user's: radius 36.8 mm, 3.89 turns over 11 s, with 10.2 LSB
    // of white noise a sample (640 ug/sqrt(Hz)). While it turns slowly an axis stays
    // one-sided for longer than the hold's 0.25 s, so the motion is held, and the
    // acceleration's change from that level starts a shadow. Neither hypothesis comes to
    // rest within the longest stroke; at that timeout the acceleration is quiet against the
    // held motion's zero, so the last sub-window's mean is no hand's: nothing held is
    // delivered, and it becomes the zero. Draws 1, 2, 3 and 5 end 14 to 21 mm off, within
    // max(5 % of the 899 mm path, 3 floors) = 283 mm. Control, the held motion going on
    // under the hold's tests (as it did until this rule): delivered when their runs broke,
    // with the velocity its start had missed, it glided to the longest calm, 1.4 to 1.9 m
    // off.
    circles_arrive((0.0368, 3.89, 11.04, 1.0), [1, 2, 3, 5], 9);
}

#[test]
fn a_small_circle_whose_shadow_rests_is_dropped_not_delivered() {
    // A small circle: radius 6 mm, 3 turns over 6 s, with 8.3 LSB of white noise a sample
    // (520 ug/sqrt(Hz)). Held as in the slow circle above, its change's shadow times out
    // with the acceleration at the shadow's level while the held motion's is off its own
    // zero: the device is not accelerating on one of the two hypotheses, so the last
    // sub-window's mean is no hand's, and it becomes the zero. Draws 1 and 8 (of draws 1-8,
    // the two this rule changes) end 6 % of their allowance off; control, the held motion
    // going on unless it is quiet on its own zero: 175 and 176 %.
    circles_arrive((0.006, 3.0, 6.0, 1.0), [1, 8], 6);
}

#[test]
fn a_circle_whose_release_shadow_times_out_at_rest_is_dropped_not_delivered() {
    // A circle: radius 10 mm, 1.5 turns over 4 s, with 8.3 LSB of white noise a sample (520
    // ug/sqrt(Hz)). Held as in the circles above, its hold is released where the
    // acceleration changes from a level, and a shadow begins from that level. Neither
    // hypothesis comes to rest within the longest stroke; at that timeout the device is
    // quiet against one of the two zeros, so the last sub-window's mean is no hand's: nothing
    // held is delivered, and it becomes the zero. Draws 1-8 end 13.3 to 16.0 mm off, within
    // max(5 % of the 94 mm path, 3 floors) = 50.3 mm. Control, the held motion going on
    // under the hold's tests after a release's timeout (as it did until this rule): draws
    // 1-6 end 78 to 359 mm off.
    circles_arrive((0.01, 1.5, 4.0, 1.0), 1..=8, 6);
}

/// Noise draw `seed` of [`noisy_code`]`(.., k)`: after 1 s of rest a push of `lsb` on Y for
/// `dur` [s] (raised-cosine edges of 0.1 s), then 20 s of rest; the longest time the tracker
/// held a motion back [s].
fn longest_hold(lsb: f64, dur: f64, seed: u64, k: usize) -> f64 {
    let (mut n, mut t) = noisy_calibrated(seed, k);
    let (mut pos, mut run, mut longest) = ([0i64; 2], 0usize, 0usize);
    for i in 0..((1.0 + dur + 20.0) * 3000.0) as usize {
        let time = i as f64 / 3000.0 - 1.0;
        let edge = |x: f64| 0.5 - 0.5 * (core::f64::consts::PI * x.clamp(0.0, 1.0)).cos();
        let a = lsb * edge(time / 0.1).min(edge((dur - time) / 0.1));
        feed_horizontal(&mut t, &mut n, [0.0, a], k, i, &mut pos);
        run = if t.is_holding() { run + 1 } else { 0 };
        longest = longest.max(run);
    }
    longest as f64 / 3000.0
}

#[test]
fn a_tilts_shadow_waits_no_longer_than_the_longest_stroke() {
    // A push of 1.5 or 2 LSB on Y for 1.2 s (raised-cosine edges), with 5.9 LSB of noise a
    // sample (370 ug/sqrt(Hz)), then rest. The push is held as one-sided and a shadow begins
    // from its level where it ends; at rest both the shadow's and the motion's quiet tests
    // pass, and the shadow waited for as long as they both did, past its timeout. A fifth new
    // user's stroke found in its second lobe was held so for 13.8 s while its wrong start
    // glided, then delivered 575 mm at once. The wait now ends with the longest stroke: no
    // hold outlasts the push, a sub-window and the longest stroke (3.3 s). Draws 1-6: at most
    // 2.8 s; control, waiting while both are quiet: draw 3 holds 4.0 s at either level.
    let bound = 1.2 + 0.1 + Drift::default().stroke_max_s;
    for lsb in [1.5, 2.0] {
        for seed in 1..=6 {
            let held = longest_hold(lsb, 1.2, seed, 3);
            assert!(held <= bound, "{lsb} LSB, draw {seed}: held {held:.2} s");
        }
    }
}

/// A pad tilting `lsb_x` LSB on X (a minimum-jerk ramp over 0.45 s from 1 s after the
/// calibration, [`noisy_code`]`(.., 2)`'s noise, draw `seed`), then, `gap` s after the
/// ramp, minimum-jerk legs `(d m, dur s, deg)`, then 4 s of rest. Returns where the cursor
/// ends against where it was when the legs began [mm].
fn tilt_gap_legs(lsb_x: f64, gap: f64, legs: &[(f64, f64, f64)], seed: u64) -> [f64; 2] {
    tilt_ramp_legs((lsb_x, 0.45), gap, legs, (seed, 2))
}

/// [`tilt_gap_legs`] with the tilt's `(lsb_x, seconds)` and the noise's `(seed, k)` given.
fn tilt_ramp_legs(
    (lsb_x, tilt_s): (f64, f64),
    gap: f64,
    legs: &[(f64, f64, f64)],
    (seed, k): (u64, usize),
) -> [f64; 2] {
    let lsb = Config::default().m_s2_per_lsb;
    let (mut n, mut t) = noisy_calibrated(seed, k);
    let total: f64 = legs.iter().map(|l| l.1).sum();
    let start = 1.0 + tilt_s + gap;
    let (mut pos, mut at_start) = ([0i64; 2], None);
    for i in 0..((start + total + 4.0) * 3000.0) as usize {
        let time = i as f64 / 3000.0;
        let acc = legs_acc(legs, time - start).map(|a| a / lsb);
        let tilt = lsb_x * ramp((time - 1.0) / tilt_s);
        if time >= start && at_start.is_none() {
            at_start = Some(pos);
        }
        feed_horizontal(&mut t, &mut n, [tilt + acc[0], acc[1]], k, i, &mut pos);
    }
    assert!(t.is_still(), "draw {seed}: {:?}", t.drift_state());
    let from = at_start.unwrap_or(pos);
    [0, 1].map(|a| (pos[a] - from[a]) as f64 * 25.4 / 800.0)
}

#[test]
fn a_zigzag_that_keeps_a_confirmed_tilts_shadow_moving_is_dropped_at_its_timeout() {
    // A pad tilts 2.1 degrees (X +15 LSB over 1 s) and 0.3 s after it rests a hand zigzags
    // along X, eight legs of 50 mm in 0.4 s each (3.2 s, ending where it began), with 5.9
    // LSB of noise a sample (370 ug/sqrt(Hz)). The tilt is confirmed as the zigzag begins,
    // the zigzag goes on as the certain shadow from the pad's level, and it never comes to
    // rest within the longest stroke: at that timeout the device is still accelerating
    // against both zeros. The tilt is certain, so the pad may still be tilting: nothing held
    // is delivered and the zeros become the last sub-window's means. Draws 1-4 end 0 to 118
    // mm from where the zigzag began, within the hand's 400 mm of travel (the legs are lost,
    // not delivered as a runaway); control, a certain shadow's timeout taken as a release's
    // (the held motion going on under the hold's tests): 1.59 to 1.62 m.
    let legs: Vec<(f64, f64, f64)> = (0..8)
        .map(|i| (0.05, 0.4, if i % 2 == 0 { 0.0 } else { 180.0 }))
        .collect();
    for seed in 1..=4 {
        let end = tilt_ramp_legs((15.0, 1.0), 0.3, &legs, (seed, 3));
        let off = end[0].hypot(end[1]);
        assert!(off <= 400.0, "draw {seed}: {end:?} mm, {off:.0} mm off");
    }
}

#[test]
fn a_stroke_just_after_a_tilt_and_against_it_arrives_when_the_tilt_is_confirmed() {
    // A new user's pad tilts 3.7 degrees (X +27 LSB over 0.45 s) and 0.2 s after it rests a
    // hand makes a slow stroke, 60.6 mm over 1.72 s at 200 degrees (its first lobe against
    // the tilt on X, 0.12 m/s^2 at its crest). The tilt's hold is released as the stroke
    // begins and its shadow, from the tilt's level, carries the stroke. The tilt is confirmed
    // (one-sided for 1 s against the old zero) before the stroke's second lobe: the shadow
    // went against the tilt (by 15 sd: a hand's lobe), so its level is the settled pad's and
    // it goes on, certain. Dropped there, the latest steady level was the first lobe's
    // crest: the rest of the stroke ran against it and was dropped as a second tilt (0 mm
    // arrived). Target 3: within max(5 %, 3 bias floors), T_rest the 0.2 s since the tilt.
    let lsb = Config::default().m_s2_per_lsb;
    let nd = 23f64.sqrt() * lsb / 1500f64.sqrt();
    let (d, dur, deg): (f64, f64, f64) = (0.0606, 1.718, 200.0);
    let sd_b = nd / (2.0 * 0.2f64).sqrt();
    let floor = (nd * nd * dur.powi(3) / 6.0 + sd_b * sd_b * dur.powi(4) / 4.0).sqrt();
    let allowed = (0.05 * d).max(3.0 * floor) * 1000.0;
    let r = deg.to_radians();
    let truth = [d * 1000.0 * r.cos(), d * 1000.0 * r.sin()];
    for seed in 1..=6 {
        let end = tilt_gap_legs(27.0, 0.2, &[(d, dur, deg)], seed);
        let error = (end[0] - truth[0]).hypot(end[1] - truth[1]);
        assert!(
            error <= allowed,
            "draw {seed}: at {end:?} mm, {error:.1} mm off, allowed {allowed:.1}"
        );
    }
}

#[test]
fn a_glide_held_after_a_tilt_is_dropped_when_no_hand_could_still_be_gliding() {
    // A pad tilts 2 degrees (X +14 LSB over 0.1 s) and its tilt is confirmed; 0.8 s later,
    // while a motion so soon after a tilt is held until its acceleration reverses, a push
    // on Y (+20 or +60 LSB for 0.1 s, 48 or 143 mm/s) that never decelerates: the velocity
    // of a start found in a stroke's second lobe, or of a tilt's remainder against a zero a
    // little off. It ends unreversed after the longest stroke, quiet with its velocity
    // explained (48 mm/s: 2.6 to 4 s later in most draws) or at the longest calm a hand has
    // (6 s), and what was held of it, never a hand's, is dropped. Controls: delivered when
    // it ends explained, 270 mm at once (draw 1, 48 mm/s); stopped as a delivered glide at
    // the calm bound, 880 mm (draw 1, 143 mm/s); with the reversal tested at K_TILT, noise
    // ended the hold in draws 4 and 5 (800 mm at once).
    for (seed, lsb) in (1..=8).flat_map(|seed| [(seed, 20.0), (seed, 60.0)]) {
        let (mut n, mut t) = noisy_calibrated(seed, 2);
        let mut pos = [0i64; 2];
        let mut at_push = [0i64; 2];
        for i in 0..(13.0 * 3000.0) as usize {
            let time = i as f64 / 3000.0;
            let tilt = 14.0 * ((time - 1.0) / 0.1).clamp(0.0, 1.0);
            let push = if (3.0..3.1).contains(&time) { lsb } else { 0.0 };
            if i == 3 * 3000 {
                assert!(t.is_still(), "{:?}", t.drift_state());
                at_push = pos;
            }
            feed_horizontal(&mut t, &mut n, [tilt, push], 2, i, &mut pos);
        }
        assert!(t.is_still(), "{:?}", t.drift_state());
        assert_eq!(
            [pos[0] - at_push[0], pos[1] - at_push[1]],
            [0, 0],
            "draw {seed}, {lsb} LSB"
        );
    }
}

#[test]
fn a_held_stroke_on_a_zero_left_off_by_a_tilt_is_dropped_not_delivered_as_a_glide() {
    // A pad tilts 3.6 degrees (X +23.4 LSB over 0.92 s) and 0.34 s after it rests a hand
    // makes a 214.6 mm stroke over 1.53 s at 148 or 212 degrees, at 800 ug/sqrt(Hz) (11.7
    // LSB a sample). The tilt is confirmed 0.08 s into the stroke, and its new zero, from a
    // steady stretch that took in the stroke's start, is 2 LSB short on X: the stroke, held
    // as a motion so soon after a tilt, runs against it. After the stroke the device rests at
    // the tilt's level. The hold is released and its shadow from that level is at rest, but
    // it may not win one-sided (a crest's shadow could), while the held motion glides on the
    // zero's 2 LSB (0.05 m/s^2). At the shadow's timeout (the longest stroke), quiet with its
    // velocity explained while the held motion's is not, the level is the zero and the held
    // motion is dropped: the stroke is lost, a bounded damage. Control: delivered from there,
    // it glided on to the longest calm, 2761 and 1236 mm off (noise draw 555; 2 of 1200
    // draws of this scene, seeds 1-600 at 148 and 212 degrees).
    let d = 0.2146;
    for deg in [148.0, 212.0] {
        let end = tilt_ramp_legs((23.4, 0.92), 0.34, &[(d, 1.532, deg)], (555, 12));
        let moved = end[0].hypot(end[1]);
        assert!(
            moved <= d * 1000.0,
            "{deg} degrees: moved {moved:.1} mm, the stroke {:.1}",
            d * 1000.0
        );
    }
}

#[test]
fn the_longest_calm_is_judged_at_its_own_spans_bound() {
    // The glide of `a_glide_no_hand_makes_stops_after_the_longest_glide_and_stroke` (+20 LSB
    // for 0.1 s, then no acceleration at all), with a jolt 2.9 s into its calm: +1 LSB on X
    // for `k` samples. The calm that ends a glide no hand makes is 6 s long, 300 of the quiet
    // test's 20 ms windows, and is broken only past `chi2 + 2 ln 300` (23.2), the bound at
    // which the whole span keeps one window's 0.27 % tail: at the fade's bound (16.9, for its
    // 12.5 windows) noise broke it in about one long calm in ten, and a runaway glided on for
    // 6 s more (a new user's two strokes after a tilt, still moving 10 s after the hand). The
    // jolt's chi-square grows as `k^2`: 40 samples (between the bounds; the fade's is crossed
    // from 38) leave the glide to stop 6.1 s after its ramp; 48 (past the calm's, crossed
    // from 44) restart the calm, as a hand's deceleration does. Controls: judged at the
    // fade's bound, 40 samples restart it too; never restarted, 48 samples do not.
    for (k, moving) in [(40usize, false), (48, true)] {
        let mut t = tracker(Some(Drift::default()));
        run(&mut t, 3300 + 18_300, |i| ramp_glide(i, k));
        assert_eq!(
            t.drift_state() == Some(DriftState::Moving),
            moving,
            "a jolt of {k} samples: {:?}",
            t.drift_state()
        );
    }
}

/// Sample `i` of a scene on noise `n` with an offset on X of `x(i)` thousandths of an LSB
/// (the whole LSBs, and one more with the remainder's probability: a mean between codes).
fn dithered(i: usize, n: &mut Noise, x: impl Fn(usize) -> i64) -> [u16; 3] {
    let r = n.next();
    let p = x(i);
    let (whole, part) = (p.unsigned_abs() / 1000, p.unsigned_abs() % 1000);
    let step = (whole + u64::from((r >> 40) % 1000 < part)) as i32;
    let x = i32::from(n.code(2048)) + if p < 0 { -step } else { step };
    [x as u16, n.code(2048), n.code(2048)]
}

/// A drag along X whose ramp up the start tests miss: +0.27 LSB for 0.3 s from 1 s (a glide
/// at 1.9 mm/s), then, 2 s later, its ramp down, -0.81 LSB for 0.1 s.
fn unseen_ramp(i: usize) -> i64 {
    match i {
        3000..=3899 => 270,
        9900..=10_199 => -810,
        _ => 0,
    }
}

#[test]
fn a_drag_whose_ramp_up_is_missed_does_not_run_back_at_its_ramp_down() {
    // The ramp up's slow run rises 10 to 22 sd over 24 noise draws, under the alarm (24.5
    // sd) in 21 of them: the cursor does not move. Its ramp down, three times as steep,
    // starts a motion from zero velocity, which glides back at the drag's speed until its
    // uncertainty catches it up (0.5 to 11 mm). Its lone lobe before it, past lone_sd (10.6
    // sd: 1 % of starts find one in noise, `rest.rs`), makes it wary, and calm unreversed
    // with the lone lobe's velocity it is dropped. Two draws' runs stay under lone_sd (10.0
    // and 9.8 sd): they still go back (2.6 and 11.6 mm); no more than the two may.
    // Control: without the lone lobe's wariness 18 of the 21 go back more than 2 mm.
    //
    // The same drag 1.5 s after a brisk stroke along +X (+-20 LSB for 0.1 s each, from 0.5
    // s) that stopped: the rest since began at its stop, the drag's ramp up long after the
    // stop's wait; two of its 18 draws go back (3.1 and 2.5 mm), no more may. Control: with
    // no lone lobe kept after a stop, 15 of the 18 go back (up to 24 mm).
    for lead in [0, 1500] {
        let scene = |i: usize| match i.checked_sub(lead) {
            _ if lead > 0 && (1500..1800).contains(&i) => 20_000,
            _ if lead > 0 && (1800..2100).contains(&i) => -20_000,
            Some(k) => unseen_ramp(k),
            None => 0,
        };
        let mut missed = 0;
        let mut back = Vec::new();
        for seed in 1..=24 {
            let mut t = tracker(Some(Drift::default()));
            let mut n = Noise(Trace::new(seed));
            // The counts from just before the ramp up: the most they went back, and their
            // sum at the glide's middle.
            let (retreat, mid) =
                drag_run(&mut t, lead + 24_000, (lead + 2900, lead + 9000, 1), |i| {
                    dithered(i, &mut n, scene)
                });
            if mid == 0 {
                missed += 1;
                if retreat > 63 {
                    back.push((seed, retreat));
                }
            }
        }
        // (The case is the draws whose ramp up was missed: 21 of 24, 18 after the stroke.)
        assert!(
            missed >= 16,
            "lead {lead}: the ramp up found in {} of 24",
            24 - missed
        );
        assert!(
            back.len() <= 2,
            "lead {lead}: went back more than 2 mm: {back:?}"
        );
    }
}

#[test]
fn a_brisk_drag_after_a_lone_lobe_is_a_hands_and_is_delivered_as_it_goes() {
    // A lone lobe on X, +0.27 LSB for 0.3 s from 1 s (under the alarm and past lone_sd in
    // most noise draws, as above), then 1 s later a brisk drag the other way: -20 LSB for
    // 0.1 s (48 mm/s), a glide of 2 s and its ramp down. Its first lobe is the lone lobe's
    // mate, wary; but its velocity is soon hundreds of sd past what a lobe that never
    // alarmed can have given: the lone lobe was noise (here a glide of 1.9 mm/s), and the
    // drag is a hand's. It is delivered as it goes: 1 s into its glide, between where the
    // hand is (the lobe's glide counted) and where the drag alone took it (the lobe's glide
    // missed, 8 % more), within 3 %; and never back. Controls: dropped at its first calm as
    // the end of a missed glide, the ramp down ran the cursor back 2706-2821 counts (86-90
    // mm) in 21 of 24 draws; held on as wary, nothing arrived in those draws until the ramp
    // down reversed it.
    let scene = |i: usize| match i {
        3000..=3899 => 270,
        6000..=6299 => -20_000,
        12_300..=12_599 => 20_000,
        _ => 0,
    };
    let lsb = Config::default().m_s2_per_lsb;
    let counts = |m: f64| m / 0.0254 * 800.0;
    // 1 s into the glide, 0.05 s of ramp behind it; the lobe's glide from its middle.
    let drag = counts(20.0 * lsb * 0.1 * 1.05);
    let hand = drag - counts(0.27 * lsb * 0.3 * 1.85);
    for seed in 1..=24 {
        let mut t = tracker(Some(Drift::default()));
        let mut n = Noise(Trace::new(seed));
        let (retreat, mid) = drag_run(&mut t, 18_000, (0, 9299, -1), |i| {
            dithered(i, &mut n, scene)
        });
        let mid = mid as f64;
        assert!(
            mid > 0.97 * hand && mid < 1.03 * drag,
            "seed {seed}: {mid} counts 1 s into the glide, the hand {hand:.0}, the drag {drag:.0}"
        );
        assert!(retreat <= 63, "seed {seed}: back {retreat} counts");
    }
}

/// Asserts that a stroke beginning at sample `start` of `scene` (dithered on the tests'
/// noise, 24 draws) has its first count on X within 25 ms (75 samples) in every draw.
fn starts_within_25_ms(scene: impl Fn(usize) -> i64 + Copy, start: usize) {
    for seed in 1..=24 {
        let mut t = tracker(Some(Drift::default()));
        let mut n = Noise(Trace::new(seed));
        let mut first = None;
        for i in 0..start + 1500 {
            t.feed(&[dithered(i, &mut n, scene)]);
            if i % 3 == 2 && t.take_counts()[0] != 0 && i >= start {
                first = first.or(Some(i - start));
            }
        }
        assert!(
            first.is_some_and(|k| k <= 75),
            "seed {seed}: first count {first:?} samples after the stroke began"
        );
    }
}

#[test]
fn the_rest_of_a_deceleration_after_a_stop_is_no_lone_lobe() {
    // A brisk stroke along +X, +-20 LSB for 0.1 s each, whose deceleration goes on under the
    // stop tests (-0.27 LSB for 0.3 s after its end): the stop comes first, and the rest of
    // the deceleration is a slow run on the other side from 20 ms after it. Begun within a
    // stop's wait it is not a lone lobe, and the next stroke along +X, 1.3 s later, arrives
    // with a plain start's latency: its first count within 25 ms in every draw (17 ms, the
    // hold). Control: taken for a lone lobe, that stroke is held as its mate until it
    // reverses, its first count 160 ms late in 16 of 24 draws.
    let scene = |i: usize| match i {
        3000..=3299 | 7500..=7799 => 20_000,
        3300..=3599 | 7800..=8099 => -20_000,
        3600..=4499 => -270,
        _ => 0,
    };
    starts_within_25_ms(scene, 7500);
}

#[test]
fn a_brisk_stroke_against_a_lone_lobe_arrives_with_a_plain_starts_latency() {
    // The lone lobe of the tests above, +0.27 LSB on X for 0.3 s, then 1 s later a brisk
    // stroke the other way, -20 LSB for 0.1 s and +20 LSB for 0.1 s (24 mm). It is the lone
    // lobe's mate, wary; but within a few ticks its velocity is past anything the lone lobe
    // can have given: a hand's stroke, delivered with a plain start's latency (its first
    // count within 25 ms in every draw: 17-20 ms). Control: refuted only at its first calm,
    // it is held until its reversal is seen, its first count 160 ms late in 19 of 24 draws.
    let scene = |i: usize| match i {
        3000..=3899 => 270,
        6000..=6299 => -20_000,
        6300..=6599 => 20_000,
        _ => 0,
    };
    starts_within_25_ms(scene, 6000);
}

#[test]
fn a_stroke_soon_after_calibration_is_not_taught_to_the_noise_before_it_is_found() {
    // 0.4 s after the calibration, short strokes on a noisy sensor (k = 12: 740 ug/sqrt(Hz))
    // whose first lobe stays under the alarms: the two-lobe sum finds them at the second
    // lobe's end. The noise is learnt from ticks 320 ms old, so meanwhile the first lobe's
    // blocks were learnt as noise: in draw 1007 the learnt sd on X rose 7.7 % in one block,
    // and the second lobe's run, standardised by it, fell short: both draws never moved. A
    // block is learnt as at most 16 times the variance (4 sd of its sum, see drift::noise):
    // that block raised the sd 5.7 %, and both arrive.
    for (d, dur, seed) in [(0.007, 0.6, 1007), (0.008, 0.7, 1017)] {
        let (case, error, allowed, retreat, _) = stroke_outcome(d, dur, 30.0, 0.4, seed, 12);
        assert!(error <= allowed, "{case}: allowed {allowed:.1} mm");
        assert!(retreat <= 2.0, "{case}");
    }
}

/// The horizontal acceleration [m/s^2] at `time` [s] of a stroke of `d` m along `deg` that
/// speeds up over a half sine of `t_acc` s and stops over one of `t_dec` s (a hand that eases
/// in and stops sharply, or the reverse).
fn asym_acc(d: f64, t_acc: f64, t_dec: f64, deg: f64, time: f64) -> [f64; 2] {
    use core::f64::consts::PI;
    let peak = 2.0 * d / (t_acc + t_dec);
    let a = if (0.0..t_acc).contains(&time) {
        peak * PI / (2.0 * t_acc) * (PI * time / t_acc).sin()
    } else if (t_acc..t_acc + t_dec).contains(&time) {
        -peak * PI / (2.0 * t_dec) * (PI * (time - t_acc) / t_dec).sin()
    } else {
        0.0
    };
    let dir = deg.to_radians();
    [a * dir.cos(), a * dir.sin()]
}

/// [`asym_acc`]'s stroke `lead` s after a calibration of 1 s, then 4 s of rest, with
/// [`noisy_code`]`(.., 2)`'s noise (4.8 LSB a sample) in noise draw `seed`: the case, the
/// error and what target 1 allows (max(5 %, 3 floors), the floor `ND T^1.5 / sqrt 6` for `T =
/// t_acc + t_dec`) [mm], and how far the cursor went back against the stroke [mm].
fn asym_outcome(d: f64, t_acc: f64, t_dec: f64, lead: f64, seed: u64) -> (String, f64, f64, f64) {
    let deg = 3.0f64;
    let dir = deg.to_radians();
    let nd = 23f64.sqrt() * Config::default().m_s2_per_lsb / 1500f64.sqrt();
    let allowed = (0.05 * d).max(3.0 * nd * (t_acc + t_dec).powf(1.5) / 6f64.sqrt()) * 1000.0;
    let (end, retreat, _) = run_stroke(seed, 2, lead + t_acc + t_dec + 4.0, dir, |time| {
        asym_acc(d, t_acc, t_dec, deg, time - lead)
    });
    let error = (end[0] - d * 1000.0 * dir.cos()).hypot(end[1] - d * 1000.0 * dir.sin());
    let case = format!(
        "{:.1} mm over {t_acc} + {t_dec} s, draw {seed}: at {end:.1?} mm, error {error:.1} mm, back {retreat:.1} mm",
        d * 1000.0
    );
    (case, error, allowed, retreat)
}

#[test]
fn a_stroke_that_eases_in_and_stops_sharply_starts_from_its_first_lobe() {
    // 8.8 mm speeding up over 0.9 s and stopping in 0.3 s, 0.3 s after calibration: the first
    // lobe (its peak 1.07 LSB, 0.9 sd of a tick) hardly lifts the slow run; the sharp stop
    // alarms the fast CUSUM within a tick. The tick's end would have taken the onset back to
    // the slow run's first lobe; the test within the tick took it from the fast run alone,
    // integrated the stop from zero velocity, and the cursor glided back (draws 7, 10 and 25:
    // 140, 19 and 106 mm) until the longest glide. Each now within max(5 %, 3 floors) = 4.8
    // mm, never back by more than 2 mm. Control: without the first lobe in the test within a
    // tick, all three go back.
    for seed in [7, 10, 25] {
        let (case, error, allowed, retreat) = asym_outcome(0.0088, 0.9, 0.3, 0.3, seed);
        assert!(
            error <= allowed && retreat <= 2.0,
            "{case}, allowed {allowed:.1} mm"
        );
    }
}

#[test]
fn a_stroke_that_came_to_rest_near_the_velocity_it_resumed_did_not_hold_it() {
    // 20 mm along X over 1.2 s, then 0.1 s at rest, then 25 mm over 0.3 s at 120 degrees,
    // with 6.8 LSB of white noise a sample (428 ug/sqrt(Hz)). The slow stroke stops with a
    // velocity its uncertainty explains and keeps it for the stop's wait; the brisk one
    // begins within it, its first lobe against that velocity, and resumes it as the rest of
    // a deceleration, with the stopped motion's uncertainty. It came to rest with a velocity
    // nearer the one it resumed than zero: it carried that velocity, a motion of its own.
    // Its stop takes back what the carried velocity moved over its own samples and bridges
    // only its own velocity error. Draws 17 and 43 end 3.0 and 1.8 mm off, within max(5 % of
    // the 45 mm path, 3 floors of the 1.6 s) = 10.4 mm; control: bridged as one motion over
    // the whole span, 10.9 and 10.6 mm off.
    let legs = [(0.02, 1.2, 0.0), (0.0, 0.1, 0.0), (0.025, 0.3, 120.0)];
    zigzag_arrives(&legs, [17, 43], 4);
}

#[test]
fn a_stroke_that_took_up_a_faded_glide_along_its_own_way_gives_it_back() {
    // A new tester's chain at 100 Hz: 6.7 mm over 1.455 s at 124 degrees, 0.26 s at rest,
    // then 36.8 mm over 0.396 s at 138 degrees; here at 3 kHz with 3.4 LSB of white noise a
    // sample (214 ug/sqrt(Hz)). The slow stroke's deceleration is calm past the fade's
    // quiet time, so it stops as a faded glide at a few mm/s, its velocity kept; the brisk
    // stroke takes it up and comes to rest with it still in its velocity: it carried it,
    // along its own travel. Its stop takes it back over its own samples, a step back against
    // that travel. Judged on the brisk stroke alone, within max(5 % of its 36.8 mm, 3 floors
    // of its 0.396 s) = 1.84 mm: draws 1, 6 and 12 end 0.18, 0.15 and 0.12 mm off; control
    // (no correction that points back against the travel, as the bridge): 3.05, 3.55 and
    // 3.43, 18 of draws 1-40 outside against none.
    let legs = [
        (0.0067, 1.455, 124.0),
        (0.0, 0.26, 0.0),
        (0.0368, 0.396, 138.0),
    ];
    for seed in [1, 6, 12] {
        let (error, allowed) = last_leg(&legs, seed, 1);
        assert!(
            error <= allowed,
            "draw {seed}: {error:.2} mm off, allowed {allowed:.2}"
        );
    }
}

/// How far the cursor's motion over the last of minimum-jerk legs `(d m, dur s, deg)` (from
/// its start to 3.5 s after the legs, [`legs_moved`]) is from that leg's, and the error
/// allowed it, max(5 % of its length, 3 floors of its duration) [mm].
fn last_leg(legs: &[(f64, f64, f64)], seed: u64, k: usize) -> (f64, f64) {
    let total: f64 = legs.iter().map(|l| l.1).sum();
    let &(d, dur, deg) = legs.last().expect("a leg");
    let allowed = (0.05 * d).max(3.0 * legs_nd(k) * dur.powf(1.5) / 6f64.sqrt()) * 1000.0;
    let r = f64::to_radians(deg);
    let moved = legs_moved(legs, seed, k, total - dur);
    let miss = [
        moved[0] - d * 1000.0 * r.cos(),
        moved[1] - d * 1000.0 * r.sin(),
    ];
    (miss[0].hypot(miss[1]), allowed)
}
