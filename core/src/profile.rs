//! The device's settable configuration: the tracker's [`Config`] plus the axis mapping, as
//! named keys with one `f64` value each, validated as a whole.
//!
//! # Design
//! A user changes settings by name (`counts_per_inch=1600`), over USB and in flash, so the
//! configuration is a table of [`Key`]s, each with a stable one-byte id (the wire and the
//! stored record use it; a key is never renumbered), a name, and one `f64` value: integers
//! are carried exactly, an optional value that is off is NaN ("off" to a user). A value
//! that does not fit its key (a fraction for an integer, out of the integer's range, a sign
//! other than +-1) is refused at [`Profile::set`] with [`ProfileError::Value`]; a profile
//! whose values fit but do not make a working tracker is refused by [`Profile::validate`]
//! with the key that is wrong ([`ProfileError::Invalid`]), from [`Config::validate`]'s error.
//!
//! Drift control's parameters are kept while drift control is off, so turning it on again
//! restores them.
//!
//! The axis mapping says which sensor axis (ADC scan order 0 = X, 1 = Y, 2 = Z) moves the
//! cursor right and which moves it up (away from the user), each with a sign; the third axis
//! is the vertical one, which drift control's lift detection watches. [`AxisMap::route`]
//! puts a sample triple into that order (cursor X, cursor Y, vertical) before the tracker,
//! and [`AxisMap::screen`] applies the signs to the tracker's counts.
//!
//! The stored record ([`Profile::encode`]) is a format byte, a key count and `(id, value)`
//! pairs. A record from another firmware version decodes as far as it can: unknown ids are
//! skipped, missing keys keep their defaults, and the result is validated again.

use core::fmt;

use crate::config::{Config, ConfigError};
use crate::drift::{Drift, DriftError};
use crate::integrator::Scheme;

/// Which sensor axis drives the cursor, and in which sense.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct AxisMap {
    /// Sensor axis (0 = X, 1 = Y, 2 = Z) that moves the cursor right.
    pub x_axis: u8,
    /// Whether that axis's positive direction moves the cursor left instead.
    pub x_flip: bool,
    /// Sensor axis that moves the cursor up (the hand moving away from the user).
    pub y_axis: u8,
    /// Whether that axis's positive direction moves the cursor down instead.
    pub y_flip: bool,
}

impl Default for AxisMap {
    /// The board as wired: sensor X right, sensor Y away (cursor up), Z vertical.
    fn default() -> Self {
        Self {
            x_axis: 0,
            x_flip: false,
            y_axis: 1,
            y_flip: false,
        }
    }
}

impl AxisMap {
    /// The vertical axis: the one neither cursor axis uses (for a valid map).
    pub const fn vertical(&self) -> u8 {
        3 - self.x_axis - self.y_axis
    }

    /// Whether both axes are in `0..=2` and differ.
    pub const fn is_valid(&self) -> bool {
        self.x_axis < 3 && self.y_axis < 3 && self.x_axis != self.y_axis
    }

    /// A sample triple in sensor order `[x, y, z]` put into the tracker's order `[cursor x,
    /// cursor y, vertical]`. Valid maps only (indices are taken modulo 3).
    #[inline]
    pub fn route(&self, codes: [u16; 3]) -> [u16; 3] {
        let v = self.vertical();
        [
            codes[usize::from(self.x_axis % 3)],
            codes[usize::from(self.y_axis % 3)],
            codes[usize::from(v % 3)],
        ]
    }

    /// The tracker's counts `[cursor x, cursor y, vertical]` with the flips applied, in the
    /// tracker's convention (positive y is away from the user); `imu_core::hid::screen_motion`
    /// turns that into screen motion.
    pub fn screen(&self, counts: [i32; 3]) -> [i32; 3] {
        let flip = |c: i32, f: bool| if f { c.saturating_neg() } else { c };
        [
            flip(counts[0], self.x_flip),
            flip(counts[1], self.y_flip),
            counts[2],
        ]
    }
}

