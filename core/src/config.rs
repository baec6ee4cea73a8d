//! Configuration in physical units, validated once into the fixed-point [`Settings`] that the
//! sample path uses.
//!
//! # Design
//! Everything a user sets is in SI or everyday units (Hz, m/s^2 per ADC LSB, counts per inch,
//! seconds). [`Config::validate`] checks every field and derives the integer coefficients;
//! a bad field gives a [`ConfigError`] naming it, and nothing that is running changes. The
//! sample path never validates and never allocates.

use core::fmt;

use crate::calibration::Calibrator;
use crate::drift::{Drift, DriftError, DriftSettings};
use crate::integrator::Scheme;
use crate::lowpass::Lowpass;
use crate::readout::Readout;

/// Lowest accepted sampling rate [Hz].
pub const FS_MIN_HZ: u32 = 1;
/// Highest accepted sampling rate [Hz]. Up to this rate a full-scale 12-bit input integrates
/// for 24 h without saturating (see [`crate::integrator`]).
pub const FS_MAX_HZ: u32 = 100_000;
/// Lowest accepted low-pass cut-off as a fraction of the sampling rate, `fc / fs`
/// (the filter's own limit).
pub use crate::lowpass::FC_OVER_FS_MIN;
/// Fewest samples a calibration window may hold.
pub const CALIBRATION_SAMPLES_MIN: u32 = 16;
/// Most samples a calibration window may hold (`2^24`: sums of squared 16-bit codes stay
/// exact in `u64`).
pub const CALIBRATION_SAMPLES_MAX: u32 = 1 << 24;
/// Metres per inch, exactly.
pub const M_PER_INCH: f64 = 0.0254;
/// Standard gravity [m/s^2], exactly.
pub const G_M_S2: f64 = 9.806_65;
/// Smallest accepted full scale, `m_s2_per_lsb * 2^adc_bits` [m/s^2]: 2 g (+-1 g). The
/// vertical axis reads 1 g at rest, so a sensor spanning less rails lying flat and can
/// never calibrate; a smaller value is a unit slip (mV or g per code typed as m/s^2).
pub const FULL_SCALE_MIN_M_S2: f64 = 2.0 * G_M_S2;
/// Largest accepted full scale [m/s^2]: 1000 g (+-500 g), above the widest MEMS
/// accelerometers made (+-400 g); a larger value is a unit slip, and it would put a hand's
/// strokes (about 1 g) in a handful of codes.
pub const FULL_SCALE_MAX_M_S2: f64 = 1000.0 * G_M_S2;
/// Highest accepted mouse resolution [counts per inch]: one count per micrometre (25 400).
/// Finer counts carry only noise: the position noise of the ADXL335 (about 300
/// ug/sqrt(Hz)) is already about 40 um after 0.1 s of double integration
/// (`sigma_x = N_v T^1.5 / sqrt(3)`, REFERENCE.md), and 30 000 or more is a typo.
pub const COUNTS_PER_INCH_MAX: u32 = 25_400;
/// Longest accepted calibration window [s]: the user keeps the mouse still through it at
/// every plug-in and recalibration, and a minute is the longest such wait a product can ask
/// (the default is 1 s; the bias error it leaves is REFERENCE.md's, falling as
/// `1 / sqrt(window)` down to the sensor's bias instability).
pub const CALIBRATION_S_MAX: f64 = 60.0;
/// Largest accepted at-rest noise bound [m/s^2 rms]: 1 g. A window whose noise is a whole g
/// rms is a shaking hand by any reading, not rest.
pub const REST_NOISE_MAX_M_S2: f64 = G_M_S2;

// The window's top is the time bound: 60 s at the fastest rate is 6e6 samples, under 2^24.
const _: () = assert!(CALIBRATION_S_MAX * FS_MAX_HZ as f64 <= CALIBRATION_SAMPLES_MAX as f64);
// The at-rest bound in codes: 1 g over the finest accepted step (2 g over 2^16 codes) is
// 2^15 LSB, under the 2^23 LSB at which the calibrator's Q16 variance would overflow.
const _: () = assert!(REST_NOISE_MAX_M_S2 / (FULL_SCALE_MIN_M_S2 / 65_536.0) < 8_388_608.0);

