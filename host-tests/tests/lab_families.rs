//! The targets of docs/drift-control.md on the hand model's families, small scenes, each
//! with a control that fails: the rule the family exercises switched off.
//!
//! # Tolerances, from the trial count
//! A family of `n` trials that meets "at least `p` within" exactly would show a fraction
//! within with sd `sqrt(p (1 - p) / n)`; a test fails it only when the fraction falls more
//! than `Z = 3.09` of those below `p` (0.1 % of the time for a process that meets the target).
//! A median target `m` holds for a sample when at least `n / 2 - Z sqrt(n) / 2` trials are
//! at most `m` (the binomial count at `p = 1/2`, the same 0.1 %). A bound on every trial (a
//! re-placement's 5 mm, a drag's 2 mm retreat, 0 counts at rest) is asserted as it is. The
//! full families (200 trials each) are `cargo lab mouse`.

use host_tests::commands::mouse::families::{self, Family, Kind};
use host_tests::oracle::twin;
use host_tests::world::hand::{Motion, Scenario, Sensor, SensorSpec};
use host_tests::world::noise;
use imu_core::drift::Tuning;
use imu_core::Drift;

/// One-sided z of the tolerances: 0.1 %.
const Z: f64 = 3.09;

fn run(kind: Kind, drift: Drift, n: usize, seed: u64) -> Family {
    let dev = families::board_device(Some(drift), seed);
    families::family(kind, &dev, n, seed, families::averaging_s(Some(drift)))
}

/// The least fraction within that `n` trials of a process meeting `p` show but for 0.1 %.
fn least_within(p: f64, n: usize) -> f64 {
    p - Z * (p * (1.0 - p) / n as f64).sqrt()
}

/// Whether at least the median count of `f`'s trials are at most `m` [m], to 0.1 %.
fn median_within(f: &Family, m: f64) -> bool {
    let n = f.results.len() as f64;
    let at_most = f.results.iter().filter(|r| r.error_m <= m).count() as f64;
    at_most >= n / 2.0 - Z * n.sqrt() / 2.0
}

fn tuned(t: Tuning) -> Drift {
    Drift {
        tuning: t,
        ..Drift::default()
    }
}

#[test]
fn strokes_arrive_within_their_noise_floor_and_a_stop_on_any_velocity_cuts_them() {
    let n = 80;
    let f = run(Kind::Strokes, Drift::default(), n, 3);
    assert!(f.within >= least_within(0.9, n), "{:.3} within", f.within);
    // Control: a stop that takes every velocity for zero (the velocity test off).
    let c = run(
        Kind::Strokes,
        tuned(Tuning {
            chi2: 1e6,
            ..Tuning::default()
        }),
        n,
        3,
    );
    assert!(c.within < least_within(0.9, n), "control: {:.3}", c.within);
}

#[test]
fn drags_glide_on_and_never_run_back_and_without_the_wait_they_do() {
    let n = 60;
    let f = run(Kind::Drags, Drift::default(), n, 4);
    assert!(f.within >= least_within(0.9, n), "{:.3} within", f.within);
    let retreat = f.results.iter().map(|r| r.second).fold(0.0, f64::max);
    assert!(retreat <= 0.002, "retreat {retreat}");
    // Control: a faded glide's velocity forgotten at once: its ramp down runs it back.
    let c = run(
        Kind::Drags,
        Drift {
            glide_max_s: 0.0,
            ..Drift::default()
        },
        n,
        4,
    );
    let back = c.results.iter().map(|r| r.second).fold(0.0, f64::max);
    assert!(back > 0.002, "control retreat {back}");
}

#[test]
fn lifts_onto_a_slope_move_nothing_and_without_lift_detection_they_run() {
    let f = run(Kind::Lifts, Drift::default(), 20, 5);
    assert!(f.error_mm.max <= 5.0, "{:?}", f.error_mm);
    let c = run(
        Kind::Lifts,
        Drift {
            lift_rise_s: None,
            ..Drift::default()
        },
        20,
        5,
    );
    assert!(c.error_mm.max > 5.0, "control {:?}", c.error_mm);
}

#[test]
fn a_tilting_pad_is_held_soon_and_stopped_and_a_late_hold_runs_away() {
    let f = run(Kind::PadTilts, Drift::default(), 40, 6);
    assert!(median_within(&f, 0.025), "{:?}", f.error_mm);
    for r in &f.results {
        assert!(
            r.second <= 0.5,
            "trial {}: stopped {} s after the pad's rest",
            r.k,
            r.second
        );
        assert_eq!(
            r.third, 0.0,
            "trial {}: {} m after 0.5 s of rest",
            r.k, r.third
        );
    }
    // Control: the hold after half the longest stroke instead of an eighth.
    let c = run(
        Kind::PadTilts,
        tuned(Tuning {
            hold_fraction: 0.5,
            ..Tuning::default()
        }),
        40,
        6,
    );
    assert!(!median_within(&c, 0.025), "control {:?}", c.error_mm);
}

