//! The per-device tracker: calibrates, then tracks, the X, Y and Z axes, fed blocks of raw
//! samples in the ADC's scan order.
//!
//! # Design
//! A small state machine driven by [`Tracker::feed`]:
//!
//! ```text
//!            window full, all axes at rest
//! Calibrating ---------------------------------> Tracking
//!   ^   |  window with motion or clipping: restart   |
//!   |   +-------------------------------------------+|
//!   +------------- recalibrate() / reconfigure() ----+
//! ```
//!
//! While calibrating, nothing moves and [`Tracker::take_counts`] returns zeros. Samples that
//! the hardware lost are reported with [`Tracker::lost`] and held (the last codes repeated).
//!
//! While tracking with drift control ([`crate::stillness`]), each sample goes through the
//! stillness detector first: still samples are not integrated (and update the bias), the
//! first moving sample integrates the detector's window from zero velocity, and a button
//! edge ([`Tracker::button_edge`]) freezes integration for the click-freeze time.

use crate::axis::Axis;
use crate::calibration::{Calibration, CalibrationError, Calibrator};
use crate::config::{Config, ConfigError, Settings};
use crate::stillness::{Detector, Verdict};
use crate::AdcCode;

/// Number of axes the tracker integrates (X, Y, Z in the ADC's scan order).
pub const AXES: usize = 3;

/// What the tracker is doing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Phase {
    /// Collecting a calibration window; the device must be still.
    Calibrating,
    /// Integrating motion.
    Tracking,
}

/// Outcome of a calibration window, returned by [`Tracker::feed`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Event {
    /// Every axis was at rest; tracking starts with these biases.
    Calibrated([Calibration; AXES]),
    /// The window was rejected on `axis` (0 = X); calibration restarts.
    Rejected {
        /// Index of the first axis that failed (0 = X, 1 = Y, 2 = Z).
        axis: u8,
        /// Why.
        error: CalibrationError,
    },
}

/// Running totals, for logs and tests.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Counters {
    /// Sample triples received.
    pub samples: u64,
    /// Sample triples reported lost by the hardware.
    pub lost: u64,
    /// Calibration windows rejected.
    pub rejected_windows: u32,
    /// Samples the stillness detector held still (not integrated).
    pub still_samples: u64,
    /// Motions started (still -> moving).
    pub motions: u32,
    /// Samples skipped by the click freeze.
    pub frozen_samples: u64,
}

/// Integrates one filtered sample on every axis. One copy for every caller (flash).
#[inline(never)]
fn integrate_all(axes: &mut [Axis; AXES], s: &Settings, y: [i64; AXES]) {
    for (axis, y) in axes.iter_mut().zip(y) {
        axis.integrate(s, y);
    }
}

/// Calibration and tracking of one device.
#[derive(Clone, Copy, Debug)]
pub struct Tracker {
    settings: Settings,
    phase: Phase,
    axes: [Axis; AXES],
    calibrators: [Calibrator; AXES],
    counters: Counters,
    detector: Option<Detector>,
    freeze_left: u32,
}

impl Tracker {
    /// A tracker that starts calibrating.
    ///
    /// # Errors
    /// The first invalid field of `config`.
    pub fn new(config: &Config) -> Result<Self, ConfigError> {
        let settings = config.validate()?;
        Ok(Self {
            settings,
            phase: Phase::Calibrating,
            axes: [Axis::default(); AXES],
            calibrators: [settings.calibrator(); AXES],
            counters: Counters::default(),
            detector: None,
            freeze_left: 0,
        })
    }

    /// Applies a new configuration and recalibrates.
    ///
    /// # Errors
    /// The first invalid field of `config`; the tracker is then left exactly as it was.
    pub fn reconfigure(&mut self, config: &Config) -> Result<(), ConfigError> {
        self.settings = config.validate()?;
        self.recalibrate();
        Ok(())
    }

    /// Stops all motion and starts a new calibration window.
    pub fn recalibrate(&mut self) {
        self.phase = Phase::Calibrating;
        self.detector = None;
        self.freeze_left = 0;
        self.calibrators = [self.settings.calibrator(); AXES];
        for axis in &mut self.axes {
            axis.stop();
        }
    }

    /// Processes a block of samples, each `[x, y, z]` in ADC codes. Returns the outcome of
    /// the last calibration window that ended in this block, if any.
    pub fn feed(&mut self, block: &[[u16; AXES]]) -> Option<Event> {
        let mut event = None;
        for sample in block {
            self.counters.samples += 1;
            match self.phase {
                Phase::Tracking => self.track(*sample),
                Phase::Calibrating => {
                    for (cal, &code) in self.calibrators.iter_mut().zip(sample) {
                        cal.push(AdcCode(code));
                    }
                    if self.calibrators[0].is_full() {
                        event = Some(self.finish_calibration());
                    }
                }
            }
        }
        event
    }

