//! What the mouse owes the host (`imu_app::mouse::Reports`), rule by rule, without a bus:
//! motion flows only while configured, a busy endpoint loses nothing, other refusals are
//! counted, every change of the link resends the buttons; and `Mouse` passes its device's
//! state and its buttons through.

use imu_app::mouse::Reports;
use imu_core::hid::buttons;
use imu_core::Link;
use usb_device::device::UsbDeviceState::{Addressed, Configured, Default as Reset, Suspend};
use usb_device::UsbError;

/// Counts `[x, y, z]` that `screen_motion` maps to `(dx, dy)` = (+x, -y).
const RIGHT_10: [i32; 3] = [10, 0, 0];

fn accept(bytes: &[u8]) -> Result<usize, UsbError> {
    Ok(bytes.len())
}

/// A time after the opening [ms].
const NOW: u32 = 1000;

/// Configured by a host and past the opening (`imu_app::opening`): the opening report sent
/// and taken at 0 ms (one report, no motion), the quiet time over by [`NOW`].
fn opened() -> Reports {
    let mut r = Reports::default();
    r.update(Configured, [0; 3], false, 0, accept);
    r.update(Configured, [0; 3], true, 0, |_| panic!("quiet"));
    assert_eq!(
        (r.reporter().reports(), r.reporter().sent_total()),
        (1, (0, 0))
    );
    r
}

#[test]
fn motion_before_configuration_is_discarded_not_delivered_late() {
    let mut r = Reports::default();
    assert_eq!(r.link(), Link::NotConfigured);
    for state in [Reset, Addressed] {
        r.update(state, RIGHT_10, false, NOW, |_| {
            panic!("nothing is pushed before configuration")
        });
    }
    assert_eq!(r.reporter().discarded(), (20, 0));
    r.update(Configured, [0; 3], false, NOW, accept);
    assert_eq!(r.link(), Link::Configured);
    assert_eq!(
        r.reporter().sent_total(),
        (0, 0),
        "the old motion is not a late jump"
    );
}

#[test]
fn configured_motion_is_pushed_and_accounted() {
    let mut r = opened();
    let mut pushed = vec![];
    r.update(Configured, RIGHT_10, false, NOW, |b| {
        pushed.push(b.to_vec());
        Ok(b.len())
    });
    assert_eq!(pushed, [vec![0, 10, 0, 0]]);
    // Taken by the stack, not yet by the host: in flight, neither owed nor sent.
    assert_eq!(r.reporter().in_flight(), (10, 0));
    assert_eq!(
        (r.reporter().sent_total(), r.reporter().reports()),
        ((0, 0), 1)
    );
    assert!(!r.pending());
    // The host's IN transfer completed.
    r.update(Configured, [0; 3], true, NOW, |_| {
        panic!("nothing new to send")
    });
    assert_eq!(
        (r.reporter().sent_total(), r.reporter().reports()),
        ((10, 0), 2)
    );
    assert_eq!(r.reporter().in_flight(), (0, 0));
}