/// Everything the device lets a user set: the tracker's configuration, drift control's
/// parameters (kept while it is off) and the axis mapping.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Profile {
    /// The tracker's configuration; `config.drift` is `Some(self.drift)` when drift control
    /// is on, `None` when off.
    pub config: Config,
    /// Drift control's parameters, kept while it is off.
    pub drift: Drift,
    /// Which sensor axis drives the cursor.
    pub map: AxisMap,
}

impl Default for Profile {
    /// The core's default configuration with the board's axis mapping.
    fn default() -> Self {
        Self::new(Config::default())
    }
}

/// How a key's value is carried.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// An integer in `min..=max` (carried exactly in the `f64`).
    Integer {
        /// Smallest value the key's type holds.
        min: u32,
        /// Largest value the key's type holds.
        max: u32,
    },
    /// Any `f64` (the tracker's validation decides).
    Real,
    /// An `f64`, or NaN for "off".
    Optional,
    /// 0 or 1 (off, on).
    Flag,
    /// +1 or -1.
    Sign,
}

macro_rules! keys {
    ($( $(#[$doc:meta])* $variant:ident = $id:literal, $name:literal, $kind:expr, $unit:literal,
        $about:literal; )*) => {
        /// A settable value of the [`Profile`]. The id (the enum's value) is stable: it is on
        /// the wire and in flash.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        #[cfg_attr(feature = "defmt", derive(defmt::Format))]
        #[repr(u8)]
        pub enum Key {
            $( $(#[$doc])* $variant = $id, )*
        }

        impl Key {
            /// Every key, in the order `config get` lists them.
            pub const ALL: [Key; [$($id),*].len()] = [$(Key::$variant),*];

            /// The key with wire id `id`, if there is one.
            pub const fn from_id(id: u8) -> Option<Key> {
                match id {
                    $( $id => Some(Key::$variant), )*
                    _ => None,
                }
            }

            /// The key's name, as a user writes it (`counts_per_inch`).
            pub const fn name(self) -> &'static str {
                match self {
                    $( Key::$variant => $name, )*
                }
            }

            /// How the key's value is carried.
            pub const fn kind(self) -> Kind {
                match self {
                    $( Key::$variant => $kind, )*
                }
            }

            /// The unit of the key's value (`""` for a word, a flag, an index or a sign).
            pub const fn unit(self) -> &'static str {
                match self {
                    $( Key::$variant => $unit, )*
                }
            }

            /// What the key does, in one line for a user (`config get` shows it).
            pub const fn about(self) -> &'static str {
                match self {
                    $( Key::$variant => $about, )*
                }
            }
        }
    };
}

const U32: Kind = Kind::Integer {
    min: 0,
    max: u32::MAX,
};

