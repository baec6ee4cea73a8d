//! Drift control: at rest nothing moves; a hand's motion arrives whole, however slow, however
//! long it glides; a tilt, a lift, a knock or a machine's vibration does not move the cursor.
//!
//! The paper proves that pure double integration drifts without bound. A mouse stays put by
//! integrating only while the hand moves, and by deciding "moves" with statistics sized to
//! the sensor's own noise (measured at calibration and learnt at rest), to what the desk adds
//! (measured as it happens), and to stated limits of a hand on a desk (REFERENCE (i), (j)).
//! No threshold here is a number fitted to a scene: each is a multiple of a measured sd, set
//! by an error rate, or a hand limit in seconds or hertz ([`Drift`]), and each is derived in
//! the module of its rule.
//!
//! # The parts, a file each
//! | file | what it decides | from |
//! |---|---|---|
//! | [`ticks`] | the tick stream: 5 ms sums of the raw codes and of the integrated samples, the hand-band filter, 20 ms blocks | the rate |
//! | [`noise`] | the noise model (calibrated, learnt at rest) and the disturbance (knock, vibration) measured as it happens | calibration, rest |
//! | [`gains`] | what a disturbance above each frequency can do through each test (computed with the settings) | the tests' windows |
//! | [`rest`] | the rest statistic: when a motion starts, and where it began | a false-start budget |
//! | [`estimator`] | when a motion ends: quiet, and its velocity explained by its own uncertainty; the velocity left corrects the position (the bridge), never backwards | error rates |
//! | [`tilt`] | a steady one-sided acceleration is a tilt, not a hand; the zero followed at rest | the longest stroke |
//! | [`lift`] | the device leaves the desk: vertical displacement, not acceleration; it lands at a level gravity gives at rest | the slowest lift |
//! | [`click`] | a click's jolt does not drag the cursor | the debounce |
//!
//! # States
//! ```text
//!        start test (replay from its onset)
//! Still ----------------------------------------> Moving ----- one-sided too long --> held
//!   ^  <-- quiet, velocity explained ------------- |  ^ <------ reverses, quiets ------ |
//!   |  <-- one-sided and steady: a tilt, new zero ------------------------------------ |
//!   +-- steady (new zero if it differs) --- Lifted <-- vertical displacement (any state)
//!                                             +-- rests, then moves along the desk --> Moving (wary)
//!   +-- click freeze over ----------------- Frozen <-- button edge (any state)
//! ```
//!
//! `Config::drift = None` is the paper's pure integration; every rule here is off then.

use core::fmt;

use crate::calibration::Calibration;

pub mod click;
pub mod estimator;
pub mod gains;
pub mod lift;
pub mod noise;
pub mod rest;
pub mod ticks;
pub mod tilt;

use gains::{boxcar, max_over};
use noise::{Disturbance, Noise};
use ticks::TickStream;

/// Shortest detector tick [s]; a tick is `ceil(fs * TICK_S)` samples, so that windows counted
/// in ticks hold at every rate; at rates where `fs * TICK_S` is not whole a tick is longer
/// than 5 ms (8.3 ms at 240 Hz), at 100 Hz it is one sample (10 ms).
pub const TICK_S: f64 = 0.005;
/// Ticks of raw-code sums kept (320 ms at 5 ms ticks): the longest tick window (the lift's,
/// the hand-band filter's, the quiet test's).
pub const RING: usize = 64;
/// Ticks at rest before the zero takes a tick in (320 ms at 5 ms ticks): older than any
/// onset a start test could still claim at its alarm.
pub const REPLAY: usize = 64;
/// 20 ms blocks of integrated-sample sums kept (1.28 s at 5 ms ticks): for replaying a
/// motion's onset (a motion replays at most `BLOCKS - 1` of them, the oldest primes the
/// trapezoid) and for the tilt tests.
pub const BLOCKS: usize = 64;
/// Length of a block [s] (rounded to whole ticks).
pub const BLOCK_S: f64 = 0.02;

/// Samples per detector tick at `fs_hz`: `ceil(fs_hz * 5 / 1000)` ([`TICK_S`], computed in
/// integers so that whole products stay whole), `1..=2^14`.
pub fn tick_samples(fs_hz: u32) -> u32 {
    let ms = (TICK_S * 1000.0) as u64; // 5
    (((u64::from(fs_hz) * ms).div_ceil(1000)) as u32).clamp(1, 1 << 14)
}

/// Drift control's settings: a false-start budget, and stated limits of a hand on a desk, in
/// physical units. Everything else is derived from these and from the noise measured at
/// calibration (see each part's module).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drift {
    /// Mean time at rest between false starts that the start tests are sized to
    /// [device-hours], `1..=1e9`. The thresholds grow with its logarithm: 10x longer costs a
    /// slow stroke about one tick of detection delay.
    pub false_start_hours: f64,
    /// Motion younger than this is not delivered, and a button edge discards it [s],
    /// `0..=0.1`. Cover the button's debounce and the housekeeping period.
    pub hold_s: f64,
    /// The lowest frequency of what is not a hand [Hz]: a desk top's ring after a knock, a
    /// machine's vibration. `5..=200`; a hand on a desk moves below about 10 Hz (REFERENCE
    /// (j)). Sets the hand-band filter and the disturbance allowances.
    pub knock_hz: f64,
    /// The longest stroke of a hand [s], `0.2..=2.4`: its acceleration keeps one sign for at
    /// most half of it. Sets the tilt tests.
    pub stroke_max_s: f64,
    /// The longest glide of a drag [s], `0..=60`: a glide's velocity that faded below its
    /// uncertainty is carried into a motion that starts within this time (its ramp down).
    pub glide_max_s: f64,
    /// The slowest rise of a lift to be caught [s], `0.05..=0.5`, or `None` for no lift
    /// detection (a two-axis sensor). Sets the lift test's window.
    pub lift_rise_s: Option<f64>,
    /// Mounting tilt and cross-axis sensitivity allowed for [degrees], `0..=30`: that share
    /// of a horizontal displacement may appear on the vertical axis without being a lift.
    pub mount_tilt_deg: f64,
    /// Time constant of the zero's tracking at rest [s], `0.2..1e6`; `None` disables it.
    pub bias_tau_s: Option<f64>,
    /// Motion suppressed after a button edge [s], `0..=2`.
    pub click_freeze_s: f64,
    /// The statistics' constants (not a user setting: see [`Tuning`]).
    pub tuning: Tuning,
}

