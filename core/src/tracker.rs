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
//! While tracking with drift control ([`crate::drift`]), a sample is integrated only
//! while the detector says a motion is under way; at every 5 ms tick the detector decides
//! and the tracker carries out its [`Action`] on the axes: integrate a motion's onset from
//! zero velocity, stop, discard a motion not yet delivered, or move the biases. A button
//! edge ([`Tracker::button_edge`]) discards a motion younger than the hold and freezes
//! integration for the click-freeze time.

use crate::axis::Axis;
use crate::calibration::{Calibration, CalibrationError, Calibrator};
use crate::config::{Config, ConfigError, Settings};
use crate::drift::{Action, Detector, State};
use crate::integrator::IntegratorState;
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
    /// Motions discarded before delivery (a click's jolt inside the hold).
    pub discarded: u32,
    /// Lifts (or knocks) that suspended tracking.
    pub lifts: u32,
    /// New biases after a tilt or a landing.
    pub rebiases: u32,
}

/// Integrates one filtered sample on every axis. One copy for every caller (flash).
#[inline(never)]
fn integrate_all(axes: &mut [Axis; AXES], s: &Settings, y: [i64; AXES]) {
    for (axis, y) in axes.iter_mut().zip(y) {
        axis.integrate(s, y);
    }
}

/// A second motion integrated beside the axes' while drift control weighs whether a tilt
/// ended ([`Action::Shadow`]): its zeros (Q16 counts) and its integrators.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Shadow {
    bias: [i64; AXES],
    states: [IntegratorState; AXES],
}

/// What the tracker holds for its phase: the calibration window's accumulators, or drift
/// control's detector. Never both (they share the memory: the detector is most of the
/// tracker's RAM, the accumulators 0.5 KiB).
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(clippy::large_enum_variant)] // the point: the small variant lives in the large one's room
enum Stage {
    /// Collecting a calibration window, one accumulator per axis.
    Calibrating([Calibrator; AXES]),
    /// Tracking; the detector is `None` without drift control.
    Tracking(Option<Detector>),
}