#[test]
fn a_report_still_in_the_endpoint_at_a_bus_reset_is_lost_and_counted_discarded() {
    let mut r = opened();
    r.update(Configured, RIGHT_10, false, NOW, accept);
    assert_eq!(r.reporter().in_flight(), (10, 0));
    // The host resets the bus before it reads the endpoint: the buffer is gone.
    r.update(Reset, [0; 3], false, NOW, |_| panic!("not configured"));
    assert_eq!(r.reporter().in_flight(), (0, 0));
    assert_eq!(r.reporter().sent_total(), (0, 0));
    assert_eq!(r.reporter().discarded(), (10, 0));
    // A completion seen in the same poll as the reset counts first: it was delivered.
    let mut r = opened();
    r.update(Configured, RIGHT_10, false, NOW, accept);
    r.update(Reset, [0; 3], true, NOW, |_| panic!("not configured"));
    assert_eq!(
        (r.reporter().sent_total(), r.reporter().discarded()),
        ((10, 0), (0, 0))
    );
    // A suspend keeps the endpoint's buffer: delivered after the resume, not discarded.
    let mut r = opened();
    r.update(Configured, RIGHT_10, false, NOW, accept);
    r.update(Suspend, [0; 3], false, NOW, |_| panic!("suspended"));
    r.update(Configured, [0; 3], false, NOW, |_| {
        Err(UsbError::WouldBlock)
    });
    r.update(Configured, [0; 3], true, NOW, |_| Err(UsbError::WouldBlock));
    assert_eq!(
        (r.reporter().sent_total(), r.reporter().discarded()),
        ((10, 0), (0, 0))
    );
    // A second report taken by the stack means the first left the buffer: delivered.
    let mut r = opened();
    r.update(Configured, RIGHT_10, false, NOW, accept);
    r.update(Configured, RIGHT_10, false, NOW, accept);
    assert_eq!(
        (r.reporter().sent_total(), r.reporter().in_flight()),
        ((10, 0), (10, 0))
    );
}

#[test]
fn a_busy_endpoint_loses_nothing_and_other_refusals_are_counted() {
    let mut r = opened();
    r.update(Configured, RIGHT_10, false, NOW, |_| {
        Err(UsbError::WouldBlock)
    });
    assert_eq!((r.reporter().undelivered(), r.drops()), ((10, 0), 0));
    assert!(r.pending());
    r.update(Configured, [0; 3], false, NOW, |_| {
        Err(UsbError::InvalidState)
    });
    assert_eq!((r.reporter().undelivered(), r.drops()), ((10, 0), 1));
    r.update(Configured, [0; 3], false, NOW, accept);
    r.update(Configured, [0; 3], true, NOW, accept);
    assert_eq!(r.reporter().sent_total(), (10, 0));
}

#[test]
fn suspend_discards_and_every_link_change_resends_the_buttons() {
    let mut r = opened();
    r.set_buttons(buttons::LEFT);
    r.update(Configured, [0; 3], false, NOW, accept);
    r.update(Configured, [0; 3], true, NOW, accept);
    assert_eq!(
        r.reporter().reports(),
        2,
        "the opening report, then the press"
    );
    r.update(Configured, [0; 3], false, NOW, |_| {
        panic!("nothing new to send")
    });
    r.update(Suspend, RIGHT_10, false, NOW, |_| {
        panic!("nothing is pushed while suspended")
    });
    assert_eq!(
        (r.link(), r.reporter().discarded()),
        (Link::Suspended, (10, 0))
    );
    let mut resent = vec![];
    r.update(Configured, [0; 3], false, NOW, |b| {
        resent.push(b[0]);
        Ok(b.len())
    });
    assert_eq!(
        resent,
        [buttons::LEFT],
        "the host is told again what is held"
    );
}

#[test]
fn a_new_configuration_opens_with_the_held_buttons_then_waits_out_linuxs_quiet_time() {
    use imu_app::opening::QUIET_MS;
    use std::cell::RefCell;
    let mut r = Reports::default();
    r.set_buttons(buttons::LEFT);
    let pushed = RefCell::new(vec![]);
    let push = |b: &[u8]| {
        pushed.borrow_mut().push(b.to_vec());
        Ok(b.len())
    };
    // Configured with motion owed: the opening report carries the held button, no motion.
    r.update(Configured, RIGHT_10, false, 100, push);
    assert_eq!(*pushed.borrow(), [vec![buttons::LEFT, 0, 0, 0]]);
    // Not yet taken: nothing else goes out, and the motion stays owed (not discarded).
    r.update(Configured, RIGHT_10, false, 150, push);
    assert_eq!(
        (pushed.borrow().len(), r.reporter().undelivered()),
        (1, (20, 0))
    );
    // Taken at 200 ms: quiet for QUIET_MS, the motion still owed.
    r.update(Configured, RIGHT_10, true, 200, push);
    r.update(Configured, [0; 3], false, 200 + QUIET_MS - 1, push);
    assert_eq!(pushed.borrow().len(), 1, "held through the quiet time");
    assert_eq!(r.reporter().undelivered(), (30, 0));
    assert_eq!(r.reporter().discarded(), (0, 0));
    // Then the held button again, with the motion owed.
    r.update(Configured, [0; 3], false, 200 + QUIET_MS, push);
    assert_eq!(pushed.borrow()[1], vec![buttons::LEFT, 30, 0, 0]);
    assert_eq!(r.reporter().reports(), 1, "the opening report, delivered");
}

