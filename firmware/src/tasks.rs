//! What the RTIC tasks do beyond `imu_app`: the stall check under one lock with the
//! tracker, and the logs, in physical units, through defmt. Every decision is made by
//! `imu_app` and `imu_core` (tested on the host).

use imu_app::Mouse;
use imu_core::{Counters, Event, LedgerCounters, Tracker};
use rtic::Mutex;
use stm32f4xx_hal::otg_fs::UsbBusType;

use crate::board;
use crate::sampling::{Outcome, Sampler};

/// Restarts a stalled sampling and tells the tracker, under one lock of both (a block cannot
/// be fed between the restart and its lost samples). Returns whether ADC data arrives.
pub fn check_stall(
    sampler: &mut impl Mutex<T = Sampler>,
    tracker: &mut impl Mutex<T = Tracker>,
) -> bool {
    sampler.lock(|s| {
        if let Outcome::Restarted(lost) = s.check_stall(board::STALL_SAMPLES) {
            tracker.lock(|t| t.restarted(lost));
            defmt::warn!("no ADC data: sampling restarted, {} samples lost", lost);
        }
        s.delivering()
    })
}

/// Logs what a DMA interrupt produced.
pub fn log_outcome(outcome: &Outcome, event: Option<&Event>, m_s2_per_lsb: f32) {
    if let Outcome::Restarted(lost) = outcome {
        defmt::warn!("DMA overrun: sampling restarted, {} samples lost", lost);
    }
    if let Some(e) = event {
        log_event(e, m_s2_per_lsb);
    }
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

/// A snapshot of every counter, taken under short locks and logged outside them.
pub struct Snapshot {
    /// The tracker's totals.
    pub tracker: Counters,
    /// The sampling ledger's totals.
    pub ledger: LedgerCounters,
    /// Reports accepted by the USB stack.
    pub reports: u32,
    /// Reports refused for a reason other than "busy".
    pub drops: u32,
    /// The USB link.
    pub link: imu_core::Link,
}

impl Snapshot {
    /// Takes the counters, one short lock each.
    pub fn take(
        tracker: &mut impl Mutex<T = Tracker>,
        sampler: &mut impl Mutex<T = Sampler>,
        mouse: &mut impl Mutex<T = Mouse<'static, UsbBusType>>,
    ) -> Self {
        let (reports, drops, link) = mouse.lock(|m| {
            let r = m.reports();
            (r.reporter().reports(), r.drops(), r.link())
        });
        Self {
            tracker: tracker.lock(|t| t.counters()),
            ledger: sampler.lock(|s| s.ledger().counters()),
            reports,
            drops,
            link,
        }
    }
}

/// The periodic counter log.
pub fn log_counters(s: &Snapshot) {
    defmt::info!(
        "samples {} lost {} late blocks {} restarts {} rejected windows {} reports {} drops {} usb {}",
        s.tracker.samples,
        s.tracker.lost,
        s.ledger.late_blocks,
        s.ledger.restarts,
        s.tracker.rejected_windows,
        s.reports,
        s.drops,
        s.link
    );
}