    fn finish_calibration(&mut self) -> Event {
        let mut results = [Calibration {
            bias_q16: 0,
            noise_rms_q16: 0,
            samples: 0,
        }; AXES];
        for (i, cal) in self.calibrators.iter_mut().enumerate() {
            match cal.finish() {
                Ok(r) => results[i] = r,
                Err(error) => {
                    self.counters.rejected_windows += 1;
                    self.calibrators = [self.settings.calibrator(); AXES];
                    return Event::Rejected {
                        axis: i as u8,
                        error,
                    };
                }
            }
        }
        for (axis, r) in self.axes.iter_mut().zip(&results) {
            axis.set_bias_q16(r.bias_q16);
            axis.stop();
        }
        self.detector = self
            .settings
            .drift()
            .map(|d| Detector::new(d, results.map(|r| r.noise_rms_q16)));
        self.phase = Phase::Tracking;
        Event::Calibrated(results)
    }

    /// One tracked sample: filter, stillness detector, then integration (or not). Not
    /// inlined: `feed` and `lost` share one copy (flash on the device).
    #[inline(never)]
    fn track(&mut self, codes: [u16; AXES]) {
        let s = self.settings;
        let y: [i64; AXES] = core::array::from_fn(|a| self.axes[a].filter(&s, AdcCode(codes[a])));
        let (Some(ds), Some(det)) = (s.drift(), self.detector.as_mut()) else {
            integrate_all(&mut self.axes, &s, y);
            return;
        };
        let was_still = det.is_still();
        let bias = self.axes.each_ref().map(Axis::bias_q16);
        let verdict = det.push(ds, codes, y, bias);
        if self.freeze_left > 0 {
            self.freeze_left -= 1;
            self.counters.frozen_samples += 1;
            if self.freeze_left == 0 {
                self.axes.iter_mut().for_each(Axis::zero_velocity);
            }
            return;
        }
        match verdict {
            Verdict::Moving => integrate_all(&mut self.axes, &s, y),
            Verdict::Started => {
                self.counters.motions += 1;
                for w in det.window(ds) {
                    integrate_all(&mut self.axes, &s, w);
                }
            }
            Verdict::Still => {
                self.counters.still_samples += 1;
                if !was_still {
                    self.axes.iter_mut().for_each(Axis::zero_velocity);
                }
                if let Some(b) = det.bias_update(ds, bias) {
                    for (axis, b) in self.axes.iter_mut().zip(b) {
                        axis.track_bias_q16(b);
                    }
                }
            }
        }
    }

    /// A button changed state: with drift control, integration pauses for the click-freeze
    /// time and restarts from zero velocity, so the jolt of a click does not drag the cursor.
    pub fn button_edge(&mut self) {
        if let (Phase::Tracking, Some(d)) = (self.phase, self.settings.drift()) {
            self.freeze_left = d.freeze_samples();
        }
    }

    /// Reports `lost` sample triples that the hardware dropped (ADC or DMA overrun). While
    /// tracking they are held: the last codes go through the same path again, so the
    /// integrator's clock stays the hardware's. While calibrating they only count.
    pub fn lost(&mut self, lost: u32) {
        self.counters.lost += u64::from(lost);
        if self.phase == Phase::Tracking {
            let last = self.axes.each_ref().map(|a| a.last_code().0);
            for _ in 0..lost {
                self.track(last);
            }
        }
    }

    /// Whether drift control currently holds the device still (`false` without drift
    /// control or while calibrating).
    pub fn is_still(&self) -> bool {
        self.phase == Phase::Tracking && self.detector.is_some_and(|d| d.is_still())
    }

    /// Drains the motion since the last call as whole mouse counts `[x, y, z]`, remainders
    /// carried. Zeros while calibrating.
    pub fn take_counts(&mut self) -> [i32; AXES] {
        let settings = &self.settings;
        self.axes.each_mut().map(|axis| axis.take_counts(settings))
    }

    /// The current phase.
    pub const fn phase(&self) -> Phase {
        self.phase
    }

    /// The validated configuration in use.
    pub const fn settings(&self) -> &Settings {
        &self.settings
    }

    /// The axes' states (index 0 = X).
    pub const fn axes(&self) -> &[Axis; AXES] {
        &self.axes
    }

    /// Running totals.
    pub const fn counters(&self) -> Counters {
        self.counters
    }
}
