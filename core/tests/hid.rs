//! The report scheduler under random motion and random USB refusals.

use imu_core::bench::testsignal::Trace;
use imu_core::hid::{buttons, MouseReport, Reporter, MAX_COUNTS_PER_REPORT};

/// A small deterministic generator for test inputs (the core's SplitMix64 trace).
struct Gen(Trace);
impl Gen {
    fn next(&mut self) -> u64 {
        self.0.next_u64()
    }
    fn range(&mut self, lo: i32, hi: i32) -> i32 {
        lo + (self.next() % (hi - lo + 1) as u64) as i32
    }
}

#[test]
fn every_count_arrives_even_when_pushes_fail() {
    let mut g = Gen(Trace::new(7));
    let mut r = Reporter::default();
    let (mut moved, mut received) = ([0i64; 2], [0i64; 2]);
    for _ in 0..200_000 {
        if g.next().is_multiple_of(3) {
            let (dx, dy) = (g.range(-900, 900), g.range(-900, 900));
            r.add_motion(dx, dy);
            moved[0] += i64::from(dx);
            moved[1] += i64::from(dy);
        }
        if let Some(rep) = r.pending() {
            // The host takes the report only two times in three (WouldBlock otherwise).
            if !g.next().is_multiple_of(3) {
                r.sent(&rep);
                received[0] += i64::from(rep.x);
                received[1] += i64::from(rep.y);
            }
        }
    }
    while let Some(rep) = r.pending() {
        r.sent(&rep);
        received[0] += i64::from(rep.x);
        received[1] += i64::from(rep.y);
    }
    assert_eq!(moved, received);
    assert_eq!(r.undelivered(), (0, 0));
}

#[test]
fn clamped_reports_point_the_way_the_hand_moved() {
    // A clamped report has its larger axis at exactly 127 and only the smaller one rounded
    // (by at most 0.5 count), so its direction is within 0.5 / 127 rad (0.23 degrees) of the
    // motion owed: d(theta) = x d(y) / (x^2 + y^2) <= 0.5 * 127 / 127^2.
    let mut g = Gen(Trace::new(11));
    for _ in 0..20_000 {
        let mut r = Reporter::default();
        let (dx, dy) = (g.range(-100_000, 100_000), g.range(-100_000, 100_000));
        r.add_motion(dx, dy);
        let rep = r.pending().expect("motion pending");
        assert!(i32::from(rep.x).abs() <= MAX_COUNTS_PER_REPORT);
        assert!(i32::from(rep.y).abs() <= MAX_COUNTS_PER_REPORT);
        if dx == 0 && dy == 0 {
            continue;
        }
        let want = f64::from(dy).atan2(f64::from(dx));
        let got = f64::from(rep.y).atan2(f64::from(rep.x));
        let diff = (want - got)
            .abs()
            .min(2.0 * std::f64::consts::PI - (want - got).abs());
        assert!(
            diff <= 0.5 / 127.0 + 1e-12,
            "({dx}, {dy}) -> {rep:?}: {diff} rad"
        );
        // The larger axis is full scale whenever the motion needs clamping.
        if dx.abs().max(dy.abs()) > 127 {
            assert_eq!(i32::from(rep.x).abs().max(i32::from(rep.y).abs()), 127);
        }
    }
}

#[test]
fn button_changes_are_reported_without_motion_and_idle_sends_nothing() {
    let mut r = Reporter::default();
    assert_eq!(r.pending(), None);
    r.set_buttons(buttons::LEFT);
    let rep = r.pending().expect("press reported");
    assert_eq!(
        rep,
        MouseReport {
            buttons: buttons::LEFT,
            ..Default::default()
        }
    );
    r.sent(&rep);
    assert_eq!(r.pending(), None); // held, nothing new
    r.add_motion(3, -2);
    assert_eq!(
        r.pending().map(|p| (p.buttons, p.x, p.y)),
        Some((buttons::LEFT, 3, -2))
    );
    r.set_buttons(0);
    assert_eq!(r.pending().map(|p| p.buttons), Some(0));
}

