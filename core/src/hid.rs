//! USB HID mouse: the report descriptor the device presents, the report's byte layout, and
//! the scheduling of accumulated motion into reports.
//!
//! # Design
//! The descriptor is a plain relative mouse (HID 1.11 appendix E style): 3 buttons, 5 bits of
//! padding, X, Y and wheel as signed bytes in `-127..=127`, no report ID; 4-byte reports.
//! The host (`cargo lab hid`) uses the same constants, so it shows exactly what the device
//! sends.
//!
//! [`Reporter`] holds the counts that the tracker has produced and the host has not yet
//! received. [`Reporter::pending`] proposes the next report; only after the USB stack
//! accepted it does [`Reporter::accepted`] subtract what it carried, and only when the host's
//! IN transfer completes does [`Reporter::delivered`] count it as sent (a bus reset in
//! between loses the endpoint's buffer: the report is counted discarded). If the push fails
//! (the host has not read the last report yet), nothing is lost: the same motion is proposed
//! again, together with whatever arrived since. A report can carry at most 127 counts per axis; a
//! larger motion is scaled down with both axes by the same factor, so the report points the
//! way the hand moved, and the rest is carried into later reports. The sum of all reports
//! equals the sum of all motion, exactly.

/// The HID report descriptor (52 bytes).
pub const MOUSE_REPORT_DESCRIPTOR: [u8; 52] = [
    0x05, 0x01, // Usage Page (Generic Desktop)
    0x09, 0x02, // Usage (Mouse)
    0xA1, 0x01, // Collection (Application)
    0x09, 0x01, //   Usage (Pointer)
    0xA1, 0x00, //   Collection (Physical)
    0x05, 0x09, //     Usage Page (Button)
    0x19, 0x01, //     Usage Minimum (Button 1)
    0x29, 0x03, //     Usage Maximum (Button 3)
    0x15, 0x00, //     Logical Minimum (0)
    0x25, 0x01, //     Logical Maximum (1)
    0x95, 0x03, //     Report Count (3)
    0x75, 0x01, //     Report Size (1)
    0x81, 0x02, //     Input (Data, Variable, Absolute): buttons
    0x95, 0x01, //     Report Count (1)
    0x75, 0x05, //     Report Size (5)
    0x81, 0x03, //     Input (Constant, Variable, Absolute): padding
    0x05, 0x01, //     Usage Page (Generic Desktop)
    0x09, 0x30, //     Usage (X)
    0x09, 0x31, //     Usage (Y)
    0x09, 0x38, //     Usage (Wheel)
    0x15, 0x81, //     Logical Minimum (-127)
    0x25, 0x7F, //     Logical Maximum (127)
    0x75, 0x08, //     Report Size (8)
    0x95, 0x03, //     Report Count (3)
    0x81, 0x06, //     Input (Data, Variable, Relative): X, Y, wheel
    0xC0, //       End Collection
    0xC0, //     End Collection
];

/// Length of one input report [bytes].
pub const REPORT_LEN: usize = 4;

/// Largest motion one report carries per axis [counts] (the descriptor's logical maximum).
pub const MAX_COUNTS_PER_REPORT: i32 = 127;

/// Button bits of a report.
pub mod buttons {
    /// Left button (button 1): bit 0.
    pub const LEFT: u8 = 0b001;
    /// Right button (button 2): bit 1.
    pub const RIGHT: u8 = 0b010;
    /// Middle button (button 3): bit 2.
    pub const MIDDLE: u8 = 0b100;
    /// All buttons the descriptor declares: bits 0 to 2.
    pub const ALL: u8 = 0b111;
}

/// Maps the tracker's counts `[x, y, z]` to HID motion (right, down) for a sensor mounted
/// with its X axis to the right and its Y axis pointing away from the user: screen-down is
/// sensor `-Y`; Z is not reported.
pub const fn screen_motion(counts: [i32; 3]) -> (i32, i32) {
    (counts[0], counts[1].saturating_neg())
}

/// One mouse input report.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct MouseReport {
    /// Buttons held ([`buttons`] bits; others are ignored).
    pub buttons: u8,
    /// Motion to the right [counts], `-127..=127`.
    pub x: i8,
    /// Motion downwards (HID convention) [counts], `-127..=127`.
    pub y: i8,
    /// Wheel [detents], `-127..=127`; always 0 from this device.
    pub wheel: i8,
}

impl MouseReport {
    /// The report as the bytes on the wire.
    pub const fn to_bytes(&self) -> [u8; REPORT_LEN] {
        [
            self.buttons & buttons::ALL,
            self.x as u8,
            self.y as u8,
            self.wheel as u8,
        ]
    }
}

/// [`Reporter`]'s record of the buttons last sent when they are to be sent again: no
/// buttons value equals it (they are masked to [`buttons::ALL`]).
const RESEND: u8 = 0xFF;