impl Default for Drift {
    /// The defaults, each with its reason:
    /// - `false_start_hours` 1e4: at rest, a false start less than once in 10 000
    ///   device-hours (so 200 device-hours show none with 98 % probability);
    /// - `hold_s` 16 ms: a button edge 10 ms after the finger (debounce and housekeeping),
    ///   plus the 5 ms tick within which the onset of a click's jolt is placed;
    /// - `knock_hz` 20: a desk top rings at 20-60 Hz, a machine at 30-100 Hz, a hand stays
    ///   below 10 Hz (REFERENCE (j));
    /// - `stroke_max_s` 2 s: the longest pointing stroke of the hand model (docs/drift-control.md);
    /// - `glide_max_s` 4 s: the longest glide of the hand model's drags;
    /// - `lift_rise_s` 0.5 s: the slowest lift of the hand model;
    /// - `mount_tilt_deg` 5: a sensor soldered within 4 degrees of the case's floor and the
    ///   ADXL335's 1 % cross-axis sensitivity;
    /// - `bias_tau_s` 10 s: the tracked zero's own noise `ND / sqrt(2 tau)` (67 ug for the
    ///   ADXL335: a drag's bias floor counts it), while it lags a temperature ramp by only
    ///   `rate * tau`, far below a tick's sd for the ADXL335's drift;
    /// - `click_freeze_s` 0.15 s: the jolt of a click.
    fn default() -> Self {
        Self {
            false_start_hours: 1e4,
            hold_s: 0.016,
            knock_hz: 20.0,
            stroke_max_s: 2.0,
            glide_max_s: 4.0,
            lift_rise_s: Some(0.5),
            mount_tilt_deg: 5.0,
            bias_tau_s: Some(10.0),
            click_freeze_s: 0.15,
            tuning: Tuning::default(),
        }
    }
}

/// The constants of drift control's statistics: sd multiples set by error rates, windows set
/// by what each test must see, fractions of the stated hand limits. Every default is derived
/// in the module of the rule that uses it; they are here, not in the settings a user sets over
/// USB, so that the lab can vary each (`cargo lab mouse --sensitivity`: what each target does
/// at half and at twice its value) and tests can switch a rule off (its control).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tuning {
    /// The tilt, landing and fall tests' bound [sd], `1..=20`: 3, a 0.13 % tail each side.
    pub k_sd: f64,
    /// The quiet and velocity tests' bound on the chi-square of the two horizontal axes,
    /// `1..=1e6`: 11.83, its 99.73 % point for 2 degrees of freedom ([`estimator`]).
    pub chi2: f64,
    /// The slow and the fast CUSUM's reference values [sd], `0.05..=10` each: 1/2 and 3/2,
    /// half the offsets each is quickest for ([`rest`]).
    pub kappa: [f64; 2],
    /// A stroke's first lobe's least height on its CUSUM [sd], `0..=100`: 5, which noise
    /// reaches in 0.7 % of runs ([`rest`]).
    pub lobe_sd: f64,
    /// The tilt test's short and long sub-windows [s], `0.02..=0.6` ([`tilt`]).
    pub sub_s: [f64; 2],
    /// The hold after a one-sided acceleration, as a fraction of `stroke_max_s`, `0..=0.5`:
    /// 1/8, its runaway bound ([`tilt`]).
    pub hold_fraction: f64,
    /// The quiet time after which a stop is a faded glide (and the time any stop's velocity
    /// waits), as a fraction of `stroke_max_s`, `0..=1`: 1/8 ([`estimator`]).
    pub fade_fraction: f64,
    /// The one-sided time that is a tilt, as a fraction of `stroke_max_s`, `0.25..=1.5`: 1/2,
    /// no lobe of a hand's stroke being longer ([`tilt`]).
    pub confirm_fraction: f64,
    /// The quiet test's window [s], `0.005..=0.3`: 20 ms, the stop latency it costs.
    pub quiet_s: f64,
    /// The disturbance's average [s], `0.02..=2`: 160 ms ([`noise`]).
    pub disturbance_s: f64,
    /// The disturbance's margin over its own noise [relative sd of an average, sd of one
    /// tick's residual], `0..=20`: 3 ([`noise`]).
    pub disturbance_sigmas: f64,
    /// The lift test's window as a fraction of the slowest rise, `0.1..=2`: 0.605, where a
    /// minimum-jerk rise's displacement gains most on the noise ([`lift`]).
    pub lift_window: f64,
    /// How far above the calibration's long-run variance the detector starts [sd of that
    /// estimate], `0..=10`: 2 ([`noise`]).
    pub q_inflation_sd: f64,
}

impl Default for Tuning {
    fn default() -> Self {
        Self {
            k_sd: 3.0,
            chi2: 11.83,
            kappa: [0.5, 1.5],
            lobe_sd: 5.0,
            sub_s: [0.1, 0.4],
            hold_fraction: 0.125,
            fade_fraction: 0.125,
            confirm_fraction: 0.5,
            quiet_s: 0.02,
            disturbance_s: 0.16,
            disturbance_sigmas: 3.0,
            lift_window: 0.605,
            q_inflation_sd: 2.0,
        }
    }
}

/// The documented range of each of drift control's parameters, inclusive, in the field's
/// unit ([`Drift`] says why each bound is where it is). [`Drift::validate`] checks them and
/// the device's key table ([`crate::profile::Profile::range`]) shows them.
pub mod range {
    /// `false_start_hours` [device-hours].
    pub const FALSE_START_HOURS: (f64, f64) = (1.0, 1e9);
    /// `hold_s` [s].
    pub const HOLD_S: (f64, f64) = (0.0, 0.1);
    /// `knock_hz` [Hz] (and its filter must fit the tick ring at the rate).
    pub const KNOCK_HZ: (f64, f64) = (5.0, 200.0);
    /// `stroke_max_s` [s].
    pub const STROKE_MAX_S: (f64, f64) = (0.2, 2.4);
    /// `glide_max_s` [s].
    pub const GLIDE_MAX_S: (f64, f64) = (0.0, 60.0);
    /// `lift_rise_s` [s], when on.
    pub const LIFT_RISE_S: (f64, f64) = (0.05, 0.5);
    /// `mount_tilt_deg` [degrees].
    pub const MOUNT_TILT_DEG: (f64, f64) = (0.0, 30.0);
    /// `bias_tau_s` [s], when on; the top is excluded.
    pub const BIAS_TAU_S: (f64, f64) = (0.2, 1e6);
    /// `click_freeze_s` [s].
    pub const CLICK_FREEZE_S: (f64, f64) = (0.0, 2.0);
}

/// The hand-band filter's two boxcars for `knock_hz` at ticks of `tick_s` [s]: 1 / knock_hz
/// and two thirds of it, in whole ticks (at least one).
fn knock_boxcars(knock_hz: f64, tick_s: f64) -> (u32, u32) {
    use crate::math::round_to_u64 as round;
    (
        round(1.0 / (knock_hz * tick_s)).max(1) as u32,
        round(2.0 / (3.0 * knock_hz * tick_s)).max(1) as u32,
    )
}

/// Whether the hand-band filter for `knock_hz` fits the tick ring at ticks of `tick_s` [s].
fn knock_fits(knock_hz: f64, tick_s: f64) -> bool {
    boxcars_fit(knock_boxcars(knock_hz, tick_s))
}

/// Whether boxcars of `l1` and `l2` ticks fit the tick ring.
fn boxcars_fit((l1, l2): (u32, u32)) -> bool {
    (l1 + l2) as usize <= RING - 2
}

