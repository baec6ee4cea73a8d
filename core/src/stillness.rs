//! Drift control: stillness detection, zero-velocity updates, bias tracking at rest, and a
//! click freeze. The paper proves that pure double integration drifts without bound; the
//! mouse stays put at rest by not integrating while it is still.
//!
//! # Design
//! - Detector: over a window of `W` samples per axis (running sums, exact integers), both the
//!   variance of the raw codes and the squared distance of their mean from the bias, each
//!   compared with the calibrated noise variance `sigma^2` (floored at 1/4 LSB^2). The device
//!   is still when, on every axis, both are below `still_factor * sigma^2`, and moving as soon
//!   as either exceeds `move_factor * sigma^2` on any axis (hysteresis). The variance catches a
//!   changing acceleration, the mean a steady one (a pure variance test would call the flat
//!   top of a stroke's acceleration "still" and stop it mid-stroke). A tilt, which moves
//!   gravity into an axis, is therefore motion until the device is recalibrated.
//! - Zero-velocity update: while still nothing is integrated, velocity is held at zero and
//!   no position accrues, so the cursor cannot creep. The window's filtered samples are
//!   kept; when motion is detected they are integrated first, from zero velocity, so the
//!   stroke's onset (which the window needed to see) is not lost.
//! - Bias tracking: while still, each full window moves the bias `1/M` of the way to the
//!   window's mean (`M = bias_tau / window`), following slow drift (temperature).
//! - Click freeze: for `click_freeze` after a button edge nothing is integrated, and
//!   velocity restarts from zero: the hand's jolt when clicking does not drag the cursor.

use core::fmt;

/// Most samples the detector window may hold.
pub const WINDOW_MAX: usize = 128;
/// Fewest samples the detector window may hold.
pub const WINDOW_MIN: usize = 8;

/// Drift control settings in physical units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drift {
    /// Detector window [s]; `round(window_s * fs)` must lie in `8..=128` samples (the
    /// buffer is a fixed 128 samples: above 3.2 kHz use a shorter window than the default).
    pub window_s: f64,
    /// Still when every axis's window variance is below this multiple of its calibrated
    /// noise variance, `>= 1`.
    pub still_factor: f64,
    /// Moving when any axis's window variance exceeds this multiple, `>= still_factor`.
    pub move_factor: f64,
    /// Time constant of the bias tracking while still [s], `>= window_s`; `None` disables it.
    pub bias_tau_s: Option<f64>,
    /// Motion suppressed after a button edge [s], `0..=2`.
    pub click_freeze_s: f64,
}

impl Default for Drift {
    /// A 40 ms window; still below 2x the calibrated noise variance, moving above 4x; bias
    /// tracked with a 5 s time constant; 150 ms click freeze.
    fn default() -> Self {
        Self {
            window_s: 0.04,
            still_factor: 2.0,
            move_factor: 4.0,
            bias_tau_s: Some(5.0),
            click_freeze_s: 0.15,
        }
    }
}

/// A [`Drift`] field that failed validation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DriftError {
    /// `window_s * fs` not in `8..=128` samples.
    Window,
    /// `still_factor < 1`, `move_factor < still_factor`, or either not finite or above 1e6.
    Factors,
    /// `bias_tau_s` below `window_s` or not finite.
    BiasTau,
    /// `click_freeze_s` outside `0..=2`.
    ClickFreeze,
}

impl fmt::Display for DriftError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Window => "drift.window_s: the detector window must hold 8..=128 samples",
            Self::Factors => "drift.still_factor / move_factor: need 1 <= still <= move <= 1e6",
            Self::BiasTau => "drift.bias_tau_s: must be finite and at least the window",
            Self::ClickFreeze => "drift.click_freeze_s: must be within 0..=2 s",
        })
    }
}

/// Validated drift-control coefficients.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DriftSettings {
    window: u16,
    still_q8: u32,
    move_q8: u32,
    bias_steps: Option<u32>,
    freeze: u32,
}

impl Drift {
    /// Validates for sampling rate `fs_hz`.
    ///
    /// # Errors
    /// The first invalid field.
    pub fn validate(&self, fs_hz: u32) -> Result<DriftSettings, DriftError> {
        let fs = f64::from(fs_hz);
        let w = self.window_s * fs;
        if !(w.is_finite() && w >= WINDOW_MIN as f64 - 0.5 && w < WINDOW_MAX as f64 + 0.5) {
            return Err(DriftError::Window);
        }
        let window = crate::math::round_to_u64(w) as u16;
        let ok = |v: f64| v.is_finite() && (1.0..=1e6).contains(&v);
        if !(ok(self.still_factor) && ok(self.move_factor) && self.move_factor >= self.still_factor)
        {
            return Err(DriftError::Factors);
        }
        let bias_steps = match self.bias_tau_s {
            None => None,
            Some(tau) if tau.is_finite() && tau >= self.window_s && tau < 1e6 => {
                Some(crate::math::round_to_u64(tau / self.window_s).max(1) as u32)
            }
            Some(_) => return Err(DriftError::BiasTau),
        };
        if !(0.0..=2.0).contains(&self.click_freeze_s) {
            return Err(DriftError::ClickFreeze);
        }
        Ok(DriftSettings {
            window,
            still_q8: crate::math::round_to_u64(self.still_factor * 256.0) as u32,
            move_q8: crate::math::round_to_u64(self.move_factor * 256.0) as u32,
            bias_steps,
            freeze: crate::math::round_to_u64(self.click_freeze_s * fs) as u32,
        })
    }
}