keys! {
    /// Sampling rate [Hz] (`Config::fs_hz`).
    FsHz = 1, "fs_hz", U32, "Hz",
        "sampling rate of each axis; a board takes only the rates its timer divides exactly";
    /// Digital low-pass cut-off [Hz], off = no filter.
    LowpassFcHz = 2, "lowpass_fc_hz", Kind::Optional, "Hz",
        "single-pole low-pass before the integration (between 1e-6 fs and fs/2), or off";
    /// Acceleration per ADC code [m/s^2].
    MS2PerLsb = 3, "m_s2_per_lsb", Kind::Real, "m/s^2",
        "acceleration per ADC code; its full scale (times 2^adc_bits) must be 2 to 1000 g";
    /// ADC resolution [bits].
    AdcBits = 4, "adc_bits", Kind::Integer { min: 0, max: 255 }, "bits",
        "ADC resolution; a board takes only its own ADC's";
    /// Mouse resolution [counts per inch].
    CountsPerInch = 5, "counts_per_inch", U32, "counts/inch",
        "mouse resolution: cursor counts per inch the hand moves";
    /// Integration scheme: 0 Euler, 1 trapezoid.
    Scheme = 6, "scheme", Kind::Integer { min: 0, max: 1 }, "",
        "double integration: euler or trapezoid";
    /// Calibration window [s].
    CalibrationS = 7, "calibration_s", Kind::Real, "s",
        "still window averaged into the zero at start-up and recalibration (16 samples or more)";
    /// Largest rms noise accepted as at rest [m/s^2].
    RestNoiseMaxMS2 = 8, "rest_noise_max_m_s2", Kind::Real, "m/s^2 rms",
        "noisiest calibration window still taken as rest";
    /// Drift control on (1) or off (0).
    Drift = 9, "drift", Kind::Flag, "",
        "drift control: stillness, zero-velocity updates, zero tracking (on or off)";
    /// Drift control: mean time at rest between false starts [device-hours].
    FalseStartHours = 40, "drift.false_start_hours", Kind::Real, "device-hours",
        "mean time at rest between two false starts of the cursor";
    /// Drift control: hold of young motion [s].
    HoldS = 11, "drift.hold_s", Kind::Real, "s",
        "young motion held back until it is confirmed";
    /// Drift control: lowest frequency of a knock's ring or a machine's vibration [Hz].
    KnockHz = 41, "drift.knock_hz", Kind::Real, "Hz",
        "lowest frequency of a knock's ring or a machine's vibration, not taken as motion";
    /// Drift control: the longest stroke of a hand [s].
    StrokeMaxS = 42, "drift.stroke_max_s", Kind::Real, "s",
        "longest stroke of a hand";
    /// Drift control: the longest glide of a drag [s].
    GlideMaxS = 45, "drift.glide_max_s", Kind::Real, "s",
        "longest glide of a drag at steady speed";
    /// Drift control: the slowest lift's rise [s], off = no lift detection.
    LiftRiseS = 43, "drift.lift_rise_s", Kind::Optional, "s",
        "slowest rise of a lift, or off for no lift detection";
    /// Drift control: mounting tilt and cross-axis allowance [degrees].
    MountTiltDeg = 44, "drift.mount_tilt_deg", Kind::Real, "degrees",
        "mounting tilt and cross-axis allowance of the sensor";
    /// Drift control: zero tracking time constant [s], off = none.
    BiasTauS = 22, "drift.bias_tau_s", Kind::Optional, "s",
        "time constant of zero tracking at rest, or off";
    /// Drift control: motion suppressed after a click [s].
    ClickFreezeS = 23, "drift.click_freeze_s", Kind::Real, "s",
        "motion suppressed after a click";
    /// Sensor axis that moves the cursor right (0 X, 1 Y, 2 Z).
    XAxis = 30, "x_axis", Kind::Integer { min: 0, max: 2 }, "",
        "sensor axis that moves the cursor right: 0 X, 1 Y, 2 Z";
    /// +1, or -1 if that axis's positive direction moves the cursor left.
    XSign = 31, "x_sign", Kind::Sign, "",
        "1, or -1 if that axis's positive direction moves the cursor left";
    /// Sensor axis that moves the cursor up (0 X, 1 Y, 2 Z).
    YAxis = 32, "y_axis", Kind::Integer { min: 0, max: 2 }, "",
        "sensor axis that moves the cursor up (the hand away from the user): 0 X, 1 Y, 2 Z";
    /// +1, or -1 if that axis's positive direction moves the cursor down.
    YSign = 33, "y_sign", Kind::Sign, "",
        "1, or -1 if that axis's positive direction moves the cursor down";
}

/// The values a key takes given the rest of a profile ([`Profile::range`]), in the key's
/// unit: `min..=max`, either end possibly excluded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    /// The smallest value.
    pub min: f64,
    /// Whether `min` itself is excluded.
    pub min_excluded: bool,
    /// The largest value.
    pub max: f64,
    /// Whether `max` itself is excluded.
    pub max_excluded: bool,
}

impl Range {
    /// `min..=max`, both ends included.
    pub const fn within(min: f64, max: f64) -> Self {
        Self {
            min,
            min_excluded: false,
            max,
            max_excluded: false,
        }
    }

    /// Whether `v` lies in the range (NaN does not).
    pub fn contains(&self, v: f64) -> bool {
        let above = if self.min_excluded {
            v > self.min
        } else {
            v >= self.min
        };
        let below = if self.max_excluded {
            v < self.max
        } else {
            v <= self.max
        };
        above && below
    }
}