/// Accumulated motion and buttons not yet delivered to the host.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Reporter {
    dx: i64,
    dy: i64,
    buttons: u8,
    sent_buttons: u8,
    reports: u32,
    sent: (i64, i64),
    discarded: (i64, i64),
    in_flight: Option<(i8, i8)>,
}

impl Reporter {
    /// Adds motion [counts] (right, down). Saturates at `i64` limits, which no real motion
    /// reaches.
    pub fn add_motion(&mut self, dx: i32, dy: i32) {
        self.dx = self.dx.saturating_add(i64::from(dx));
        self.dy = self.dy.saturating_add(i64::from(dy));
    }

    /// Sets the buttons held now ([`buttons`] bits).
    pub fn set_buttons(&mut self, held: u8) {
        self.buttons = held & buttons::ALL;
    }

    /// Drops motion not yet delivered (the host is not listening: suspended or not yet
    /// configured; delivering it later would be a jump). Buttons are kept.
    pub fn discard_motion(&mut self) {
        self.discarded.0 = self.discarded.0.wrapping_add(self.dx);
        self.discarded.1 = self.discarded.1.wrapping_add(self.dy);
        self.dx = 0;
        self.dy = 0;
    }

    /// The host reset or re-enumerated the device: motion owed is dropped (see
    /// [`Self::discard_motion`]) and the host is assumed to know no buttons, so held buttons
    /// are reported again.
    pub fn host_reset(&mut self) {
        self.discard_motion();
        self.sent_buttons = 0;
    }

    /// The endpoint's buffer was lost (a bus reset; a suspend keeps it): a report still in
    /// flight never reaches the host, and is counted discarded.
    pub fn endpoint_lost(&mut self) {
        if let Some((x, y)) = self.in_flight.take() {
            self.discarded.0 = self.discarded.0.wrapping_add(i64::from(x));
            self.discarded.1 = self.discarded.1.wrapping_add(i64::from(y));
        }
    }

    /// The motion of a report the USB stack took that the host has not yet taken [counts]
    /// (right, down); `(0, 0)` when none is in flight. See [`Self::accepted`].
    pub fn in_flight(&self) -> (i64, i64) {
        self.in_flight
            .map_or((0, 0), |(x, y)| (i64::from(x), i64::from(y)))
    }

    /// Motion not yet delivered [counts] (right, down).
    pub const fn undelivered(&self) -> (i64, i64) {
        (self.dx, self.dy)
    }

    /// Reports delivered to the host so far.
    pub const fn reports(&self) -> u32 {
        self.reports
    }

    /// Motion delivered to the host so far [counts] (right, down), wrapping. With
    /// [`Self::discarded`], [`Self::in_flight`] and [`Self::undelivered`] it accounts for
    /// every count added.
    pub const fn sent_total(&self) -> (i64, i64) {
        self.sent
    }

    /// Every count added so far [counts] (right, down), wrapping: sent, in flight, owed or
    /// discarded (the cursor's motion as the tracker produced it, whether or not a host
    /// took it).
    pub const fn added(&self) -> (i64, i64) {
        let (f0, f1) = match self.in_flight {
            Some((x, y)) => (x as i64, y as i64),
            None => (0, 0),
        };
        (
            self.sent
                .0
                .wrapping_add(self.discarded.0)
                .wrapping_add(f0)
                .wrapping_add(self.dx),
            self.sent
                .1
                .wrapping_add(self.discarded.1)
                .wrapping_add(f1)
                .wrapping_add(self.dy),
        )
    }

    /// Motion dropped so far because the host was not listening [counts], wrapping.
    pub const fn discarded(&self) -> (i64, i64) {
        self.discarded
    }

    /// A report of the held buttons alone, with no motion (the opening report after a new
    /// configuration, `imu_app::opening`); accounted by [`Self::accepted`] like any other.
    pub const fn buttons_only(&self) -> MouseReport {
        MouseReport {
            buttons: self.buttons,
            x: 0,
            y: 0,
            wheel: 0,
        }
    }

    /// The host is to be told the held buttons again with the next report, even if they
    /// have not changed since the last one; nothing when none is held (a host that lost the
    /// last report assumes none).
    pub fn resend_buttons(&mut self) {
        if self.buttons != 0 {
            self.sent_buttons = RESEND;
        }
    }

    /// The next report to send, or `None` when there is no motion and no button change.
    pub fn pending(&self) -> Option<MouseReport> {
        if self.dx == 0 && self.dy == 0 && self.buttons == self.sent_buttons {
            return None;
        }
        let (x, y) = clamp_keeping_direction(self.dx, self.dy);
        Some(MouseReport {
            buttons: self.buttons,
            x,
            y,
            wheel: 0,
        })
    }

    /// Records that `report` (from [`Self::pending`]) was delivered to the host: its motion
    /// is no longer owed, and it counts as sent ([`Self::accepted`] then
    /// [`Self::delivered`]; where there is no endpoint to wait for: simulations, tools).
    pub fn sent(&mut self, report: &MouseReport) {
        self.accepted(report);
        self.delivered();
    }

