//! The pointing targets (issue 10) on small scenes, each with a control that fails: the
//! rule it exercises switched off, or the detector made blind to what the scene needs.
//!
//! Tolerances are the targets themselves, except where a small scene's sampling error
//! must be allowed for; those are derived where they are used. Every scene is seeded, so
//! a run is repeatable; the full scenes are `cargo lab mouse` (README).

use host_tests::commands::mouse::pointing::{self, floor_m};
use imu_core::Drift;

fn on() -> Option<Drift> {
    Some(Drift::default())
}

#[test]
fn slow_and_small_strokes_arrive_near_the_noise_floor() {
    // 80 strokes of 5 mm-30 cm over 0.2-2 s. The full run (200 strokes) has 93 % within
    // max(5 %, 3 floor). For 80 strokes of a 93 % process the fraction has sd 2.9 %; 3.3 sd
    // (0.1 %) below is 83.5 %. The error in units of the noise floor is the sharper check:
    // a 2-D error with the floor's sd per axis has a median of 1.18 floors (Rayleigh); the
    // bias estimate and the onset add to it, and 2 floors is what the full run stays under
    // (1.20).
    let s = pointing::strokes(on(), 80, 3);
    assert!(s.within >= 0.835, "{:.3} within", s.within);
    assert!(s.error_over_floor.median <= 2.0, "{:?}", s.error_over_floor);
    // Control: a stop that takes any velocity for zero (the old detector's rule) cuts slow
    // strokes in the middle.
    let blind = Drift {
        velocity_sigmas: 1000.0,
        ..Drift::default()
    };
    let c = pointing::strokes(Some(blind), 80, 3);
    assert!(
        c.within < 0.835 || c.error_over_floor.median > 2.0,
        "control passed: {:.3} within, {:?}",
        c.within,
        c.error_over_floor
    );
}

#[test]
fn a_15_mm_stroke_over_a_second_arrives() {
    // The example: SNR 12 at the floor (1.2 mm per axis at T = 1 s). Ten strokes in
    // ten directions; each must arrive within 3 floors (3.6 mm), as target 1 asks of 90 %.
    let s = pointing::strokes_of(on(), 0.015, 1.0, 10, 5);
    for r in &s {
        assert!(
            r.error_m <= 3.0 * floor_m(1.0),
            "{:.2} mm off",
            r.error_m * 1e3
        );
    }
}

#[test]
fn circles_and_figure_eights_close() {
    let c = pointing::continuous(on(), 6, 2);
    assert!(c.closure_pct.median <= 5.0, "{:?}", c.closure_pct);
    assert!(
        (c.travel_ratio.median - 1.0).abs() <= 0.1,
        "{:?}",
        c.travel_ratio
    );
    // Control: a detector that calls everything quiet and every velocity explained stops
    // the figure at every tick: it "closes" but travels a fraction of the way.
    let cutting = Drift {
        quiet_sigmas: 1000.0,
        velocity_sigmas: 1000.0,
        ..Drift::default()
    };
    let d = pointing::continuous(Some(cutting), 2, 2);
    assert!(d.travel_ratio.median < 0.9, "{:?}", d.travel_ratio);
}

#[test]
fn lifts_onto_a_tilt_do_not_move_the_cursor_and_tilts_stop_it() {
    let t = pointing::tilts(on(), 4, 4);
    assert!(t.replacement_mm.max <= 5.0, "{:?}", t.replacement_mm);
    assert!(t.stop_s.max <= 0.5, "{:?}", t.stop_s);
    assert_eq!(t.late_counts, 0);
    // Control: without lift detection the tilted landing runs away until it is taken for
    // a tilt.
    let no_lift = Drift {
        lift_m_s2: None,
        ..Drift::default()
    };
    let c = pointing::tilts(Some(no_lift), 2, 4);
    assert!(c.replacement_mm.max > 5.0, "{:?}", c.replacement_mm);
}

#[test]
fn knocks_move_nothing() {
    let k = pointing::knocks(on(), 12, 6);
    assert!(k.counts.median <= 10.0, "{:?}", k.counts);
    // Control: pure integration keeps what the knock's ringing and the noise leave.
    let c = pointing::knocks(None, 6, 6);
    assert!(c.counts.median > 10.0, "{:?}", c.counts);
}

#[test]
fn rests_send_no_count_in_any_seed() {
    let r = pointing::rests(on(), 6, 2.0, 7);
    assert_eq!(r.wander_counts, vec![0; 6]);
    // Control: an alarm at 4 sd instead of 16 starts on noise.
    let jumpy = Drift {
        start_sigmas: 4.0,
        ..Drift::default()
    };
    let c = pointing::rests(Some(jumpy), 2, 2.0, 7);
    assert!(
        c.wander_counts.iter().all(|&w| w > 0),
        "{:?}",
        c.wander_counts
    );
}

#[test]
fn the_map_has_the_floor_line_and_every_cell() {
    let m = pointing::map(on(), 3, 3, 1, 8);
    assert_eq!(m.error_pct.len(), 3);
    assert!(m.error_pct.iter().all(|r| r.len() == 3));
    // 30 cm over 0.55 s is a brisk stroke: within 5 %. 1 mm over 3 s is far below the
    // noise floor (D = 3 floor at 3 s is 18.7 mm).
    assert!(m.error_pct[2][1] <= 5.0, "{:?}", m.error_pct);
    assert!(m.error_pct[0][2] > 50.0, "{:?}", m.error_pct);
    let svg = pointing::map_svg(&m);
    assert!(svg.contains("<polyline") && svg.matches("<rect").count() >= 10);
}