#[test]
fn a_pad_settling_onto_the_level_its_shadow_took_is_not_delivered() {
    // The full family's trials (seed 1) in which the pad went on tilting after the level a
    // shadow was started from: the shadow came to rest first, and its motion, more of the
    // same tilt that never went against it, was once delivered 0.61 s after the pad's rest
    // (0.35 mm in trial 146). Now it is the new zero, and nothing arrives after the hold,
    // which came before the pad's rest in all three.
    // Each also mirrored (the pad tilting the other way on both axes, the same noise): the
    // tilt's direction is the level's sign against the old zero, whichever it is.
    let dev = families::board_device(Some(Drift::default()), 1);
    let avg = families::averaging_s(Some(Drift::default()));
    let mirror = |sc: &mut Scenario| {
        for m in &mut sc.motions {
            if let Motion::Tilt { to, .. } = m {
                *to = to.map(|x| -x);
            }
        }
    };
    for k in [16, 36, 146] {
        let plain = families::trial(Kind::PadTilts, &dev, k, 1, avg);
        let mirrored = families::trial_with(Kind::PadTilts, &dev, k, 1, avg, mirror);
        let both = plain.iter().map(|r| ("", r));
        for (how, r) in both.chain(mirrored.iter().map(|r| (", mirrored", r))) {
            assert_eq!(r.second, 0.0, "trial {k}{how}: moved {} s after", r.second);
            assert_eq!(r.third, 0.0, "trial {k}{how}: {} m after 0.5 s", r.third);
        }
    }
}

#[test]
fn a_tilts_shadow_turned_by_noise_is_not_taken_for_a_hand() {
    // The full families' trials (seeds 1 and 2) in which a tilt's shadow saw a sub-window
    // against the tilt by 3 to 5 sd of noise before the tilt was confirmed. Kept as a
    // hand's for that (the test at K_TILT), the shadow came to rest and was adopted: 0.8 to
    // 2.6 mm arrived 0.68 to 0.90 s after the pad rested. A hand's lobe is taken only
    // beyond K_TURN (5 sd).
    for (seed, k) in [(1, 118), (2, 103), (2, 118), (2, 127)] {
        for r in trial_on(Kind::PadTilts, k, seed) {
            assert!(r.second <= 0.5, "seed {seed} trial {k}: {} s", r.second);
            assert_eq!(r.third, 0.0, "seed {seed} trial {k}: {} m late", r.third);
        }
    }
    // And a hand's: the strokes (seeds 2 and 3) that began 0.12 to 0.57 s after a tilt and
    // went against it (by more than K_TURN) before the tilt was confirmed, while their
    // shadow ran. Dropped there, the confirmation's latest steady level was in the stroke
    // and the stroke was lost or bent (37.8 and 4.7 mm off). (Seed 1's trial 41 was one,
    // 72.5 mm off, until the lab's pads rocked back: its pad now returns over 0.82 s just
    // before the stroke, and `a_stroke_after_a_pad_let_go_arrives` asks it.)
    for (seed, k) in [(2, 20), (3, 190)] {
        for r in trial_on(Kind::AfterTilt, k, seed) {
            assert!(r.error_m <= r.allowed_m, "seed {seed} trial {k}: {r:?}");
        }
    }
    // Small slow strokes (6.2-7.5 mm over 0.87-1.20 s, seed 1) soon after a tilt whose
    // reversal never passes K_TURN: the stop tests end each at its mid-point, and each half
    // ends unreversed. Dropped for that alone (not only once it outlasted the longest
    // stroke), they were lost whole.
    for k in [16, 27, 189] {
        assert!(trial_within(Kind::AfterTilt, k), "after-tilt trial {k}");
    }
}

#[test]
fn strokes_after_a_tilt_arrive() {
    // Target 3: a stroke 0.1-2 s after a pad tilt or a set-down, at least 90 % within;
    // asserted at what 60 trials of a 90 % process show but for 0.1 %.
    let n = 60;
    let f = run(Kind::AfterTilt, Drift::default(), n, 7);
    assert!(f.within >= least_within(0.9, n), "{:.3} within", f.within);
    // Control: a tilt confirmed only after the longest stroke: what the tilt left in the
    // zero and its held runaway spoil the strokes after it.
    let c = run(
        Kind::AfterTilt,
        tuned(Tuning {
            confirm_fraction: 1.5,
            ..Tuning::default()
        }),
        n,
        7,
    );
    assert!(
        c.within < f.within,
        "control {:.3} against {:.3}",
        c.within,
        f.within
    );
}

/// Trial `k` of `kind` (seed 1, the board's sensor): its strokes' results.
fn trial_of(kind: Kind, k: usize) -> Vec<families::Trial> {
    trial_on(kind, k, 1)
}

/// Trial `k` of `kind` on `seed` (the board's sensor): its strokes' results.
fn trial_on(kind: Kind, k: usize, seed: u64) -> Vec<families::Trial> {
    let dev = families::board_device(Some(Drift::default()), seed);
    let avg = families::averaging_s(Some(Drift::default()));
    families::trial(kind, &dev, k, seed, avg)
}

