//! Drift control: when the device rests, nothing moves; when the hand moves, the motion
//! arrives whole, however slow; a tilt, a lift or a knock does not move the cursor.
//!
//! The paper proves that pure double integration drifts without bound. A mouse stays put by
//! not integrating while it rests, and by deciding "rest" with statistics sized to the
//! sensor's own noise, measured at calibration (REFERENCE (i)).
//!
//! # Ticks and the noise model
//! The detector works on ticks of `D = ceil(fs * 5 ms)` samples (at least 1): per tick and
//! axis it keeps the sum of the raw codes `s` and the [`BlockSums`] of the filtered samples
//! (so a motion's onset can be integrated after the fact, exactly). Its statistics come from
//! the calibration ([`Calibration`]): `q`, the long-run variance per sample (a sum of `n`
//! samples at rest has variance `q n`), and `g0`, the variance of one tick's sum per sample.
//! The calibration's `q` comes from one second and is uncertain by 20 %: the detector
//! starts from its upper 2-sd bound and learns `q` at rest (`learn_noise`), block by block.
//! Tick decisions cost a few hundred operations every 5 ms, at any rate from 100 Hz to
//! 100 kHz; a sample costs one add per axis and sum.
//!
//! # States
//! ```text
//!        CUSUM alarm on X or Y (replay from its onset)
//! Still ---------------------------------------------> Moving
//!   ^  <-- quiet and velocity explained by noise -------- |
//!   |  <-- steady offset for rest_s: a tilt, new bias --- |
//!   |                                                     |
//!   +-- steady for rest_s (new bias if it differs) -- Lifted <-- Z offset (any state)
//!   +-- click freeze over ---------------------------- Frozen <-- button edge (any state)
//! ```
//! - **Start** (Still): two-sided CUSUMs per horizontal axis on the tick means' offset from
//!   the bias, in units of their long-run sd `sqrt(q / D)`: `S = max(0, S + z - kappa)`,
//!   a slow one (`kappa = 1/2`, alarm at `S > h = start_sigmas`) and a fast one
//!   (`kappa = 3/2`, alarm at `h / 2`) that a brisk stroke's ramp crosses 3 ms sooner. It sees a slow stroke's small acceleration by accumulating it
//!   (a 15 mm stroke over 1 s is found about 55 ms in), and it knows where the run began:
//!   the ticks since `S` was last zero are integrated from zero velocity at once, so the
//!   stroke's onset is not lost. Within a tick the alarm is checked on the samples so far
//!   (`kappa` pro rata): a brisk stroke starts without waiting for the tick's end. At rest the expected time to a false alarm is about
//!   `e^(2 kappa (h + 1.17)) / (2 kappa^2)` ticks (Siegmund): 2e7 ticks (28 h) per side for
//!   the slow one at `h = 16`, 2e11 for the fast one.
//! - **Hold**: a motion younger than `hold_s` (from its onset) is integrated but not yet
//!   delivered; a button edge inside it discards it. A click's jolt starts before its
//!   debounced edge is known, and this is what keeps it from dragging the cursor. A jolt is
//!   a step (one tick crosses the alarm alone), so its hold runs from the alarm: an onset
//!   that noise placed earlier must not shorten it. A hand's stroke ramps up and is
//!   delivered from `hold_s` after its onset, which its detection usually passes already.
//! - **Stop** (Moving): the last `quiet_s` of X and Y have a mean within `quiet_sigmas` of
//!   the bias, and the velocity is explained: within `velocity_sigmas` of its own
//!   uncertainty `sd(V)^2 = q n + q n^2 / N_b` (`n` samples since the onset, the bias
//!   averaged over `N_b` samples), or below `stop_fraction` of the motion's peak. Mid-stroke
//!   the acceleration passes through zero while the hand moves fastest; the velocity test
//!   keeps the stroke going there. A velocity that no acceleration explains is stopped
//!   after `coast_s` of quiet over both `quiet_s` and `rest_s` (an accelerometer cannot see
//!   constant velocity; the longer window sees a slow stroke's small acceleration).
//! - **Tilt** (Moving): the last `rest_s` are steady on every axis (the tick sums' scatter
//!   at most `rest_factor` times the calibrated `g0`, no linear trend) but off the bias: the
//!   motion is held (the cursor stops) and the window's means remembered. Steady at those
//!   means for `tilt_s` more, it is a tilt (a hand cannot keep accelerating one way that
//!   long): the held motion is dropped and the means become the biases. If the
//!   acceleration changes first (after the first `rest_s`, in which a tilt may still
//!   settle), it was the broad peak of a slow stroke: what was held is delivered.
//! - **Lift** (any state but Frozen): a tick's Z offset above `lift_m_s2` plus
//!   `lift_xy_ratio` times the horizontal offsets (the mounting tilt and cross-axis
//!   sensitivity put a fraction of a horizontal stroke on Z). Nothing is integrated until
//!   the device has been steady for `rest_s`; then the biases become the window's means if
//!   any differs from the old bias by more than the two estimates' noise allows (a new
//!   tilt), and stay otherwise (a knock). Optical mice stop tracking when lifted, too.
//! - **Bias tracking** (Still): the tick `REPLAY` ticks old (older than any onset a CUSUM
//!   alarm could still claim) is averaged into the bias with weight `D / min(N_b, bias_tau_s * fs)`: a running mean
//!   after a re-zero, an exponential with time constant `bias_tau_s` later.
//! - **Click freeze**: for `click_freeze_s` after a button edge nothing is integrated; then
//!   Still, from zero velocity.

use core::fmt;

use crate::calibration::Calibration;
use crate::integrator::BlockSums;

/// Shortest detector tick [s]; a tick is `ceil(fs * TICK_S)` samples, so that the windows
/// counted in ticks (the rest window up to [`RING`] ticks) hold at every rate; at rates where
/// `fs * TICK_S` is not whole a tick is longer than 5 ms (8.3 ms at 240 Hz).
pub const TICK_S: f64 = 0.005;
/// Ticks of raw-code sums kept (320 ms at 5 ms ticks): the longest `quiet_s` and `rest_s`.
pub const RING: usize = 64;
/// Ticks of filtered sums kept for replaying a motion's onset (320 ms at 5 ms ticks; a
/// motion replays at most `REPLAY - 1` of them, the oldest primes the trapezoid). A slow
/// stroke's CUSUM alarm comes up to 0.3 s after its onset; with 200 ms, 2.5 % more of the
/// strokes of target 1 missed (93.0 % against 90.5 % within).
pub const REPLAY: usize = 64;

/// One axis's filtered sums over one tick, compact ([`BlockSums`] without the tick's
/// length and first sample, which the replay does not need).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct TickSums {
    sum: i64,
    sum_of_prefixes: i64,
    last: i64,
}
/// The CUSUMs' reference values `kappa` [sd of a tick mean], Q8: 1/2 for the slow one (the
/// quickest for offsets near one sd: slow strokes), 3/2 for the fast one (offsets near 3
/// sd: brisk strokes), whose alarm is half the slow one's.
const KAPPA_Q8: [i64; 2] = [128, 384];

/// Samples per detector tick at `fs_hz`: `ceil(fs_hz * 5 / 1000)` ([`TICK_S`], computed in
/// integers so that whole products stay whole), `1..=2^14`.
pub fn tick_samples(fs_hz: u32) -> u32 {
    let ms = (TICK_S * 1000.0) as u64; // 5
    (((u64::from(fs_hz) * ms).div_ceil(1000)) as u32).clamp(1, 1 << 14)
}

/// Drift control settings in physical units (seconds, m/s^2) and multiples of the noise
/// measured at calibration (sd).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drift {
    /// CUSUM alarm threshold [sd of a tick mean], `1..=1000`.
    pub start_sigmas: f64,
    /// Motion younger than this is not delivered and a button edge discards it [s],
    /// `0..=0.1`. Cover the button's debounce and polling delay.
    pub hold_s: f64,
    /// Window of the stop test [s]; `1..=64` ticks.
    pub quiet_s: f64,
    /// The stop test's bound on the window mean's offset [sd of that mean], `0 < k <= 1000`.
    pub quiet_sigmas: f64,
    /// A velocity within this many of its sd counts as zero [sd], `0..=1000` (0: off).
    pub velocity_sigmas: f64,
    /// A velocity below this fraction of the motion's peak counts as zero, `0..=1` (0: off).
    pub stop_fraction: f64,
    /// Quiet this long stops any motion [s], `quiet_s..=60`.
    pub coast_s: f64,
    /// Window of the steadiness test (tilt, landing) [s]; `4..=64` ticks.
    pub rest_s: f64,
    /// Steady: the tick sums' scatter at most this multiple of the calibrated one, `1..=1000`.
    pub rest_factor: f64,
    /// A motion steady at the same offset this long after `rest_s` is a tilt [s],
    /// `rest_s..=10`. The cursor stops after `rest_s`; the new zero is taken after this.
    pub tilt_s: f64,
    /// A Z offset that means "lifted" [m/s^2], `> 0` and finite, or `None` for no lift
    /// detection (a two-axis sensor).
    pub lift_m_s2: Option<f64>,
    /// Added to the lift threshold per unit of horizontal offset, `0..=10`.
    pub lift_xy_ratio: f64,
    /// Time constant of the bias tracking at rest [s], `rest_s..1e6`; `None` disables it.
    pub bias_tau_s: Option<f64>,
    /// Motion suppressed after a button edge [s], `0..=2`.
    pub click_freeze_s: f64,
}