impl fmt::Display for Range {
    /// As `0.2..=2.4`, in words where an end is excluded: `0.003 to below 1500`, `above 0,
    /// up to 9.80665`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // Each included end rounded inwards to the digits shown, so that the value a user
        // reads and types back is taken (0.00478840... shows as 0.0047885, not 0.0047884).
        let (lo, hi) = (
            Shown(if self.min_excluded {
                self.min
            } else {
                Shown::inward(self.min, true)
            }),
            Shown(if self.max_excluded {
                self.max
            } else {
                Shown::inward(self.max, false)
            }),
        );
        match (self.min_excluded, self.max_excluded) {
            (false, false) => write!(f, "{lo}..={hi}"),
            (false, true) => write!(f, "{lo} to below {hi}"),
            (true, false) => write!(f, "above {lo}, up to {hi}"),
            (true, true) => write!(f, "above {lo}, below {hi}"),
        }
    }
}

/// A number as a person reads it in a message: plainly from 1e-4 to below 1e7 (and 0),
/// in exponent form outside (`1e9`, not `1000000000`), with at most 6 significant digits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shown(pub f64);

impl Shown {
    /// The digits [`Shown`] prints after the point for `v` (plain form), if it prints it plain.
    fn decimals(v: f64) -> Option<i32> {
        let a = libm::fabs(v);
        if v == 0.0 || !v.is_finite() {
            return Some(0);
        }
        (1e-4..1e7)
            .contains(&a)
            .then(|| (5 - libm::floor(libm::log10(a)) as i32).clamp(0, 9))
    }

    /// `v` rounded up (`up`) or down to the digits it is shown with, so that what is shown
    /// lies on that side of `v`. Values shown in exponent form are shown exactly.
    pub fn inward(v: f64, up: bool) -> f64 {
        match Self::decimals(v) {
            Some(d) => {
                let scale = libm::pow(10.0, f64::from(d));
                let r = if up {
                    libm::ceil(v * scale - 1e-6)
                } else {
                    libm::floor(v * scale + 1e-6)
                };
                // `+ 0.0` makes the ceiling of a tiny negative, -0, the 0 a person types.
                r / scale + 0.0
            }
            None => v,
        }
    }
}

impl fmt::Display for Shown {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // -0 is shown as 0.
        let v = self.0 + 0.0;
        let Some(digits) = Self::decimals(v) else {
            return write!(f, "{v:e}");
        };
        // Six significant digits, trailing zeros dropped: 0.023942 stays, 1/3 is 0.333333.
        let digits = digits as usize;
        let mut buf = heapless::String::<32>::new();
        if fmt::write(&mut buf, format_args!("{v:.digits$}")).is_err() {
            return write!(f, "{v}");
        }
        let s = if buf.contains('.') {
            buf.trim_end_matches('0').trim_end_matches('.')
        } else {
            buf.as_str()
        };
        f.write_str(s)
    }
}

/// The words a user types for the scheme's values (0 Euler, 1 trapezoid).
pub const SCHEMES: [&str; 2] = ["euler", "trapezoid"];
/// The words a user types for a flag's values (0 off, 1 on).
pub const FLAG_WORDS: [&str; 2] = ["off", "on"];