/// Tracker configuration in physical units. Build the running form with [`Config::validate`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Config {
    /// Sampling rate of each axis [Hz], `FS_MIN_HZ..=FS_MAX_HZ`. Fixed by the ADC trigger
    /// timer; the core never measures time itself.
    pub fs_hz: u32,
    /// Cut-off of the optional digital single-pole low-pass [Hz], or `None` for no filter.
    /// Valid: `fs * 1e-6 <= fc < fs / 2`.
    pub lowpass_fc_hz: Option<f64>,
    /// Acceleration per ADC LSB [m/s^2], finite, with a full scale `m_s2_per_lsb *
    /// 2^adc_bits` within [`FULL_SCALE_MIN_M_S2`]`..=`[`FULL_SCALE_MAX_M_S2`] (an ADXL335,
    /// ratiometric, 300 mV/g at 3 V and so 330 mV/g at 3.3 V, on a 12-bit ADC referenced to
    /// the same 3.3 V: 10 g over 4096 codes, `9.80665 * 10 / 4096 = 0.023942`).
    pub m_s2_per_lsb: f64,
    /// ADC resolution [bits], `2..=16` (at 1 bit both codes are rails, and no calibration
    /// could ever succeed). Codes `0` and `2^bits - 1` are the rails: a
    /// calibration window that touches them is rejected as clipped.
    pub adc_bits: u8,
    /// Mouse resolution [counts per inch], `1..=COUNTS_PER_INCH_MAX`.
    pub counts_per_inch: u32,
    /// Double-integration scheme.
    pub scheme: Scheme,
    /// Length of the at-rest calibration window [s], at most [`CALIBRATION_S_MAX`];
    /// `round(calibration_s * fs)` must lie in
    /// `CALIBRATION_SAMPLES_MIN..=CALIBRATION_SAMPLES_MAX`.
    pub calibration_s: f64,
    /// Largest per-sample rms noise accepted as "at rest" during calibration [m/s^2], finite,
    /// `> 0` and at most [`REST_NOISE_MAX_M_S2`]. A window noisier than this is rejected, not
    /// averaged in. Motion itself is caught by the window's own motion test, sized to the
    /// noise it holds ([`crate::calibration`]); this bound only refuses a sensor no mouse
    /// could point with (a floating input, a shaking hand).
    pub rest_noise_max_m_s2: f64,
    /// Drift control (stillness detection, zero-velocity updates, bias tracking, click
    /// freeze), or `None` for pure double integration as in the paper.
    pub drift: Option<Drift>,
}

impl Default for Config {
    /// The Black Pill with an ADXL335 (REFERENCE (g)): 3 kHz, no digital filter (the sensor's
    /// RC output filter is the paper's single pole), 12-bit ADC, 800 counts per inch, Euler,
    /// 1 s calibration, noise below 1 m/s^2 rms (0.1 g: 37 times the ADXL335's own
    /// 300 ug/sqrt(Hz) through a 50 Hz RC filter, 2.7 mg rms; 7 times the same part with no
    /// filter capacitor at all, 1.6 kHz wide, 15 mg rms, which the bound of 0.1 m/s^2 this
    /// replaces refused). Motion is the motion test's to find, not this bound's.
    fn default() -> Self {
        Self {
            fs_hz: 3000,
            lowpass_fc_hz: None,
            m_s2_per_lsb: 9.806_65 * 10.0 / 4096.0,
            adc_bits: 12,
            counts_per_inch: 800,
            scheme: Scheme::Euler,
            calibration_s: 1.0,
            rest_noise_max_m_s2: 1.0,
            drift: Some(Drift::default()),
        }
    }
}