impl Default for Drift {
    /// The defaults, each with its reason:
    /// - `start_sigmas` 16: a false start less than once in 28 h per axis and side at rest;
    /// - `hold_s` 16 ms: a button edge 10 ms after the finger (the firmware's 5 ms debounce
    ///   counted in 2 ms housekeeping periods, until issue 11 fixes them to 1 ms), plus the
    ///   5 ms tick within which the onset of a click's jolt is placed;
    /// - `quiet_s` 20 ms, `quiet_sigmas` 3: stops within about 20 ms of a stroke's end;
    /// - `velocity_sigmas` 3, `stop_fraction` 1/4: a min-jerk stroke's velocity is above
    ///   1/4 of its peak until the last 13 % of it, where its deceleration is still large;
    /// - `coast_s` 0.5 s: longer than the quiet middle of any stroke above the noise floor;
    /// - `rest_s` 0.3 s, `rest_factor` 2: a stroke's acceleration changes measurably within
    ///   0.3 s; 2 is 4 sd of the scatter's own noise over 60 ticks;
    /// - `tilt_s` 1 s: a minimum-jerk stroke of 2 s holds its acceleration within 15 % of
    ///   its peak for 0.44 s, and changes it by the whole peak within 0.6 s;
    /// - `lift_m_s2` 0.3 m/s^2, `lift_xy_ratio` 1/4: a 1 cm lift in 0.3 s peaks at
    ///   0.64 m/s^2; a quarter of a horizontal stroke's acceleration on Z is a 14 degree
    ///   mounting tilt;
    /// - `bias_tau_s` 2 s: the tracked bias lags a temperature ramp by `rate * (tau + 0.2 s)`,
    ///   which must stay well below the CUSUM's `kappa` (half a tick's sd) for the start test
    ///   to keep its false-alarm rate; its own noise, `sqrt(q / (2 tau fs))`, is 0.05 LSB for
    ///   an ADXL335 (0.6 mm over a 1 s stroke); `click_freeze_s` 0.15 s: the jolt of a click.
    fn default() -> Self {
        Self {
            start_sigmas: 16.0,
            hold_s: 0.016,
            quiet_s: 0.02,
            quiet_sigmas: 3.0,
            velocity_sigmas: 2.0,
            stop_fraction: 0.25,
            coast_s: 0.5,
            rest_s: 0.3,
            rest_factor: 2.0,
            tilt_s: 1.0,
            lift_m_s2: Some(0.3),
            lift_xy_ratio: 0.25,
            bias_tau_s: Some(2.0),
            click_freeze_s: 0.15,
        }
    }
}

/// A [`Drift`] field that failed validation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DriftError {
    /// `start_sigmas` not finite or outside `1..=1000`.
    StartSigmas,
    /// `hold_s` outside `0..=0.1`.
    Hold,
    /// `quiet_s` not `1..=64` ticks.
    QuietWindow,
    /// `quiet_sigmas` not in `(0, 1000]`.
    QuietSigmas,
    /// `velocity_sigmas` outside `0..=1000`.
    VelocitySigmas,
    /// `stop_fraction` outside `0..=1`.
    StopFraction,
    /// `coast_s` below `quiet_s` or above 60 s.
    Coast,
    /// `rest_s` not `4..=64` ticks.
    RestWindow,
    /// `rest_factor` outside `1..=1000`.
    RestFactor,
    /// `tilt_s` outside `rest_s..=10`.
    Tilt,
    /// `lift_m_s2` not finite and `> 0` (or above 2^15 LSB).
    Lift,
    /// `lift_xy_ratio` outside `0..=10`.
    LiftRatio,
    /// `bias_tau_s` below `rest_s` or not below 1e6 s.
    BiasTau,
    /// `click_freeze_s` outside `0..=2`.
    ClickFreeze,
}

impl fmt::Display for DriftError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::StartSigmas => "drift.start_sigmas: must be within 1..=1000",
            Self::Hold => "drift.hold_s: must be within 0..=0.1 s",
            Self::QuietWindow => "drift.quiet_s: the stop window must hold 1..=64 ticks of 5 ms",
            Self::QuietSigmas => "drift.quiet_sigmas: must be > 0 and <= 1000",
            Self::VelocitySigmas => "drift.velocity_sigmas: must be within 0..=1000",
            Self::StopFraction => "drift.stop_fraction: must be within 0..=1",
            Self::Coast => "drift.coast_s: must be within quiet_s..=60 s",
            Self::RestWindow => "drift.rest_s: the rest window must hold 4..=64 ticks of 5 ms",
            Self::RestFactor => "drift.rest_factor: must be within 1..=1000",
            Self::Tilt => "drift.tilt_s: must be within rest_s..=10 s",
            Self::Lift => "drift.lift_m_s2: must be finite, > 0 and below 2^15 ADC LSB",
            Self::LiftRatio => "drift.lift_xy_ratio: must be within 0..=10",
            Self::BiasTau => "drift.bias_tau_s: must be finite, at least rest_s and below 1e6 s",
            Self::ClickFreeze => "drift.click_freeze_s: must be within 0..=2 s",
        })
    }
}

/// Validated drift-control coefficients (integers; factors in Q8).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DriftSettings {
    tick: u32,
    start_q8: i64,
    hold: u64,
    quiet_ticks: u32,
    quiet_k2_q8: u64,
    velocity_k2_q8: u64,
    stop_fraction_q8: u64,
    coast_ticks: u32,
    rest_ticks: u32,
    rest_factor_q8: u64,
    tilt_ticks: u32,
    lift_q16: Option<i64>,
    lift_ratio_q8: i64,
    bias_samples_max: Option<u64>,
    freeze: u32,
}

impl Drift {
    /// Validates for sampling rate `fs_hz` and a scale of `m_s2_per_lsb` (both already
    /// validated by [`crate::Config::validate`]).
    ///
    /// # Errors
    /// The first invalid field.
    pub fn validate(&self, fs_hz: u32, m_s2_per_lsb: f64) -> Result<DriftSettings, DriftError> {
        use crate::math::round_to_u64 as round;
        let fs = f64::from(fs_hz);
        let tick = tick_samples(fs_hz);
        let tick_s = f64::from(tick) / fs;
        let within = |v: f64, lo: f64, hi: f64| v.is_finite() && v >= lo && v <= hi;
        let ticks = |s: f64, lo: u32, e: DriftError| -> Result<u32, DriftError> {
            let t = s / tick_s;
            if within(t, f64::from(lo) - 0.5, RING as f64 + 0.499) {
                Ok(round(t) as u32)
            } else {
                Err(e)
            }
        };
        let q8 = |v: f64| round(v * 256.0);
        if !within(self.start_sigmas, 1.0, 1e3) {
            return Err(DriftError::StartSigmas);
        }
        if !within(self.hold_s, 0.0, 0.1) {
            return Err(DriftError::Hold);
        }
        let quiet_ticks = ticks(self.quiet_s, 1, DriftError::QuietWindow)?;
        if !(within(self.quiet_sigmas, 0.0, 1e3) && self.quiet_sigmas > 0.0) {
            return Err(DriftError::QuietSigmas);
        }
        if !within(self.velocity_sigmas, 0.0, 1e3) {
            return Err(DriftError::VelocitySigmas);
        }
        if !within(self.stop_fraction, 0.0, 1.0) {
            return Err(DriftError::StopFraction);
        }
        if !within(self.coast_s, self.quiet_s, 60.0) {
            return Err(DriftError::Coast);
        }
        let rest_ticks = ticks(self.rest_s, 4, DriftError::RestWindow)?;
        if !within(self.rest_factor, 1.0, 1e3) {
            return Err(DriftError::RestFactor);
        }
        if !within(self.tilt_s, self.rest_s, 10.0) {
            return Err(DriftError::Tilt);
        }
        let lift_q16 = match self.lift_m_s2 {
            None => None,
            Some(l) if within(l / m_s2_per_lsb, 1e-6, 32_768.0) => {
                Some(round(l / m_s2_per_lsb * 65_536.0) as i64)
            }
            Some(_) => return Err(DriftError::Lift),
        };
        if !within(self.lift_xy_ratio, 0.0, 10.0) {
            return Err(DriftError::LiftRatio);
        }
        let bias_samples_max = match self.bias_tau_s {
            None => None,
            Some(tau) if within(tau, self.rest_s, 1e6) && tau < 1e6 => Some(round(tau * fs).max(1)),
            Some(_) => return Err(DriftError::BiasTau),
        };
        if !within(self.click_freeze_s, 0.0, 2.0) {
            return Err(DriftError::ClickFreeze);
        }
        Ok(DriftSettings {
            tick,
            start_q8: q8(self.start_sigmas) as i64,
            hold: round(self.hold_s * fs),
            quiet_ticks,
            quiet_k2_q8: q8(self.quiet_sigmas * self.quiet_sigmas),
            velocity_k2_q8: q8(self.velocity_sigmas * self.velocity_sigmas),
            stop_fraction_q8: q8(self.stop_fraction),
            coast_ticks: round(self.coast_s / tick_s).max(1) as u32,
            rest_ticks,
            rest_factor_q8: q8(self.rest_factor),
            tilt_ticks: round(self.tilt_s / tick_s).max(1) as u32,
            lift_q16,
            lift_ratio_q8: q8(self.lift_xy_ratio) as i64,
            bias_samples_max,
            freeze: round(self.click_freeze_s * fs) as u32,
        })
    }
}

impl DriftSettings {
    /// Samples per detector tick.
    pub const fn tick_samples(&self) -> u32 {
        self.tick
    }
    /// Click freeze [samples].
    pub const fn freeze_samples(&self) -> u32 {
        self.freeze
    }
    /// Hold of a new motion [samples].
    pub const fn hold_samples(&self) -> u64 {
        self.hold
    }
}

/// What drift control is doing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum State {
    /// At rest: nothing is integrated; the bias follows slow drift.
    Still,
    /// A motion: every sample is integrated.
    Moving,
    /// Lifted (or knocked): nothing is integrated until the device is steady again.
    Lifted,
    /// After a button edge: nothing is integrated for the click freeze.
    Frozen,
}

/// What the tracker must do to its axes after a sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    /// Nothing.
    None,
    /// A motion started: integrate the last `ticks` complete ticks and the current tick's
    /// samples so far ([`Detector::replay`]) from zero velocity, then every sample.
    Start {
        /// Complete ticks to replay, `0..=REPLAY`.
        ticks: usize,
    },
    /// The motion ended: zero velocity; what was integrated stays.
    Stop,
    /// The motion was held and must not be delivered: zero velocity and position.
    Discard,
    /// New biases (Q16 counts) after a tilt or a landing; zero velocity, and with
    /// `discard` the held motion (the tilt's runaway) is dropped too.
    Rebias {
        /// The biases [Q16 counts].
        bias: [i64; 3],
        /// Drop the position not yet delivered.
        discard: bool,
    },
    /// New biases (Q16 counts) from tracking at rest; nothing else changes.
    TrackBias([i64; 3]),
}