#[test]
fn discarded_motion_is_gone_but_buttons_stay() {
    let mut r = Reporter::default();
    r.add_motion(500, 500);
    r.set_buttons(buttons::LEFT);
    r.discard_motion();
    let rep = r.pending().expect("button still owed");
    assert_eq!((rep.x, rep.y, rep.buttons), (0, 0, buttons::LEFT));
}

#[test]
fn host_reset_resends_held_buttons_and_drops_motion() {
    let mut r = Reporter::default();
    r.set_buttons(buttons::RIGHT);
    let rep = r.pending().expect("press");
    r.sent(&rep);
    r.add_motion(40, 0);
    r.host_reset();
    let rep = r.pending().expect("buttons re-sent after reset");
    assert_eq!((rep.buttons, rep.x, rep.y), (buttons::RIGHT, 0, 0));
}

/// Every count added is sent, discarded (host not listening) or still owed, whatever the
/// pattern of refused pushes and resets.
#[test]
fn every_count_is_sent_discarded_or_owed() {
    let mut r = Reporter::default();
    let (mut added_x, mut added_y) = (0i64, 0i64);
    let mut state = 12345u64;
    for i in 0..10_000u32 {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let dx = ((state >> 33) % 301) as i32 - 150;
        let dy = ((state >> 45) % 41) as i32 - 20;
        r.add_motion(dx, dy);
        added_x += i64::from(dx);
        added_y += i64::from(dy);
        match (state >> 60) % 4 {
            0 => {} // the host is busy: WouldBlock
            1 if i % 7 == 0 => r.host_reset(),
            _ => {
                if let Some(rep) = r.pending() {
                    r.sent(&rep);
                }
            }
        }
    }
    let (sx, sy) = r.sent_total();
    let (dx, dy) = r.discarded();
    let (ox, oy) = r.undelivered();
    assert_eq!((sx + dx + ox, sy + dy + oy), (added_x, added_y));
    assert_eq!(r.added(), (added_x, added_y));
    assert!(
        dx != 0 && sx != 0,
        "both paths taken: sent {sx}, discarded {dx}"
    );
}

#[test]
fn a_report_is_sent_when_the_host_takes_it_and_lost_if_the_bus_resets_first() {
    let mut r = Reporter::default();
    r.add_motion(30, -4);
    let rep = r.pending().expect("motion");
    r.accepted(&rep);
    // In the endpoint: no longer owed, not yet sent, still added.
    assert_eq!(r.undelivered(), (0, 0));
    assert_eq!(r.in_flight(), (30, -4));
    assert_eq!(r.added(), (30, -4));
    assert_eq!((r.sent_total(), r.reports()), ((0, 0), 0));
    r.delivered();
    assert_eq!(
        (r.sent_total(), r.reports(), r.in_flight()),
        ((30, -4), 1, (0, 0))
    );
    r.delivered();
    assert_eq!(
        r.reports(),
        1,
        "a completion with nothing in flight counts nothing"
    );
    // The next one is lost with the endpoint's buffer at a bus reset: discarded.
    r.add_motion(-7, 9);
    let rep = r.pending().expect("motion");
    r.accepted(&rep);
    r.host_reset();
    assert_eq!(
        r.in_flight(),
        (-7, 9),
        "a suspend or resume keeps the endpoint's buffer"
    );
    r.endpoint_lost();
    assert_eq!((r.in_flight(), r.discarded()), ((0, 0), (-7, 9)));
    assert_eq!(r.sent_total(), (30, -4));
    // A report taken by the stack while one is in flight: the first left the buffer.
    r.add_motion(5, 0);
    let a = r.pending().expect("motion");
    r.accepted(&a);
    r.add_motion(0, 6);
    let b = r.pending().expect("motion");
    r.accepted(&b);
    assert_eq!((r.sent_total(), r.in_flight()), ((35, -4), (0, 6)));
}