/// The lowest `knock_hz` [Hz] a profile at `fs_hz` takes: the range's bottom, or higher where
/// its filter would not fit the tick ring (the filter's length falls as the frequency rises,
/// so the lowest that fits is found by bisection, to 1e-9 Hz).
pub fn knock_hz_min(fs_hz: u32) -> f64 {
    let tick_s = f64::from(tick_samples(fs_hz)) / f64::from(fs_hz.max(1));
    let (mut lo, mut hi) = range::KNOCK_HZ;
    if knock_fits(lo, tick_s) {
        return lo;
    }
    if !knock_fits(hi, tick_s) {
        return f64::INFINITY;
    }
    while hi - lo > 1e-9 {
        let mid = 0.5 * (lo + hi);
        if knock_fits(mid, tick_s) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

/// A [`Drift`] field that failed validation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DriftError {
    /// `false_start_hours` not finite or outside `1..=1e9`.
    FalseStart,
    /// `hold_s` outside `0..=0.1`.
    Hold,
    /// `knock_hz` outside `5..=200`, or its filter longer than the tick ring at this rate.
    Knock,
    /// `stroke_max_s` outside `0.2..=2.4`, or half of it longer than the block ring.
    Stroke,
    /// `glide_max_s` outside `0..=60`.
    Glide,
    /// `lift_rise_s` outside `0.05..=0.5`, or its window longer than the tick ring.
    Lift,
    /// `mount_tilt_deg` outside `0..=30`.
    MountTilt,
    /// `bias_tau_s` below 0.2 s or not below 1e6 s.
    BiasTau,
    /// `click_freeze_s` outside `0..=2`.
    ClickFreeze,
    /// A [`Tuning`] field (named) outside its range.
    Tuning(&'static str),
}

impl fmt::Display for DriftError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use range::*;
        let (name, (lo, hi), unit, tail) = match self {
            Self::FalseStart => ("false_start_hours", FALSE_START_HOURS, " device-hours", ""),
            Self::Hold => ("hold_s", HOLD_S, " s", ""),
            Self::Knock => ("knock_hz", KNOCK_HZ, " Hz", " (and its filter fit 320 ms)"),
            Self::Stroke => ("stroke_max_s", STROKE_MAX_S, " s", ""),
            Self::Glide => ("glide_max_s", GLIDE_MAX_S, " s", ""),
            Self::Lift => ("lift_rise_s", LIFT_RISE_S, " s", ", or off"),
            Self::MountTilt => ("mount_tilt_deg", MOUNT_TILT_DEG, " degrees", ""),
            Self::BiasTau => {
                let (lo, hi) = BIAS_TAU_S;
                return write!(
                    f,
                    "drift.bias_tau_s: must be at least {lo} s and below {hi:e} s, or off"
                );
            }
            Self::ClickFreeze => ("click_freeze_s", CLICK_FREEZE_S, " s", ""),
            Self::Tuning(field) => {
                return write!(f, "drift.tuning.{field}: outside its documented range")
            }
        };
        let hi = crate::profile::Shown(hi);
        write!(f, "drift.{name}: must be within {lo}..={hi}{unit}{tail}")
    }
}