#[test]
fn only_a_new_configuration_opens_and_a_busy_endpoint_retries_the_opening() {
    use imu_app::opening::QUIET_MS;
    let mut r = Reports::default();
    // The endpoint is busy: the opening report is tried again on the next poll.
    r.update(Configured, [0; 3], false, 0, |_| Err(UsbError::WouldBlock));
    let mut first = vec![];
    r.update(Configured, RIGHT_10, false, 1, |b| {
        first.push(b.to_vec());
        Ok(b.len())
    });
    assert_eq!(first, [vec![0, 0, 0, 0]], "buttons alone, no motion");
    r.update(Configured, [0; 3], true, 2, |_| panic!("quiet"));
    // Nothing held: after the quiet time the motion goes out with no button resend.
    let mut next = vec![];
    r.update(Configured, [0; 3], false, 2 + QUIET_MS, |b| {
        next.push(b.to_vec());
        Ok(b.len())
    });
    assert_eq!(next, [vec![0, 10, 0, 0]]);
    r.update(Configured, [0; 3], true, 3 + QUIET_MS, |_| {
        panic!("nothing new")
    });
    // A suspend and resume keeps the host's open device: no new opening.
    r.update(Suspend, [0; 3], false, 500, |_| panic!("suspended"));
    let mut resumed = vec![];
    r.update(Configured, RIGHT_10, false, 501, |b| {
        resumed.push(b.to_vec());
        Ok(b.len())
    });
    assert_eq!(
        resumed,
        [vec![0, 10, 0, 0]],
        "motion at once after a resume"
    );
    // A bus reset is a new configuration: it opens again.
    r.update(Reset, [0; 3], true, 600, |_| panic!("not configured"));
    let mut reopened = vec![];
    r.update(Configured, RIGHT_10, false, 601, |b| {
        reopened.push(b.to_vec());
        Ok(b.len())
    });
    assert_eq!(reopened, [vec![0, 0, 0, 0]]);
    r.update(Configured, RIGHT_10, false, 602 + QUIET_MS, |_| {
        panic!("the opening report is not taken yet: hold")
    });
}

#[test]
fn after_the_quiet_time_a_held_button_is_reported_again_even_with_no_motion() {
    use imu_app::opening::QUIET_MS;
    // usbhid's 50 ms, two ticks of a 100 Hz kernel clock, 10 ms of scheduling.
    assert_eq!(QUIET_MS, 80);
    let open = |held: u8| {
        let mut r = Reports::default();
        r.set_buttons(held);
        r.update(Configured, [0; 3], false, 0, accept);
        r.update(Configured, [0; 3], true, 0, |_| panic!("quiet"));
        r
    };
    // Held: the host that dropped the opening report learns it now.
    let mut r = open(buttons::LEFT);
    let mut again = vec![];
    r.update(Configured, [0; 3], false, QUIET_MS, |b| {
        again.push(b.to_vec());
        Ok(b.len())
    });
    assert_eq!(again, [vec![buttons::LEFT, 0, 0, 0]]);
    // None held and nothing owed: nothing to say.
    let mut r = open(0);
    r.update(Configured, [0; 3], false, QUIET_MS, |_| {
        panic!("no button held, no motion: no report")
    });
}
