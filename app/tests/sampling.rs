//! The sample path's glue (`imu_app::sampling`) and the status it feeds: unfilled buffers
//! are recognised, blocks reach the tracker (lost samples first), calibration outcomes reach
//! the LED, and while suspended blocks are only motion probes that can wake the host.

use imu_app::sampling::{filled, mark_unfilled, on_block, UNFILLED};
use imu_app::stream::Stream;
use imu_app::{device, Status};
use imu_core::profile::AxisMap;
use imu_core::{Delivery, Event, Indicator, Link, PowerAction, Tracker};
use rtic_core::{Exclusive, Mutex};

/// `on_block` with the board's axis mapping and no stream running.
fn feed(
    block: &[[u16; 3]],
    delivery: Delivery,
    now_ms: u32,
    tracker: &mut impl Mutex<T = Tracker>,
    status: &mut impl Mutex<T = Status>,
) -> Option<Event> {
    let mut stream = Stream::default();
    let map = AxisMap::default();
    on_block(
        block,
        delivery,
        now_ms,
        map,
        tracker,
        status,
        &mut Exclusive(&mut stream),
    )
}

fn tracker() -> Tracker {
    Tracker::new(&device::tracker_config(3000)).expect("valid")
}

#[test]
fn a_buffer_is_filled_only_once_its_last_word_is_a_code() {
    let mut buffer = [2048u16; 9];
    assert!(filled(&buffer));
    mark_unfilled(&mut buffer);
    assert_eq!(buffer[8], UNFILLED);
    assert!(!filled(&buffer), "the DMA never wrote it");
    buffer[8] = 4095;
    assert!(filled(&buffer), "a rail is still a code");
    assert!(!filled(&[]), "an empty buffer holds nothing");
    let mut empty: [u16; 0] = [];
    mark_unfilled(&mut empty);
}

#[test]
fn blocks_reach_the_tracker_with_lost_samples_first() {
    let (mut t, mut s) = (tracker(), Status::new(20));
    let block = [[2048, 2048, 2457]; 3];
    assert_eq!(
        feed(
            &block,
            Delivery::OnTime,
            1,
            &mut Exclusive(&mut t),
            &mut Exclusive(&mut s)
        ),
        None
    );
    feed(
        &block,
        Delivery::Late(6),
        2,
        &mut Exclusive(&mut t),
        &mut Exclusive(&mut s),
    );
    let c = t.counters();
    assert_eq!((c.samples, c.lost), (6, 6));
}

#[test]
fn calibration_outcomes_reach_the_led() {
    // A window with motion is rejected: returned, recorded, and shown (flicker for 1 s);
    // one on a rail shows the fault pattern.
    let (mut t, mut s) = (tracker(), Status::new(20));
    let mut event = None;
    for k in 0..1000u32 {
        let c = if k % 2 == 0 { 1800 } else { 2300 };
        let e = feed(
            &[[c, 2048, 2457]; 3],
            Delivery::OnTime,
            k,
            &mut Exclusive(&mut t),
            &mut Exclusive(&mut s),
        );
        event = event.or(e);
    }
    assert!(matches!(event, Some(Event::Rejected { .. })), "{event:?}");
    assert_eq!(
        s.indicator(Link::Configured, true, &t, 1000),
        Indicator::Rejected
    );
    let (mut t, mut s) = (tracker(), Status::new(20));
    for k in 0..1000u32 {
        feed(
            &[[0, 2048, 2457]; 3],
            Delivery::OnTime,
            k,
            &mut Exclusive(&mut t),
            &mut Exclusive(&mut s),
        );
    }
    assert_eq!(
        s.indicator(Link::Configured, true, &t, 1000),
        Indicator::Fault
    );
}

#[test]
fn suspended_blocks_are_probes_that_wake_the_host_on_motion() {
    let (mut t, mut s) = (tracker(), Status::new(20));
    assert!(!s.suspended());
    assert_eq!(s.wake_motion_lsb(), 20);
    // A bus that reads suspended before any host configured the device is not a suspend.
    assert_eq!(s.power(0, Link::Suspended, true, false), PowerAction::None);
    assert!(!s.suspended());
    assert_eq!(
        s.indicator(Link::Suspended, true, &t, 0),
        s.indicator(Link::NotConfigured, true, &t, 0)
    );
    assert_eq!(s.power(0, Link::Configured, true, false), PowerAction::None);
    assert_eq!(
        s.power(0, Link::Suspended, true, false),
        PowerAction::Suspend
    );
    assert!(s.suspended());
    let rest = [[2048, 2048, 2457]; 3];
    for ms in 1..10u32 {
        let e = feed(
            &rest,
            Delivery::OnTime,
            ms,
            &mut Exclusive(&mut t),
            &mut Exclusive(&mut s),
        );
        assert_eq!(e, None);
        assert_eq!(s.power(ms, Link::Suspended, true, false), PowerAction::None);
    }
    assert_eq!(t.counters().samples, 0, "probes are not tracking data");
    let moved = [[2048 + 21, 2048, 2457]; 3];
    feed(
        &moved,
        Delivery::OnTime,
        10,
        &mut Exclusive(&mut t),
        &mut Exclusive(&mut s),
    );
    assert_eq!(s.power(11, Link::Suspended, true, false), PowerAction::Wake);
}

#[test]
fn the_tracker_gets_blocks_routed_by_the_map_and_the_stream_gets_them_as_sampled() {
    // Z on a rail during calibration: the board's map rejects axis 2 (vertical); a map that
    // makes Z the cursor's X axis rejects axis 0.
    let rail = [[2048u16, 2048, 4095]; 20];
    let map = AxisMap {
        x_axis: 2,
        x_flip: false,
        y_axis: 0,
        y_flip: false,
    };
    let mut outcomes = Vec::new();
    for m in [AxisMap::default(), map] {
        let (mut t, mut s, mut stream) = (tracker(), Status::new(20), Stream::default());
        stream.start(12);
        let mut event = None;
        for k in 0..150 {
            let e = on_block(
                &rail[..20],
                if k == 1 {
                    Delivery::Late(7)
                } else {
                    Delivery::OnTime
                },
                k,
                m,
                &mut Exclusive(&mut t),
                &mut Exclusive(&mut s),
                &mut Exclusive(&mut stream),
            );
            event = event.or(e);
        }
        let Some(Event::Rejected { axis, .. }) = event else {
            panic!("a rail is rejected: {event:?}")
        };
        outcomes.push(axis);
        // A block of 20 is fed whole (the longest the device makes), the lost ones counted.
        assert_eq!((t.counters().samples, t.counters().lost), (150 * 20, 7));
        // The stream: as sampled, the gap where it was.
        let f = stream.frame().expect("queued");
        assert_eq!((f.lost, f.triples[0]), (0, [2048, 2048, 4095]));
        stream.sent(&f);
        let f = stream.frame().expect("queued");
        stream.sent(&f);
        assert_eq!(stream.frame().expect("queued").lost, 7);
    }
    assert_eq!(outcomes, [2, 0]);
}

#[test]
fn a_block_longer_than_the_routing_buffer_is_fed_whole() {
    let (mut t, mut s, mut stream) = (tracker(), Status::new(20), Stream::default());
    let block = [[2048u16, 2048, 2457]; 3 * imu_app::sampling::BLOCK_MAX + 1];
    on_block(
        &block,
        Delivery::OnTime,
        0,
        AxisMap::default(),
        &mut Exclusive(&mut t),
        &mut Exclusive(&mut s),
        &mut Exclusive(&mut stream),
    );
    assert_eq!(t.counters().samples, block.len() as u64);
}