impl Tuning {
    /// Checks every field against its documented range.
    fn validate(&self) -> Result<(), DriftError> {
        let within = |v: f64, lo: f64, hi: f64| v.is_finite() && v >= lo && v <= hi;
        let checks: [(&'static str, bool); 13] = [
            ("k_sd", within(self.k_sd, 1.0, 20.0)),
            ("chi2", within(self.chi2, 1.0, 1e6)),
            ("kappa", self.kappa.iter().all(|&k| within(k, 0.05, 10.0))),
            ("lobe_sd", within(self.lobe_sd, 0.0, 100.0)),
            ("sub_s", self.sub_s.iter().all(|&w| within(w, 0.02, 0.6))),
            ("hold_fraction", within(self.hold_fraction, 0.0, 0.5)),
            ("fade_fraction", within(self.fade_fraction, 0.0, 1.0)),
            ("confirm_fraction", within(self.confirm_fraction, 0.25, 1.5)),
            ("quiet_s", within(self.quiet_s, 0.005, 0.3)),
            ("disturbance_s", within(self.disturbance_s, 0.02, 2.0)),
            (
                "disturbance_sigmas",
                within(self.disturbance_sigmas, 0.0, 20.0),
            ),
            ("lift_window", within(self.lift_window, 0.1, 2.0)),
            ("q_inflation_sd", within(self.q_inflation_sd, 0.0, 10.0)),
        ];
        match checks.iter().find(|c| !c.1) {
            Some((name, _)) => Err(DriftError::Tuning(name)),
            None => Ok(()),
        }
    }
}

/// Standard normal upper tail `P(Z > z)`.
fn upper_tail(z: f64) -> f64 {
    0.5 * libm::erfc(z / core::f64::consts::SQRT_2)
}

/// The `z` with `P(Z > z) = p`, `0 < p < 1/2`, by bisection on [`upper_tail`].
pub(crate) fn z_of_tail(p: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, 40.0);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if upper_tail(mid) > p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

/// Siegmund's average run length of a one-sided CUSUM to a false alarm, with reference value
/// `kappa` and threshold `b` (both in sd of the increments), on unit-variance Gaussian
/// increments: `(e^(2 kappa b) - 1 - 2 kappa b) / (2 kappa^2)` [increments]. For a sum of
/// smooth (filtered) increments there is no overshoot and `b = h`; for raw ticks `b = h +
/// 1.166` (REFERENCE (j)).
pub fn cusum_arl(kappa: f64, b: f64) -> f64 {
    let x = 2.0 * kappa * b;
    (libm::expm1(x) - x) / (2.0 * kappa * kappa)
}

/// The `b` at which [`cusum_arl`] reaches `arl`.
fn cusum_threshold(kappa: f64, arl: f64) -> f64 {
    solve_rising(|b| cusum_arl(kappa, b), arl)
}

/// The alarm `b` on the sum of two consecutive runs of opposite sides, the first at least
/// `lobe` (a stroke's two lobes, [`rest`]), as rare as one run's passing the alarm of
/// [`cusum_threshold`]`(kappa, arl)`: a run's height has the tail `c e^(-2 kappa x)`, so
/// that sum's is `c e^(-2 kappa b) (1 + 2 kappa c (b - lobe))`, at most `1 + 2 kappa (b -
/// lobe)` times one run's; `b` solves `ARL(b) / (1 + 2 kappa (b - lobe)) = arl`.
fn pair_threshold(kappa: f64, lobe: f64, arl: f64) -> f64 {
    solve_rising(
        |b| cusum_arl(kappa, b) / (1.0 + 2.0 * kappa * (b - lobe)).max(1.0),
        arl,
    )
}

/// The `b` in `0..=1000` at which a rising `f` reaches `target`, by bisection (to 2^-200 of
/// the bracket).
fn solve_rising(f: impl Fn(f64) -> f64, target: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, 1000.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

/// `round(x * 2^16)` for a finite `0 <= x < 2^47`.
fn q16(x: f64) -> u64 {
    crate::math::round_to_u64(x * 65_536.0)
}

/// Validated drift-control coefficients (integers; sd multiples in Q8, gains in Q16). The
/// derivation of each is in the module of the rule that uses it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DriftSettings {
    /// Samples per tick `D`.
    pub(crate) tick: u32,
    /// Samples between the early start test's checks within a tick: those of one USB frame
    /// (1 ms at full speed, the mouse's polling interval), at least one ([`rest`]).
    pub(crate) early_stride: u32,
    /// Ticks per block.
    pub(crate) block: u32,
    /// The hand-band filter's two boxcars [ticks] and its delay [ticks].
    pub(crate) band: [u32; 2],
    /// How far apart a stroke's lobes' runs may end and begin for the start's onset to
    /// bridge them [ticks]: the gap `0.385 T / 1.5` for the longest stroke `T`, and the
    /// hand-band filter's length, over which it smears a lobe's end ([`rest`]).
    pub(crate) lobe_slack: u32,
    pub(crate) band_delay: u32,
    /// The tilt test's sub-windows [blocks].
    pub(crate) sub_blocks: [u32; 2],
    /// The landing test's window [blocks]; a landing without a fall seen waits this long
    /// [ticks].
    pub(crate) land_blocks: u32,
    pub(crate) land_timeout: u32,
    /// The disturbance's frequency bins: the residual's power ratio at each bin's lower
    /// edge above the first (Q16), and each bin's gains.
    pub(crate) bin_ratio_q16: [u64; noise::BINS - 1],
    pub(crate) gains: [noise::Gains; noise::BINS],
    /// Blocks before a disturbed motion's onset whose mean velocity is zero (its start).
    pub(crate) pre_blocks: u32,
    /// A glide fades after this many calm ticks; its velocity waits this many [ticks].
    pub(crate) fade_ticks: u32,
    /// The quiet test's chi-square bound over the fade's span (Q8): `chi2 + 2 ln m` for its
    /// `m = fade_ticks / quiet_ticks` windows, the same tail for the span as `chi2` for one
    /// window ([`estimator`]).
    pub(crate) fade_chi2_q8: u128,
    pub(crate) glide_ticks: u32,
    /// The longest calm a hand's motion has: the longest glide and the longest stroke
    /// [ticks] ([`estimator`]).
    pub(crate) calm_max: u32,
    /// The quiet test's chi-square bound over the longest calm (Q8): `chi2 + 2 ln m` for its
    /// `m = calm_max / quiet_ticks` windows ([`estimator`]).
    pub(crate) calm_chi2_q8: u128,
    /// What sampling at `fs` can leave of a hand's stroke's velocity, per unit of its peak
    /// velocity (Q32): `16 / (3 (D fs)^2)` for the shortest stroke `D = 2 / knock_hz`
    /// ([`estimator`]).
    pub(crate) alias_q32: u64,
    /// The block ends back over which the hand's band output is compared: the filter's span
    /// `L1 + L2 - 1` ticks and the block under way, at most `BAND_PAST`.
    pub(crate) band_lag: u32,
    /// The disturbance's average: `2^dist_shift` ticks; its margin over the noise (Q8).
    pub(crate) dist_shift: u32,
    pub(crate) dist_margin_q8: u64,
    /// The short average's margin (Q8): its upper bound's factor.
    pub(crate) dist_margin_short_q8: u64,
    /// A burst: a tick's residual beyond this many of its sd, squared (Q8).
    pub(crate) burst_k2_q8: u64,
    /// The slow CUSUM's alarm, the fast CUSUM's alarm, the slow one's two lobes' alarm [sd,
    /// Q8].
    pub(crate) alarm_q8: [u64; 3],
    /// Their reference values [sd, Q8]; a first lobe's least height [sd, Q8].
    pub(crate) kappa_q8: [i64; 2],
    pub(crate) lobe_q8: i32,
    /// A lone lobe's least height [sd, Q8]: `ln(n / P_LONE) / (2 kappa)` for the at most
    /// `n = glide_ticks / 2` runs noise makes over the longest glide ([`rest`]).
    pub(crate) lone_q8: i32,
    /// The tilt, landing and fall tests' bound squared [sd^2, Q8]; the 2-D tests' chi-square
    /// bound [Q8]; the calibrated q's inflation [sd of its estimate, Q8].
    pub(crate) k2_q8: u64,
    pub(crate) chi2_q8: u128,
    pub(crate) inflation_q8: u64,
    /// Hold of a new motion [samples].
    pub(crate) hold: u64,
    /// Quiet window [ticks].
    pub(crate) quiet_ticks: u32,
    /// Tilt durations [blocks]: the one-sided hold, half the longest stroke.
    pub(crate) tilt_blocks: [u32; 2],
    /// The lift test: window [ticks], persistence [ticks], sd multiple squared (Q8), mounting
    /// ratio (Q16); `None` without lift detection.
    pub(crate) lift: Option<lift::LiftSettings>,
    /// Bias tracking's longest average [samples].
    pub(crate) bias_samples_max: Option<u64>,
    /// Click freeze [samples].
    pub(crate) freeze: u32,
    /// Predicted mean time between false starts at rest [ticks], for reports.
    pub(crate) arl_ticks: u64,
    /// The rate [Hz].
    pub(crate) fs_hz: u32,
}

impl Drift {
    /// Validates for sampling rate `fs_hz` and a scale of `m_s2_per_lsb` (both already
    /// validated by [`crate::Config::validate`]). Every threshold is in sd of the measured
    /// noise; the scale gives only gravity in LSB, for the landing's rest ([`lift`]).
    ///
    /// # Errors
    /// The first invalid field.
    pub fn validate(&self, fs_hz: u32, m_s2_per_lsb: f64) -> Result<DriftSettings, DriftError> {
        use crate::math::round_to_u64 as round;
        use range::*;
        let within = |v: f64, lo: f64, hi: f64| v.is_finite() && v >= lo && v <= hi;
        let t = &self.tuning;
        t.validate()?;
        let fs = f64::from(fs_hz);
        let tick = tick_samples(fs_hz);
        let tick_s = f64::from(tick) / fs;
        let f_tick = 1.0 / tick_s;
        if !within(
            self.false_start_hours,
            FALSE_START_HOURS.0,
            FALSE_START_HOURS.1,
        ) {
            return Err(DriftError::FalseStart);
        }
        if !within(self.hold_s, HOLD_S.0, HOLD_S.1) {
            return Err(DriftError::Hold);
        }
        if !within(self.knock_hz, KNOCK_HZ.0, KNOCK_HZ.1) {
            return Err(DriftError::Knock);
        }
        // The hand-band filter: boxcars of 1 / knock_hz (a null there) and two thirds of it
        // (a null at 1.5 knock_hz), in whole ticks.
        let (l1, l2) = knock_boxcars(self.knock_hz, tick_s);
        if !boxcars_fit((l1, l2)) {
            return Err(DriftError::Knock);
        }
        if !within(self.stroke_max_s, STROKE_MAX_S.0, STROKE_MAX_S.1) {
            return Err(DriftError::Stroke);
        }
        let block = round(BLOCK_S / tick_s).max(1) as u32;
        let block_s = f64::from(block) * tick_s;
        // Tilt durations (tilt.rs): the hold after an eighth of the longest stroke (its
        // runaway bound), the confirmation after half of it plus the sub-window.
        let sub_blocks = t.sub_s.map(|w| round(w / block_s).max(1) as u32);
        let hold_blocks = (round(self.stroke_max_s * t.hold_fraction / block_s) as u32).max(1);
        let confirm = round(self.stroke_max_s * t.confirm_fraction / block_s) as u32;
        // The landing window (lift.rs): the hold's, in thirds.
        let land_blocks = hold_blocks.max(3);
        // The tilt tests look back over four short sub-windows and one long one, the landing
        // over its window: at most `BLOCKS - 1` complete blocks of the ring. (Within the
        // tuning's ranges only the short sub-windows can reach it; the others are kept so
        // that a wider range cannot index past the ring.)
        let looked_back = [land_blocks, 4 * sub_blocks[0], sub_blocks[1]];
        if looked_back.into_iter().max().unwrap_or(0) >= BLOCKS as u32 {
            return Err(DriftError::Stroke);
        }
        if !within(self.glide_max_s, GLIDE_MAX_S.0, GLIDE_MAX_S.1) {
            return Err(DriftError::Glide);
        }
        let lift = match self.lift_rise_s {
            None => None,
            Some(r) if within(r, LIFT_RISE_S.0, LIFT_RISE_S.1) => Some(
                lift::LiftSettings::new(
                    (r, r * t.lift_window),
                    self.knock_hz,
                    self.mount_tilt_deg,
                    self.false_start_hours,
                    (tick_s, tick),
                    m_s2_per_lsb,
                )
                .ok_or(DriftError::Lift)?,
            ),
            Some(_) => return Err(DriftError::Lift),
        };
        if !within(self.mount_tilt_deg, MOUNT_TILT_DEG.0, MOUNT_TILT_DEG.1) {
            return Err(DriftError::MountTilt);
        }
        let bias_samples_max = match self.bias_tau_s {
            None => None,
            Some(tau) if within(tau, BIAS_TAU_S.0, BIAS_TAU_S.1) && tau < BIAS_TAU_S.1 => {
                Some(round(tau * fs).max(1))
            }
            Some(_) => return Err(DriftError::BiasTau),
        };
        if !within(self.click_freeze_s, CLICK_FREEZE_S.0, CLICK_FREEZE_S.1) {
            return Err(DriftError::ClickFreeze);
        }

        // The start tests (rest.rs): 8 one-sided CUSUMs (slow and fast, X and Y, both
        // signs) and the slow ones' 4 two-lobe sums share the budget.
        let arl = self.false_start_hours * 3600.0 / tick_s * 12.0;
        let slow = cusum_threshold(t.kappa[0], arl);
        let fast = (cusum_threshold(t.kappa[1], arl) - 1.166).max(0.0);
        let pair = pair_threshold(t.kappa[0], t.lobe_sd, arl);
        let arl_ticks = round(self.false_start_hours * 3600.0 / tick_s);

        // Gains at and above each frequency bin of the disturbance, up to Nyquist (ticks and
        // windows average within a tick): what a sinusoid of tick-sum amplitude A can do
        // through each test (noise.rs).
        let sample_box = |f: f64| boxcar(tick, f / fs);
        let quiet_ticks = round(t.quiet_s / tick_s).max(1) as u32;
        let fade_ticks = round(self.stroke_max_s * t.fade_fraction / tick_s).max(1) as u32;
        let calm_max =
            round((self.glide_max_s + self.stroke_max_s) / tick_s).min(u64::from(u32::MAX)) as u32;
        // The quiet test's bound over a span of `ticks`: `chi2 + 2 ln m` for its `m` windows,
        // the same tail for the span as `chi2` for one window (Q8).
        let span_chi2_q8 = |ticks: u32| {
            let m = (f64::from(ticks) / f64::from(quiet_ticks)).max(1.0);
            u128::from(round((t.chi2 + 2.0 * libm::log(m)) * 256.0))
        };
        // (With one sample a tick, 0.8 of the tick rate is past Nyquist; the gains there
        // only fall with frequency, so the range's top does not bind.)
        let top = (0.8 * f_tick).max(self.knock_hz);
        let edge = |k: usize| {
            let hi = (f_tick / 2.0).max(self.knock_hz);
            self.knock_hz * libm::pow(hi / self.knock_hz, k as f64 / noise::BINS as f64)
        };
        let tau = core::f64::consts::TAU;
        let win = |ticks: u32| move |x: f64| boxcar(ticks.max(1), x);
        let (sub0, sub1, land) = (
            win(sub_blocks[0] * block),
            win(sub_blocks[1] * block),
            win(land_blocks / 3 * block),
        );
        // A sinusoid at x cycles a tick sums over any run of ticks to at most 1 / |sin(pi x)|
        // of its amplitude (rest.rs); x = 0 is never a sinusoid's residue here (the tick's
        // boxcar nulls the tick rate's aliases, and with one sample a tick they lie past
        // Nyquist), the guard only keeps the grid's first point finite.
        let band_run = |x: f64| {
            let s = libm::sin(core::f64::consts::PI * x).abs().max(1e-12);
            boxcar(l1, x) * boxcar(l2, x) / s
        };
        let tests: [&dyn Fn(f64) -> f64; 5] = [&band_run, &win(quiet_ticks), &sub0, &sub1, &land];
        let los: [f64; noise::BINS] = core::array::from_fn(edge);
        let longest = (sub_blocks[1] * block)
            .max(land_blocks / 3 * block)
            .max(l1)
            .max(quiet_ticks);
        let aliased = gains::aliased_maxima(fs, tick, longest, los, tests);
        let gains: [noise::Gains; noise::BINS] = core::array::from_fn(|k| {
            let lo = los[k];
            let [band_run, quiet, sub0, sub1, land] = aliased[k];
            // A sinusoid of tick-sum amplitude A at f has a per-sample amplitude of at most
            // A / (D |box(f)|), a velocity amplitude of that times fs / (2 pi f) and a
            // displacement amplitude times (fs / 2 pi f)^2 (in samples); up to 0.8 of the tick
            // rate, where the tick's own boxcar keeps at least 0.23 of it.
            let vel = max_over(lo, top.max(lo), |f| {
                fs / (tau * f * f64::from(tick) * sample_box(f).max(1e-3))
            });
            let disp = max_over(lo, top.max(lo), |f| {
                let w = fs / (tau * f);
                w * w / (f64::from(tick) * sample_box(f).max(1e-3))
            });
            noise::Gains {
                band_run_q16: q16(band_run),
                quiet_q16: q16(quiet),
                sub_q16: [q16(sub0), q16(sub1)],
                land_q16: q16(land),
                velocity_q16: q16(vel),
                // 2 d (the lift test's units), peak to peak from an arbitrary start: 4x.
                displacement: round(4.0 * disp),
            }
        });
        let bin_ratio_q16 = core::array::from_fn(|k| {
            let x = libm::sin(core::f64::consts::PI * edge(k + 1) / f_tick);
            q16(4.0 * x * x)
        });
        // The disturbance's average over about 160 ms, and its margin: 3 relative sd of an
        // average of 2^k / 2 independent squares (noise.rs).
        let dist_shift =
            (libm::round(libm::log2(t.disturbance_s / tick_s)) as i32).clamp(3, 10) as u32;
        let margin =
            |shift: u32| 1.0 + t.disturbance_sigmas * libm::sqrt(2.0 / f64::from(1u32 << shift));
        let dist_margin = margin(dist_shift);
        let dist_margin_short = margin(dist_shift - 2);
        Ok(DriftSettings {
            tick,
            early_stride: (fs_hz / 1000).max(1),
            block,
            dist_shift,
            alias_q32: {
                let d = 2.0 / self.knock_hz * fs;
                round(16.0 / 3.0 / (d * d) * 4_294_967_296.0)
            },
            dist_margin_q8: round(dist_margin * 256.0),
            dist_margin_short_q8: round(dist_margin_short * 256.0),
            burst_k2_q8: round(t.disturbance_sigmas * t.disturbance_sigmas * 256.0),
            fade_ticks,
            fade_chi2_q8: span_chi2_q8(fade_ticks),
            glide_ticks: round(self.glide_max_s / tick_s).min(u64::from(u32::MAX)) as u32,
            calm_max,
            calm_chi2_q8: span_chi2_q8(calm_max),
            band: [l1, l2],
            band_lag: ((l1 + l2 - 1).div_ceil(block) + 1).min(ticks::BAND_PAST as u32),
            lobe_slack: round(0.385 / 1.5 * self.stroke_max_s / tick_s) as u32 + l1 + l2,
            band_delay: (l1 + l2 - 2) / 2,
            sub_blocks,
            land_blocks,
            land_timeout: round(self.stroke_max_s / tick_s) as u32,
            bin_ratio_q16,
            gains,
            pre_blocks: (libm::ceil(1.0 / self.knock_hz / block_s) as u32).max(2),
            alarm_q8: [
                round(slow * 256.0),
                round(fast * 256.0),
                round(pair * 256.0),
            ],
            kappa_q8: t.kappa.map(|k| round(k * 256.0) as i64),
            lobe_q8: round(t.lobe_sd * 256.0) as i32,
            lone_q8: {
                let runs = (self.glide_max_s / tick_s / 2.0).max(1.0);
                round(libm::log(runs / rest::P_LONE) / (2.0 * t.kappa[0]) * 256.0) as i32
            },
            k2_q8: round(t.k_sd * t.k_sd * 256.0),
            chi2_q8: u128::from(round(t.chi2 * 256.0)),
            inflation_q8: round(t.q_inflation_sd * 256.0),
            hold: round(self.hold_s * fs),
            quiet_ticks,
            tilt_blocks: [hold_blocks, confirm],
            lift,
            bias_samples_max,
            freeze: round(self.click_freeze_s * fs) as u32,
            arl_ticks,
            fs_hz,
        })
    }
}

impl DriftSettings {
    /// Every derived coefficient by name and index, in its natural unit (ticks, blocks,
    /// samples as integers; Q8 and Q16 values divided out): for reports, and for the test
    /// that checks the derivation against an independent one (`host-tests/tools/
    /// drift_settings_truth.py`).
    pub fn for_each_derived(&self, mut f: impl FnMut(&'static str, usize, f64)) {
        let q8 = |v: u64| v as f64 / 256.0;
        let q16 = |v: u64| v as f64 / 65_536.0;
        let n = |v: u32| f64::from(v);
        f("tick", 0, n(self.tick));
        f("early_stride", 0, n(self.early_stride));
        f("block", 0, n(self.block));
        for (i, &l) in self.band.iter().enumerate() {
            f("band", i, n(l));
        }
        f("band_delay", 0, n(self.band_delay));
        for (i, &m) in self.sub_blocks.iter().enumerate() {
            f("sub_blocks", i, n(m));
        }
        f("land_blocks", 0, n(self.land_blocks));
        f("land_timeout", 0, n(self.land_timeout));
        for (i, &r) in self.bin_ratio_q16.iter().enumerate() {
            f("bin_ratio", i, q16(r));
        }
        for (i, g) in self.gains.iter().enumerate() {
            f("gain_band_run", i, q16(g.band_run_q16));
            f("gain_quiet", i, q16(g.quiet_q16));
            f("gain_sub_short", i, q16(g.sub_q16[0]));
            f("gain_sub_long", i, q16(g.sub_q16[1]));
            f("gain_land", i, q16(g.land_q16));
            f("gain_velocity", i, q16(g.velocity_q16));
            f("gain_displacement", i, g.displacement as f64);
        }
        f("pre_blocks", 0, n(self.pre_blocks));
        f("fade_ticks", 0, n(self.fade_ticks));
        f("glide_ticks", 0, n(self.glide_ticks));
        f("calm_max", 0, n(self.calm_max));
        f("dist_shift", 0, n(self.dist_shift));
        f("dist_margin", 0, q8(self.dist_margin_q8));
        f("dist_margin_short", 0, q8(self.dist_margin_short_q8));
        f("burst_k2", 0, q8(self.burst_k2_q8));
        for (i, &a) in self.alarm_q8.iter().enumerate() {
            f("alarm", i, q8(a));
        }
        for (i, &k) in self.kappa_q8.iter().enumerate() {
            f("kappa", i, k as f64 / 256.0);
        }
        f("lobe", 0, f64::from(self.lobe_q8) / 256.0);
        f("lone", 0, f64::from(self.lone_q8) / 256.0);
        f("k2", 0, q8(self.k2_q8));
        f("chi2", 0, self.chi2_q8 as f64 / 256.0);
        f("inflation", 0, q8(self.inflation_q8));
        f("hold", 0, self.hold as f64);
        f("quiet_ticks", 0, n(self.quiet_ticks));
        f("lobe_slack", 0, n(self.lobe_slack));
        f("fade_chi2", 0, self.fade_chi2_q8 as f64 / 256.0);
        f("calm_chi2", 0, self.calm_chi2_q8 as f64 / 256.0);
        for (i, &b) in self.tilt_blocks.iter().enumerate() {
            f("tilt_blocks", i, n(b));
        }
        if let Some(l) = &self.lift {
            f("lift_window", 0, n(l.window));
            f("lift_persist", 0, n(l.persist));
            f("lift_k2", 0, q8(l.k2_q8));
            f("lift_mount", 0, q16(u64::from(l.mount_q16)));
            f("lift_seen", 0, n(u32::from(l.seen)));
            f("lift_cube", 0, l.cube as f64);
            f("lift_two_g", 0, q16(l.two_g_q16));
            f("lift_cube_4_3", 0, l.cube_4_3 as f64);
        }
        if let Some(b) = self.bias_samples_max {
            f("bias_samples_max", 0, b as f64);
        }
        f("band_lag", 0, n(self.band_lag));
        f("alias", 0, self.alias_q32 as f64 / 4_294_967_296.0);
        f("freeze", 0, n(self.freeze));
        f("arl_ticks", 0, self.arl_ticks as f64);
    }

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
    /// The start tests' alarms [sd]: the slow (hand-band) CUSUM's, the fast one's, and the
    /// slow one's on a stroke's two lobes together.
    pub fn alarms_sd(&self) -> [f64; 3] {
        self.alarm_q8.map(|a| a as f64 / 256.0)
    }
    /// The predicted mean time between false starts at rest [s], from the CUSUMs' Gaussian
    /// run lengths (for reports beside the measured rate).
    pub fn false_start_interval_s(&self) -> f64 {
        self.arl_ticks as f64 * f64::from(self.tick) / f64::from(self.fs_hz)
    }
}

/// What drift control is doing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum State {
    /// At rest: nothing is integrated; the zero follows slow drift.
    Still,
    /// A motion: every sample is integrated.
    Moving,
    /// Lifted (or tilted off the desk): nothing is integrated until the device is steady.
    Lifted,
    /// After a button edge: nothing is integrated for the click freeze.
    Frozen,
}

/// What the tracker must do to its axes after a sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    /// Nothing.
    None,
    /// A motion started: from the velocity `carry` (zero, or a glide's that faded below its
    /// uncertainty, [`estimator`]), integrate the last `ticks` complete ticks and the current
    /// tick's samples so far ([`Detector::replay`]), then every sample.
    Start {
        /// Complete blocks to replay, `0..BLOCKS`.
        blocks: usize,
        /// The horizontal velocity the motion starts from (`W = 2 V`, Q16 counts times
        /// samples); the vertical starts from zero.
        carry: [i64; 2],
    },
    /// The motion ended: zero velocity; what was integrated stays.
    Stop,
    /// The motion ended at rest after its own deceleration: the velocity left (but for what
    /// the desk's disturbance can swing) is error, and the position moves by `dz` for it
    /// (`S -= V n / 2` over its `n` samples, less what its stops corrected already, none
    /// backwards: the zero-velocity update's bridge, [`estimator`]), then zero velocity.
    Settle {
        /// The correction per horizontal axis (`Z = 4 S` units).
        dz: [i128; 2],
    },
    /// The motion was held and must not be delivered: zero velocity and position.
    Discard,
    /// New zeros (Q16 counts) after a tilt or a landing; zero velocity, and with `discard`
    /// the held motion (the tilt's runaway) is dropped too.
    Rebias {
        /// The zeros [Q16 counts].
        bias: [i64; 3],
        /// Drop the position not yet delivered.
        discard: bool,
    },
    /// Landed, and a motion began on the desk before the landing's window was steady: the
    /// zeros (new ones if the rest between differs from the old, the old ones otherwise),
    /// then a motion from zero velocity over the last `blocks` complete blocks and the
    /// current block so far, as [`Action::Start`] ([`lift`]).
    Land {
        /// The zeros [Q16 counts].
        bias: [i64; 3],
        /// Complete blocks to replay, `0..BLOCKS`.
        blocks: usize,
    },
    /// New zeros (Q16 counts) from tracking at rest; nothing else changes.
    TrackBias([i64; 3]),
    /// The held acceleration changed from a level that may have been a tilt's: integrate,
    /// beside the motion, its shadow, the hypothesis that a tilt to zeros `bias` (Q16 counts)
    /// ended and a new motion began: from zero velocity over the last `blocks` complete blocks
    /// and the current block so far, then every sample, against `bias` ([`tilt`]).
    Shadow {
        /// The tilt's zeros [Q16 counts].
        bias: [i64; 3],
        /// Complete blocks to replay, `0..BLOCKS`.
        blocks: usize,
    },
    /// The shadow won at rest: its zeros and its motion replace the axes' (the held motion,
    /// the tilt's runaway, is dropped), at zero velocity. Any other action ends a shadow.
    Adopt,
}

