//! Stop mode's decisions over a scripted stand-in for the board: when it may stop, what
//! each wake-up source leads to, the probe in Stop, the watchdog and the time credited, and
//! the reset when the clocks do not come back.

use std::collections::VecDeque;

use imu_app::sleep::{self, End, Episode, StopMode, Wakes, Why};
use imu_app::Status;
use imu_core::{Link, PowerAction};

/// The board's probe period [ms] (50 Hz).
const PROBE_MS: u32 = 20;
/// Motion threshold [ADC codes].
const MOTION: u16 = 12;
const STILL: [u16; 3] = [2048, 2048, 2458];
const MOVED: [u16; 3] = [2048, 2048, 2458 + MOTION + 1];

#[derive(Default)]
struct Board {
    wakes: VecDeque<Wakes>,
    scans: VecDeque<Option<[u16; 3]>>,
    restores: bool,
    stops: u32,
    feeds: u32,
    scanned: u32,
    restored: u32,
}

impl StopMode for Board {
    fn stop(&mut self) -> Wakes {
        self.stops += 1;
        self.wakes.pop_front().expect("the script ran out of wakes")
    }
    fn scan(&mut self) -> Option<[u16; 3]> {
        self.scanned += 1;
        self.scans.pop_front().unwrap_or(Some(STILL))
    }
    fn feed(&mut self) {
        self.feeds += 1;
    }
    fn restore(&mut self) -> bool {
        self.restored += 1;
        self.restores
    }
}

const fn wakes(usb: bool, key: bool, timer: bool) -> Wakes {
    Wakes { usb, key, timer }
}

const TIMER: Wakes = wakes(false, false, true);
const USB: Wakes = wakes(true, false, false);
const KEY: Wakes = wakes(false, true, false);
const NONE: Wakes = wakes(false, false, false);

fn board(wakes: &[Wakes], scans: &[Option<[u16; 3]>]) -> Board {
    Board {
        wakes: wakes.iter().copied().collect(),
        scans: scans.iter().copied().collect(),
        restores: true,
        ..Board::default()
    }
}

/// Configured at 0 ms, suspended at 1 ms.
fn suspended() -> Status {
    let mut s = Status::new(MOTION);
    assert_eq!(s.power(0, Link::Configured, true, false), PowerAction::None);
    assert_eq!(
        s.power(1, Link::Suspended, true, false),
        PowerAction::Suspend
    );
    s
}

#[test]
fn the_board_stops_only_when_nothing_needs_its_clocks() {
    let awake = Status::new(MOTION);
    assert!(
        !sleep::may_stop(&awake, 10, true, false, false, true),
        "awake"
    );
    let mut s = suspended();
    assert!(sleep::may_stop(&s, 10, true, false, false, true));
    assert!(
        !sleep::may_stop(&s, 10, true, false, false, false),
        "the host resumed since Power's last tick: the USB core no longer reads suspended"
    );
    assert!(
        !sleep::may_stop(&s, 10, true, true, false, true),
        "the OTG core signals a remote wake-up from its 48 MHz clock"
    );
    assert!(
        !sleep::may_stop(&s, 10, true, false, true, true),
        "KEY held: the debounce must see the press"
    );
    s.probe(STILL);
    s.probe(MOVED);
    assert!(
        !sleep::may_stop(&s, 10, true, false, false, true),
        "motion that the next tick signals"
    );
    assert!(
        sleep::may_stop(&s, 10, false, false, false, true),
        "motion, but the host did not enable remote wake-up: nothing to signal"
    );
}

#[test]
fn timer_wakes_probe_feed_and_credit_until_the_host_resumes() {
    let mut s = suspended();
    let mut b = board(&[TIMER, TIMER, TIMER, USB], &[]);
    let e = sleep::episode(&mut b, &mut s, 10, true, PROBE_MS);
    assert_eq!(
        e,
        Episode {
            slept_ms: 3 * PROBE_MS,
            probes: 3,
            end: End::Awake(Why::Usb)
        }
    );
    assert_eq!((b.stops, b.feeds, b.scanned, b.restored), (4, 3, 3, 1));
}