impl Key {
    /// The words the key takes instead of numbers, by value (a flag's `off`/`on`, the
    /// scheme's); empty for a key of numbers.
    pub const fn words(self) -> &'static [&'static str] {
        match (self, self.kind()) {
            (_, Kind::Flag) => &FLAG_WORDS,
            (Key::Scheme, _) => &SCHEMES,
            _ => &[],
        }
    }

    /// Value `v` of this key as a word, where it is one: `off` for an optional key that is
    /// off (NaN), a flag's or the scheme's word; `None` for a number (shown as the caller
    /// formats numbers).
    pub fn word(self, v: f64) -> Option<&'static str> {
        if self.kind() == Kind::Optional && v.is_nan() {
            return Some("off");
        }
        // A word key's values are its words' positions; anything else shows as a number
        // (NaN is not whole).
        if v < 0.0 || libm::trunc(v) != v {
            return None;
        }
        self.words().get(v as usize).copied()
    }

    /// The value `text` gives the key as a user types it (`KEY=text`), or `None` if the key
    /// does not take it ([`Self::wanted`] says what it takes). A key of words takes its words
    /// only, in any case (`drift=1` is not a flag's number); the others take finite numbers,
    /// and `off` where they may be off. Only the form is judged here: [`Profile::set`] and
    /// [`Profile::validate`] judge the value.
    pub fn read(self, text: &str) -> Option<f64> {
        let t = text.trim();
        let words = self.words();
        if !words.is_empty() {
            return words
                .iter()
                .position(|w| w.eq_ignore_ascii_case(t))
                .map(|i| i as f64);
        }
        if self.kind() == Kind::Optional && t.eq_ignore_ascii_case("off") {
            return Some(f64::NAN);
        }
        t.parse::<f64>().ok().filter(|v| v.is_finite())
    }

    /// What a typed value must be, in words, for a message: `must be on or off`.
    pub const fn wanted(self) -> &'static str {
        match (self, self.kind()) {
            (_, Kind::Flag) => "must be on or off",
            (Key::Scheme, _) => "must be euler or trapezoid",
            (_, Kind::Optional) => "must be a finite number or off",
            _ => "must be a finite number",
        }
    }

    /// The key called `name`, if there is one.
    pub fn from_name(name: &str) -> Option<Key> {
        Key::ALL.into_iter().find(|k| k.name() == name)
    }

    /// The key a [`ConfigError`] names.
    pub const fn of_error(e: ConfigError) -> Key {
        match e {
            ConfigError::SampleRate { .. } => Key::FsHz,
            ConfigError::LowpassCutoff => Key::LowpassFcHz,
            ConfigError::Scale => Key::MS2PerLsb,
            ConfigError::AdcBits { .. } => Key::AdcBits,
            ConfigError::CountsPerInch { .. } => Key::CountsPerInch,
            ConfigError::CalibrationWindow => Key::CalibrationS,
            ConfigError::RestNoise => Key::RestNoiseMaxMS2,
            ConfigError::Drift(d) => match d {
                DriftError::FalseStart => Key::FalseStartHours,
                DriftError::Hold => Key::HoldS,
                DriftError::Knock => Key::KnockHz,
                DriftError::Stroke => Key::StrokeMaxS,
                DriftError::Glide => Key::GlideMaxS,
                DriftError::Lift => Key::LiftRiseS,
                DriftError::MountTilt => Key::MountTiltDeg,
                DriftError::BiasTau => Key::BiasTauS,
                DriftError::ClickFreeze => Key::ClickFreezeS,
                // The tuning has no key (a profile always has the default one).
                DriftError::Tuning(_) => Key::Drift,
            },
        }
    }
}

impl fmt::Display for Key {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Why a value or a profile was refused.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ProfileError {
    /// The value does not fit the key's kind (a fraction or out of range for an integer, not
    /// 0 or 1 for a flag, not +-1 for a sign).
    Value(Key),
    /// Both cursor axes are the same sensor axis.
    SameAxis,
    /// The configuration does not validate ([`Config::validate`]).
    Invalid(ConfigError),
}

impl ProfileError {
    /// The key the error names.
    pub const fn key(&self) -> Key {
        match *self {
            Self::Value(k) => k,
            Self::SameAxis => Key::YAxis,
            Self::Invalid(e) => Key::of_error(e),
        }
    }
}

impl fmt::Display for ProfileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Value(k) => match k.kind() {
                Kind::Integer { min, max } => write!(f, "{k}: must be an integer in {min}..={max}"),
                Kind::Flag => write!(f, "{k}: must be 0 (off) or 1 (on)"),
                Kind::Sign => write!(f, "{k}: must be 1 or -1"),
                Kind::Real | Kind::Optional => write!(f, "{k}: not a valid number"),
            },
            Self::SameAxis => f.write_str("y_axis: must differ from x_axis"),
            Self::Invalid(e) => write!(f, "{e}"),
        }
    }
}

/// Format byte of the stored record ([`Profile::encode`]).
pub const RECORD_FORMAT: u8 = 1;
/// Length of a stored record with every key [bytes]: format, count, 9 bytes per key.
pub const RECORD_LEN: usize = 2 + 9 * Key::ALL.len();