/// Drift-control state of a three-axis device (X, Y horizontal, Z vertical); see the module
/// docs and each part's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Detector {
    pub(crate) stream: TickStream,
    pub(crate) noise: [Noise; 3],
    pub(crate) disturbance: [Disturbance; 3],
    pub(crate) learn: noise::Learn,
    pub(crate) rest: rest::Rest,
    pub(crate) motion: estimator::Motion,
    pub(crate) latent: estimator::Latent,
    pub(crate) tilt: tilt::Tilt,
    pub(crate) lift: lift::Lift,
    pub(crate) click: click::Click,
    pub(crate) state: State,
    /// At rest after a motion soon after a landing in doubt: for this many ticks since the
    /// rest began, what it moved is held ([`lift::LiftSettings`]' `seen`; 0 otherwise).
    pub(crate) air: u8,
    /// The tick at which the current state was entered.
    pub(crate) entered: u64,
    /// Samples the current zero is averaged over.
    pub(crate) bias_samples: u64,
    /// A motion starting before this tick follows a tilt's new zero ([`tilt`]).
    pub(crate) tilted_until: u64,
    /// The tick the last motion that was not discarded ended (or the last new zero).
    pub(crate) real_end: u64,
    /// The zeros from before the tilts taken since, less the present ones [Q16 counts, each
    /// within `i32`]; all 0 when none, or since a lift ([`tilt`], "The tilt let go").
    pub(crate) untilt: [i32; 3],
}