/// Calibration and tracking of one device.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tracker {
    settings: Settings,
    stage: Stage,
    axes: [Axis; AXES],
    counters: Counters,
    shadow: Option<Shadow>,
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
            stage: Stage::Calibrating([settings.calibrator(); AXES]),
            axes: [Axis::default(); AXES],
            counters: Counters::default(),
            shadow: None,
        })
    }

    /// Applies a new configuration and recalibrates. The axes start afresh: their read-out
    /// remainders are in units of the old configuration's shift (kept, they would turn into
    /// phantom counts of a still device), and the filter and bias are recalibrated anyway. At
    /// most a fraction of a count not yet sent is dropped.
    ///
    /// # Errors
    /// The first invalid field of `config`; the tracker is then left exactly as it was.
    pub fn reconfigure(&mut self, config: &Config) -> Result<(), ConfigError> {
        self.settings = config.validate()?;
        self.axes = [Axis::default(); AXES];
        self.recalibrate();
        Ok(())
    }

    /// Stops all motion and starts a new calibration window.
    pub fn recalibrate(&mut self) {
        self.stage = Stage::Calibrating([self.settings.calibrator(); AXES]);
        self.shadow = None;
        for axis in &mut self.axes {
            axis.stop();
        }
    }

    /// Processes a block of samples, each `[x, y, z]` in ADC codes. Returns the outcome of
    /// the last calibration window that ended in this block, if any.
    pub fn feed(&mut self, block: &[[u16; AXES]]) -> Option<Event> {
        let mut event = None;
        let mut rest = block;
        while let Stage::Calibrating(calibrators) = &mut self.stage {
            let Some((sample, later)) = rest.split_first() else {
                return event;
            };
            rest = later;
            self.counters.samples += 1;
            for (cal, &code) in calibrators.iter_mut().zip(sample) {
                cal.push(AdcCode(code));
            }
            if calibrators[0].is_full() {
                event = Some(self.finish_calibration());
            }
        }
        if self.detector().is_none() {
            // Without drift control nothing decides per sample: the block goes through each
            // axis in one pass.
            self.track_block(rest);
        } else {
            self.counters.samples += rest.len() as u64;
            self.track_run(rest, 1);
        }
        event
    }

    /// Ends a calibration window. Out of line: it builds the detector (several KiB), which
    /// inlined would give [`Self::feed`] a frame of that size to set up on every block.
    #[cold]
    #[inline(never)]
    fn finish_calibration(&mut self) -> Event {
        let mut results = [Calibration {
            bias_q16: 0,
            noise_rms_q16: 0,
            samples: 0,
            tick_var_q32: 0,
            long_run_var_q32: 0,
            tick_lags_q32: [0; 3],
        }; AXES];
        let Stage::Calibrating(calibrators) = &mut self.stage else {
            unreachable!("finish_calibration is called only while calibrating")
        };
        for (i, cal) in calibrators.iter_mut().enumerate() {
            match cal.finish() {
                Ok(r) => results[i] = r,
                Err(error) => {
                    self.counters.rejected_windows += 1;
                    *calibrators = [self.settings.calibrator(); AXES];
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
        self.stage = Stage::Tracking(self.settings.drift().map(|d| Detector::new(d, &results)));
        Event::Calibrated(results)
    }

    /// Tracked samples without drift control: each axis takes the block at once
    /// ([`Axis::update_block`]), exactly as [`Self::track`] on each sample.
    fn track_block(&mut self, block: &[[u16; AXES]]) {
        self.counters.samples += block.len() as u64;
        let s = &self.settings;
        for (a, axis) in self.axes.iter_mut().enumerate() {
            axis.update_block(s, block.iter().map(|t| AdcCode(t[a])));
        }
    }

    /// Tracks each of `samples`, `times` times over ([`Self::track`]). The one copy of the
    /// per-sample path (`feed` passes a block once, `lost` the last codes `lost` times: flash
    /// on the device), with the sample's work inlined into the loop: a call per sample cost
    /// its prologue and epilogue, about 12 instructions a sample triple on the Cortex-M4.
    #[inline(never)]
    fn track_run(&mut self, samples: &[[u16; AXES]], times: u32) {
        for _ in 0..times {
            for &codes in samples {
                self.track(codes);
            }
        }
    }

    /// One tracked sample: filter, integration while a motion is under way, then the
    /// detector's decision.
    #[inline(always)]
    fn track(&mut self, codes: [u16; AXES]) {
        // Borrowed field by field: the settings (320 bytes) are not copied per sample.
        let Self {
            settings: s,
            axes,
            stage,
            counters,
            shadow,
        } = self;
        let detector = match stage {
            Stage::Tracking(d) => d,
            Stage::Calibrating(_) => &mut None,
        };
        // Spelled out, not `from_fn`: on the Cortex-M4 its drop guard costs more than the
        // filter (20 instructions a sample).
        let [ax, ay, az] = axes;
        let y: [i64; AXES] = [
            ax.filter(s, AdcCode(codes[0])),
            ay.filter(s, AdcCode(codes[1])),
            az.filter(s, AdcCode(codes[2])),
        ];
        let (Some(ds), Some(det)) = (s.drift(), detector.as_mut()) else {
            integrate_all(axes, s, y);
            return;
        };
        match det.state() {
            State::Moving => {
                integrate_all(axes, s, y);
                if let Some(sh) = shadow {
                    for ((st, b), y) in sh.states.iter_mut().zip(sh.bias).zip(y) {
                        s.scheme().step(st, y - b);
                    }
                }
            }
            State::Still => counters.still_samples += 1,
            State::Frozen => counters.frozen_samples += 1,
            State::Lifted => {}
        }
        let [ax, ay, az] = &*axes;
        let bias = [ax.bias_q16(), ay.bias_q16(), az.bias_q16()];
        let velocities = || {
            let velocity = [ax, ay, az].map(|a| a.integrator().velocity());
            let shadow = shadow
                .as_ref()
                .map(|sh| sh.states.each_ref().map(IntegratorState::velocity));
            (velocity, shadow)
        };
        let action = det.push(ds, codes, y, bias, velocities);
        if det.state() == State::Lifted
            && matches!(
                action,
                Action::Stop | Action::Settle { .. } | Action::Discard
            )
        {
            counters.lifts += 1;
        }
        if action != Action::None {
            self.apply(action);
        }
    }

    /// Carries out a drift-control decision on the axes.
    fn apply(&mut self, action: Action) {
        // Every decision ends a shadow (a new one replaces it, an adoption takes it).
        let shadow = self.shadow.take();
        match action {
            Action::None => {}
            Action::Shadow { bias, blocks } => {
                let mut sh = Shadow {
                    bias,
                    states: [IntegratorState::default(); AXES],
                };
                if let (Some(det), Some(ds)) = (self.detector(), self.settings.drift()) {
                    let scheme = self.settings.scheme();
                    if let Some(prev) = det.replay_prev(blocks) {
                        for ((st, b), y) in sh.states.iter_mut().zip(bias).zip(prev) {
                            st.prime(y - b);
                        }
                    }
                    for sums in det.replay(ds, blocks) {
                        for ((st, b), sums) in sh.states.iter_mut().zip(bias).zip(&sums) {
                            scheme.step_block(st, sums, b);
                        }
                    }
                }
                self.shadow = Some(sh);
            }
            Action::Adopt => {
                if let Some(sh) = shadow {
                    self.counters.rebiases += 1;
                    self.counters.discarded += 1;
                    for ((axis, b), st) in self.axes.iter_mut().zip(sh.bias).zip(sh.states) {
                        axis.track_bias_q16(b);
                        axis.set_integrator(st);
                        axis.zero_velocity();
                    }
                }
                self.shadow = None;
            }
            Action::Start { blocks, carry } => self.start(blocks, carry),
            Action::Stop => self.axes.iter_mut().for_each(Axis::zero_velocity),
            Action::Settle { dz } => {
                for (axis, dz) in self.axes.iter_mut().zip(dz) {
                    axis.correct(dz);
                }
                self.axes.iter_mut().for_each(Axis::zero_velocity);
            }
            Action::Discard => {
                self.counters.discarded += 1;
                self.axes.iter_mut().for_each(Axis::stop);
            }
            Action::Rebias { bias, discard } => {
                self.counters.rebiases += 1;
                for (axis, b) in self.axes.iter_mut().zip(bias) {
                    axis.track_bias_q16(b);
                    if discard {
                        axis.stop();
                    } else {
                        axis.zero_velocity();
                    }
                }
            }
            Action::Land { bias, blocks } => {
                if self.axes.iter().zip(bias).any(|(a, b)| a.bias_q16() != b) {
                    self.counters.rebiases += 1;
                }
                for (axis, b) in self.axes.iter_mut().zip(bias) {
                    axis.track_bias_q16(b);
                }
                self.start(blocks, [0; 2]);
            }
            Action::TrackBias(b) => {
                for (axis, b) in self.axes.iter_mut().zip(b) {
                    axis.track_bias_q16(b);
                }
            }
        }
    }

    /// Starts a motion from the horizontal velocity `carry` (`W`, Q16 counts times samples;
    /// the vertical from zero) and integrates its onset ([`Self::replay`]).
    fn start(&mut self, blocks: usize, carry: [i64; 2]) {
        self.counters.motions += 1;
        for (axis, w) in self.axes.iter_mut().zip([carry[0], carry[1], 0]) {
            axis.set_velocity(w);
        }
        self.replay(blocks);
    }

    /// Integrates a new motion's onset: the detector's last `blocks` blocks and the current
    /// block so far, the trapezoid primed on the sample before them.
    fn replay(&mut self, blocks: usize) {
        let s = &self.settings;
        if let (Stage::Tracking(Some(det)), Some(ds)) = (&self.stage, s.drift()) {
            if let Some(prev) = det.replay_prev(blocks) {
                for (axis, y) in self.axes.iter_mut().zip(prev) {
                    axis.prime(y);
                }
            }
            for sums in det.replay(ds, blocks) {
                for (axis, b) in self.axes.iter_mut().zip(&sums) {
                    axis.integrate_block(s, b);
                }
            }
        }
    }

    /// A button changed state: with drift control, a motion younger than the hold is
    /// discarded (the click's jolt began before its debounced edge was known), and
    /// integration pauses for the click-freeze time, restarting from zero velocity.
    pub fn button_edge(&mut self) {
        let (Some(ds), Stage::Tracking(Some(det))) = (self.settings.drift(), &mut self.stage)
        else {
            return;
        };
        let action = det.click(ds);
        self.apply(action);
    }

    /// Reports `lost` sample triples that the hardware dropped (ADC or DMA overrun). While
    /// tracking they are held: the last codes go through the same path again, so the
    /// integrator's clock stays the hardware's. While calibrating they only count.
    pub fn lost(&mut self, lost: u32) {
        self.counters.lost += u64::from(lost);
        if self.phase() == Phase::Tracking {
            let last = self.axes.each_ref().map(|a| a.last_code().0);
            self.track_run(&[last], lost);
        }
    }

    /// Reports that the sampling died and was restarted, `lost` sample triples after the
    /// last good block. Unlike [`Self::lost`] nothing is held: the acceleration of the gap
    /// is unknown (holding the last codes through a long gap mid-stroke would integrate a
    /// stale acceleration for all of it), so the motion in progress stops at zero velocity
    /// and drift control starts again from rest. What was integrated before the gap stays.
    pub fn restarted(&mut self, lost: u32) {
        self.counters.lost += u64::from(lost);
        if let Stage::Tracking(detector) = &mut self.stage {
            self.axes.iter_mut().for_each(Axis::zero_velocity);
            if let Some(det) = detector {
                det.restart();
            }
        }
    }

    /// Whether drift control currently holds the device still (`false` without drift
    /// control or while calibrating).
    pub fn is_still(&self) -> bool {
        self.drift_state() == Some(State::Still)
    }

    /// Drift control's state while tracking (`None` without drift control or while
    /// calibrating).
    pub fn drift_state(&self) -> Option<State> {
        self.detector().map(Detector::state)
    }

    /// Whether drift control holds a motion back from delivery (younger than its hold, or
    /// held by the tilt tests); `false` without drift control or while calibrating.
    pub fn is_holding(&self) -> bool {
        self.detector().is_some_and(Detector::holds)
    }

    /// Drains the motion since the last call as whole mouse counts `[x, y, z]`, remainders
    /// carried. Zeros while calibrating, and while drift control holds a new motion back
    /// (younger than its hold, or held by the tilt tests) or pauses a calm one whose velocity
    /// points back against its travel ([`Detector::pauses`]); the counts follow once it is
    /// released, or with the stop's correction. `x` and `y` are the sensor's axes (positive `y` away from the user);
    /// [`crate::profile::AxisMap::screen`] and [`crate::hid::screen_motion`] turn them into
    /// screen motion. `z` is the vertical axis's travel, not a mouse axis: a pointer drops it,
    /// as the firmware does.
    pub fn take_counts(&mut self) -> [i32; AXES] {
        let velocity = || self.axes.each_ref().map(|a| a.integrator().velocity());
        if self.detector().is_some_and(|d| d.pauses(velocity)) {
            return [0; AXES];
        }
        let settings = &self.settings;
        // At rest nothing was integrated: an idle axis is not read out (the same 0).
        self.axes.each_mut().map(|axis| {
            if axis.is_idle() {
                0
            } else {
                axis.take_counts(settings)
            }
        })
    }

    /// The current phase.
    pub const fn phase(&self) -> Phase {
        match self.stage {
            Stage::Calibrating(_) => Phase::Calibrating,
            Stage::Tracking(_) => Phase::Tracking,
        }
    }

    /// Drift control's detector while tracking with drift control.
    const fn detector(&self) -> Option<&Detector> {
        match &self.stage {
            Stage::Tracking(Some(d)) => Some(d),
            _ => None,
        }
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