/// Why a stored record could not be read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RecordError {
    /// Shorter than its header or its pairs say.
    Truncated,
    /// A format this firmware does not read.
    Format(u8),
}

fn opt(v: Option<f64>) -> f64 {
    v.unwrap_or(f64::NAN)
}

fn from_opt(v: f64) -> Option<f64> {
    (!v.is_nan()).then_some(v)
}

impl Profile {
    /// A profile with `config` (its drift parameters, or the defaults if it has none) and
    /// the board's axis mapping.
    pub fn new(config: Config) -> Self {
        Self {
            config,
            drift: config.drift.unwrap_or_default(),
            map: AxisMap::default(),
        }
    }

    /// The value of `key` (NaN for an optional value that is off).
    pub fn get(&self, key: Key) -> f64 {
        let (c, d, m) = (&self.config, &self.drift, &self.map);
        let sign = |flip: bool| if flip { -1.0 } else { 1.0 };
        match key {
            Key::FsHz => f64::from(c.fs_hz),
            Key::LowpassFcHz => opt(c.lowpass_fc_hz),
            Key::MS2PerLsb => c.m_s2_per_lsb,
            Key::AdcBits => f64::from(c.adc_bits),
            Key::CountsPerInch => f64::from(c.counts_per_inch),
            Key::Scheme => match c.scheme {
                Scheme::Euler => 0.0,
                Scheme::Trapezoid => 1.0,
            },
            Key::CalibrationS => c.calibration_s,
            Key::RestNoiseMaxMS2 => c.rest_noise_max_m_s2,
            Key::Drift => f64::from(u8::from(c.drift.is_some())),
            Key::HoldS => d.hold_s,
            Key::BiasTauS => opt(d.bias_tau_s),
            Key::ClickFreezeS => d.click_freeze_s,
            Key::FalseStartHours => d.false_start_hours,
            Key::KnockHz => d.knock_hz,
            Key::StrokeMaxS => d.stroke_max_s,
            Key::LiftRiseS => opt(d.lift_rise_s),
            Key::MountTiltDeg => d.mount_tilt_deg,
            Key::GlideMaxS => d.glide_max_s,
            Key::XAxis => f64::from(m.x_axis),
            Key::XSign => sign(m.x_flip),
            Key::YAxis => f64::from(m.y_axis),
            Key::YSign => sign(m.y_flip),
        }
    }

    /// Sets `key` to `value`. Only the value's kind is checked here; [`Self::validate`]
    /// checks the whole.
    ///
    /// # Errors
    /// [`ProfileError::Value`] if `value` does not fit the key's [`Kind`]; nothing changes.
    pub fn set(&mut self, key: Key, value: f64) -> Result<(), ProfileError> {
        let bad = ProfileError::Value(key);
        let int = |v: f64| -> Result<u32, ProfileError> {
            let Kind::Integer { min, max } = key.kind() else {
                return Err(bad);
            };
            // In range first (NaN fails), then whole: the cast truncates exactly in range.
            if v >= f64::from(min) && v <= f64::from(max) && f64::from(v as u32) == v {
                Ok(v as u32)
            } else {
                Err(bad)
            }
        };
        let flip = |v: f64| match v {
            1.0 => Ok(false),
            -1.0 => Ok(true),
            _ => Err(bad),
        };
        let real = |v: f64| if v.is_nan() { Err(bad) } else { Ok(v) };
        let (c, d, m) = (&mut self.config, &mut self.drift, &mut self.map);
        match key {
            Key::FsHz => c.fs_hz = int(value)?,
            Key::LowpassFcHz => c.lowpass_fc_hz = from_opt(value),
            Key::MS2PerLsb => c.m_s2_per_lsb = real(value)?,
            Key::AdcBits => c.adc_bits = int(value)? as u8,
            Key::CountsPerInch => c.counts_per_inch = int(value)?,
            Key::Scheme => {
                c.scheme = if int(value)? == 0 {
                    Scheme::Euler
                } else {
                    Scheme::Trapezoid
                }
            }
            Key::CalibrationS => c.calibration_s = real(value)?,
            Key::RestNoiseMaxMS2 => c.rest_noise_max_m_s2 = real(value)?,
            Key::Drift => match value {
                0.0 => c.drift = None,
                1.0 => c.drift = Some(*d),
                _ => return Err(bad),
            },
            Key::HoldS => d.hold_s = real(value)?,
            Key::BiasTauS => d.bias_tau_s = from_opt(value),
            Key::ClickFreezeS => d.click_freeze_s = real(value)?,
            Key::FalseStartHours => d.false_start_hours = real(value)?,
            Key::KnockHz => d.knock_hz = real(value)?,
            Key::StrokeMaxS => d.stroke_max_s = real(value)?,
            Key::LiftRiseS => d.lift_rise_s = from_opt(value),
            Key::MountTiltDeg => d.mount_tilt_deg = real(value)?,
            Key::GlideMaxS => d.glide_max_s = real(value)?,
            Key::XAxis => m.x_axis = int(value)? as u8,
            Key::XSign => m.x_flip = flip(value)?,
            Key::YAxis => m.y_axis = int(value)? as u8,
            Key::YSign => m.y_flip = flip(value)?,
        }
        if c.drift.is_some() {
            c.drift = Some(*d);
        }
        Ok(())
    }

