//! Overlapping Allan deviation and the noise figures read from it (`cargo lab allan`).
//!
//! # Estimator
//! The same as allantools' `oadev(data, rate, data_type="freq", taus="octave")` (NIST SP 1065
//! eq 11), so CI can hold one to the other: the mean is removed, the values are integrated to
//! "phase" `x = [0, cumsum(y) / fs]` (N + 1 points), and for `m = 1, 2, 4, ...` below N + 1
//!
//! ```text
//! sigma^2(m / fs) = sum_i (x[i+2m] - 2 x[i+m] + x[i])^2 / (2 n tau^2),   n = N + 1 - 2m
//! ```
//!
//! keeping the taus with n >= 2.
//!
//! # Noise figures (REFERENCE (f); conventions stated because they differ between sources)
//! - Velocity random walk `N_v` [m/s/sqrt(s)]: on the white-noise part of the curve,
//!   `sigma(tau) = N_v / sqrt(tau)`; fitted with the slope fixed at -1/2, equal weights,
//!   over the taus from the first up to the
//!   minimum where the local slope is within -0.5 +- 0.1 and `n / m >= 100` (so no point
//!   rests on fewer than 100 independent differences). The tight slope band matters for
//!   filtered noise: below a few filter time constants the curve lies under the -1/2 line
//!   (REFERENCE (f): filtered noise is white only for tau >> tau_c), and a loose band let
//!   those points pull the estimate down (an ADXL335 simulation at 300 ug/sqrt(Hz) read
//!   251 with +-0.25, 300 with +-0.1).
//! - Noise density, ONE-sided (data-sheet convention): `ND = sqrt(2) N_v`
//!   [m/s^2/sqrt(Hz)]. (IEEE 952-style two-sided densities equal `N_v`.)
//! - Bias instability `B` [m/s^2]: the flat minimum of the curve divided by
//!   `sqrt(2 ln 2 / pi) = 0.664` (the flicker-floor convention of IEEE 952).

use serde::Serialize;

/// Allan deviation at octave-spaced taus.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Adev {
    /// Averaging times [s].
    pub taus_s: Vec<f64>,
    /// Overlapping Allan deviation [unit of the data].
    pub adev: Vec<f64>,
    /// Number of second differences in each.
    pub n: Vec<usize>,
}

/// Overlapping Allan deviation of `y` sampled at `fs`, at octave taus.
pub fn oadev(y: &[f64], fs: f64) -> Adev {
    let mean = y.iter().sum::<f64>() / y.len().max(1) as f64;
    let mut x = Vec::with_capacity(y.len() + 1);
    x.push(0.0);
    let mut acc = 0.0;
    for v in y {
        acc += v - mean;
        x.push(acc / fs);
    }
    let mut out = Adev {
        taus_s: vec![],
        adev: vec![],
        n: vec![],
    };
    let mut m = 1usize;
    while m < x.len() {
        if x.len() > 2 * m {
            let n = x.len() - 2 * m;
            if n >= 2 {
                let s: f64 = (0..n)
                    .map(|i| {
                        let d = x[i + 2 * m] - 2.0 * x[i + m] + x[i];
                        d * d
                    })
                    .sum();
                let tau = m as f64 / fs;
                out.taus_s.push(tau);
                out.adev.push((s / (2.0 * n as f64)).sqrt() / tau);
                out.n.push(n);
            }
        }
        m *= 2;
    }
    out
}

/// The figures read from an Allan deviation curve.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Figures {
    /// Velocity random walk `N_v` [m/s/sqrt(s)] (= ADEV at 1 s on the -1/2 line).
    pub vrw_m_s_rts: f64,
    /// One-sided white-noise density `sqrt(2) N_v` [m/s^2/sqrt(Hz)].
    pub noise_density_m_s2_rthz: f64,
    /// Bias instability `B = min ADEV / 0.664` [m/s^2].
    pub bias_instability_m_s2: f64,
    /// Where the minimum is [s].
    pub tau_min_s: f64,
    /// Whether the minimum is at the longest tau, where the curve may still be falling: then
    /// the bias instability is an upper bound (a longer record would find it lower).
    pub bias_is_bound: bool,
    /// The taus the -1/2 fit used [s].
    pub fit_taus_s: Vec<f64>,
    /// Whether no tau on the -1/2 line had 100 averages (a short record): the fit took the
    /// slope alone, and the figures are rough.
    pub fit_is_short: bool,
}

