//! `cargo lab mouse` on a smaller desk scene: the targets of docs/drift-control.md hold with
//! drift control and fail without it.
//!
//! The thresholds are the product targets themselves: 0 counts of wander, stroke length
//! error median <= 5 % and p90 <= 10 %, direction error median <= 2 degrees, 0 counts of
//! click drag with the button edge as late as the firmware's debounce delivers it, start
//! latency <= 25 ms and stop latency <= 30 ms (medians). With 24 strokes the p90 is the
//! least certain figure (the third-largest of 24); the full scene's values are in
//! docs/drift-control.md.

use host_tests::commands::mouse::{compare, desk};
use imu_core::Drift;

#[test]
fn drift_control_meets_the_targets_and_pure_integration_does_not() {
    let r = compare(24, 2.0, 11);
    let m = &r.drift_control;
    assert_eq!(m.strokes, 24);
    assert!(m.clicks >= 8, "{} clicks", m.clicks);
    assert_eq!(m.stationary_wander_counts, 0);
    assert!(
        m.stroke_length_error_pct.median <= 5.0,
        "{:?}",
        m.stroke_length_error_pct
    );
    assert!(
        m.stroke_length_error_pct.p90 <= 10.0,
        "{:?}",
        m.stroke_length_error_pct
    );
    assert!(
        m.direction_error_deg.median <= 2.0,
        "{:?}",
        m.direction_error_deg
    );
    assert_eq!(m.click_drag_counts, 0);
    assert!(m.latency_ms.stop_median <= 30.0, "{:?}", m.latency_ms);
    assert!(m.latency_ms.start_median <= 25.0, "{:?}", m.latency_ms);

    let p = &r.pure_integration;
    assert!(
        p.stationary_wander_counts > 1000,
        "{}",
        p.stationary_wander_counts
    );
    assert!(
        p.stroke_length_error_pct.median > 5.0,
        "{:?}",
        p.stroke_length_error_pct
    );
}

#[test]
fn a_click_whose_edge_comes_10_ms_late_does_not_drag_and_without_the_hold_it_does() {
    // 10 ms: the firmware's debounce while its housekeeping runs every 2 ms.
    let m = desk(Some(Drift::default()), 16, 0.1, 4, 0.010);
    assert!(m.clicks >= 6, "{} clicks", m.clicks);
    assert_eq!(m.click_drag_counts, 0);
    // Control: no hold. A jolt's first tick is also a burst, and a motion started in one is
    // held until its velocity stands out of it (the disturbance's rule, drift/estimator.rs):
    // that is switched off too, or it would keep the jolt back on its own.
    let no_hold = Drift {
        hold_s: 0.0,
        tuning: imu_core::drift::Tuning {
            disturbance_sigmas: 20.0,
            ..imu_core::drift::Tuning::default()
        },
        ..Drift::default()
    };
    let c = desk(Some(no_hold), 16, 0.1, 4, 0.010);
    assert!(c.click_drag_counts > 0, "{}", c.click_drag_counts);
}

#[test]
fn json_has_the_documented_keys() {
    let r = compare(4, 0.1, 2);
    let json = serde_json::to_value(&r).expect("serialisable");
    for key in [
        "stationary_minutes",
        "stationary_wander_counts",
        "strokes",
        "stroke_length_error_pct",
        "direction_error_deg",
        "click_drag_counts",
        "latency_ms",
        "pure_integration",
    ] {
        assert!(json.get(key).is_some(), "missing {key}");
    }
    assert!(json["stroke_length_error_pct"].get("median").is_some());
    assert!(json["pure_integration"]
        .get("direction_error_deg")
        .is_some());
}