/// Asserts that trial `k` of `kind` on `seed` ends within its target.
fn assert_within_on(kind: Kind, k: usize, seed: u64) {
    for r in trial_on(kind, k, seed) {
        assert!(
            r.error_m <= r.allowed_m,
            "{kind:?} {k}, seed {seed}: {:.2} mm off, allowed {:.2}",
            r.error_m * 1e3,
            r.allowed_m * 1e3
        );
    }
}

/// Asserts that drag `k` on `seed` ends within its target and never retreats by more than
/// its 2 mm.
fn assert_drag_on(k: usize, seed: u64) {
    for r in trial_on(Kind::Drags, k, seed) {
        assert!(
            r.error_m <= r.allowed_m && r.second <= 2e-3,
            "drag {k}, seed {seed}: {:.2} mm off, allowed {:.2}; {:.2} mm back",
            r.error_m * 1e3,
            r.allowed_m * 1e3,
            r.second * 1e3
        );
    }
}

#[test]
fn a_drag_whose_glide_drifted_settles_after_its_ramp_down_instead_of_running_back() {
    // Seed 4's drag 110: a glide of 25.1 mm/s whose estimated velocity drifted down to 13
    // mm/s in 1.7 s (its ticks 0.26 LSB against the travel, 4 sd of a 1.8 s mean), and seed
    // 13's drag 141. Their ramp downs took the whole glide and left the velocity pointing
    // back against the travel, 3.4 sd and so unexplained: the motion glided back until the
    // longest calm. A motion calm for the stop's wait whose velocity points against its own
    // travel now settles with the bridge, which moves it forward by what a constant zero
    // error gave it. Each ends within its target; control: without the rule, 24.4 and 45.6
    // mm off (allowed 14.5 and 31.1), running back. During the stop's wait (0.25 s) each
    // still ran back at 12 mm/s, 4.3 and 4.5 mm, and the bridge then moved it forward
    // again: nothing is delivered while a calm motion's velocity points back against its
    // travel, so each retreats at most its target's 2 mm (control: without the pause, 4.3
    // and 4.5 mm).
    for (k, seed) in [(110, 4), (141, 13)] {
        assert_drag_on(k, seed);
    }
}

#[test]
fn a_glide_whose_calm_noise_broke_fades_when_its_velocity_held_near_its_mean() {
    // Seed 11's drag 122: a 12.9 mm/s glide whose calm a noise window broke (19.2 against
    // the span's 16.9), its velocity explained 32 ticks later at 9.2 mm/s (3.4 sd): it
    // stopped as a motion that decelerated to rest, and its ramp down, 1.7 s later, started
    // from zero velocity and ran the cursor back. Its velocity was nearer its mean than zero
    // and it was calm at the longest calm's bound: a glide that faded, which its ramp down
    // resumes. Control: without the rule, 34.9 mm off (allowed 21.6) and 9.2 mm back.
    assert_drag_on(122, 11);
    // The rule's two other conditions. A knock's few ticks before a stroke have a mean
    // velocity but no calm: taken for a glide, the stroke after it (seed 13's knocky
    // stroke 90, 8.0 mm) resumes the knock's velocity, 1.40 mm off against 0.66 allowed.
    // And a slow stroke soon after a tilt whose mean is within its uncertainty (seed 11's
    // after-tilt 172, 19.8 mm over 1.6 s): taken for a glide, 35.5 mm off, allowed 18.4.
    for (kind, k, seed) in [(Kind::KnockyStrokes, 90, 13), (Kind::AfterTilt, 172, 11)] {
        assert_within_on(kind, k, seed);
    }
}

#[test]
fn a_stroke_that_resumed_a_knocks_velocity_and_came_to_rest_near_it_did_not_hold_it() {
    // A knock 0.08-0.28 s before a stroke starts a short motion that stops with the knock's
    // velocity, explained, kept for the stop's wait; the stroke begins within it, its first
    // lobe against that velocity, and resumes it as the rest of a deceleration, with the
    // knock's uncertainty. It came to rest with a velocity nearer the knock's than zero: it
    // carried it. Its stop takes back what the knock's velocity moved over its own samples
    // and bridges only its own error. Seed 5's knocky stroke 96 (9.1 mm over 0.53 s, a
    // knock of 0.31 g 76 ms before it), seed 9's 27 (9.0 mm over 0.40 s, 0.10 g 0.28 s
    // before) and seed 19's 144 (9.7 mm over 0.39 s, 0.22 g 0.25 s before) end 0.58, 0.33
    // and 0.52 mm off, allowed 1.40, 0.91 and 0.87. Control: bridged as one motion with the
    // knock's, 1.67, 1.37 and 1.61 mm off.
    for (k, seed) in [(96, 5), (27, 9), (144, 19)] {
        assert_within_on(Kind::KnockyStrokes, k, seed);
    }
}