#[test]
fn motion_ends_the_episode_only_when_it_will_be_signalled() {
    // Remote wake-up enabled: the probe that moved ends it.
    let mut s = suspended();
    let mut b = board(
        &[TIMER, TIMER, TIMER, TIMER],
        &[Some(STILL), Some(STILL), Some(MOVED)],
    );
    let e = sleep::episode(&mut b, &mut s, 10, true, PROBE_MS);
    assert_eq!(e.end, End::Awake(Why::Motion));
    assert_eq!((e.probes, e.slept_ms, b.stops), (3, 60, 3));
    assert_eq!(s.power(70, Link::Suspended, true, false), PowerAction::Wake);
    // Not enabled: motion changes nothing, the probe goes on until something else wakes.
    let mut s = suspended();
    let mut b = board(&[TIMER, TIMER, TIMER, KEY], &[Some(STILL), Some(MOVED)]);
    let e = sleep::episode(&mut b, &mut s, 10, false, PROBE_MS);
    assert_eq!(e.end, End::Awake(Why::Key));
    assert_eq!(e.probes, 3);
}

#[test]
fn within_the_retry_interval_motion_waits_in_stop_on_the_credited_time() {
    // A wake-up was signalled at 6 ms and the host slept on; the next one is allowed at
    // 1006 ms. The episode starts at 10 ms with motion on every probe: it stays in Stop
    // until the credited time reaches 1006 ms (50 probes, 1000 ms), not for ever.
    let mut s = suspended();
    s.probe(STILL);
    s.probe(MOVED);
    assert_eq!(s.power(6, Link::Suspended, true, false), PowerAction::Wake);
    // (The signal spent the reference: the first probe after it is the new one.)
    let mut scans = vec![Some(STILL)];
    scans.extend([Some(MOVED); 59]);
    let mut b = board(&[TIMER; 60], &scans);
    let e = sleep::episode(&mut b, &mut s, 10, true, PROBE_MS);
    assert_eq!(e.end, End::Awake(Why::Motion));
    assert_eq!((e.probes, e.slept_ms), (50, 1000));
    assert_eq!(b.feeds, 50, "the watchdog fed on every probe");
}

#[test]
fn key_usb_and_a_pending_interrupt_end_it_at_once() {
    for (first, why) in [(KEY, Why::Key), (USB, Why::Usb), (NONE, Why::Other)] {
        let mut s = suspended();
        let mut b = board(&[first], &[]);
        let e = sleep::episode(&mut b, &mut s, 10, true, PROBE_MS);
        assert_eq!(
            e,
            Episode {
                slept_ms: 0,
                probes: 0,
                end: End::Awake(why)
            }
        );
        assert_eq!(
            (b.feeds, b.scanned),
            (0, 0),
            "{why:?}: no probe period passed"
        );
    }
    // The timer fired with KEY: the period is credited and the watchdog fed, no scan.
    let mut s = suspended();
    let mut b = board(&[wakes(false, true, true)], &[]);
    let e = sleep::episode(&mut b, &mut s, 10, true, PROBE_MS);
    assert_eq!((e.end, e.slept_ms, e.probes), (End::Awake(Why::Key), 20, 0));
    assert_eq!((b.feeds, b.scanned), (1, 0));
}

#[test]
fn a_scan_that_fails_wakes_the_board() {
    let mut s = suspended();
    let mut b = board(&[TIMER, TIMER], &[Some(STILL), None]);
    let e = sleep::episode(&mut b, &mut s, 10, true, PROBE_MS);
    assert_eq!(e.end, End::Awake(Why::Scan));
    assert_eq!((e.probes, e.slept_ms), (1, 40));
}

#[test]
fn clocks_that_do_not_come_back_reset_the_board() {
    let mut s = suspended();
    let mut b = board(&[TIMER, USB], &[]);
    b.restores = false;
    let e = sleep::episode(&mut b, &mut s, 10, true, PROBE_MS);
    assert_eq!(e.end, End::Reset(Why::Usb));
    assert_eq!(b.restored, 1);
}
