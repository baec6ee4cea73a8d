//! What the RTIC tasks do, as plain functions over their resources, so that each task body
//! in `main.rs` is a few lines. Every decision here is made by `imu_core` (tested on the
//! host); this module only connects it to the hardware and the logs.

use imu_core::{
    ButtonEvent, CalibrationError, Event, Indicator, LastCalibration, Phase, Reporter, Tracker,
};

use crate::sampling::{Outcome, Sampler};
use crate::usb::Mouse;

/// State shared with the LED: the last calibration outcome and when it happened [ms].
#[derive(Clone, Copy)]
pub struct Status {
    /// The last calibration outcome.
    pub last: Event,
    /// When it happened (monotonic ms), or `None` before the first window ends.
    pub at_ms: Option<u32>,
}

/// DMA interrupt: hands a full block to the tracker, or accounts for lost samples.
/// Returns the calibration event of the block, if one ended.
pub fn on_dma(sampler: &mut Sampler, tracker: &mut Tracker, now_cycles: u32) -> Option<Event> {
    let mut event = None;
    match sampler.on_dma(now_cycles, |block| event = tracker.feed(block)) {
        Outcome::Restarted(lost) => on_restart(tracker, lost),
        Outcome::Block | Outcome::Idle => {}
    }
    event
}

/// Accounts for a sampling restart.
pub fn on_restart(tracker: &mut Tracker, lost: u32) {
    tracker.lost(lost);
    defmt::warn!("sampling restarted after an overrun: {} samples lost", lost);
}

/// Logs a calibration outcome in physical units.
pub fn log_event(event: &Event, m_s2_per_lsb: f32) {
    match event {
        Event::Calibrated(axes) => {
            for (name, c) in ["x", "y", "z"].iter().zip(axes) {
                let bias_lsb = c.bias_q16 as f32 / 65_536.0;
                let rms_lsb = c.noise_rms_q16 as f32 / 65_536.0;
                defmt::info!(
                    "calibrated {}: bias {} LSB ({} m/s^2), noise {} m/s^2 rms over {} samples",
                    name,
                    bias_lsb,
                    bias_lsb * m_s2_per_lsb,
                    rms_lsb * m_s2_per_lsb,
                    c.samples
                );
            }
        }
        Event::Rejected { axis, error } => {
            defmt::warn!(
                "calibration rejected on axis {}: {}; keep still",
                axis,
                error
            )
        }
    }
}

/// What the LED should show.
pub fn indicator(
    tracker: &Tracker,
    status: &Status,
    usb_configured: bool,
    now_ms: u32,
) -> Indicator {
    let last = match (status.last, status.at_ms) {
        (
            Event::Rejected {
                error: CalibrationError::Clipped { .. },
                ..
            },
            Some(_),
        ) => LastCalibration::Clipped,
        (Event::Rejected { .. }, Some(at)) => LastCalibration::Moved {
            ms: now_ms.wrapping_sub(at),
        },
        _ => LastCalibration::Fine,
    };
    Indicator::choose(usb_configured, tracker.phase() == Phase::Tracking, last)
}

/// A debounced KEY event: left button state (each edge starts the click freeze), and
/// recalibration on a long press.
pub fn on_button(event: ButtonEvent, buttons: &mut u8, tracker: &mut Tracker) {
    match event {
        ButtonEvent::Pressed => {
            *buttons = imu_core::hid::buttons::LEFT;
            tracker.button_edge();
        }
        ButtonEvent::Released => {
            *buttons = 0;
            tracker.button_edge();
        }
        ButtonEvent::LongPress => {
            tracker.recalibrate();
            defmt::info!("KEY held: recalibrating, keep still");
        }
    }
}

/// USB interrupt: adds the tracker's fresh counts `[x, y, z]` to the reporter and services
/// the device. (The counts are taken under the tracker's lock by the caller; the USB poll
/// itself runs without it, so the DMA task is never held up by USB.)
pub fn on_usb(counts: [i32; 3], mouse: &mut Mouse, reporter: &mut Reporter, buttons: u8) {
    let (dx, dy) = imu_core::hid::screen_motion(counts);
    reporter.add_motion(dx, dy);
    reporter.set_buttons(buttons);
    mouse.service(reporter);
}

/// A snapshot of every counter, taken under short locks and logged outside them.
pub struct Snapshot {
    /// The tracker's totals.
    pub tracker: imu_core::Counters,
    /// Sampling restarts.
    pub restarts: u32,
    /// Reports accepted by the USB stack.
    pub reports: u32,
    /// Reports refused for a reason other than "busy".
    pub drops: u32,
    /// Whether the host has configured the device.
    pub usb: bool,
}

/// The periodic counter log.
pub fn log_counters(s: &Snapshot) {
    defmt::info!(
        "samples {} lost {} restarts {} rejected windows {} reports {} drops {} usb {}",
        s.tracker.samples,
        s.tracker.lost,
        s.restarts,
        s.tracker.rejected_windows,
        s.reports,
        s.drops,
        s.usb
    );
}