#[test]
fn a_ramp_down_that_brings_its_resumed_glide_to_rest_is_bridged_not_unwound() {
    // The judgment's other side: a drag's glide fades, its velocity latent, and its ramp
    // down resumes it and brings it to rest. The stop's velocity is nearer zero than the
    // glide's: the ramp down held the glide's velocity, and the stop bridges what is left
    // over the whole span. Seed 3's drag 41, seed 1's 51 and seed 4's 47 end 5.8, 11.9 and
    // 13.4 mm off, allowed 7.9, 13.9 and 20.4, never back by more than 2 mm. Control:
    // every resumed velocity taken as carried, 10.3, 16.4 and 21.8 mm off (the lab's drags
    // on seeds 1-21: 99.02 -> 96.76 % within).
    for (k, seed) in [(41, 3), (51, 1), (47, 4)] {
        assert_drag_on(k, seed);
    }
}

#[test]
fn a_motion_soon_after_a_landings_new_zero_is_held_until_it_reverses() {
    // Seed 14's lift 29: set down on a 4.8 degree slope, the new zero taken 0.24 s after
    // the set-down from 83 ms of the window was about 1 LSB (2.7 mg) off on X; 0.3 s later
    // that offset started a motion, and 12 mm arrived before the hold (15.8 mm in all,
    // allowed 5). A landing's new zero is a tilt's in all but name (a short window's level
    // on a pad that may settle): a motion within the longest stroke after it is held until
    // its acceleration reverses, as after a tilt's. A hand's stroke after a set-down does
    // reverse (seed 5's after-tilt 9 and seed 4's 183: 14.7 and 20.0 mm off without the
    // rule, allowed 7.5 and 8.6). Control: without the rule, those three outside.
    for (kind, k, seed) in [
        (Kind::Lifts, 29, 14),
        (Kind::AfterTilt, 9, 5),
        (Kind::AfterTilt, 183, 4),
    ] {
        assert_within_on(kind, k, seed);
    }
}

#[test]
fn a_machine_just_started_proves_a_replay_only_past_the_largest_amplitude_it_may_have() {
    // Seed 17's vibration-rest 13: a machine starts at once at 46.7 mg and 35 Hz on every
    // axis. The measured amplitude follows it from below while the long average catches up
    // (160 ms), so two starts within its first 0.2 s were proven a hand's against too small
    // an allowance (one by its replay, one a tick after it began) and delivered 7 counts
    // (0.22 mm). Until the desk has been disturbed for the long average's span, a motion
    // that starts on it is proven by its replay only against the largest amplitude the
    // short average allows. Control: against the measured amplitude, 5 counts (0.13 mm);
    // against that bound however long the desk has shaken, a stroke found whole after it
    // ended on a shaking desk is taken for the shaking (`core/tests/drift.rs`).
    assert_within_on(Kind::VibrationRest, 13, 17);
}

#[test]
fn a_tilts_shadow_whose_velocity_never_stood_out_delivers_nothing() {
    // Seed 6's pad tilt 121 (1.5 degrees over 0.68 s) and seed 13's 17: confirmed 0.6 s
    // after the pad rested, each from a steady level with a noise sub-window after it, so
    // the rest went on as a shadow; noise took one of its sub-windows against the tilt at
    // 3 sd, and at its end the shadow was adopted and its integrated noise delivered (a
    // few counts, 0.62 and 0.65 s after the pad rested, 0.13 and 0.41 mm). A shadow whose
    // velocity never stood out of its uncertainty carried no hand's motion: its zeros are
    // taken and nothing is delivered. Control: without the rule, those late moves.
    for (k, seed) in [(121, 6), (17, 13)] {
        for r in trial_on(Kind::PadTilts, k, seed) {
            assert!(
                r.second <= 0.5 && r.third == 0.0,
                "pad tilt {k}, seed {seed}: last move {:.3} s after the pad's rest, {:.2} mm later",
                r.second,
                r.third * 1e3
            );
        }
    }
}

/// Whether trial `k` of `kind` (seed 1, the board's sensor) is within its target.
fn trial_within(kind: Kind, k: usize) -> bool {
    trial_of(kind, k).iter().all(|r| r.error_m <= r.allowed_m)
}

#[test]
fn a_stroke_on_a_settled_tilted_pad_arrives_from_the_change() {
    // The full family's trials (seed 1) in which the pad tilted and settled and the hand
    // moved while the tilt was still held: each stroke was lost whole, dropped with the
    // tilt's runaway when the tilt was confirmed, until the change from the settled level
    // began a shadow from it (tilt.rs).
    for k in [115, 118, 141, 146] {
        assert!(trial_within(Kind::AfterTilt, k), "after-tilt trial {k}");
    }
    // (Trial 13 was one too until the lab's pads rocked back: its pad now returns over
    // 0.85 s, 0.35 s before the stroke, and the return, one-sided against the tilted zeros,
    // is confirmed as a second tilt with the stroke in it: a scene docs/drift-control.md
    // lists as not mended.)
}