/// Reads the figures from `a` (at least two taus).
pub fn figures(a: &Adev) -> Option<Figures> {
    if a.adev.len() < 2 {
        return None;
    }
    let (imin, &min) = a
        .adev
        .iter()
        .enumerate()
        .min_by(|x, y| x.1.total_cmp(y.1))?;
    let slope_off = |i: usize| {
        let slope = if i + 1 < a.adev.len() {
            (a.adev[i + 1] / a.adev[i]).ln() / (a.taus_s[i + 1] / a.taus_s[i]).ln()
        } else {
            -0.5
        };
        (slope + 0.5).abs()
    };
    let slope_ok = |i: usize| slope_off(i) <= 0.1;
    let averages = |i: usize| a.n[i] as f64 / (a.taus_s[i] / a.taus_s[0]).round();
    let mut fit = vec![];
    for i in 0..imin.max(1) {
        if slope_ok(i) && averages(i) >= 100.0 {
            fit.push(i);
        } else if !fit.is_empty() {
            break;
        }
    }
    // A record too short for 100 averages on the white part: the slope alone picks the taus
    // (the first tau of a filtered sensor lies on its flat part and reads far low: a 3 s
    // record at 3 kHz read 28 instead of about 300 ug/sqrt(Hz)).
    let short = fit.is_empty();
    if short {
        fit = (0..imin.max(1)).filter(|&i| slope_ok(i)).collect();
    }
    if fit.is_empty() {
        // No slope within 0.1 of -1/2 either: the tau whose slope comes nearest.
        fit.extend((0..imin.max(1)).min_by(|&i, &j| slope_off(i).total_cmp(&slope_off(j))));
    }
    // Equal weights: the smallest taus are the most precise but, for filtered noise, the
    // most biased (still approaching the -1/2 line from below).
    let ln_nv = fit
        .iter()
        .map(|&i| a.adev[i].ln() + 0.5 * a.taus_s[i].ln())
        .sum::<f64>()
        / fit.len() as f64;
    let nv = ln_nv.exp();
    Some(Figures {
        vrw_m_s_rts: nv,
        noise_density_m_s2_rthz: std::f64::consts::SQRT_2 * nv,
        bias_instability_m_s2: min / (2.0 * std::f64::consts::LN_2 / std::f64::consts::PI).sqrt(),
        tau_min_s: a.taus_s[imin],
        bias_is_bound: imin + 1 == a.adev.len(),
        fit_taus_s: fit.iter().map(|&i| a.taus_s[i]).collect(),
        fit_is_short: short,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_definition_on_a_tiny_series() {
        // y = [1, 3, 2, 6] at 2 Hz: y - mean = [-2, 0, -1, 3], x = [0, -2, -2, -3, 0] / 2.
        let a = oadev(&[1.0, 3.0, 2.0, 6.0], 2.0);
        let x = [0.0, -2.0, -2.0, -3.0, 0.0].map(|v: f64| v / 2.0);
        let d: Vec<f64> = (0..3).map(|i| x[i + 2] - 2.0 * x[i + 1] + x[i]).collect();
        let want = (d.iter().map(|v| v * v).sum::<f64>() / 6.0).sqrt() / 0.5;
        assert_eq!(a.taus_s[0], 0.5);
        assert!((a.adev[0] - want).abs() < 1e-15);
        assert_eq!(a.n, vec![3]); // m = 2 leaves n = 1: dropped, as allantools does
    }

    #[test]
    fn white_noise_gives_its_velocity_random_walk() {
        // White noise of sd 0.05 at 100 Hz: N_v = sd / sqrt(fs) = 0.005 (REFERENCE (f)). Each
        // fitted point rests on >= 100 independent differences (relative sd <= 1 / sqrt(2 *
        // 100 / 1.5) = 8.7 %), averaged over ~10 points in logs: about 3 %; the 5 % bound is
        // well over 1.5 of those.
        use rand::{Rng, SeedableRng};
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(5);
        let y: Vec<f64> = (0..200_000)
            .map(|_| 0.05 * rng.sample::<f64, _>(rand_distr::StandardNormal))
            .collect();
        let f = figures(&oadev(&y, 100.0)).expect("enough data");
        assert!((f.vrw_m_s_rts / 0.005 - 1.0).abs() < 0.05, "{f:?}");
        assert!(
            (f.noise_density_m_s2_rthz / (0.005 * std::f64::consts::SQRT_2) - 1.0).abs() < 0.05
        );
    }
}