/// A [`Config`] field that failed validation, with the offending value where it is an integer.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ConfigError {
    /// `fs_hz` outside `FS_MIN_HZ..=FS_MAX_HZ`.
    SampleRate {
        /// The rejected rate [Hz].
        fs_hz: u32,
    },
    /// `lowpass_fc_hz` not finite, or `fc / fs` outside `[1e-6, 0.5)`.
    LowpassCutoff,
    /// `m_s2_per_lsb` not finite, or its full scale `m_s2_per_lsb * 2^adc_bits` outside
    /// `FULL_SCALE_MIN_M_S2..=FULL_SCALE_MAX_M_S2`.
    Scale,
    /// `adc_bits` outside `2..=16`.
    AdcBits {
        /// The rejected resolution [bits].
        adc_bits: u8,
    },
    /// `counts_per_inch` is outside `1..=COUNTS_PER_INCH_MAX`, or together with `m_s2_per_lsb` and `fs_hz` it gives a
    /// counts-per-integrator-unit ratio outside `[2^-63, 2^31)` (see [`crate::readout`]).
    CountsPerInch {
        /// The rejected resolution [counts/inch].
        counts_per_inch: u32,
    },
    /// `calibration_s` over `CALIBRATION_S_MAX` (which keeps the window within
    /// `CALIBRATION_SAMPLES_MAX` samples at every rate), or `calibration_s * fs_hz` not finite
    /// or under `CALIBRATION_SAMPLES_MIN` samples.
    CalibrationWindow,
    /// `rest_noise_max_m_s2` is not `> 0` or over `REST_NOISE_MAX_M_S2` (NaN included).
    RestNoise,
    /// A `drift` field is invalid.
    Drift(DriftError),
}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::SampleRate { fs_hz } => write!(
                f,
                "fs_hz = {fs_hz}: the sampling rate must be {FS_MIN_HZ}..={FS_MAX_HZ} Hz"
            ),
            Self::LowpassCutoff => {
                f.write_str("lowpass_fc_hz: the cut-off must satisfy 1e-6 * fs <= fc < fs / 2")
            }
            Self::Scale => write!(
                f,
                "m_s2_per_lsb: the full scale m_s2_per_lsb * 2^adc_bits must be {}..={} g",
                FULL_SCALE_MIN_M_S2 / G_M_S2,
                FULL_SCALE_MAX_M_S2 / G_M_S2
            ),
            Self::AdcBits { adc_bits } => {
                write!(f, "adc_bits = {adc_bits}: the ADC resolution must be 2..=16 bits (at 1 bit every code is a rail)")
            }
            Self::CountsPerInch { counts_per_inch } => write!(
                f,
                "counts_per_inch = {counts_per_inch}: must be 1..={COUNTS_PER_INCH_MAX} and give a read-out ratio in [2^-63, 2^31) counts per integrator unit"
            ),
            Self::CalibrationWindow => write!(
                f,
                "calibration_s: the window must be at most {CALIBRATION_S_MAX} s and hold at least {CALIBRATION_SAMPLES_MIN} samples"
            ),
            Self::RestNoise => f.write_str(
                "rest_noise_max_m_s2: the at-rest noise bound must be > 0 and at most 1 g (9.80665 m/s^2)",
            ),
            Self::Drift(e) => write!(f, "{e}"),
        }
    }
}