#[test]
fn a_rock_back_to_rest_never_glides_on() {
    // The rocks family's trials (seed 1) that ran away once the pad was back: the device
    // rocked 1-5 degrees and back within 0.4-1.3 s, held as a stroke's slow first lobe, its
    // runs breaking with the device at rest on the zeros and the velocity the rock's pulse
    // gave (0.1-0.3 m/s): released and delivered, it glided until the longest calm, 0.8-1.5
    // m. Held on until the device rests there, then an undone shadow from rest, nothing of
    // it arrives after its hold. Target 3 for a pad tilt: the last count within 0.5 s of the
    // pad's rest, nothing after.
    for k in [1, 78, 160, 162] {
        for r in trial_of(Kind::Rocks, k) {
            assert!(
                r.second <= 0.5 && r.third == 0.0,
                "rock {k}: last move {:.3} s after the pad's rest, {:.1} mm later",
                r.second,
                r.third * 1e3
            );
        }
    }
    // A 5 degree rock (0.21 s down, 0.55 s back, seed 7) whose runs broke before the device
    // rested at the zeros: released and delivered there, it glided 1.1 m (819 mm of it
    // later than 0.5 s after the pad's rest). Held on until the device rests, it is dropped.
    for r in trial_on(Kind::Rocks, 137, 7) {
        assert!(
            r.third == 0.0,
            "rock 137, seed 7: {:.1} mm late",
            r.third * 1e3
        );
    }
    // And a stroke begun as a tilt's remainder was held (seed 7's after-tilt 156: a pad
    // tilting 2.7 degrees over 1.8 s, a 143.8 mm stroke over 0.21 s 1.3 s after): its
    // reversal releases the hold mid-stroke, the level before it at the zeros but the device
    // not at rest. An undone shadow begun there, 8 ms into the stroke, missed its start and
    // never came to rest: the stroke was lost (143.8 mm off). It is begun only at rest.
    assert_within_on(Kind::AfterTilt, 156, 7);
}

#[test]
fn a_stroke_after_a_pad_let_go_arrives() {
    // After-tilt trials whose pad tilts slowly (1.1-1.9 s) and rocks back: the tilt is
    // confirmed while the pad still tilts, its zeros taken, and what follows (the rest of
    // the tilt, the return and the stroke after it) is one motion held against those zeros,
    // confirmed as a second tilt with the stroke in it, or never ended: the stroke was lost
    // (seed 1's 41, 72.5 mm over 1.95 s 0.12 s after the return; seed 3's 121, 120.5 mm
    // 0.6 s after; seed 2's 30). Back at rest on the zeros from before the tilt, the pad
    // was let go: the held return is dropped and those zeros come back. Control: without
    // the rule, those three lost. Seed 1's 190 and 72 (strokes 0.9 and 1.3 s after a
    // return): with those zeros followed as the tilted ones were tracked at rest, they came
    // back 0.7-0.9 LSB off and the strokes ended 125 and 2.3 mm off (1.2 and 0.6 before).
    // Seed 7's 47 and seed 13's 136 (15 and 22 mm over 1.5 s, 1.2 s after a return): a
    // let-go is a held motion back at the old zeros and off the present ones; asked only the
    // first, it fired in the strokes' slow lobes, at rest on both, and dropped them (17.9 and
    // 25.2 mm off).
    for (seed, k) in [
        (1, 41),
        (3, 121),
        (2, 30),
        (1, 190),
        (1, 72),
        (7, 47),
        (13, 136),
    ] {
        assert_within_on(Kind::AfterTilt, k, seed);
    }
}

#[test]
fn a_long_strokes_crest_is_not_taken_for_a_tilts_level() {
    // The full family's trials (seed 1) in which a long stroke's acceleration stood steady
    // at its crest, then changed: the shadow from the crest's level came to rest first and
    // took the stroke's first half for a tilt, until a shadow begun at a change could win
    // only once it had gone both ways against its level on one axis.
    for k in [141, 143] {
        assert!(trial_within(Kind::Strokes, k), "strokes trial {k}");
    }
}

#[test]
fn a_slow_tilt_that_changes_while_held_is_confirmed_from_its_last_level() {
    // The full family's trials (seed 1) in which a slow tilt's own change began a shadow
    // that never went both ways (more of the tilt): it kept the tilt's confirmation from
    // taking the latest steady level, and the stroke after it was lost, until the
    // confirmation ended such a shadow.
    for k in [131, 154] {
        assert!(trial_within(Kind::AfterTilt, k), "after-tilt trial {k}");
    }
}

