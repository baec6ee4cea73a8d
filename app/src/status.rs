//! What the device shows and how it stands: the last calibration outcome, the suspend state
//! machine, and the LED pattern chosen from them.

use imu_core::{
    Calibration, CalibrationError, Event, Indicator, LastCalibration, Link, Phase, Power,
    PowerAction, Tracker,
};

/// The device's status, shared by the sample path (calibration outcomes, suspend probe) and
/// housekeeping (LED, power decisions).
#[derive(Clone, Copy, Debug)]
pub struct Status {
    last: Option<(Event, u32)>,
    calibrated: Option<[Calibration; 3]>,
    power: Power,
}

impl Status {
    /// No calibration outcome yet, awake; a suspended device wakes the host on a change of
    /// `wake_motion_lsb` ADC codes on any axis.
    pub const fn new(wake_motion_lsb: u16) -> Self {
        Self {
            last: None,
            calibrated: None,
            power: Power::new(wake_motion_lsb),
        }
    }

    /// A calibration window ended with `event` at `now_ms` [ms].
    pub fn record(&mut self, event: Event, now_ms: u32) {
        self.last = Some((event, now_ms));
        if let Event::Calibrated(c) = event {
            self.calibrated = Some(c);
        }
    }

    /// The last successful calibration, if any.
    pub const fn calibration(&self) -> Option<[Calibration; 3]> {
        self.calibrated
    }

    /// Whether the device is suspended (its blocks are motion probes, not tracking data).
    pub const fn suspended(&self) -> bool {
        self.power.suspended()
    }

    /// The suspend probe's motion threshold [ADC codes on any axis].
    pub const fn wake_motion_lsb(&self) -> u16 {
        self.power.motion_lsb()
    }

    /// A probe sample `[x, y, z]` [ADC codes] while suspended.
    pub fn probe(&mut self, codes: [u16; 3]) {
        self.power.probe(codes);
    }

    /// Whether a probe found motion that the next tick at `now_ms` [ms] would signal (see
    /// [`Power::motion_pending`]).
    pub fn motion_pending(&self, now_ms: u32, remote_wakeup: bool) -> bool {
        self.power.motion_pending(now_ms, remote_wakeup)
    }

    /// The suspend decision for this tick (see [`Power::tick`]).
    pub fn power(
        &mut self,
        now_ms: u32,
        link: Link,
        remote_wakeup: bool,
        key_pressed: bool,
    ) -> PowerAction {
        self.power.tick(now_ms, link, remote_wakeup, key_pressed)
    }

    /// The LED pattern at `now_ms` [ms] for the USB `link`, whether ADC data `arrives`, and
    /// the `tracker`'s phase.
    pub fn indicator(
        &self,
        link: Link,
        arrives: bool,
        tracker: &Tracker,
        now_ms: u32,
    ) -> Indicator {
        let link = self.power.link_seen(link);
        let last = match self.last {
            Some((
                Event::Rejected {
                    error: CalibrationError::Clipped { .. },
                    ..
                },
                _,
            )) => LastCalibration::Clipped,
            Some((Event::Rejected { .. }, at)) => LastCalibration::Moved {
                ms: now_ms.wrapping_sub(at),
            },
            _ => LastCalibration::Fine,
        };
        Indicator::choose(link, arrives, tracker.phase() == Phase::Tracking, last)
    }
}