impl Config {
    /// Checks every field and derives the fixed-point coefficients.
    ///
    /// # Errors
    /// The first invalid field, in declaration order (except that the scale is checked after
    /// the resolution its full scale needs), as a [`ConfigError`].
    pub fn validate(&self) -> Result<Settings, ConfigError> {
        if !(FS_MIN_HZ..=FS_MAX_HZ).contains(&self.fs_hz) {
            return Err(ConfigError::SampleRate { fs_hz: self.fs_hz });
        }
        let fs = f64::from(self.fs_hz);
        let lowpass = match self.lowpass_fc_hz {
            None => None,
            Some(fc) => Some(Lowpass::from_ratio(fc / fs).ok_or(ConfigError::LowpassCutoff)?),
        };
        if !(2..=16).contains(&self.adc_bits) {
            return Err(ConfigError::AdcBits {
                adc_bits: self.adc_bits,
            });
        }
        // The full scale needs the resolution, so it is checked after it.
        let full_scale = self.m_s2_per_lsb * f64::from(1u32 << self.adc_bits);
        if !(FULL_SCALE_MIN_M_S2..=FULL_SCALE_MAX_M_S2).contains(&full_scale) {
            return Err(ConfigError::Scale);
        }
        let cpi_error = ConfigError::CountsPerInch {
            counts_per_inch: self.counts_per_inch,
        };
        if !(1..=COUNTS_PER_INCH_MAX).contains(&self.counts_per_inch) {
            return Err(cpi_error);
        }
        let metres_per_unit = self.m_s2_per_lsb / (Readout::POSITION_UNITS_PER_LSB_S2 * fs * fs);
        let counts_per_unit = metres_per_unit * f64::from(self.counts_per_inch) / M_PER_INCH;
        let readout = Readout::from_ratio(counts_per_unit).ok_or(cpi_error)?;
        let window = self.calibration_s * fs;
        if !(window.is_finite()
            && self.calibration_s <= CALIBRATION_S_MAX
            && window >= f64::from(CALIBRATION_SAMPLES_MIN) * (1.0 - 1e-12))
        {
            return Err(ConfigError::CalibrationWindow);
        }
        let window = crate::math::round_to_u64(window) as u32;
        // The bound as a variance in LSB^2 with 16 fractional bits; below 2^23 LSB (REST_LSB_MAX)
        // the Q16 variance is under 2^62 and fits the calibrator's u64.
        let rest = self.rest_noise_max_m_s2 / self.m_s2_per_lsb; // [LSB]
        if !(rest > 0.0 && self.rest_noise_max_m_s2 <= REST_NOISE_MAX_M_S2) {
            return Err(ConfigError::RestNoise);
        }
        let var_q16 = rest * rest * 65_536.0;
        let tick = crate::drift::tick_samples(self.fs_hz);
        let tick_us = (u64::from(tick) * 1_000_000 / u64::from(self.fs_hz)) as u32;
        let bounds = crate::calibration::BLOCK_TICKS
            .map(|ticks| crate::calibration::steady_min_q16(window / (tick * ticks)));
        let calibrator = Calibrator::new(
            window,
            crate::math::round_to_u64(var_q16).max(1),
            self.adc_bits,
            (tick, tick_us),
            bounds,
        );
        let drift = match &self.drift {
            None => None,
            Some(d) => Some(
                d.validate(self.fs_hz, self.m_s2_per_lsb)
                    .map_err(ConfigError::Drift)?,
            ),
        };
        Ok(Settings {
            drift,
            fs_hz: self.fs_hz,
            lowpass,
            scheme: self.scheme,
            readout,
            calibrator,
            metres_per_unit,
            m_s2_per_lsb: self.m_s2_per_lsb,
        })
    }
}

/// A validated [`Config`]: the fixed-point coefficients of every stage. Cheap to copy; shared
/// by all axes of a device.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    drift: Option<DriftSettings>,
    fs_hz: u32,
    lowpass: Option<Lowpass>,
    scheme: Scheme,
    readout: Readout,
    calibrator: Calibrator,
    metres_per_unit: f64,
    m_s2_per_lsb: f64,
}

impl Settings {
    /// The validated drift control, if enabled.
    pub fn drift(&self) -> Option<&DriftSettings> {
        self.drift.as_ref()
    }
    /// Sampling rate of each axis [Hz].
    pub fn fs_hz(&self) -> u32 {
        self.fs_hz
    }
    /// The digital low-pass, if configured.
    pub fn lowpass(&self) -> Option<&Lowpass> {
        self.lowpass.as_ref()
    }
    /// The low-pass coefficient `k = 1 - exp(-2 pi fc / fs)` in Q0.32, 0 without a filter.
    pub fn lowpass_k_q32(&self) -> u32 {
        self.lowpass.map_or(0, |l| l.k_q32())
    }
    /// The double-integration scheme.
    pub fn scheme(&self) -> Scheme {
        self.scheme
    }
    /// The position-to-counts read-out.
    pub fn readout(&self) -> &Readout {
        &self.readout
    }
    /// A fresh calibrator for one axis, with this configuration's window and motion bound.
    pub fn calibrator(&self) -> Calibrator {
        self.calibrator
    }
    /// Acceleration per ADC LSB [m/s^2].
    pub fn m_s2_per_lsb(&self) -> f64 {
        self.m_s2_per_lsb
    }
    /// Metres per unit of the integrator's position accumulator
    /// ([`crate::IntegratorState::position`]):
    /// `m_s2_per_lsb / (4 * 2^16 * fs^2)`. For host-side analysis; not used on the device.
    pub fn metres_per_position_unit(&self) -> f64 {
        self.metres_per_unit
    }
}