#[test]
fn a_stroke_while_the_pad_still_tilts_is_never_delivered_larger_than_itself() {
    // A new user's case: the pad tilts 1 degree over 1.5 s and a 150 mm stroke over 1 s
    // begins 0.7 s into the tilt, along it. The level a change's shadow took was the tilt's
    // ramp, not a settled pad's: that shadow never came to rest, and adopting it at its
    // timeout delivered the stroke with the rest of the tilt, 364 mm, 1.1 s after the hand
    // stopped. Now such a shadow is dropped at its timeout and the held motion goes on as it
    // was: the stroke may be lost, but the cursor is never further off than the stroke's
    // length beyond where it stood when the stroke began (the tilt's runaway before its
    // hold).
    let phi: f64 = 0.7;
    let to = [phi.cos(), phi.sin()].map(|c| c * 1f64.to_radians());
    let stroke = (1.1, 0.15);
    let sc = Scenario {
        motions: vec![
            Motion::Tilt {
                t0: 0.4,
                dur: 1.5,
                from: [0.0; 2],
                to,
            },
            Motion::Stroke {
                t0: stroke.0,
                dur: 1.0,
                d: stroke.1,
                dir: phi,
            },
        ],
        edges: vec![],
        seconds: stroke.0 + 3.0,
    };
    for dev in [1, 2] {
        let d = families::board_device(Some(Drift::default()), dev);
        let p = families::run(&d, &sc, 11);
        let start = p.at(stroke.0);
        let end = p.at(sc.seconds);
        let want = [
            start[0] + stroke.1 * phi.cos(),
            start[1] + stroke.1 * phi.sin(),
        ];
        let off = (end[0] - want[0]).hypot(end[1] - want[1]);
        assert!(off <= stroke.1, "device {dev}: {:.1} mm off", off * 1e3);
    }
}

#[test]
fn knocks_that_flex_the_desk_move_nothing() {
    // Target 4: each knock flexes the desk by 20-200 um, up to a third of it horizontal: up
    // to 2 counts out and back. The median knock moves the cursor by at most 0.3 mm.
    let f = run(Kind::Knocks, Drift::default(), 40, 8);
    assert!(median_within(&f, 0.0003), "{:?}", f.error_mm);
}

/// The cursor over each of `n` hard knocks, one at a time, 1 s after the device's
/// calibration: its travel during the knock and its distance from the start 1.5 s later [m].
/// Each knock flexes the desk by 150-200 um, 60 % of it horizontal, so that it moves the
/// device by 2.8 to 3.8 counts and back (800 cpi).
fn hard_knocks(n: usize) -> Vec<(f64, f64)> {
    use host_tests::world::hand::{Motion, Scenario, G};
    use rand::{Rng, SeedableRng};
    let dev = families::board_device(Some(Drift::default()), 12);
    let mut rng = rand::rngs::StdRng::seed_from_u64(12);
    (0..n)
        .map(|k| {
            let knock = Motion::Knock {
                t0: 1.0,
                peak: rng.random_range(0.3..0.5) * G,
                f: rng.random_range(20.0..60.0),
                periods: rng.random_range(1.0..3.0),
                flex: rng.random_range(150e-6..200e-6),
                share: 0.6,
                dir: rng.random_range(0.0..std::f64::consts::TAU),
            };
            let sc = Scenario {
                motions: vec![knock],
                edges: vec![],
                seconds: 2.5,
            };
            let p = families::run(&dev, &sc, 100 + k as u64);
            let (a, b) = (p.at(1.0), p.at(2.5));
            (p.travel(1.0, 2.5), (b[0] - a[0]).hypot(b[1] - a[1]))
        })
        .collect()
}

#[test]
fn hard_knocks_move_the_cursor_out_and_back() {
    // Target 4 on knocks that move the device by several counts. The cursor follows such a
    // knock's flex (the device did move: no rule holds it back, docs/drift-control.md) and
    // comes back: the median knock's travel is at most 0.3 mm (measured 0.29 mm, 0.86 mm at
    // most, on these 20), and the median knock leaves the cursor within 0.3 mm of where it
    // was (measured 1 count; 4 at most).
    let r = hard_knocks(20);
    let mut travel: Vec<f64> = r.iter().map(|t| t.0).collect();
    travel.sort_by(f64::total_cmp);
    assert!(travel[10] <= 0.3e-3, "median travel {} m", travel[10]);
    let mut end: Vec<f64> = r.iter().map(|t| t.1).collect();
    end.sort_by(f64::total_cmp);
    assert!(end[10] <= 0.3e-3, "median end {} m", end[10]);
}

#[test]
fn strokes_with_knocks_arrive_and_with_the_ring_in_the_hand_band_they_are_lost() {
    let n = 60;
    let f = run(Kind::KnockyStrokes, Drift::default(), n, 9);
    assert!(f.within >= least_within(0.9, n), "{:.3} within", f.within);
    // Control: the lowest frequency of what is not a hand at 60 Hz, so that a knock's ring
    // (20-60 Hz) passes the hand-band filter and the disturbance is measured above it: the
    // ring is taken for a hand (0.517 within, measured). Blind to the disturbance instead
    // (its margin 20 sd), the strokes arrive as well as they do with it (0.965 and 0.975 of
    // 200): since the stop's bridge (estimator.rs) they no longer need the allowance; what
    // it still keeps is a vibrating desk's rest (the control below).
    let c = run(
        Kind::KnockyStrokes,
        Drift {
            knock_hz: 60.0,
            ..Drift::default()
        },
        n,
        9,
    );
    assert!(
        c.within < least_within(0.9, n),
        "control {:.3} against {:.3}",
        c.within,
        f.within
    );
}