    /// Records that the USB stack took `report` (from [`Self::pending`]) into the endpoint's
    /// buffer: its motion is no longer owed, but it is in flight until the host's IN transfer
    /// completes ([`Self::delivered`]); a bus reset first loses it ([`Self::endpoint_lost`]
    /// counts it discarded). A stack that takes a report has a free buffer, so a report
    /// still in flight then was delivered.
    pub fn accepted(&mut self, report: &MouseReport) {
        self.delivered();
        self.dx -= i64::from(report.x);
        self.dy -= i64::from(report.y);
        self.sent_buttons = report.buttons;
        self.in_flight = Some((report.x, report.y));
    }

    /// The host took the report in flight (its IN transfer completed): it counts as sent.
    /// Nothing happens with none in flight.
    pub fn delivered(&mut self) {
        if let Some((x, y)) = self.in_flight.take() {
            self.reports = self.reports.wrapping_add(1);
            self.sent.0 = self.sent.0.wrapping_add(i64::from(x));
            self.sent.1 = self.sent.1.wrapping_add(i64::from(y));
        }
    }
}

/// `(dx, dy)` scaled by one common factor so that neither exceeds 127 counts, each rounded
/// half away from zero; unchanged when both already fit.
fn clamp_keeping_direction(dx: i64, dy: i64) -> (i8, i8) {
    let max = dx.unsigned_abs().max(dy.unsigned_abs());
    let limit = MAX_COUNTS_PER_REPORT as u64;
    if max <= limit {
        return (dx as i8, dy as i8); // |dx|, |dy| <= 127
    }
    let scale = |v: i64| -> i8 {
        // round(|v| 127 / max) with the sign of v; |v| <= max so the result is <= 127.
        let mag = (u128::from(v.unsigned_abs()) * u128::from(limit) * 2 + u128::from(max))
            / (2 * u128::from(max));
        if v < 0 {
            -(mag as i8)
        } else {
            mag as i8
        }
    };
    (scale(dx), scale(dy))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn button_bits_are_the_descriptors_buttons_1_to_3() {
        // The descriptor's usages 1..3 map to bits 0..2, in that order (HID 1.11, 6.2.2.7).
        assert_eq!(
            (buttons::LEFT, buttons::RIGHT, buttons::MIDDLE, buttons::ALL),
            (1, 2, 4, 7)
        );
    }

    #[test]
    fn held_buttons_alone_and_told_again_on_request() {
        let mut r = Reporter::default();
        r.set_buttons(buttons::RIGHT);
        r.add_motion(5, 5);
        let opening = r.buttons_only();
        assert_eq!(
            opening.to_bytes(),
            [buttons::RIGHT, 0, 0, 0],
            "no motion in it"
        );
        r.sent(&opening);
        assert_eq!(r.undelivered(), (5, 5), "the motion is still owed");
        r.add_motion(-5, -5);
        assert_eq!(r.pending(), None, "nothing changed since");
        r.resend_buttons();
        assert_eq!(r.pending().map(|p| p.buttons), Some(buttons::RIGHT));
        // With none held there is nothing to tell again.
        let mut r = Reporter::default();
        r.resend_buttons();
        assert_eq!(r.pending(), None);
    }

    #[test]
    fn reports_counts_every_accepted_report() {
        let mut r = Reporter::default();
        r.add_motion(300, 0);
        let mut sent = 0;
        while let Some(report) = r.pending() {
            r.sent(&report);
            sent += 1;
            assert!(sent < 10, "the motion must drain");
        }
        assert_eq!((sent, r.reports()), (3, 3)); // 127 + 127 + 46
        assert_eq!(r.sent_total(), (300, 0));
    }

    #[test]
    fn descriptor_declares_a_four_byte_report() {
        // 3 + 5 bits of buttons and padding, then 3 x 8 bits.
        assert_eq!(MOUSE_REPORT_DESCRIPTOR.len(), 52);
        assert_eq!(REPORT_LEN * 8, 3 + 5 + 3 * 8);
    }

    #[test]
    fn bytes_are_twos_complement() {
        let r = MouseReport {
            buttons: 0xFF,
            x: -1,
            y: 127,
            wheel: -127,
        };
        assert_eq!(r.to_bytes(), [0x07, 0xFF, 0x7F, 0x81]);
    }

    #[test]
    fn screen_motion_maps_sensor_y_away_to_cursor_up() {
        assert_eq!(screen_motion([3, 5, 7]), (3, -5));
        assert_eq!(screen_motion([0, i32::MIN, 0]), (0, i32::MAX));
    }

    #[test]
    fn clamp_keeps_direction_and_sign() {
        assert_eq!(clamp_keeping_direction(300, 100), (127, 42)); // 42.33
        assert_eq!(clamp_keeping_direction(-300, 150), (-127, 64)); // 63.5 -> 64
        assert_eq!(clamp_keeping_direction(5, -127), (5, -127));
        assert_eq!(clamp_keeping_direction(i64::MIN, 0), (-127, 0));
    }
}
