//! Statistics: the mean square of a set of Monte Carlo trials with its standard error, the
//! z-score of a predicted RMS, a weighted log-log slope, quantiles of a set of measurements,
//! and the overlapping Allan deviation ([`allan`]).
//!
//! # How a prediction is judged
//! Over `M` independent trials of the position `s`, `mean(s^2)` estimates `E[s^2]` with
//! standard error `se = sd(s^2) / sqrt(M)` (central limit theorem; `M >= 1000` here). The
//! z-score of a predicted RMS `p` is `(mean(s^2) - p^2) / se`. The 95 % interval of the RMS
//! is `sqrt(mean(s^2) -+ 1.96 se)` (delta method). A test passes when `|z| < Z_CRIT`.

use serde::Serialize;

pub mod allan;

/// Two-sided critical z for the Monte Carlo tests: 3.29 is a 0.1 % false-failure rate per
/// check, so at most 1.6 % for the sixteen checks of `tests/monte_carlo.rs` (Bonferroni).
/// Control rows, which apply a wrong law, must land beyond it.
pub const Z_CRIT: f64 = 3.29;

/// Mean square of Monte Carlo trials.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeanSquare {
    /// Number of trials.
    pub trials: usize,
    /// `mean(s^2)` [unit^2].
    pub mean: f64,
    /// Standard error of `mean` [unit^2].
    pub se: f64,
}

impl MeanSquare {
    /// From the trial values `s` (not squared).
    pub fn of(s: &[f64]) -> Self {
        let m = s.len() as f64;
        let mean = s.iter().map(|x| x * x).sum::<f64>() / m;
        let var = s.iter().map(|x| (x * x - mean).powi(2)).sum::<f64>() / (m - 1.0);
        Self {
            trials: s.len(),
            mean,
            se: (var / m).sqrt(),
        }
    }

    /// The measured RMS.
    pub fn rms(&self) -> f64 {
        self.mean.sqrt()
    }

    /// The 95 % interval of the RMS.
    pub fn ci95(&self) -> (f64, f64) {
        let lo = (self.mean - 1.96 * self.se).max(0.0).sqrt();
        (lo, (self.mean + 1.96 * self.se).sqrt())
    }

    /// z-score of a predicted RMS.
    pub fn z(&self, predicted_rms: f64) -> f64 {
        (self.mean - predicted_rms * predicted_rms) / self.se
    }

    /// Standard error of `ln(rms)`: `se / (2 mean)` (delta method).
    pub fn se_ln_rms(&self) -> f64 {
        self.se / (2.0 * self.mean)
    }
}

/// Weighted least-squares slope of `y` on `x` with per-point standard errors `se_y`, and its
/// standard error.
pub fn wls_slope(x: &[f64], y: &[f64], se_y: &[f64]) -> (f64, f64) {
    let w: Vec<f64> = se_y.iter().map(|s| 1.0 / (s * s)).collect();
    let sw: f64 = w.iter().sum();
    let xm = w.iter().zip(x).map(|(w, x)| w * x).sum::<f64>() / sw;
    let ym = w.iter().zip(y).map(|(w, y)| w * y).sum::<f64>() / sw;
    let sxx: f64 = w.iter().zip(x).map(|(w, x)| w * (x - xm).powi(2)).sum();
    let sxy: f64 = (0..x.len()).map(|i| w[i] * (x[i] - xm) * (y[i] - ym)).sum();
    (sxy / sxx, (1.0 / sxx).sqrt())
}

/// Median, 90th percentile and maximum of a set of measurements.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Spread {
    /// Median.
    pub median: f64,
    /// 90th percentile.
    pub p90: f64,
    /// Largest.
    pub max: f64,
}

/// Median, 90th percentile and maximum of `v` (NaN for none).
pub fn spread(mut v: Vec<f64>) -> Spread {
    if v.is_empty() {
        return Spread {
            median: f64::NAN,
            p90: f64::NAN,
            max: f64::NAN,
        };
    }
    v.sort_by(f64::total_cmp);
    let q = |p: f64| v[((v.len() - 1) as f64 * p).round() as usize];
    Spread {
        median: q(0.5),
        p90: q(0.9),
        max: v[v.len() - 1],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mean_square_and_interval() {
        let ms = MeanSquare::of(&[1.0, -1.0, 3.0, -3.0]);
        assert_eq!(ms.mean, 5.0);
        // s^2 = 1, 1, 9, 9: sample variance 64/3, se = sqrt(64/3 / 4).
        assert!((ms.se - (16.0f64 / 3.0).sqrt()).abs() < 1e-12);
        assert!((ms.z(5f64.sqrt())).abs() < 1e-12);
        let (lo, hi) = ms.ci95();
        assert!(lo < ms.rms() && ms.rms() < hi);
    }

    #[test]
    fn slope_of_a_line_is_exact() {
        let x = [0.0, 1.0, 2.0];
        let y = [1.0, -0.5, -2.0];
        let (b, se) = wls_slope(&x, &y, &[1.0, 1.0, 1.0]);
        assert!((b + 1.5).abs() < 1e-15);
        assert!((se - 0.5f64.sqrt()).abs() < 1e-15);
    }
}