#[test]
fn strokes_on_a_vibrating_desk_arrive_and_rest_does_not_move() {
    let n = 60;
    for kind in [Kind::VibrationZ, Kind::VibrationAll] {
        let f = run(kind, Drift::default(), n, 10);
        assert!(
            f.within >= least_within(0.9, n),
            "{}: {:.3} within",
            kind.name(),
            f.within
        );
    }
    // A minute each on eight desks, one a machine of 48 mg at 30 Hz starting up.
    let r = run(Kind::VibrationRest, Drift::default(), 8, 10);
    let count = 0.0254 / 800.0;
    for t in &r.results {
        assert!(t.error_m <= count, "{} m in a minute", t.error_m);
        assert_eq!(t.second, 0.0, "tracking suspended");
    }
    // Control: blind to the disturbance, a vibrating desk moves the cursor at rest. On
    // sixteen desks: the burst test still catches a machine's start, so the blind detector
    // moves on few of them (1 and 2 counts on 2 of 16 since the early start test runs once a
    // USB frame; 6 counts on 1 of 8 when it ran every sample).
    let c = run(
        Kind::VibrationRest,
        tuned(Tuning {
            disturbance_sigmas: 20.0,
            ..Tuning::default()
        }),
        16,
        10,
    );
    assert!(
        c.results.iter().any(|t| t.error_m > count),
        "control: {:?}",
        c.results.iter().map(|t| t.error_m).collect::<Vec<_>>()
    );
}

#[test]
fn every_family_has_its_name_and_a_trace() {
    for k in Kind::ALL {
        assert_eq!(Kind::from_name(k.name()), Some(k));
    }
    let t = families::trace(
        Kind::Strokes,
        Some(Drift::default()),
        SensorSpec::ADXL335,
        1,
        0,
        None,
    );
    assert!(t.contains("Moving") && t.contains("end: cursor"), "{t}");
    // A line every 100 ms as well: the 1.3 s or so of a stroke trial gives ten more.
    let every = families::trace(
        Kind::Strokes,
        Some(Drift::default()),
        SensorSpec::ADXL335,
        1,
        0,
        Some(100),
    );
    assert!(every.lines().count() >= t.lines().count() + 10, "{every}");
}

#[test]
fn the_long_rest_table_says_missed_when_anything_moved() {
    let rest = |counts: i64, moved: usize| families::LongRest {
        sensor: "s".into(),
        devices: 20,
        hours_each: 10.0,
        false_starts: moved as u64,
        devices_moved: moved,
        counts,
        predicted_false_starts: 0.02,
    };
    let quiet = families::long_rest_table(&[rest(0, 0), rest(0, 0)]);
    assert!(
        quiet.contains("0 counts: met (0 devices moved, 0 counts)"),
        "{quiet}"
    );
    let moved = families::long_rest_table(&[rest(0, 0), rest(151, 3)]);
    assert!(
        moved.contains("MISSED (3 devices moved, 151 counts)"),
        "{moved}"
    );
}

#[test]
fn brisk_strokes_sampled_at_100_hz_stop_on_what_sampling_left() {
    // The 100 Hz sweep row's brisk strokes (seed 1): 96, 126 and 271 mm over 0.21-0.25 s,
    // 0.9-2.2 m/s at their peaks. A minimum-jerk stroke starts and ends with a jerk step of
    // 32 v / D^2, which sampling aliases into the summed velocity by up to a step / (12
    // fs^2): 10.7 mm/s left at the end of the first, 10 sd of what the noise explains. The
    // stop allows for it at the shortest stroke a hand makes below knock_hz / 2 (0.1 s: 5.3 %
    // of the motion's top speed at 100 Hz, 0.006 % at 3 kHz). Each arrives within max(5 %,
    // 3 floors); control: without the allowance its velocity left is not explained, the
    // cursor glides back and they end 7.8, 7.4 and 14.6 mm off (allowed 4.8, 6.3, 13.5).
    let spec = SensorSpec {
        fs: 100.0,
        ..SensorSpec::ADXL335
    };
    let base = imu_core::Config {
        drift: Some(Drift::default()),
        ..imu_core::Config::default()
    };
    let seed = 1 ^ 100;
    let dev = families::Device::calibrated(spec, base, seed);
    let avg = families::averaging_s(Some(Drift::default()));
    for k in [60, 77, 171] {
        assert_within(&families::trial(Kind::Strokes, &dev, k, seed, avg), k);
    }
}

/// Every judged stroke of trial `k`'s `trials` within its target.
fn assert_within(trials: &[families::Trial], k: usize) {
    for r in trials {
        assert!(
            r.error_m <= r.allowed_m,
            "trial {k}: {:.1} mm off, allowed {:.1}",
            r.error_m * 1e3,
            r.allowed_m * 1e3
        );
    }
}