impl DriftSettings {
    /// Detector window [samples].
    pub const fn window(&self) -> usize {
        self.window as usize
    }
    /// Click freeze [samples].
    pub const fn freeze_samples(&self) -> u32 {
        self.freeze
    }
}

/// What the detector decided for one sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// Still: do not integrate.
    Still,
    /// Moving, and it just started: integrate the buffered window first.
    Started,
    /// Moving.
    Moving,
}

/// Detector state: the window of raw codes and filtered samples of three axes.
#[derive(Clone, Copy, Debug)]
pub struct Detector {
    codes: [[u16; 3]; WINDOW_MAX],
    filtered: [[i64; 3]; WINDOW_MAX],
    head: usize,
    filled: usize,
    sum: [u64; 3],
    sum_sq: [u64; 3],
    /// Per-axis thresholds on `W sum_sq - sum^2` (= W^2 var), still and moving.
    still_thr: [u64; 3],
    move_thr: [u64; 3],
    still: bool,
    since_bias: u32,
}

impl Detector {
    /// A detector for calibrated per-axis noise `noise_rms_q16` (Q16 LSB), starting still
    /// (calibration has just shown the device at rest).
    pub fn new(s: &DriftSettings, noise_rms_q16: [u64; 3]) -> Self {
        let w = u64::from(s.window);
        let thr = |rms_q16: u64, f_q8: u32| -> u64 {
            // W^2 * max(sigma^2, 1/4) * f, with sigma^2 in Q32 and f in Q8.
            let var_q32 = u128::from(rms_q16) * u128::from(rms_q16);
            let var_q32 = var_q32.max(1 << 30);
            let t = (u128::from(w * w) * var_q32 * u128::from(f_q8)) >> 40;
            t.min(u128::from(u64::MAX)) as u64
        };
        Self {
            codes: [[0; 3]; WINDOW_MAX],
            filtered: [[0; 3]; WINDOW_MAX],
            head: 0,
            filled: 0,
            sum: [0; 3],
            sum_sq: [0; 3],
            still_thr: noise_rms_q16.map(|r| thr(r, s.still_q8)),
            move_thr: noise_rms_q16.map(|r| thr(r, s.move_q8)),
            still: true,
            since_bias: 0,
        }
    }

    /// Adds one sample (raw codes and the filtered values) and decides, against the axes'
    /// current biases (Q16 counts).
    pub fn push(
        &mut self,
        s: &DriftSettings,
        codes: [u16; 3],
        filtered: [i64; 3],
        bias_q16: [i64; 3],
    ) -> Verdict {
        let w = s.window as usize;
        if self.filled == w {
            let old = self.codes[self.head];
            for ((sum, sum_sq), &o) in self.sum.iter_mut().zip(&mut self.sum_sq).zip(&old) {
                let o = u64::from(o);
                *sum -= o;
                *sum_sq -= o * o;
            }
        } else {
            self.filled += 1;
        }
        self.codes[self.head] = codes;
        self.filtered[self.head] = filtered;
        self.head = (self.head + 1) % w;
        for ((sum, sum_sq), &v) in self.sum.iter_mut().zip(&mut self.sum_sq).zip(&codes) {
            let v = u64::from(v);
            *sum += v;
            *sum_sq += v * v;
        }
        if self.filled < w {
            return if self.still {
                Verdict::Still
            } else {
                Verdict::Moving
            };
        }
        let n = w as u64;
        // W^2 var and W^2 (mean - bias)^2, in LSB^2: the thresholds' units.
        let scatter = |a: usize| n * self.sum_sq[a] - self.sum[a] * self.sum[a];
        let offset = |a: usize| {
            // W (mean - bias) in Q8 LSB: |d| < 128 * 65536 * 2^8 = 2^31, so d^2 fits u64.
            let d = ((self.sum[a] as i64) << 8) - ((n as i64 * bias_q16[a]) >> 8);
            (d.unsigned_abs() * d.unsigned_abs()) >> 16
        };
        let was = self.still;
        if self.still {
            self.still =
                (0..3).all(|a| scatter(a) <= self.move_thr[a] && offset(a) <= self.move_thr[a]);
        } else {
            self.still =
                (0..3).all(|a| scatter(a) < self.still_thr[a] && offset(a) < self.still_thr[a]);
        }
        match (was, self.still) {
            (true, false) => Verdict::Started,
            (_, true) => Verdict::Still,
            (false, false) => Verdict::Moving,
        }
    }

