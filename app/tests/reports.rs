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

#[test]
fn motion_before_configuration_is_discarded_not_delivered_late() {
    let mut r = Reports::default();
    assert_eq!(r.link(), Link::NotConfigured);
    for state in [Reset, Addressed] {
        r.update(state, RIGHT_10, false, |_| {
            panic!("nothing is pushed before configuration")
        });
    }
    assert_eq!(r.reporter().discarded(), (20, 0));
    r.update(Configured, [0; 3], false, accept);
    assert_eq!(r.link(), Link::Configured);
    assert_eq!(
        r.reporter().sent_total(),
        (0, 0),
        "the old motion is not a late jump"
    );
}

#[test]
fn configured_motion_is_pushed_and_accounted() {
    let mut r = Reports::default();
    let mut pushed = vec![];
    r.update(Configured, RIGHT_10, false, |b| {
        pushed.push(b.to_vec());
        Ok(b.len())
    });
    assert_eq!(pushed, [vec![0, 10, 0, 0]]);
    // Taken by the stack, not yet by the host: in flight, neither owed nor sent.
    assert_eq!(r.reporter().in_flight(), (10, 0));
    assert_eq!(
        (r.reporter().sent_total(), r.reporter().reports()),
        ((0, 0), 0)
    );
    assert!(!r.pending());
    // The host's IN transfer completed.
    r.update(Configured, [0; 3], true, |_| panic!("nothing new to send"));
    assert_eq!(
        (r.reporter().sent_total(), r.reporter().reports()),
        ((10, 0), 1)
    );
    assert_eq!(r.reporter().in_flight(), (0, 0));
}

#[test]
fn a_report_still_in_the_endpoint_at_a_bus_reset_is_lost_and_counted_discarded() {
    let mut r = Reports::default();
    r.update(Configured, RIGHT_10, false, accept);
    assert_eq!(r.reporter().in_flight(), (10, 0));
    // The host resets the bus before it reads the endpoint: the buffer is gone.
    r.update(Reset, [0; 3], false, |_| panic!("not configured"));
    assert_eq!(r.reporter().in_flight(), (0, 0));
    assert_eq!(r.reporter().sent_total(), (0, 0));
    assert_eq!(r.reporter().discarded(), (10, 0));
    // A completion seen in the same poll as the reset counts first: it was delivered.
    let mut r = Reports::default();
    r.update(Configured, RIGHT_10, false, accept);
    r.update(Reset, [0; 3], true, |_| panic!("not configured"));
    assert_eq!(
        (r.reporter().sent_total(), r.reporter().discarded()),
        ((10, 0), (0, 0))
    );
    // A suspend keeps the endpoint's buffer: delivered after the resume, not discarded.
    let mut r = Reports::default();
    r.update(Configured, RIGHT_10, false, accept);
    r.update(Suspend, [0; 3], false, |_| panic!("suspended"));
    r.update(Configured, [0; 3], false, |_| Err(UsbError::WouldBlock));
    r.update(Configured, [0; 3], true, |_| Err(UsbError::WouldBlock));
    assert_eq!(
        (r.reporter().sent_total(), r.reporter().discarded()),
        ((10, 0), (0, 0))
    );
    // A second report taken by the stack means the first left the buffer: delivered.
    let mut r = Reports::default();
    r.update(Configured, RIGHT_10, false, accept);
    r.update(Configured, RIGHT_10, false, accept);
    assert_eq!(
        (r.reporter().sent_total(), r.reporter().in_flight()),
        ((10, 0), (10, 0))
    );
}

#[test]
fn a_busy_endpoint_loses_nothing_and_other_refusals_are_counted() {
    let mut r = Reports::default();
    r.update(Configured, RIGHT_10, false, |_| Err(UsbError::WouldBlock));
    assert_eq!((r.reporter().undelivered(), r.drops()), ((10, 0), 0));
    assert!(r.pending());
    r.update(Configured, [0; 3], false, |_| Err(UsbError::InvalidState));
    assert_eq!((r.reporter().undelivered(), r.drops()), ((10, 0), 1));
    r.update(Configured, [0; 3], false, accept);
    r.update(Configured, [0; 3], true, accept);
    assert_eq!(r.reporter().sent_total(), (10, 0));
}

#[test]
fn suspend_discards_and_every_link_change_resends_the_buttons() {
    let mut r = Reports::default();
    r.set_buttons(buttons::LEFT);
    r.update(Configured, [0; 3], false, accept);
    r.update(Configured, [0; 3], true, accept);
    assert_eq!(r.reporter().reports(), 1, "the press");
    r.update(Configured, [0; 3], false, |_| panic!("nothing new to send"));
    r.update(Suspend, RIGHT_10, false, |_| {
        panic!("nothing is pushed while suspended")
    });
    assert_eq!(
        (r.link(), r.reporter().discarded()),
        (Link::Suspended, (10, 0))
    );
    let mut resent = vec![];
    r.update(Configured, [0; 3], false, |b| {
        resent.push(b[0]);
        Ok(b.len())
    });
    assert_eq!(
        resent,
        [buttons::LEFT],
        "the host is told again what is held"
    );
}