/// Per-axis noise thresholds from the calibration, in the detector's integer units.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Noise {
    /// Long-run variance per sample `q` [LSB^2, Q32].
    q_q32: u64,
    /// Tick-sum variance per sample `g0` [LSB^2, Q32].
    g0_q32: u64,
    /// `kappa sqrt(q D)` and `h sqrt(q D)` of the slow and the fast CUSUM: their drifts and
    /// alarms [Q16 LSB samples].
    kappa: [i64; 2],
    alarm: [i64; 2],
}

impl Noise {
    fn new(s: &DriftSettings, q_q32: u64, g0_q32: u64) -> Self {
        // sqrt(q D) in Q16: the square root of a Q32 value.
        let sd = crate::math::isqrt_u128(u128::from(q_q32) * u128::from(s.tick)) as i64;
        Self {
            q_q32,
            g0_q32,
            kappa: KAPPA_Q8.map(|k| (k * sd) >> 8),
            alarm: [
                ((i128::from(s.start_q8) * i128::from(sd)) >> 8) as i64,
                ((i128::from(s.start_q8) * i128::from(sd)) >> 9) as i64,
            ],
        }
    }
}

/// Widening of the steadiness tests (Q8 factors on the scatter bound and on the squared
/// sd multiple).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Slack {
    scatter_q8: u128,
    k2_q8: u128,
}

impl Slack {
    /// Finding a tilt: the tests as configured.
    const FIND: Self = Self {
        scatter_q8: 256,
        k2_q8: 256,
    };
    /// Keeping a suspected tilt for `tilt_s` (200 ticks, 3 axes, 3 tests each): the scatter
    /// bound 1.5x and the sd multiples 5/3x (3 sd -> 5 sd: 6e-7 per test, under 0.1 % for
    /// the family), so that noise alone does not refute a real tilt.
    const KEEP: Self = Self {
        scatter_q8: 384,
        k2_q8: 711, // (5/3)^2 * 256
    };
    /// A settled tilt's offset moving on (7 sd): a window 0.3 s after another is not
    /// independent of the anchor's re-anchoring history, and a release drops the whole held
    /// runaway on the cursor at once; a slow stroke's acceleration moves by its peak.
    const MOVED: Self = Self {
        scatter_q8: 384,
        k2_q8: 1394, // (7/3)^2 * 256
    };
}

/// Ticks per block of the noise learnt at rest (80 ms at 5 ms ticks: a 50 Hz pole's
/// correlation is gone, so a block sum's variance is `q` times its length within 4 %).
const LEARN_TICKS: u32 = 16;
/// Blocks in the learnt noise's exponential average (about 10 s of rest; relative sd of the
/// estimate `sqrt(2 / (2 * 128))`, 9 %).
const LEARN_BLOCKS: u64 = 128;

/// The code sums of the last few ticks on each axis ([`Detector::window`]).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Window {
    sums: [u64; 3],
    /// Samples summed, `k D`.
    samples: i64,
}

impl Window {
    /// Offset of the sum on `axis` from the bias [Q16 LSB samples]. At most 64 ticks of
    /// `2^14` samples of 16-bit codes: the sum is below `2^36`, shifted `2^52`, and
    /// `k D bias < 2^52`: `i64`.
    fn offset(&self, axis: usize, bias: i64) -> i64 {
        ((self.sums[axis] as i64) << 16) - self.samples * bias
    }

    /// Samples summed.
    fn n(&self) -> u64 {
        self.samples as u64
    }

    /// The window's means as biases (Q16 counts, rounded).
    fn means(&self, bias: [i64; 3]) -> [i64; 3] {
        let mut out = bias;
        for (a, b) in out.iter_mut().enumerate() {
            *b += crate::math::div_round(self.offset(a, *b), self.samples);
        }
        out
    }
}

/// Drift-control state of a three-axis device; see the module docs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Detector {
    codes: [[u32; 3]; RING],
    sums: [[TickSums; 3]; REPLAY],
    cur_codes: [u32; 3],
    cur_sums: [BlockSums; 3],
    cur_n: u32,
    ticks: u64,
    state: State,
    entered: u64,
    /// `[slow, fast][axis X, Y][side +, -]`.
    cusum: [[[i64; 2]; 2]; 2],
    /// Per horizontal axis, the least headroom of its four CUSUMs below their alarms,
    /// `min (alarm[c] - cusum[c][a][side])` [Q16 LSB samples]: a tick so far whose offset
    /// is no larger in magnitude cannot alarm (the pro-rata drift only lowers a CUSUM), so
    /// at rest a sample is tested against it and nothing else
    /// ([`Self::within_headroom`]). Kept by [`Self::refresh_headroom`] wherever a CUSUM or
    /// an alarm changes.
    headroom: [i64; 2],
    onset: [[[u64; 2]; 2]; 2],
    quiet_run: u32,
    /// The tick from which a motion has looked like a tilt (steady, off the bias).
    suspect: Option<(u64, [i64; 3])>,
    motion_samples: u64,
    /// Samples the new motion is still held for.
    hold_left: u64,
    peak_w: [u64; 2],
    freeze_left: u32,
    bias_samples: u64,
    noise: [Noise; 3],
    learn_sum: [u64; 3],
    learn_ticks: u32,
}

/// `a * b`, saturating, for threshold products.
fn mul(a: u128, b: u128) -> u128 {
    a.saturating_mul(b)
}

impl Detector {
    /// A detector starting Still after a calibration of `cal` (the device has just been
    /// seen at rest).
    pub fn new(s: &DriftSettings, cal: &[Calibration; 3]) -> Self {
        let ticks = u64::from(cal[0].samples / s.tick).max(1);
        let noise = cal.map(|c| {
            // The calibration's q comes from k ticks, about k / 4 independent ones at the
            // ADXL335's correlation: its relative sd is sqrt(8 / k) (20 % for 1 s). Start
            // from the upper 2-sd bound; rest refines it (`learn_noise`).
            let q = u128::from(c.long_run_var_q32);
            let inflate_q8 = 256 + crate::math::isqrt_u128(8 * 4 * 65_536 / u128::from(ticks));
            let q = ((q * inflate_q8) >> 8).min(u128::from(u64::MAX)) as u64;
            Noise::new(s, q, c.tick_var_q32)
        });
        let mut d = Self {
            codes: [[0; 3]; RING],
            sums: [[TickSums::default(); 3]; REPLAY],
            cur_codes: [0; 3],
            cur_sums: [BlockSums::default(); 3],
            cur_n: 0,
            ticks: 0,
            state: State::Still,
            entered: 0,
            cusum: [[[0; 2]; 2]; 2],
            headroom: [0; 2],
            onset: [[[0; 2]; 2]; 2],
            quiet_run: 0,
            suspect: None,
            motion_samples: 0,
            hold_left: 0,
            peak_w: [0; 2],
            freeze_left: 0,
            bias_samples: u64::from(cal[0].samples),
            noise,
            learn_sum: [0; 3],
            learn_ticks: 0,
        };
        d.refresh_headroom();
        d
    }

    /// The current state.
    pub const fn state(&self) -> State {
        self.state
    }

    /// Whether a motion is held back from delivery: younger than `hold_s`, or looking like
    /// a tilt (steady and off the bias for `rest_s`) and not yet confirmed or refuted.
    pub const fn holds(&self) -> bool {
        matches!(self.state, State::Moving) && (self.hold_left > 0 || self.suspect.is_some())
    }