impl Detector {
    /// A detector starting Still after a calibration of `cal` (the device has just been seen
    /// at rest).
    pub fn new(s: &DriftSettings, cal: &[Calibration; 3]) -> Self {
        let stream = TickStream::new(s, cal);
        // Only X and Y feed the start tests ([`rest`]).
        let noise = core::array::from_fn(|a| Noise::from_calibration(s, &cal[a], a < 2));
        let disturbance = cal.map(|c| Disturbance::new(s, &c));
        let mut d = Self {
            stream,
            noise,
            disturbance,
            learn: noise::Learn::default(),
            rest: rest::Rest::default(),
            motion: estimator::Motion::default(),
            latent: estimator::Latent::default(),
            tilt: tilt::Tilt::default(),
            lift: lift::Lift::default(),
            click: click::Click::default(),
            state: State::Still,
            air: 0,
            entered: 0,
            bias_samples: u64::from(cal[0].samples),
            tilted_until: 0,
            real_end: 0,
            untilt: [0; 3],
        };
        if let Some(l) = s.lift {
            d.lift.refill(&l, &d.stream);
        }
        d.enter_still();
        d
    }

    /// The current state.
    pub const fn state(&self) -> State {
        self.state
    }

    /// Whether a motion is held back from delivery: younger than the hold, started on a
    /// disturbed desk and not yet out of its velocity, or held by the tilt tests and not yet
    /// confirmed or released; or, at rest, what a motion soon after a landing in doubt moved,
    /// until a set-down could have been seen ([`lift`]).
    pub const fn holds(&self) -> bool {
        match self.state {
            State::Moving => self.click.hold_left > 0 || self.tilt.held() || self.motion.unproven,
            State::Still => self.air_held(),
            State::Lifted | State::Frozen => false,
        }
    }

