//! The sampling's decisions over a recording stand-in for the board's timer, ADC and DMA.

use imu_app::sampler::{Acquisition, DmaEvent, Outcome, Sampling};
use imu_core::Delivery;

const TIMER_HZ: u32 = 96_000_000;
/// The board's probe: 50 Hz.
const PROBE_ARR: u32 = TIMER_HZ / 50 - 1;

#[derive(Debug, PartialEq, Eq, Clone, Copy)]
enum Call {
    Period(u32),
    Stop,
    Run,
    Rearm(usize),
}

#[derive(Default)]
struct Board {
    now: u32,
    calls: Vec<Call>,
}

impl Acquisition for Board {
    fn now(&self) -> u32 {
        self.now
    }
    fn set_period(&mut self, arr: u32) {
        self.calls.push(Call::Period(arr));
    }
    fn stop(&mut self) {
        self.calls.push(Call::Stop);
    }
    fn run(&mut self) {
        self.calls.push(Call::Run);
    }
    fn rearm(&mut self, words: usize) {
        self.calls.push(Call::Rearm(words));
    }
}

fn started(fs_hz: u32) -> (Sampling, Board) {
    let mut s = Sampling::new(TIMER_HZ, fs_hz, PROBE_ARR, 5).expect("accepted rate");
    let mut b = Board::default();
    s.start(&mut b);
    (s, b)
}

#[test]
fn start_loads_the_running_period_then_runs_the_trigger() {
    let (s, b) = started(3000);
    assert_eq!(b.calls, [Call::Period(31_999), Call::Run]);
    assert_eq!((s.block(), s.arr()), (3, 31_999));
    assert!(s.ledger().running());
}

#[test]
fn a_stall_at_the_running_rate_restarts_and_counts_what_was_lost() {
    let (mut s, mut b) = started(3000);
    // Blocks every 1 ms, then none: the limit is 5 blocks of 3 samples (5 ms).
    for _ in 0..10 {
        b.now += 96_000;
        assert_eq!(
            s.on_dma(&mut b, DmaEvent::Full),
            Outcome::Block(Delivery::OnTime)
        );
    }
    b.now += 5 * 96_000;
    assert_eq!(s.check_stalled(&mut b), Outcome::Idle, "at the limit");
    b.now += 32_000 * 2;
    b.calls.clear();
    // 5 ms and two samples since the last block: 17 samples lost.
    assert!(s.delivering(), "blocks came since the start");
    assert_eq!(s.check_stalled(&mut b), Outcome::Restarted(17));
    assert_eq!(b.calls, [Call::Rearm(9)]);
    assert!(
        !s.delivering(),
        "restarted, and no block since: no ADC data"
    );
    assert_eq!(s.ledger().counters().lost, 17);
}

#[test]
fn while_suspended_the_probe_blocks_never_restart_sampling() {
    // The first flash's defect: probe blocks 20 ms apart at 50 Hz made the ledger run at
    // 3 kHz's limits, and the stall check restarted sampling every few milliseconds.
    let (mut s, mut b) = started(3000);
    b.now += 96_000;
    s.on_dma(&mut b, DmaEvent::Full);
    b.calls.clear();
    s.suspend(&mut b);
    assert_eq!(b.calls, [Call::Period(PROBE_ARR)]);
    for _ in 0..200 {
        b.now = b.now.wrapping_add(3 * 1_920_000); // a probe block of 3 scans at 50 Hz
        assert_eq!(
            s.on_dma(&mut b, DmaEvent::Full),
            Outcome::Block(Delivery::OnTime)
        );
        for _ in 0..60 {
            b.now = b.now.wrapping_add(96_000);
            assert_eq!(s.check_stalled(&mut b), Outcome::Idle);
        }
    }
    assert!(s.delivering(), "a paused sampling is not a failed one");
    assert_eq!(s.ledger().counters().restarts, 0);
    assert!(!b.calls.contains(&Call::Rearm(9)));
    // Resumed: the acquisition rebuilt in a retime's order (in Stop mode the board parked
    // it), the running period, and the stall check at its limits again.
    b.calls.clear();
    s.resume(&mut b);
    assert_eq!(
        b.calls,
        [Call::Stop, Call::Rearm(9), Call::Period(31_999), Call::Run]
    );
    assert!(s.ledger().running(), "counting from the resume");
    b.now += 6 * 96_000;
    assert!(matches!(s.check_stalled(&mut b), Outcome::Restarted(_)));
}

#[test]
fn dma_events_are_timed_dropped_ignored_or_restart() {
    let (mut s, mut b) = started(20_000);
    b.now += 96_000;
    assert_eq!(
        s.on_dma(&mut b, DmaEvent::Full),
        Outcome::Block(Delivery::OnTime)
    );
    b.now += 3 * 96_000;
    // Two block periods missed: 2 blocks of 20 triples overwritten.
    assert_eq!(
        s.on_dma(&mut b, DmaEvent::Full),
        Outcome::Block(Delivery::Late(40))
    );
    assert_eq!(s.on_dma(&mut b, DmaEvent::Unfilled), Outcome::Idle);
    assert_eq!(s.ledger().counters().late_blocks, 3);
    b.calls.clear();
    assert_eq!(s.on_dma(&mut b, DmaEvent::NotReady), Outcome::Idle);
    assert!(b.calls.is_empty());
    b.now += 4_800 * 3; // three samples after the last block
    assert_eq!(s.on_dma(&mut b, DmaEvent::Overrun), Outcome::Restarted(3));
    assert_eq!(b.calls, [Call::Rearm(60)]);
}

#[test]
fn a_retime_stops_rearms_then_loads_and_runs_and_a_bad_rate_changes_nothing() {
    let (mut s, mut b) = started(3000);
    b.calls.clear();
    s.retime(&mut b, 20_000).expect("accepted");
    assert_eq!(
        b.calls,
        [Call::Stop, Call::Rearm(60), Call::Period(4_799), Call::Run]
    );
    assert_eq!((s.block(), s.arr()), (20, 4_799));
    // 7 Hz does not divide 96 MHz into whole cycles: refused, nothing touched.
    let before = s;
    b.calls.clear();
    assert!(s.retime(&mut b, 7).is_err());
    assert_eq!((s, b.calls.len()), (before, 0));
}