    /// The filtered sums of the last `ticks` complete ticks (`< REPLAY`), oldest first,
    /// then those of the current tick so far (if it has samples).
    pub fn replay(
        &self,
        s: &DriftSettings,
        ticks: usize,
    ) -> impl Iterator<Item = [BlockSums; 3]> + '_ {
        let first = self.ticks - ticks.min(REPLAY - 1) as u64;
        let n = s.tick;
        (first..self.ticks)
            .map(move |i| {
                self.sums[(i % REPLAY as u64) as usize].map(|t| BlockSums {
                    n,
                    sum: t.sum,
                    sum_of_prefixes: t.sum_of_prefixes,
                    first: 0,
                    last: t.last,
                })
            })
            .chain((self.cur_n > 0).then_some(self.cur_sums))
    }

    /// The last filtered sample of the tick before the last `ticks` complete ones (Q16
    /// counts), to prime a trapezoid replay; `None` if there is no such tick.
    pub fn replay_prev(&self, ticks: usize) -> Option<[i64; 3]> {
        let i = self.ticks.checked_sub(ticks as u64 + 1)?;
        // The ring holds the last REPLAY ticks: a replay of at most REPLAY - 1 (the cap in
        // `start`) leaves its predecessor in it.
        (ticks < REPLAY).then(|| self.sums[(i % REPLAY as u64) as usize].map(|t| t.last))
    }

    /// The sample stream was interrupted (a sampling restart): whatever was moving is
    /// over, and the detector waits at rest for the next start.
    pub fn restart(&mut self) {
        self.enter_still();
    }

    /// A button changed state: the held motion (if any) is discarded, a delivered one
    /// stops, and nothing is integrated for the click freeze.
    pub fn click(&mut self, s: &DriftSettings) -> Action {
        let action = match self.state {
            State::Moving if self.holds() => Action::Discard,
            State::Moving => Action::Stop,
            _ => Action::None,
        };
        if s.freeze > 0 {
            self.state = State::Frozen;
            self.freeze_left = s.freeze;
        } else if self.state == State::Moving {
            self.enter_still();
        }
        action
    }

    /// Adds one sample: its raw `codes`, its filtered values `y` (Q16 counts), the axes'
    /// biases (Q16 counts) and velocities (`W = 2 V`, [`crate::IntegratorState::velocity`])
    /// after it was integrated (if it was). Returns what the tracker must do.
    pub fn push(
        &mut self,
        s: &DriftSettings,
        codes: [u16; 3],
        y: [i64; 3],
        bias: [i64; 3],
        velocity: [i64; 3],
    ) -> Action {
        for a in 0..3 {
            self.cur_codes[a] += u32::from(codes[a]);
            self.cur_sums[a].push(y[a]);
        }
        self.cur_n += 1;
        match self.state {
            State::Moving => {
                self.motion_samples += 1;
                self.hold_left = self.hold_left.saturating_sub(1);
            }
            State::Frozen => {
                // The click stopped the motion and nothing was integrated since.
                self.freeze_left = self.freeze_left.saturating_sub(1);
                if self.freeze_left == 0 {
                    self.enter_still();
                }
            }
            State::Still | State::Lifted => {}
        }
        if self.cur_n < s.tick {
            if self.state == State::Still && !self.within_headroom(bias) {
                return self.early_alarm(s, bias);
            }
            return Action::None;
        }
        let slot = (self.ticks % RING as u64) as usize;
        self.codes[slot] = core::mem::take(&mut self.cur_codes);
        self.sums[(self.ticks % REPLAY as u64) as usize] =
            core::mem::take(&mut self.cur_sums).map(|b| TickSums {
                sum: b.sum,
                sum_of_prefixes: b.sum_of_prefixes,
                last: b.last,
            });
        self.cur_n = 0;
        self.ticks += 1;
        let action = self.tick(s, bias, velocity);
        self.refresh_headroom();
        action
    }

    /// Recomputes [`Self::headroom`] from the CUSUMs and their alarms: after every tick
    /// (which moves the CUSUMs and may learn a new noise) and whenever the detector enters
    /// Still (which clears them).
    fn refresh_headroom(&mut self) {
        for (a, room) in self.headroom.iter_mut().enumerate() {
            *room = (0..2)
                .flat_map(|c| self.cusum[c][a].map(|sum| self.noise[a].alarm[c] - sum))
                .min()
                .unwrap_or(0);
        }
    }

    fn enter_still(&mut self) {
        self.state = State::Still;
        self.learn_sum = [0; 3];
        self.learn_ticks = 0;
        self.suspect = None;
        self.entered = self.ticks;
        self.cusum = [[[0; 2]; 2]; 2];
        self.onset = [[[self.ticks; 2]; 2]; 2];
        self.refresh_headroom();
    }

    /// The code sums of the last `k` ticks, one pass over the ring for all three axes.
    #[inline(never)]
    fn window(&self, s: &DriftSettings, k: u32) -> Window {
        let mut sums = [0u64; 3];
        for i in 0..u64::from(k) {
            let t = &self.codes[(self.ticks.wrapping_sub(1 + i) % RING as u64) as usize];
            for (sum, &c) in sums.iter_mut().zip(t) {
                *sum += u64::from(c);
            }
        }
        Window {
            sums,
            samples: i64::from(k) * i64::from(s.tick),
        }
    }

    /// Whether an offset `d` (Q16) of a sum over `n` samples is within `k2_q8` (a squared
    /// multiple, Q8) of its sd, counting the bias's own uncertainty (`N_b` samples).
    #[inline(never)]
    fn explained(&self, axis: usize, d: i64, n: u64, k2_q8: u64) -> bool {
        self.explained_against(axis, d, n, k2_q8, self.bias_samples)
    }

    /// [`Self::explained`] against a reference averaged over `nb` samples.
    #[inline(never)]
    fn explained_against(&self, axis: usize, d: i64, n: u64, k2_q8: u64, nb: u64) -> bool {
        // n^2 / N_b without a 128-bit division (a software routine on the device).
        let var = mul(
            u128::from(self.noise[axis].q_q32),
            u128::from(n) + crate::math::square_over(n, nb.max(1)),
        );
        let d = u128::from(d.unsigned_abs());
        d * d <= mul(var, u128::from(k2_q8)) >> 8
    }

    /// Whether the last `k` ticks are steady on every axis: the tick sums' scatter
    /// `k sum s^2 - (sum s)^2` at most `rest_factor k (k - 1) D g0` (no jolt, no wobble),
    /// and their trend `b = sum x s` with `x = 2 i - (k - 1)` within `quiet_sigmas` of its
    /// sd `sqrt(q D k (k^2 - 1) / 3)` (no ramp: a stroke's acceleration rises and falls
    /// smoothly, which the scatter alone sees only when it is large).
    #[inline(never)]
    fn steady(&self, s: &DriftSettings, k: u32, slack: Slack) -> bool {
        (0..3).all(|a| {
            // k <= 64 ticks of sums below 2^25: every sum below fits u64 / i64.
            let (mut sum, mut sum_sq, mut trend) = (0u64, 0u64, 0i64);
            for i in 0..u64::from(k) {
                let v = self.codes[(self.ticks.wrapping_sub(1 + i) % RING as u64) as usize][a];
                let v = u64::from(v);
                sum += v;
                sum_sq += v * v;
                // Newest first: x runs from k - 1 down to -(k - 1).
                trend += (i64::from(k) - 1 - 2 * i as i64) * v as i64;
            }
            let kk = u64::from(k);
            let scatter = u128::from(kk * sum_sq - sum * sum); // < 2^6 * 2^56
            let noise = self.noise[a];
            let kk = u128::from(kk);
            let bound = mul(
                mul(
                    (u128::from(s.rest_factor_q8) * slack.scatter_q8) >> 8,
                    kk * (kk - 1) * u128::from(s.tick),
                ),
                u128::from(noise.g0_q32),
            );
            // |trend| < 2^6 * 2^6 * 2^25: its square below 2^74, shifted 2^106.
            let t = u128::from(trend.unsigned_abs());
            let t_bound = mul(
                mul(
                    (u128::from(s.quiet_k2_q8) * slack.k2_q8) >> 8,
                    u128::from(noise.q_q32),
                ),
                u128::from(s.tick) * kk * (kk * kk - 1) / 3,
            ) >> 8;
            scatter << 40 <= bound && (t * t) << 32 <= t_bound
        })
    }

    #[inline(never)]
    fn lifted(&self, s: &DriftSettings, bias: [i64; 3]) -> bool {
        let Some(lift) = s.lift_q16 else {
            return false;
        };
        let w = self.window(s, 1);
        let off = |a: usize| i128::from(w.offset(a, bias[a]).unsigned_abs());
        let xy = off(0) + off(1);
        off(2) > i128::from(s.tick) * i128::from(lift) + ((i128::from(s.lift_ratio_q8) * xy) >> 8)
    }

    /// Decisions at the end of a tick.
    fn tick(&mut self, s: &DriftSettings, bias: [i64; 3], velocity: [i64; 3]) -> Action {
        if matches!(self.state, State::Still | State::Moving) && self.lifted(s, bias) {
            let held = self.holds();
            self.state = State::Lifted;
            self.entered = self.ticks;
            return if held { Action::Discard } else { Action::Stop };
        }
        match self.state {
            State::Still => self.still_tick(s, bias),
            State::Moving => self.moving_tick(s, bias, velocity),
            State::Lifted => self.lifted_tick(s, bias),
            State::Frozen => Action::None,
        }
    }

    /// Whether the tick so far is within [`Self::headroom`] on both horizontal axes, so that
    /// no CUSUM can alarm on it: the test made on every sample at rest, kept small enough to
    /// inline; only past it does [`Self::early_alarm`] make the exact test.
    #[inline(always)]
    fn within_headroom(&self, bias: [i64; 3]) -> bool {
        let within = |a: usize| {
            (-self.headroom[a]..=self.headroom[a]).contains(&self.tick_offset(a, bias[a]))
        };
        within(0) && within(1)
    }

    /// Offset of the current tick's code sum on `axis` so far from `bias` (Q16 counts)
    /// [Q16 LSB samples]: below `2^14` codes of 16 bits, `2^46`, and `n bias < 2^46`.
    #[inline(always)]
    fn tick_offset(&self, axis: usize, bias: i64) -> i64 {
        (i64::from(self.cur_codes[axis]) << 16) - i64::from(self.cur_n) * bias
    }

    /// The CUSUM checked within a tick, on the samples of it so far (`kappa` pro rata), so
    /// that a brisk start is not kept waiting for the tick's end.
    ///
    /// The test `sum + z - floor(kappa n / D) > alarm` is made without the division: for
    /// the integer `x = sum + z - alarm` and `kappa n >= 0`, `x > floor(kappa n / D)` is
    /// `x D > kappa n` (likewise for the step's `z - floor(kappa n / D) > alarm_slow / 2`).
    #[inline(never)]
    fn early_alarm(&mut self, s: &DriftSettings, bias: [i64; 3]) -> Action {
        let mut alarm: Option<u64> = None;
        let mut step = false;
        for (a, &b) in bias.iter().enumerate().take(2) {
            let d = self.tick_offset(a, b);
            let noise = self.noise[a];
            for (c, (cusum, onset)) in self.cusum.iter().zip(&self.onset).enumerate() {
                // kappa < 2^41 (sd < 2^39) and n <= 2^14; `x D > kappa n` with x <= 0 is false.
                let drift = u128::from(noise.kappa[c].unsigned_abs()) * u128::from(self.cur_n);
                let exceeds = |x: i64| {
                    u64::try_from(x).is_ok_and(|x| u128::from(x) * u128::from(s.tick) > drift)
                };
                for (side, z) in [d, -d].into_iter().enumerate() {
                    let sum = cusum[a][side];
                    if exceeds(sum + z - noise.alarm[c]) {
                        let on = if sum == 0 { self.ticks } else { onset[a][side] };
                        alarm = Some(alarm.map_or(on, |o| o.min(on)));
                        step |= exceeds(z - noise.alarm[0] / 2);
                    }
                }
            }
        }
        alarm.map_or(Action::None, |onset| self.start(s, onset, step))
    }

    /// A motion starts: replay the complete ticks since `onset` (at most `REPLAY`) and the
    /// current tick's samples so far. It is held until `hold_s` after its onset; after a
    /// `step` (one tick alone crossed the alarm: a jolt, not a hand's ramp) until `hold_s`
    /// after now, since a jolt began at most a tick ago whatever the onset says.
    fn start(&mut self, s: &DriftSettings, onset: u64, step: bool) -> Action {
        // Keep one tick before the replay: it primes the trapezoid.
        let ticks = (self.ticks - onset)
            .min(REPLAY as u64 - 1)
            .min(self.ticks.saturating_sub(1));
        self.state = State::Moving;
        self.entered = self.ticks;
        self.motion_samples = ticks * u64::from(s.tick) + u64::from(self.cur_n);
        self.hold_left = if step {
            s.hold
        } else {
            s.hold.saturating_sub(self.motion_samples)
        };
        self.peak_w = [0; 2];
        self.quiet_run = 0;
        self.suspect = None;
        Action::Start {
            ticks: ticks as usize,
        }
    }

    #[inline(never)]
    fn still_tick(&mut self, s: &DriftSettings, bias: [i64; 3]) -> Action {
        let mut alarm: Option<u64> = None;
        let mut step = false;
        let w = self.window(s, 1);
        for (a, &b) in bias.iter().enumerate().take(2) {
            let d = w.offset(a, b);
            let n = self.noise[a];
            for c in 0..2 {
                for (side, z) in [d, -d].into_iter().enumerate() {
                    let sum = &mut self.cusum[c][a][side];
                    *sum = (*sum + z - n.kappa[c]).max(0);
                    if *sum == 0 {
                        self.onset[c][a][side] = self.ticks;
                    } else if *sum > n.alarm[c] {
                        let on = self.onset[c][a][side];
                        alarm = Some(alarm.map_or(on, |o| o.min(on)));
                        step |= z - n.kappa[c] > n.alarm[0] / 2;
                    }
                }
            }
        }
        if let Some(onset) = alarm {
            return self.start(s, onset, step);
        }
        // The tick REPLAY ticks old, once the device has been still all the time since: the
        // ticks a motion's onset could still claim are not averaged in.
        if self.ticks - self.entered < REPLAY as u64 {
            return Action::None;
        }
        let old = ((self.ticks - REPLAY as u64) % RING as u64) as usize;
        self.learn_noise(s, old, bias);
        let Some(max) = s.bias_samples_max else {
            return Action::None;
        };
        self.bias_samples = (self.bias_samples + u64::from(s.tick)).min(max);
        let w = self.bias_samples as i64; // <= 1e6 s * 1e5 Hz < 2^37
        let mut out = bias;
        for (b, &c) in out.iter_mut().zip(&self.codes[old]) {
            // A tick's offset: below 2^41 in Q16 LSB samples.
            let d = (i64::from(c) << 16) - i64::from(s.tick) * *b;
            *b += crate::math::div_round(d, w);
        }
        Action::TrackBias(out)
    }

    /// Learns `q` at rest: the squared offset of each block of `LEARN_TICKS` rest ticks,
    /// per sample, averaged over `LEARN_BLOCKS` blocks. The calibration measured one
    /// second; this follows the sensor as it is, for as long as it rests.
    #[inline(never)]
    fn learn_noise(&mut self, s: &DriftSettings, tick: usize, bias: [i64; 3]) {
        for (sum, &c) in self.learn_sum.iter_mut().zip(&self.codes[tick]) {
            *sum += u64::from(c);
        }
        self.learn_ticks += 1;
        if self.learn_ticks < LEARN_TICKS {
            return;
        }
        let n = i128::from(LEARN_TICKS) * i128::from(s.tick);
        for (a, &b) in bias.iter().enumerate() {
            // Offset in Q16 LSB samples; its square over n is a variance per sample in Q32.
            let e = (i128::from(self.learn_sum[a]) << 16) - n * i128::from(b); // < 2^59
            let var = crate::math::square_over(e.unsigned_abs() as u64, n as u64) // e < 2^59
                .min(u128::from(u64::MAX));
            let q = u128::from(self.noise[a].q_q32);
            let m = u128::from(LEARN_BLOCKS);
            let q = ((q * (m - 1) + var) / m).max(1 << 30) as u64;
            self.noise[a] = Noise::new(s, q, self.noise[a].g0_q32);
        }
        self.learn_sum = [0; 3];
        self.learn_ticks = 0;
    }

    #[inline(never)]
    fn moving_tick(&mut self, s: &DriftSettings, bias: [i64; 3], velocity: [i64; 3]) -> Action {
        let k = s.quiet_ticks;
        let wq = self.window(s, k);
        let quiet = (0..2).all(|a| self.explained(a, wq.offset(a, bias[a]), wq.n(), s.quiet_k2_q8));
        // The coast clock runs only while the rest_s window is quiet too: its mean sees an
        // acceleration 4x smaller than the quiet_s window does (a slow stroke's 1 LSB).
        let m = s
            .rest_ticks
            .min((self.ticks - self.entered).max(1) as u32)
            .max(k);
        let calm = quiet && {
            let wc = self.window(s, m);
            (0..2).all(|a| self.explained(a, wc.offset(a, bias[a]), wc.n(), s.quiet_k2_q8))
        };
        self.quiet_run = if calm { self.quiet_run + 1 } else { 0 };
        for (peak, v) in self.peak_w.iter_mut().zip(velocity) {
            *peak = (*peak).max(v.unsigned_abs());
        }
        let v_ok = (0..2).all(|a| {
            // W = 2 V: compare V = W / 2 with its sd.
            let by_noise =
                self.explained(a, velocity[a] / 2, self.motion_samples, s.velocity_k2_q8);
            let by_peak = u128::from(velocity[a].unsigned_abs()) << 8
                <= u128::from(self.peak_w[a]) * u128::from(s.stop_fraction_q8);
            by_noise || by_peak
        });
        if quiet && (v_ok || self.quiet_run >= s.coast_ticks) {
            // A motion that ends younger than the hold was a jolt, not a stroke; a tilt
            // suspicion that ends in a stop was refuted: deliver.
            let held = self.hold_left > 0;
            self.enter_still();
            return if held { Action::Discard } else { Action::Stop };
        }
        // A tilt: steady and off the bias for rest_s. Hold the motion from then on, and
        // remember the window's means. If the device stays steady at those means for tilt_s
        // it was never motion: discard it and take them as the new zero. If the acceleration
        // changes, it was a slow stroke's broad peak: deliver what was held.
        let m = s.rest_ticks;
        let wr = self.window(s, m);
        let nm = wr.n();
        // Once suspected, the same tests run every tick for tilt_s: refute only on evidence
        // that holds for the whole family (Slack::KEEP).
        let slack = if self.suspect.is_some() {
            Slack::KEEP
        } else {
            Slack::FIND
        };
        let steady = self.ticks - self.entered >= u64::from(m) && self.steady(s, m, slack);
        match self.suspect {
            None => {
                let off =
                    (0..2).any(|a| !self.explained(a, wr.offset(a, bias[a]), nm, s.quiet_k2_q8));
                if steady && off {
                    self.suspect = Some((self.ticks, wr.means(bias)));
                }
            }
            Some((since, tilt)) => {
                let settling = self.ticks - since < 2 * u64::from(m);
                let same = |slack: Slack| {
                    (0..3).all(|a| {
                        let d = wr.offset(a, tilt[a]);
                        let k2 = ((u128::from(s.quiet_k2_q8) * slack.k2_q8) >> 8) as u64;
                        self.explained_against(a, d, nm, k2, nm)
                    })
                };
                if !steady {
                    self.suspect = None;
                } else if settling && !same(Slack::KEEP) {
                    // Steady at another offset within 2 rest_s of the suspicion: the tilt was
                    // still settling. Keep holding, against the new means.
                    self.suspect = Some((since, wr.means(bias)));
                } else if !settling && !same(Slack::MOVED) {
                    // Later, a changed offset is a slow stroke's acceleration moving on.
                    self.suspect = None;
                } else if self.ticks - since >= u64::from(s.tilt_ticks) {
                    self.enter_still();
                    self.bias_samples = nm;
                    return Action::Rebias {
                        bias: wr.means(bias),
                        discard: true,
                    };
                }
            }
        }
        Action::None
    }

    #[inline(never)]
    fn lifted_tick(&mut self, s: &DriftSettings, bias: [i64; 3]) -> Action {
        let m = s.rest_ticks;
        if self.ticks - self.entered < u64::from(m) || !self.steady(s, m, Slack::FIND) {
            return Action::None;
        }
        let w = self.window(s, m);
        let nm = w.n();
        let moved = (0..3).any(|a| !self.explained(a, w.offset(a, bias[a]), nm, s.quiet_k2_q8));
        let b = w.means(bias);
        self.enter_still();
        if moved {
            self.bias_samples = nm;
            Action::Rebias {
                bias: b,
                discard: false,
            }
        } else {
            Action::Stop
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validation_names_the_field() {
        let d = Drift::default();
        let v = |d: Drift| d.validate(3000, 0.023942);
        assert_eq!(
            v(Drift {
                start_sigmas: 0.5,
                ..d
            }),
            Err(DriftError::StartSigmas)
        );
        assert_eq!(v(Drift { hold_s: 0.2, ..d }), Err(DriftError::Hold));
        assert_eq!(
            v(Drift {
                quiet_s: 0.001,
                ..d
            }),
            Err(DriftError::QuietWindow)
        );
        assert_eq!(v(Drift { quiet_s: 0.4, ..d }), Err(DriftError::QuietWindow));
        assert_eq!(
            v(Drift {
                quiet_sigmas: 0.0,
                ..d
            }),
            Err(DriftError::QuietSigmas)
        );
        assert_eq!(
            v(Drift {
                velocity_sigmas: -1.0,
                ..d
            }),
            Err(DriftError::VelocitySigmas)
        );
        assert_eq!(
            v(Drift {
                stop_fraction: 1.5,
                ..d
            }),
            Err(DriftError::StopFraction)
        );
        assert_eq!(v(Drift { coast_s: 0.01, ..d }), Err(DriftError::Coast));
        assert_eq!(v(Drift { rest_s: 0.01, ..d }), Err(DriftError::RestWindow));
        assert_eq!(v(Drift { rest_s: 0.5, ..d }), Err(DriftError::RestWindow));
        assert_eq!(
            v(Drift {
                rest_factor: 0.9,
                ..d
            }),
            Err(DriftError::RestFactor)
        );
        assert_eq!(v(Drift { tilt_s: 0.2, ..d }), Err(DriftError::Tilt));
        assert_eq!(v(Drift { tilt_s: 11.0, ..d }), Err(DriftError::Tilt));
        assert_eq!(
            v(Drift {
                lift_m_s2: Some(0.0),
                ..d
            }),
            Err(DriftError::Lift)
        );
        assert_eq!(
            v(Drift {
                lift_xy_ratio: 11.0,
                ..d
            }),
            Err(DriftError::LiftRatio)
        );
        assert_eq!(
            v(Drift {
                bias_tau_s: Some(0.1),
                ..d
            }),
            Err(DriftError::BiasTau)
        );
        assert_eq!(
            v(Drift {
                click_freeze_s: 3.0,
                ..d
            }),
            Err(DriftError::ClickFreeze)
        );
        let s = v(d).expect("valid");
        assert_eq!(s.tick_samples(), 15);
        assert_eq!((s.quiet_ticks, s.rest_ticks, s.coast_ticks), (4, 60, 100));
        assert_eq!(s.freeze_samples(), 450);
        assert_eq!(s.hold_samples(), 48);
        assert!(v(Drift {
            lift_m_s2: None,
            ..d
        })
        .is_ok());
    }

    #[test]
    fn validated_settings_are_their_definitions_and_edges_hold() {
        // Each derived value from its definition: q8(x) = round(256 x), the lift in Q16 codes,
        // the bias time constant in samples. At 3 kHz a tick is 15 samples (5 ms).
        let (fs, lsb) = (3000.0, 0.023942);
        let d = Drift {
            lift_m_s2: Some(0.3),
            bias_tau_s: Some(2.0),
            ..Drift::default()
        };
        let v = |d: Drift| d.validate(3000, lsb);
        let s = v(d).expect("valid");
        let q8 = |x: f64| (x * 256.0).round() as u64;
        assert_eq!(s.start_q8, q8(d.start_sigmas) as i64);
        assert_eq!(s.quiet_k2_q8, q8(d.quiet_sigmas * d.quiet_sigmas));
        assert_eq!(s.velocity_k2_q8, q8(d.velocity_sigmas * d.velocity_sigmas));
        assert_eq!(s.stop_fraction_q8, q8(d.stop_fraction));
        assert_eq!(s.rest_factor_q8, q8(d.rest_factor));
        assert_eq!(s.lift_ratio_q8, q8(d.lift_xy_ratio) as i64);
        assert_eq!(s.lift_q16, Some((0.3 / lsb * 65_536.0).round() as i64));
        assert_eq!(s.bias_samples_max, Some((2.0 * fs) as u64));
        assert_eq!(s.tilt_ticks, (d.tilt_s / 0.005).round() as u32);
        // Windows in ticks: half a tick rounds up to the least (1 for the quiet window) and
        // is accepted, less is not; the ring's length plus 0.4 rounds down to it.
        let tick_s = 15.0 / fs;
        let quiet = |q: f64| {
            v(Drift {
                quiet_s: q * tick_s,
                coast_s: 1.0,
                ..d
            })
        };
        assert_eq!(quiet(0.5).map(|s| s.quiet_ticks), Ok(1));
        assert_eq!(
            quiet(0.49).map(|s| s.quiet_ticks),
            Err(DriftError::QuietWindow)
        );
        assert_eq!(
            quiet(RING as f64 + 0.4).map(|s| s.quiet_ticks),
            Ok(RING as u32)
        );
        assert_eq!(
            quiet(RING as f64 + 0.5).map(|s| s.quiet_ticks),
            Err(DriftError::QuietWindow)
        );
        // The lift in codes must fit 2^15 (its Q16 value an i64 with room): 1000 m/s^2 is
        // 41 767 codes here, refused; the bias time constant stops short of 1e6 s.
        let lift = |l: f64| {
            v(Drift {
                lift_m_s2: Some(l),
                ..d
            })
            .map(|_| ())
        };
        assert_eq!(lift(1000.0), Err(DriftError::Lift));
        assert!(lift(700.0).is_ok());
        let tau = |t: f64| {
            v(Drift {
                bias_tau_s: Some(t),
                ..d
            })
            .map(|_| ())
        };
        assert_eq!(tau(1e6), Err(DriftError::BiasTau));
        assert!(tau(999_999.0).is_ok());
    }

    #[test]
    fn replay_primes_from_the_tick_before_the_replayed_ones() {
        // Ticks 0..10 done, tick k ending on the sample 100 k + axis: replaying the last 3
        // primes from tick 6; the last 9 from tick 0; the last 10 has no predecessor; a
        // replay as long as the ring has none left in it.
        let s = Drift::default().validate(3000, 0.023942).expect("valid");
        let cal = Calibration {
            bias_q16: 2048 << 16,
            noise_rms_q16: 1 << 16,
            samples: 3000,
            tick_var_q32: 1 << 32,
            long_run_var_q32: 1 << 32,
        };
        let mut d = Detector::new(&s, &[cal; 3]);
        for (k, sums) in d.sums.iter_mut().enumerate().take(10) {
            for (a, t) in sums.iter_mut().enumerate() {
                t.last = (100 * k + a) as i64;
            }
        }
        d.ticks = 10;
        assert_eq!(d.replay_prev(3), Some([600, 601, 602]));
        assert_eq!(d.replay_prev(9), Some([0, 1, 2]));
        assert_eq!(d.replay_prev(10), None);
        d.ticks = 1000;
        assert!(d.replay_prev(REPLAY - 1).is_some());
        assert_eq!(d.replay_prev(REPLAY), None);
    }

    /// A detector at 3 kHz with a noise of exactly 1 LSB^2 per sample (long-run and tick).
    fn unit_noise_detector() -> (DriftSettings, Detector) {
        let s = Drift::default().validate(3000, 0.023942).expect("valid");
        let cal = Calibration {
            bias_q16: 2048 << 16,
            noise_rms_q16: 1 << 16,
            samples: 3000,
            tick_var_q32: 1 << 32,
            long_run_var_q32: 1 << 32,
        };
        let mut d = Detector::new(&s, &[cal; 3]);
        d.noise = [Noise::new(&s, 1 << 32, 1 << 32); 3];
        d.refresh_headroom();
        (s, d)
    }

    #[test]
    fn an_offset_is_explained_within_its_sd_including_the_bias_uncertainty() {
        // q = 1 LSB^2, n = 300 samples, a bias from 3000: var = n + n^2 / N_b = 330 LSB^2;
        // at 1 sd the largest explained offset is sqrt(330) 2^16 = 1 190 520.5 (Q16).
        let (_, d) = unit_noise_detector();
        assert!(d.explained_against(0, 1_190_520, 300, 256, 3000));
        assert!(!d.explained_against(0, 1_190_521, 300, 256, 3000));
        assert!(!d.explained_against(0, -1_190_521, 300, 256, 3000));
    }

    #[test]
    fn steadiness_reads_the_last_complete_ticks_only() {
        // Ten ticks of 15 samples at one level; the slot the next tick will fill holds an old
        // outlier. The last k complete ticks are steady; reading one slot too far is not.
        let (s, mut d) = unit_noise_detector();
        d.ticks = 10;
        for slot in d.codes.iter_mut() {
            *slot = [15 * 2048; 3];
        }
        d.codes[10 % RING] = [15 * 2200; 3];
        assert!(d.steady(&s, 10, Slack::FIND));
        d.codes[9] = [15 * 2200; 3];
        assert!(!d.steady(&s, 10, Slack::FIND));
    }

    #[test]
    fn steadiness_bounds_are_exact() {
        // Two ticks (k = 2) of D = 15 samples, tick sums v (newest) and u. Scatter
        // k sum s^2 - (sum s)^2 = (v - u)^2 against rest_factor k (k - 1) D g0 = 60 (g0 = 1):
        // 7 apart is steady, 8 is not. Trend v - u against quiet_sigmas^2 q D k (k^2 - 1) / 3
        // = 9 * 30 = 270 (q = 1): 16 apart is steady, 17 is not. Each bound alone: the other
        // noise figure made huge.
        let (s, mut d) = unit_noise_detector();
        d.ticks = 10;
        let base = 15 * 2048;
        let apart = |d: &mut Detector, q: u64, g0: u64, diff: u32| {
            d.noise = [Noise::new(&s, q, g0); 3];
            d.codes[9] = [base + diff; 3];
            d.codes[8] = [base; 3];
            d.steady(&s, 2, Slack::FIND)
        };
        assert!(apart(&mut d, 1 << 50, 1 << 32, 7));
        assert!(!apart(&mut d, 1 << 50, 1 << 32, 8));
        assert!(apart(&mut d, 1 << 32, 1 << 50, 16));
        assert!(!apart(&mut d, 1 << 32, 1 << 50, 17));
    }

    #[test]
    fn a_lift_is_a_z_offset_beyond_its_bound_plus_a_share_of_the_horizontal() {
        // Last tick's offsets from the bias in codes (x, y, z); lift 1 LSB (Q16) per sample:
        // z must exceed D = 15 codes plus lift_ratio (1/4) of |x| + |y|.
        let (mut s, mut d) = unit_noise_detector();
        s.lift_q16 = Some(1 << 16);
        s.lift_ratio_q8 = 64;
        d.ticks = 10;
        let bias = [2048i64 << 16; 3];
        let mut lifted = |x: u32, y: u32, z: u32| {
            d.codes[9] = [15 * 2048 + x, 15 * 2048 + y, 15 * 2048 + z];
            d.lifted(&s, bias)
        };
        assert!(!lifted(0, 0, 15));
        assert!(lifted(0, 0, 16));
        // |x| + |y| = 128 codes: 32 more allowed.
        assert!(!lifted(100, 28, 47));
        assert!(lifted(100, 28, 48));
        let mut off = s;
        off.lift_q16 = None;
        d.codes[9] = [15 * 2048, 15 * 2048, 15 * 4095];
        assert!(!d.lifted(&off, bias), "no lift detection configured");
    }

    /// A still detector at tick 10 (entered now), whose CUSUMs drift 1 code a tick and
    /// alarm at 10 codes (slow) and 100 codes (fast), all at the bias 2048; the last tick's
    /// X sum `2048 D + dx` codes.
    fn cusum_detector(dx: i64) -> (DriftSettings, Detector) {
        let (s, mut d) = unit_noise_detector();
        for n in d.noise.iter_mut() {
            n.kappa = [1 << 16, 1 << 16];
            n.alarm = [10 << 16, 100 << 16];
        }
        d.ticks = 10;
        d.entered = 10;
        d.onset = [[[10; 2]; 2]; 2];
        for slot in d.codes.iter_mut() {
            *slot = [15 * 2048; 3];
        }
        d.codes[9][0] = (15 * 2048 + dx) as u32;
        d.refresh_headroom();
        (s, d)
    }

    #[test]
    fn a_slow_cusum_alarms_beyond_its_threshold_from_its_onset() {
        // The slow CUSUM holds 9 codes since tick 5. A tick 2 codes up adds 2 - 1: exactly the
        // alarm, no start; 3 up crosses it: a start replaying the 5 ticks since the onset,
        // not a step (2 codes over the drift is below half the slow alarm), so the hold
        // counts from the onset: 5 ticks of 15 samples have used 75 of its 48.
        let bias = [2048 << 16; 3];
        for (dx, started) in [(2, false), (3, true)] {
            let (s, mut d) = cusum_detector(dx);
            d.cusum[0][0][0] = 9 << 16;
            d.onset[0][0][0] = 5;
            let action = d.still_tick(&s, bias);
            if started {
                assert_eq!(action, Action::Start { ticks: 5 });
                assert_eq!((d.motion_samples, d.hold_left), (75, 0));
                assert_eq!(d.state, State::Moving);
            } else {
                assert_eq!(action, Action::None, "{dx}");
                assert_eq!(d.cusum[0][0][0], 10 << 16);
            }
        }
        // The same downwards, on the other side.
        let (s, mut d) = cusum_detector(-3);
        d.cusum[0][0][1] = 9 << 16;
        d.onset[0][0][1] = 5;
        assert_eq!(d.still_tick(&s, bias), Action::Start { ticks: 5 });
        // An onset older than the replay ring: REPLAY - 1 ticks are replayed, no more.
        let (s, mut d) = cusum_detector(3);
        d.ticks = 200;
        d.entered = 200;
        d.codes[199 % RING] = d.codes[9];
        d.cusum[0][0][0] = 9 << 16;
        d.onset[0][0][0] = 50;
        assert_eq!(d.still_tick(&s, bias), Action::Start { ticks: REPLAY - 1 });
    }

    #[test]
    fn a_jolt_is_a_step_and_holds_from_now() {
        // One tick 12 codes up: 11 over the drift crosses the slow alarm alone and is more
        // than half of it: a step, held the whole hold from now. 6 up is exactly half: the
        // CUSUM holds it (5 codes), no alarm yet.
        let bias = [2048 << 16; 3];
        let (s, mut d) = cusum_detector(12);
        assert_eq!(d.still_tick(&s, bias), Action::Start { ticks: 0 });
        assert_eq!(d.hold_left, s.hold);
        let (s, mut d) = cusum_detector(6);
        d.cusum[0][0][0] = 5 << 16;
        d.onset[0][0][0] = 8;
        // 5 + 6 - 1 = 10: at the alarm, no start.
        assert_eq!(d.still_tick(&s, bias), Action::None);
        let (s, mut d) = cusum_detector(7);
        d.cusum[0][0][0] = 5 << 16;
        d.onset[0][0][0] = 8;
        // 5 + 7 - 1 = 11 > 10 from tick 8; the tick alone (6 over the drift) is more than
        // half the alarm: a step, held from now.
        assert_eq!(d.still_tick(&s, bias), Action::Start { ticks: 2 });
        assert_eq!(d.hold_left, s.hold);
        let (s, mut d) = cusum_detector(6);
        d.cusum[0][0][0] = 6 << 16;
        d.onset[0][0][0] = 8;
        // 6 + 6 - 1 = 11 > 10; the tick alone is 5 over the drift: exactly half, not a step.
        assert_eq!(d.still_tick(&s, bias), Action::Start { ticks: 2 });
        assert_eq!(d.hold_left, s.hold.saturating_sub(30));
    }

    #[test]
    fn rest_updates_the_bias_from_the_tick_a_replay_can_no_longer_claim() {
        // Still for REPLAY ticks exactly: the tick REPLAY ago (slot 10 % 64 = 10 at tick 74)
        // is averaged in over bias_samples + D = 3015 samples; one tick earlier nothing is.
        let (s, mut d) = cusum_detector(0);
        let bias = [2048 << 16; 3];
        d.ticks = 10 + REPLAY as u64 - 1;
        assert_eq!(d.still_tick(&s, bias), Action::None);
        let (s, mut d) = cusum_detector(0);
        d.ticks = 10 + REPLAY as u64;
        d.codes[10] = [15 * 2049, 15 * 2048, 15 * 2047];
        d.bias_samples = 3000;
        let step = (15 * 65_536 + 3015 / 2) / 3015; // div_round(15 2^16, 3015)
        assert_eq!(
            d.still_tick(&s, bias),
            Action::TrackBias([(2048 << 16) + step, 2048 << 16, (2048 << 16) - step])
        );
    }

    /// Within a tick: 5 of its 15 samples, X's sum `5 2048 + dx` codes, the slow CUSUM at
    /// `sum_q16` since tick 5, the drift `kappa` codes a tick (pro rata here).
    fn early(kappa: i64, sum_q16: i64, dx: i64) -> (DriftSettings, Detector) {
        let (s, mut d) = cusum_detector(0);
        for n in d.noise.iter_mut() {
            n.kappa = [kappa << 16; 2];
        }
        d.cur_n = 5;
        d.cur_codes = [5 * 2048; 3];
        d.cur_codes[0] = (5 * 2048 + dx) as u32;
        d.cusum[0][0] = [sum_q16; 2];
        d.onset[0][0] = [5; 2];
        d.refresh_headroom();
        (s, d)
    }

    /// The least headroom of the CUSUMs below their alarms, from scratch.
    fn headroom_now(d: &Detector) -> [i64; 2] {
        core::array::from_fn(|a| {
            let mut room = i64::MAX;
            for c in 0..2 {
                for side in 0..2 {
                    room = room.min(d.noise[a].alarm[c] - d.cusum[c][a][side]);
                }
            }
            room
        })
    }

    #[test]
    fn the_early_alarm_headroom_is_kept_through_every_change() {
        // Rest (the CUSUMs move every tick, the noise is learnt), slow pushes that start
        // motions, clicks and a restart: after every sample and event the kept headroom is
        // the CUSUMs' own. A stale one would let an early alarm pass unseen.
        let (s, mut d) = unit_noise_detector();
        let bias = [2048 << 16; 3];
        let noise_before = d.noise;
        let mut trace = crate::bench::testsignal::Trace::new(0x4EAD);
        let (mut changes, mut starts) = (0, 0);
        for k in 0..60_000u32 {
            let before = d.headroom;
            let noise = i32::from(trace.next_code() % 3) - 1;
            let push = match k % 9000 {
                6000..=6299 => 2,
                6300..=6599 => -2,
                _ => 0,
            };
            let codes = [2048 + noise + push, 2048 - noise, 2048 + noise].map(|v| v as u16);
            let y = codes.map(|c| i64::from(c) << 16);
            if matches!(d.push(&s, codes, y, bias, [0; 3]), Action::Start { .. }) {
                starts += 1;
            }
            if k % 9000 == 8000 {
                d.click(&s);
            }
            if k == 40_000 {
                d.restart();
            }
            assert_eq!(d.headroom, headroom_now(&d), "sample {k}");
            changes += usize::from(d.headroom != before);
        }
        assert!(
            changes > 500 && starts >= 6,
            "{changes} changes, {starts} starts"
        );
        assert_ne!(d.noise, noise_before, "the noise was learnt at rest");
    }

    #[test]
    fn a_sample_at_rest_is_decided_by_the_headroom_alone() {
        // Five samples into a tick at rest (a code of noise either way): within the
        // headroom, no exact test. Forty codes up on X or on Y: past it.
        let (_, d) = unit_noise_detector();
        let bias = [2048 << 16; 3];
        let mut rest = d;
        rest.cur_n = 5;
        rest.cur_codes = [5 * 2048 + 1, 5 * 2048 - 1, 5 * 2048];
        assert!(rest.within_headroom(bias));
        for axis in [0, 1] {
            let mut step = rest;
            step.cur_codes[axis] += 40;
            assert!(!step.within_headroom(bias), "axis {axis}");
        }
        // The bound itself, on one sample against a bias set to put the offset on it:
        // an offset equal to the headroom is within, one more is not.
        let mut one = d;
        one.cur_n = 1;
        one.cur_codes = [2048; 3];
        for (axis, sign) in [(0, 1), (1, -1)] {
            let room = one.headroom[axis];
            let mut at = bias;
            at[axis] = (2048 << 16) - sign * room;
            assert!(one.within_headroom(at), "axis {axis} at the bound");
            at[axis] -= sign;
            assert!(!one.within_headroom(at), "axis {axis} past the bound");
        }
    }

    #[test]
    fn a_brisk_start_on_either_axis_alarms_before_its_tick_ends() {
        // A step of 40 codes on X, or on Y, from a tick's first sample: its offset crosses
        // the fast CUSUM's alarm (8 sd of a tick, 31 codes) at once, and the motion starts
        // on that sample, not at the tick's end.
        for axis in [0, 1] {
            let (s, mut d) = unit_noise_detector();
            let bias = [2048 << 16; 3];
            let mut codes = [2048u16; 3];
            codes[axis] += 40;
            let y = codes.map(|c| i64::from(c) << 16);
            let action = d.push(&s, codes, y, bias, [0; 3]);
            assert_eq!(action, Action::Start { ticks: 0 }, "axis {axis}");
            assert_eq!(d.cur_n, 1);
        }
    }

    #[test]
    fn an_early_alarm_prorates_the_drift_over_the_samples_so_far() {
        let bias = [2048 << 16; 3];
        // Drift 1 code a tick is 21 845 (Q16) over 5 of 15 samples. From 9 codes, 2 codes
        // up: 720 896 - 21 845 > 655 360, a start (a full tick's drift would be exactly at
        // the alarm); 1 code up from 9 codes + 16 000: 649 515, none.
        let (s, mut d) = early(1, 9 << 16, 2);
        assert_eq!(d.early_alarm(&s, bias), Action::Start { ticks: 5 });
        assert_eq!(d.motion_samples, 5 * 15 + 5);
        let (s, mut d) = early(1, (9 << 16) + 16_000, 1);
        assert_eq!(d.early_alarm(&s, bias), Action::None);
        // Exactly at the alarm is no alarm: 611 669 + 65 536 - 21 845 = 655 360.
        let (s, mut d) = early(1, 611_669, 1);
        assert_eq!(d.early_alarm(&s, bias), Action::None);
        // Downwards, on the other side.
        let (s, mut d) = early(1, 9 << 16, -2);
        assert_eq!(d.early_alarm(&s, bias), Action::Start { ticks: 5 });
        // The CUSUMs themselves are not advanced mid-tick.
        assert_eq!(d.cusum[0][0], [9 << 16; 2]);
    }

    #[test]
    fn an_early_step_is_more_than_half_the_slow_alarm_over_the_drift() {
        // Drift 3 codes a tick: 1 code over 5 samples. From 9 codes, 6 up: 14 > 10, and 5 over
        // the drift is exactly half the alarm: no step, held from the onset (80 samples used
        // all 48). 7 up: 6 over the drift, a step, held from now.
        let bias = [2048 << 16; 3];
        let (s, mut d) = early(3, 9 << 16, 6);
        assert_eq!(d.early_alarm(&s, bias), Action::Start { ticks: 5 });
        assert_eq!(d.hold_left, 0);
        let (s, mut d) = early(3, 9 << 16, 7);
        assert_eq!(d.early_alarm(&s, bias), Action::Start { ticks: 5 });
        assert_eq!(d.hold_left, s.hold);
    }

    #[test]
    fn rest_learns_the_noise_every_sixteen_ticks_as_a_slow_average() {
        // q = 1 LSB^2. Sixteen rest ticks of 15 samples, each 3 codes over the bias: the
        // block's offset is 48 codes over 240 samples, a variance of 48^2 / 240 = 9.6 LSB^2
        // per sample, averaged in with weight 1/128. Fifteen ticks change nothing.
        let (s, mut d) = unit_noise_detector();
        let bias = [2048 << 16; 3];
        d.codes[0] = [15 * 2048 + 3; 3];
        for _ in 0..15 {
            d.learn_noise(&s, 0, bias);
        }
        assert_eq!(d.noise[0].q_q32, 1 << 32);
        d.learn_noise(&s, 0, bias);
        let var: u128 = (48u128 << 16).pow(2) / 240;
        let want = (((1u128 << 32) * 127 + var) / 128) as u64;
        assert_eq!(d.noise[0].q_q32, want);
        assert_eq!(d.noise[0], Noise::new(&s, want, 1 << 32));
        // A quiet block cannot take q below a quarter of an LSB^2.
        let (s, mut d) = unit_noise_detector();
        d.noise = [Noise::new(&s, 1 << 30, 1 << 32); 3];
        d.codes[0] = [15 * 2048; 3];
        for _ in 0..16 {
            d.learn_noise(&s, 0, bias);
        }
        assert_eq!(d.noise[0].q_q32, 1 << 30);
    }

    /// A detector moving since tick 100, now at tick `ticks`, for 300 samples, every tick
    /// in the ring `15 (2048 + dx)` codes on X (the bias is 2048).
    fn moving_detector(ticks: u64, dx: u32) -> (DriftSettings, Detector) {
        let (s, mut d) = unit_noise_detector();
        d.state = State::Moving;
        d.entered = 100;
        d.ticks = ticks;
        d.motion_samples = 300;
        for slot in d.codes.iter_mut() {
            *slot = [15 * (2048 + dx), 15 * 2048, 15 * 2048];
        }
        (s, d)
    }

    #[test]
    fn a_motion_stops_when_quiet_and_its_velocity_is_explained_or_has_fallen_or_coasted() {
        let bias = [2048 << 16; 3];
        // V = W / 2 against 2 sd of sqrt(q (n + n^2 / N_b)) = sqrt(330) over n = 300: W up to
        // 2 x 2 x 18.17 x 2^16 = 4 762 082 is explained.
        let (s, mut d) = moving_detector(110, 0);
        assert_eq!(d.moving_tick(&s, bias, [4_700_000, 0, 0]), Action::Stop);
        assert_eq!(d.state, State::Still);
        let (s, mut d) = moving_detector(110, 0);
        assert_eq!(d.moving_tick(&s, bias, [4_800_000, 0, 0]), Action::None);
        // Or a quarter of the motion's peak: 4.8e6 against a peak of 19.2e6, not 19.1e6.
        for (peak, stop) in [(19_200_000, true), (19_100_000, false)] {
            let (s, mut d) = moving_detector(110, 0);
            d.peak_w = [peak, 0];
            let want = if stop { Action::Stop } else { Action::None };
            assert_eq!(d.moving_tick(&s, bias, [4_800_000, 0, 0]), want, "{peak}");
        }
        // Or quiet for coast_s (100 ticks), whatever the velocity.
        for (run, stop) in [(99, true), (98, false)] {
            let (s, mut d) = moving_detector(110, 0);
            d.quiet_run = run;
            let want = if stop { Action::Stop } else { Action::None };
            assert_eq!(d.moving_tick(&s, bias, [50_000_000, 0, 0]), want, "{run}");
        }
        // The calm window is the time since the motion began (10 ticks here), not rest_s:
        // older ticks off the bias do not keep a fresh motion from coasting to a stop.
        let (s, mut d) = moving_detector(110, 2);
        for t in 100..110 {
            d.codes[t % RING] = [15 * 2048; 3];
        }
        d.moving_tick(&s, bias, [50_000_000, 0, 0]);
        assert_eq!(d.quiet_run, 1);
        // Younger than its hold, it was a jolt: discarded.
        let (s, mut d) = moving_detector(110, 0);
        d.hold_left = 1;
        assert_eq!(d.moving_tick(&s, bias, [0; 3]), Action::Discard);
    }

    #[test]
    fn a_steady_offset_for_rest_s_is_a_suspected_tilt_and_tilt_s_later_the_new_zero() {
        let bias = [2048 << 16; 3];
        let v = [50_000_000, 0, 0]; // moving fast: no stop
                                    // 2 codes off on X for the whole ring, moving since tick 100: at tick 160 (rest_s =
                                    // 60 ticks done) the tilt is suspected; at 159 the window is not yet full.
        let (s, mut d) = moving_detector(159, 2);
        assert_eq!(d.moving_tick(&s, bias, v), Action::None);
        assert_eq!(d.suspect, None);
        let (s, mut d) = moving_detector(160, 2);
        assert_eq!(d.moving_tick(&s, bias, v), Action::None);
        let tilt = [2050 << 16, 2048 << 16, 2048 << 16];
        assert_eq!(d.suspect, Some((160, tilt)));
        // No offset, no suspicion.
        let (s, mut d) = moving_detector(160, 0);
        d.moving_tick(&s, bias, v);
        assert_eq!(d.suspect, None);
        // Still settling (within 2 rest_s), another steady offset: held against the new one.
        let (s, mut d) = moving_detector(200, 4);
        d.suspect = Some((160, tilt));
        d.moving_tick(&s, bias, v);
        assert_eq!(d.suspect, Some((160, [2052 << 16, 2048 << 16, 2048 << 16])));
        // 90 ticks after the suspicion it is still settling (2 rest_s = 120 ticks).
        let (s, mut d) = moving_detector(250, 4);
        d.suspect = Some((160, tilt));
        d.moving_tick(&s, bias, v);
        assert_eq!(d.suspect, Some((160, [2052 << 16, 2048 << 16, 2048 << 16])));
        // Settled (2 rest_s = 120 ticks after the suspicion, exactly), and the offset moved
        // on: a slow stroke, not a tilt.
        let (s, mut d) = moving_detector(280, 4);
        d.suspect = Some((160, tilt));
        d.moving_tick(&s, bias, v);
        assert_eq!(d.suspect, None);
        let (s, mut d) = moving_detector(300, 4);
        d.suspect = Some((160, tilt));
        d.moving_tick(&s, bias, v);
        assert_eq!(d.suspect, None);
        // Settled at the same offset for tilt_s (200 ticks): the new zero.
        let (s, mut d) = moving_detector(359, 2);
        d.suspect = Some((160, tilt));
        assert_eq!(d.moving_tick(&s, bias, v), Action::None);
        let (s, mut d) = moving_detector(360, 2);
        d.suspect = Some((160, tilt));
        assert_eq!(
            d.moving_tick(&s, bias, v),
            Action::Rebias {
                bias: tilt,
                discard: true
            }
        );
        // Not steady any more: the suspicion is dropped.
        let (s, mut d) = moving_detector(200, 2);
        d.suspect = Some((160, tilt));
        d.codes[(199 % RING as u64) as usize][0] += 15 * 40;
        d.moving_tick(&s, bias, v);
        assert_eq!(d.suspect, None);
    }

    #[test]
    fn a_lifted_device_lands_once_steady_for_rest_s() {
        // Lifted since tick 100: at 159 not yet; at 160 steady at the bias (a stop) or at an
        // offset (a new zero, the motion kept).
        let bias = [2048 << 16; 3];
        let lifted = |ticks: u64, dx: u32| {
            let (s, mut d) = moving_detector(ticks, dx);
            d.state = State::Lifted;
            let a = d.lifted_tick(&s, bias);
            (a, d.state)
        };
        assert_eq!(lifted(159, 0), (Action::None, State::Lifted));
        assert_eq!(lifted(160, 0), (Action::Stop, State::Still));
        assert_eq!(
            lifted(160, 2),
            (
                Action::Rebias {
                    bias: [2050 << 16, 2048 << 16, 2048 << 16],
                    discard: false
                },
                State::Still
            )
        );
    }

    #[test]
    fn ticks_scale_with_the_rate_and_windows_stay_in_time() {
        assert_eq!(tick_samples(100), 1);
        assert_eq!(tick_samples(20_000), 100);
        assert_eq!(tick_samples(100_000), 500);
        // At 100 Hz a tick is 10 ms: the 0.3 s rest window is 30 ticks.
        let s = Drift::default().validate(100, 0.023942).expect("valid");
        assert_eq!(s.rest_ticks, 30);
        assert!(Drift::default().validate(20_000, 0.023942).is_ok());
    }
}