    /// [`Self::holds`] at rest: within `air` ticks of a motion's stop. (The flag first: at
    /// rest, where it is 0, a read-out asks no more.)
    const fn air_held(&self) -> bool {
        self.air != 0 && self.stream.ticks() - self.entered < self.air as u64
    }

    /// Whether delivery pauses: a motion [held](Self::holds), or one in the reversed stop's
    /// wait (calm at the last tick, its velocity against its travel): that stop's bridge
    /// never moves the cursor back, so what the motion runs back meanwhile is delivered only
    /// if the wait ends otherwise ([`estimator`]). `velocity`, the axes' velocities (`W`, Q16
    /// counts times samples), is asked for only for a motion not held.
    pub fn pauses(&self, velocity: impl FnOnce() -> [i64; 3]) -> bool {
        self.holds()
            || matches!(self.state, State::Moving) && {
                let w = velocity();
                self.backing([w[0], w[1]])
            }
    }

    /// The sample stream was interrupted (a sampling restart): whatever was moving is over,
    /// and the detector waits at rest for the next start.
    pub fn restart(&mut self) {
        self.enter_still();
        self.latent = estimator::Latent::default();
    }

    /// Adds one sample: its raw `codes`, its integrated values `y` (Q16 counts), the axes'
    /// zeros (Q16 counts), and `velocities`, asked for only when a tick ends (once in
    /// [`DriftSettings::tick_samples`] samples): the axes' velocities (`W = 2 V`,
    /// [`crate::IntegratorState::velocity`]) after the sample was integrated (if it was), and
    /// the shadow's if there is one ([`Action::Shadow`]). Returns what the tracker must do.
    #[inline(always)]
    pub fn push(
        &mut self,
        s: &DriftSettings,
        codes: [u16; 3],
        y: [i64; 3],
        bias: [i64; 3],
        velocities: impl FnOnce() -> ([i64; 3], Option<[i64; 3]>),
    ) -> Action {
        self.stream.push(codes, y);
        match self.state {
            State::Moving => {
                self.motion.sample(&mut self.click);
                self.shadow_sample();
            }
            State::Frozen => {
                if self.click.frozen_sample() {
                    self.enter_still();
                }
            }
            State::Still | State::Lifted => {}
        }
        if !self.stream.tick_done(s) {
            if self.state == State::Still
                && self.stream.partial().is_multiple_of(s.early_stride)
                && !self.rest.within_headroom(&self.stream, bias)
            {
                return self.early_start(s, bias);
            }
            return Action::None;
        }
        let (velocity, shadow) = velocities();
        self.end_tick(s, bias, velocity, shadow)
    }