    /// The values `key` takes with the rest of this profile as it is, in the key's unit
    /// ([`Key::unit`]); `None` for a flag or a sign, whose values [`Kind`] lists. The range
    /// depends on the other keys where the core's validation does: the low-pass cut-off and
    /// the calibration window on `fs_hz`, the scale on `adc_bits` (each taken within its
    /// own range), and `drift.knock_hz`'s bottom on the rate (its filter must fit the tick
    /// ring). The cursor axes must differ, which is not a range.
    pub fn range(&self, key: Key) -> Option<Range> {
        use crate::config::{
            CALIBRATION_SAMPLES_MIN, CALIBRATION_S_MAX, COUNTS_PER_INCH_MAX, FC_OVER_FS_MIN,
            FS_MAX_HZ, FS_MIN_HZ, FULL_SCALE_MAX_M_S2, FULL_SCALE_MIN_M_S2, REST_NOISE_MAX_M_S2,
        };
        use crate::drift::range as d;
        let fs = f64::from(self.config.fs_hz.clamp(FS_MIN_HZ, FS_MAX_HZ));
        let codes = f64::from(1u32 << self.config.adc_bits.clamp(2, 16));
        let pair = |(lo, hi): (f64, f64)| Some(Range::within(lo, hi));
        match key {
            Key::FsHz => pair((f64::from(FS_MIN_HZ), f64::from(FS_MAX_HZ))),
            Key::LowpassFcHz => Some(Range {
                max_excluded: true,
                ..Range::within(FC_OVER_FS_MIN * fs, fs / 2.0)
            }),
            Key::MS2PerLsb => pair((FULL_SCALE_MIN_M_S2 / codes, FULL_SCALE_MAX_M_S2 / codes)),
            Key::AdcBits => pair((2.0, 16.0)),
            Key::CountsPerInch => pair((1.0, f64::from(COUNTS_PER_INCH_MAX))),
            Key::CalibrationS => pair((f64::from(CALIBRATION_SAMPLES_MIN) / fs, CALIBRATION_S_MAX)),
            Key::RestNoiseMaxMS2 => Some(Range {
                min_excluded: true,
                ..Range::within(0.0, REST_NOISE_MAX_M_S2)
            }),
            Key::FalseStartHours => pair(d::FALSE_START_HOURS),
            Key::HoldS => pair(d::HOLD_S),
            Key::KnockHz => pair((
                crate::drift::knock_hz_min(self.config.fs_hz.clamp(FS_MIN_HZ, FS_MAX_HZ)),
                d::KNOCK_HZ.1,
            )),
            Key::StrokeMaxS => pair(d::STROKE_MAX_S),
            Key::GlideMaxS => pair(d::GLIDE_MAX_S),
            Key::LiftRiseS => pair(d::LIFT_RISE_S),
            Key::MountTiltDeg => pair(d::MOUNT_TILT_DEG),
            Key::BiasTauS => Some(Range {
                max_excluded: true,
                ..Range::within(d::BIAS_TAU_S.0, d::BIAS_TAU_S.1)
            }),
            Key::ClickFreezeS => pair(d::CLICK_FREEZE_S),
            Key::Scheme | Key::XAxis | Key::YAxis => match key.kind() {
                Kind::Integer { min, max } => pair((f64::from(min), f64::from(max))),
                _ => None,
            },
            Key::Drift | Key::XSign | Key::YSign => None,
        }
    }