    /// The buffered filtered samples, oldest first.
    pub fn window(&self, s: &DriftSettings) -> impl Iterator<Item = [i64; 3]> + '_ {
        let w = s.window as usize;
        let n = self.filled;
        (0..n).map(move |i| self.filtered[(self.head + w - n + i) % w])
    }

    /// While still: once per full window, the new bias for each axis (Q16), `1/M` of the
    /// way from `bias_q16` to the window mean, rounded; `None` between updates or when
    /// tracking is off.
    pub fn bias_update(&mut self, s: &DriftSettings, bias_q16: [i64; 3]) -> Option<[i64; 3]> {
        let m = s.bias_steps?;
        self.since_bias += 1;
        if self.since_bias < u32::from(s.window) || self.filled < s.window as usize {
            return None;
        }
        self.since_bias = 0;
        let w = i64::from(s.window);
        let m = i64::from(m);
        Some(core::array::from_fn(|a| {
            // sum < 2^23, so sum 2^16 < 2^39: i64 throughout.
            let mean_q16 = ((self.sum[a] as i64) << 16) / w;
            let d = mean_q16 - bias_q16[a];
            // Round half away from zero: d / m.
            let step = (2 * d + d.signum() * m) / (2 * m);
            bias_q16[a] + step
        }))
    }

    /// Whether the detector currently says still.
    pub const fn is_still(&self) -> bool {
        self.still
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn settings() -> DriftSettings {
        Drift::default().validate(3000).expect("valid")
    }

    #[test]
    fn validation_names_the_field() {
        let d = Drift::default();
        assert_eq!(
            Drift {
                window_s: 0.001,
                ..d
            }
            .validate(3000),
            Err(DriftError::Window)
        );
        assert_eq!(
            Drift { window_s: 0.1, ..d }.validate(3000),
            Err(DriftError::Window)
        );
        assert_eq!(
            Drift {
                still_factor: 0.5,
                ..d
            }
            .validate(3000),
            Err(DriftError::Factors)
        );
        assert_eq!(
            Drift {
                move_factor: 1.5,
                ..d
            }
            .validate(3000),
            Err(DriftError::Factors)
        );
        assert_eq!(
            Drift {
                bias_tau_s: Some(0.01),
                ..d
            }
            .validate(3000),
            Err(DriftError::BiasTau)
        );
        assert_eq!(
            Drift {
                click_freeze_s: 3.0,
                ..d
            }
            .validate(3000),
            Err(DriftError::ClickFreeze)
        );
        assert_eq!(settings().window(), 120);
        assert_eq!(settings().freeze_samples(), 450);
    }

    #[test]
    fn quiet_stays_still_and_a_jolt_starts_motion() {
        let s = settings();
        let mut d = Detector::new(&s, [65_536; 3]); // 1 LSB rms
        for i in 0..1000 {
            let v = 2048 + [0, 1, 0, 65_535][i % 4] as u16 % 3; // +-1 LSB dither
            assert_ne!(
                d.push(&s, [v; 3], [0; 3], [2048 << 16; 3]),
                Verdict::Started
            );
        }
        assert!(d.is_still());
        let mut started = false;
        for i in 0..60 {
            let v = if i % 2 == 0 { 2060 } else { 2036 };
            started |= d.push(&s, [v, 2048, 2048], [0; 3], [2048 << 16; 3]) == Verdict::Started;
        }
        assert!(started && !d.is_still());
    }

    #[test]
    fn bias_moves_a_fraction_of_the_way_to_the_window_mean() {
        let s = Drift {
            bias_tau_s: Some(0.4),
            ..Drift::default()
        }
        .validate(3000)
        .expect("valid"); // M = 10
        let mut d = Detector::new(&s, [65_536; 3]);
        let mut bias = [2048 << 16; 3];
        let mut updates = 0;
        for _ in 0..240 {
            d.push(&s, [2049, 2048, 2047], [0; 3], bias);
            if let Some(b) = d.bias_update(&s, bias) {
                bias = b;
                updates += 1;
            }
        }
        assert_eq!(updates, 2);
        // Each update: 1/10 of the remaining 65536 Q16: 6554, then 5898.
        assert_eq!(bias[0], (2048 << 16) + 6554 + 5898);
        assert_eq!(bias[2], (2048 << 16) - 6554 - 5898);
        assert_eq!(bias[1], 2048 << 16);
    }
}