    /// A tick is complete: into the rings, then the decisions. Out of line: it runs once
    /// per tick (every 15 samples at 3 kHz), and inlined into the per-sample path it would
    /// only lengthen that path's code (flash) and its register pressure.
    #[inline(never)]
    fn end_tick(
        &mut self,
        s: &DriftSettings,
        bias: [i64; 3],
        velocity: [i64; 3],
        shadow: Option<[i64; 3]>,
    ) -> Action {
        self.stream.close_tick(s);
        let moving = self.state == State::Moving;
        if moving && self.stream.block_closed() {
            self.stream.band_span_refresh(s, bias);
        }
        // (A plain range: the array's iterator is not unrolled with this body.)
        for a in 0..3 {
            // While a hand moves, its own content past the filter is not the desk's.
            let hand = if moving && a < 2 {
                self.stream.hand_band(a)
            } else {
                0
            };
            let d = &mut self.disturbance[a];
            d.update(s, &self.stream, a, hand);
            d.shaken = (d.shaken << 1) | u64::from(d.disturbed());
        }
        if let Some(l) = s.lift {
            self.lift.update(&l, &self.stream);
        }
        // The decisions: a lift first, from rest or motion; then the state's own.
        let action = if matches!(self.state, State::Still | State::Moving) && self.lifted(s, bias) {
            let held = self.holds();
            self.enter(State::Lifted);
            self.untilt = [0; 3];
            if held {
                Action::Discard
            } else {
                Action::Stop
            }
        } else {
            match self.state {
                State::Still => self.still_tick(s, bias),
                State::Moving => self.moving_tick(s, bias, velocity, shadow),
                State::Lifted => self.lifted_tick(s, bias),
                State::Frozen => Action::None,
            }
        };
        self.rest
            .refresh_headroom(s, &self.noise, &self.disturbance, self.state);
        action
    }

    /// Enters `state` at this tick.
    pub(crate) fn enter(&mut self, state: State) {
        self.state = state;
        self.entered = self.stream.ticks();
    }

    /// Enters Still: the start tests begin afresh from here. Out of line: a state change,
    /// rare, and inlined into the per-sample path (a click's freeze ending) it only adds to
    /// that path's register pressure (1.3 instructions per axis-sample at 3 kHz when LLVM
    /// chose to inline it, on the nineteenth stop).
    #[inline(never)]
    pub(crate) fn enter_still(&mut self) {
        self.enter(State::Still);
        self.air = 0;
        self.real_end = self.stream.ticks();
        self.learn.restart();
        self.tilt = tilt::Tilt::default();
        self.rest.reset(self.stream.ticks());
        self.rest.no_headroom_test();
    }

    /// Whether the desk is disturbed now on X or Y (the start tests' axes).
    pub(crate) fn shaken_xy(&self) -> bool {
        self.disturbance[0].disturbed() || self.disturbance[1].disturbed()
    }

    /// Ticks since the current state was entered.
    pub(crate) fn age(&self) -> u64 {
        self.stream.ticks() - self.entered
    }

    /// The integrated-sample sums of the last `blocks` complete blocks (`< BLOCKS`), oldest
    /// first, then those of the current block so far.
    pub fn replay(
        &self,
        s: &DriftSettings,
        blocks: usize,
    ) -> impl Iterator<Item = [crate::integrator::BlockSums; 3]> + '_ {
        self.stream.replay(s, blocks)
    }

    /// The last integrated sample of the block before the last `blocks` complete ones (Q16
    /// counts), to prime a trapezoid replay; `None` if there is no such block.
    pub fn replay_prev(&self, blocks: usize) -> Option<[i64; 3]> {
        self.stream.replay_prev(blocks)
    }
}