    /// Checks the whole profile: the axis mapping and the tracker's configuration.
    ///
    /// # Errors
    /// [`ProfileError::SameAxis`], or [`ProfileError::Invalid`] with the first invalid field
    /// of the configuration, or of drift control's kept parameters while it is off.
    pub fn validate(&self) -> Result<(), ProfileError> {
        if !self.map.is_valid() {
            return Err(ProfileError::SameAxis);
        }
        self.config.validate().map_err(ProfileError::Invalid)?;
        // Drift control's parameters are kept while it is off, for when it is turned on
        // again: they are held to their ranges all the same, so that `drift=on` never fails
        // on a value set long before.
        if self.config.drift.is_none() {
            self.drift
                .validate(self.config.fs_hz, self.config.m_s2_per_lsb)
                .map_err(|e| ProfileError::Invalid(ConfigError::Drift(e)))?;
        }
        Ok(())
    }

    /// The stored record: [`RECORD_FORMAT`], the key count, then `(id, value as f64 LE)`
    /// for every key. Returns the length written ([`RECORD_LEN`]).
    pub fn encode(&self, out: &mut [u8; RECORD_LEN]) -> usize {
        out[0] = RECORD_FORMAT;
        out[1] = Key::ALL.len() as u8;
        for (pair, key) in out[2..].chunks_exact_mut(9).zip(Key::ALL) {
            pair[0] = key as u8;
            pair[1..].copy_from_slice(&self.get(key).to_le_bytes());
        }
        RECORD_LEN
    }

    /// A stored record read back onto the defaults: unknown ids and values that do not fit
    /// their key are skipped (the default stays), missing keys keep the default. The result
    /// is not validated: call [`Self::validate`].
    ///
    /// # Errors
    /// [`RecordError`] if the record is shorter than it says or of another format.
    pub fn decode(record: &[u8]) -> Result<Self, RecordError> {
        let [format, count, pairs @ ..] = record else {
            return Err(RecordError::Truncated);
        };
        if *format != RECORD_FORMAT {
            return Err(RecordError::Format(*format));
        }
        let pairs = pairs
            .get(..usize::from(*count) * 9)
            .ok_or(RecordError::Truncated)?;
        let mut p = Profile::default();
        let mut drift_on = p.config.drift.is_some();
        for pair in pairs.chunks_exact(9) {
            let mut v = [0; 8];
            v.copy_from_slice(&pair[1..]);
            let value = f64::from_le_bytes(v);
            match Key::from_id(pair[0]) {
                // Applied last, so that drift parameters stored after it are kept.
                Some(Key::Drift) => drift_on = value == 1.0,
                Some(key) => {
                    let _ = p.set(key, value);
                }
                None => {}
            }
        }
        p.config.drift = drift_on.then_some(p.drift);
        Ok(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_are_unique_and_round_trip() {
        for (i, k) in Key::ALL.iter().enumerate() {
            assert_eq!(Key::from_id(*k as u8), Some(*k));
            assert_eq!(Key::from_name(k.name()), Some(*k));
            assert!(Key::ALL[..i].iter().all(|o| *o as u8 != *k as u8));
        }
        assert_eq!(Key::from_id(0), None);
        assert_eq!(Key::from_name("fs"), None);
    }

    #[test]
    fn map_routes_and_flips() {
        let m = AxisMap {
            x_axis: 1,
            x_flip: true,
            y_axis: 2,
            y_flip: false,
        };
        assert_eq!(m.vertical(), 0);
        assert_eq!(m.route([10, 20, 30]), [20, 30, 10]);
        assert_eq!(m.screen([5, -6, 7]), [-5, -6, 7]);
        assert_eq!(AxisMap::default().route([1, 2, 3]), [1, 2, 3]);
    }
}