#[test]
fn a_slow_stroke_on_a_vibrating_desk_keeps_the_vibration_measured() {
    // Vibration-all's trial 16 (seed 2): 27.7 mg at 32 Hz on every axis, and a 43.5 mm
    // stroke over 1.82 s whose band output (0.02-0.04 m/s^2) is a tenth of the vibration's
    // residual. Its residual is the hand's only where the hand dominates the residual's
    // power: otherwise the ticks where the vibration crosses zero, within the hand's band
    // output, were left out and the rest, its crests, raised the measured amplitude; the
    // stroke never stopped. Within its target; control: with the residual the hand's
    // wherever it is within the band output, 24.2 mm off (allowed 8.9).
    let dev = families::board_device(Some(Drift::default()), 2);
    let avg = families::averaging_s(Some(Drift::default()));
    assert_within(&families::trial(Kind::VibrationAll, &dev, 16, 2, avg), 16);
}

#[test]
fn a_brisk_stroke_after_a_tilt_leaves_no_knock_behind() {
    // After-tilt's trial 22 (seed 1): the pad tilts 0.8 degrees, and 1 s later a 285 mm
    // stroke over 0.33 s is held with the tilt's shadow. The band output against the
    // motion's zero carries the tilt's offset, opposite to the stroke's start, so the
    // stroke's first residuals (its jerk step) stood out of it and were counted as a knock's
    // burst; held while the hand's band output covered every residual after, that
    // amplitude widened the quiet test for the rest of the motion, and the shadow never won.
    // A residual is the hand's only while the hand's output dominates the residual's power,
    // so an amplitude above it is measured again and forgotten. Within its target; control:
    // with the residual the hand's wherever within its band output, the stroke is never
    // delivered (285.1 mm off).
    assert!(trial_within(Kind::AfterTilt, 22), "after-tilt trial 22");
}

/// The sd [m] of the Euler double integral ([`twin::Integrator`]) over `n` samples of
/// `spec`'s X and Y codes at rest, flat, against their exact zero, over `runs` rests each.
fn rest_position_sd(spec: SensorSpec, n: usize, runs: usize, seed: u64) -> f64 {
    let mut rng = noise::rng(seed);
    let mut sensor = Sensor::new(spec, &mut rng);
    let zero = sensor.zero_codes();
    let mut sum2 = 0.0;
    for _ in 0..runs {
        let mut axes = [twin::Integrator::new(twin::Scheme::Euler); 2];
        for _ in 0..n {
            let c = sensor.codes([0.0; 3], [0.0; 3], [0.0; 2], &mut rng);
            for (a, axis) in axes.iter_mut().enumerate() {
                axis.step(f64::from(c[a]) - zero[a]);
            }
        }
        sum2 += axes.iter().map(|axis| axis.s * axis.s).sum::<f64>();
    }
    // LSB samples^2 to metres.
    (sum2 / (2 * runs) as f64).sqrt() * spec.lsb() / (spec.fs * spec.fs)
}

#[test]
fn the_floor_at_a_rate_is_what_the_sensor_model_integrates_to() {
    // The ADXL335 (300 ug/sqrt(Hz) through its 50 Hz pole, 12 bits) at 100 Hz and at 3 kHz,
    // no bias walk: 1500 rests of T each, X and Y, double-integrated against the exact zero.
    // 3000 values: the sample variance's relative sd sqrt(2 / 3000) = 2.6 %, the sd's 1.3 %;
    // the integration's finite-N terms add under 1 % (N = 400 at 100 Hz, alpha N = 314 at
    // 3 kHz): within 3.09 sd plus 1 %, 5 %. At 100 Hz the continuous floor is 26 % short.
    for (fs, t) in [(100.0, 4.0), (3000.0, 1.0)] {
        let spec = SensorSpec {
            walk_ug: 0.0,
            fs,
            ..SensorSpec::ADXL335
        };
        let n = (t * fs) as usize;
        let got = rest_position_sd(spec, n, 1500, 7) / families::floor_m(spec.nd(), t);
        let ratio = families::floor_ratio(&spec);
        assert!(
            (got / ratio - 1.0).abs() < 0.05,
            "fs {fs}: {got} floors, predicted {ratio}"
        );
    }
    // The ADC's rounding alone: white noise of 1 LSB a sample (1381 ug/sqrt(Hz) up to 50 Hz
    // on 10 bits, no pole), where rounding adds LSB^2 / 12 a sample, independent of the
    // noise within 3e-9: 1.0408 floors, not 1. 10 000 rests of 4 s, 20 000 values: the sd's
    // relative sd 0.5 %, Euler's 1 + 3 / (2 N) 0.2 %: within 2 %.
    let spec = SensorSpec {
        nd_ug: 1381.0,
        pole_hz: None,
        walk_ug: 0.0,
        bits: 10,
        fs: 100.0,
    };
    let got = rest_position_sd(spec, 400, 10_000, 8) / families::floor_m(spec.nd(), 4.0);
    let ratio = families::floor_ratio(&spec);
    assert!((ratio - 1.0408).abs() < 0.001, "{ratio}");
    assert!(
        (got / ratio - 1.0).abs() < 0.02,
        "{got} floors, predicted {ratio}"
    );
}
