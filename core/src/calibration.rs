//! Bias calibration over a window at rest: the mean with 16 fractional bits, and a noise
//! estimate that rejects a window with motion in it.
//!
//! # Design
//! The sums are exact integers (`u64` sum and sum of squares of `u16` codes, at most `2^24`
//! samples), so the mean and variance are exact rationals, rounded once:
//! - bias `= round(sum * 2^16 / n)` in Q16 counts (half up), within `2^-17` LSB of the mean;
//! - variance `= (n sum_sq - sum^2) / (n (n - 1))` [LSB^2] (unbiased), compared exactly with
//!   the configured bound; the reported rms is `floor(sqrt(variance) * 2^16)` in Q16 counts.
//!
//! A window whose variance exceeds the bound had motion in it (or a tap on the desk); it is
//! rejected as a whole, never averaged in. A window that touches either ADC rail (code `0` or
//! `2^bits - 1`) is rejected as clipped: a clipped mean is not the bias.

use core::fmt;

use crate::math;
use crate::AdcCode;

/// Result of a good calibration window for one axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Calibration {
    /// The bias (mean code at rest) in Q16 counts, `0..=65535 * 2^16`.
    pub bias_q16: i64,
    /// Per-sample rms noise at rest in Q16 counts (unbiased variance, square root floored).
    pub noise_rms_q16: u64,
    /// Number of samples averaged.
    pub samples: u32,
}

/// Why a calibration window was rejected.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum CalibrationError {
    /// The window's variance exceeded the at-rest bound: the device moved.
    Motion {
        /// The window's rms noise in Q16 counts.
        noise_rms_q16: u64,
    },
    /// A sample sat on an ADC rail (code 0 or full scale): clipped or disconnected sensor.
    Clipped {
        /// The rail code seen.
        code: u16,
    },
}

impl fmt::Display for CalibrationError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Motion { noise_rms_q16 } => write!(
                f,
                "motion during calibration: rms {:.3} LSB is above the at-rest bound",
                *noise_rms_q16 as f64 / 65_536.0
            ),
            Self::Clipped { code } => write!(
                f,
                "ADC code {code} is a rail: the sensor is clipped or disconnected"
            ),
        }
    }
}

/// Accumulates one axis's calibration window. Its window length and bound come from
/// [`crate::Settings::calibrator`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Calibrator {
    window: u32,
    var_max_q16: u64,
    rail: u16,
    n: u32,
    sum: u64,
    sum_sq: u64,
    clipped: Option<u16>,
}

impl Calibrator {
    /// A calibrator for `window` samples (`2..=2^24`) that rejects a variance above
    /// `var_max_q16` (LSB^2 in Q16) and any code at `0` or `2^adc_bits - 1`.
    pub(crate) const fn new(window: u32, var_max_q16: u64, adc_bits: u8) -> Self {
        Self {
            window,
            var_max_q16,
            rail: ((1u32 << adc_bits) - 1) as u16,
            n: 0,
            sum: 0,
            sum_sq: 0,
            clipped: None,
        }
    }

    /// Window length [samples].
    pub const fn window(&self) -> u32 {
        self.window
    }

    /// Samples accumulated so far.
    pub const fn samples(&self) -> u32 {
        self.n
    }

    /// `true` once the window is full; further samples are ignored until [`Self::restart`].
    pub const fn is_full(&self) -> bool {
        self.n >= self.window
    }

    /// Adds one sample, unless the window is already full.
    #[inline]
    pub fn push(&mut self, x: AdcCode) {
        if self.is_full() {
            return;
        }
        if x.0 == 0 || x.0 >= self.rail {
            self.clipped.get_or_insert(x.0);
        }
        let v = u64::from(x.0);
        self.n += 1;
        self.sum += v; // <= 2^24 * 2^16: exact
        self.sum_sq += v * v; // <= 2^24 * 2^32: exact
    }

    /// Empties the window.
    pub fn restart(&mut self) {
        *self = Self::new(self.window, self.var_max_q16, self.rail.count_ones() as u8);
    }

    /// The calibration from the samples so far (normally a full window; at least 2 samples).
    ///
    /// # Errors
    /// [`CalibrationError::Clipped`] if a sample sat on a rail, [`CalibrationError::Motion`]
    /// if the variance exceeds the bound.
    pub fn finish(&self) -> Result<Calibration, CalibrationError> {
        if let Some(code) = self.clipped {
            return Err(CalibrationError::Clipped { code });
        }
        let n = u128::from(self.n.max(2));
        let sum = u128::from(self.sum);
        // n * sum_sq - sum^2 >= 0 (Cauchy-Schwarz); < 2^24 * 2^56 = 2^80.
        let scatter = n * u128::from(self.sum_sq) - sum * sum;
        let dof = n * (n - 1);
        let noise_rms_q16 = math::isqrt_u128((scatter << 32) / dof) as u64;
        if scatter << 16 > u128::from(self.var_max_q16) * dof {
            return Err(CalibrationError::Motion { noise_rms_q16 });
        }
        let bias_q16 = (((sum << 17) + n) / (2 * n)) as i64; // round half up of sum 2^16 / n
        Ok(Calibration {
            bias_q16,
            noise_rms_q16,
            samples: self.n,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cal(window: u32, var_max_lsb2: u64) -> Calibrator {
        Calibrator::new(window, var_max_lsb2 << 16, 12)
    }

    #[test]
    fn mean_is_rounded_to_q16_and_variance_is_unbiased() {
        let mut c = cal(4, 100);
        for x in [2000, 2001, 2001, 2001] {
            c.push(AdcCode(x));
        }
        assert!(c.is_full());
        let r = c.finish().expect("at rest");
        // mean 2000.75 exactly; variance (4 * 16012003 - 8003^2) / 12 = 0.25 -> rms 0.5.
        assert_eq!(r.bias_q16, 2000 * 65_536 + 49_152);
        assert_eq!(r.noise_rms_q16, 32_768);
        assert_eq!(r.samples, 4);
    }

    #[test]
    fn variance_above_bound_is_motion_not_averaged_in() {
        let mut c = cal(4, 1);
        for x in [2000, 2004, 2000, 2004] {
            c.push(AdcCode(x)); // variance 16/3 > 1
        }
        assert!(matches!(c.finish(), Err(CalibrationError::Motion { .. })));
        c.restart();
        assert_eq!(c.samples(), 0);
    }

    #[test]
    fn rails_are_clipping() {
        let mut c = cal(3, 100);
        for x in [2000, 4095, 2000] {
            c.push(AdcCode(x));
        }
        assert_eq!(c.finish(), Err(CalibrationError::Clipped { code: 4095 }));
        let mut c = cal(3, 100);
        c.push(AdcCode(0));
        assert_eq!(c.finish(), Err(CalibrationError::Clipped { code: 0 }));
    }

    #[test]
    fn full_window_ignores_further_samples() {
        let mut c = cal(2, 100);
        for x in [10, 10, 3000] {
            c.push(AdcCode(x));
        }
        assert_eq!(c.finish().map(|r| r.bias_q16), Ok(10 << 16));
    }
}
