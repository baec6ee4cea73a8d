//! `cargo lab predict`: the error-budget predictor. For each duration `t`, the RMS position
//! error that each of the paper's laws (and the exact finite-N results) predicts.

use serde::Serialize;

use crate::oracle::reference as r;

/// Largest `N = t * fs` accepted: the exact integer forms of REFERENCE (c) hold to `2^40`.
pub const N_MAX: f64 = 1e12;

/// Inputs of one prediction, in SI units.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Inputs {
    /// Sampling rate [Hz], finite and `> 0`.
    pub fs: f64,
    /// Durations [s]; each `t * fs` must be a whole number of samples in `1..=1e12`.
    pub t: Vec<f64>,
    /// Per-sample white noise std [m/s^2], `>= 0`.
    pub sigma_d: Option<f64>,
    /// One-sided noise density into the single-pole filter [m/s^2/sqrt(Hz)], `>= 0`; needs `fc`.
    pub sigma_c: Option<f64>,
    /// The filter's cut-off [Hz], `0 < fc <= fs / 2`; needs `sigma_c`.
    pub fc: Option<f64>,
    /// Constant bias [m/s^2], finite.
    pub bias: Option<f64>,
}

/// Why a prediction cannot be made; each names the offending input.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PredictError {
    /// `--fs` not finite or not positive.
    #[error("--fs {}: the sampling rate must be a finite number > 0 Hz", short(*.0))]
    Fs(f64),
    /// No `--t` given.
    #[error("--t: give at least one duration in seconds")]
    NoDuration,
    /// A `--t` not finite or not positive.
    #[error("--t {}: a duration must be a finite number > 0 s", short(*.0))]
    Duration(f64),
    /// `t * fs` is not a whole number.
    #[error("--t {} at --fs {}: N = t * fs = {} is not a whole number of samples", short(*t), short(*fs), short(*n))]
    NotWhole {
        /// The duration [s].
        t: f64,
        /// The sampling rate [Hz].
        fs: f64,
        /// `t * fs`.
        n: f64,
    },
    /// `t * fs` above [`N_MAX`].
    #[error("--t {} at --fs {}: N = {} samples is above the supported 1e12", short(*t), short(*fs), short(*n))]
    TooLong {
        /// The duration [s].
        t: f64,
        /// The sampling rate [Hz].
        fs: f64,
        /// `t * fs`.
        n: f64,
    },
    /// A noise level not finite or negative.
    #[error("--{name} {}: must be a finite number >= 0", short(*.value))]
    Noise {
        /// The flag's name.
        name: &'static str,
        /// The rejected value.
        value: f64,
    },
    /// `--bias` not finite.
    #[error("--bias {}: must be a finite number (m/s^2)", short(*.0))]
    Bias(f64),
    /// `--sigma-c` without `--fc`, or the other way round.
    #[error("--sigma-c and --fc go together: the density is the input of the filter at fc")]
    FilterPair,
    /// `--fc` outside `(0, fs/2]`.
    #[error(
        "--fc {}: the cut-off must satisfy 0 < fc <= fs / 2 = {} Hz (the paper's analog \
         single-pole model takes fs / 2; the device's filter stays below it)",
        short(*.fc),
        short(*.half)
    )]
    Cutoff {
        /// The rejected cut-off [Hz].
        fc: f64,
        /// `fs / 2` [Hz].
        half: f64,
    },
    /// Nothing to predict.
    #[error("give at least one of --sigma-d, --sigma-c with --fc, or --bias")]
    NoSource,
}

/// One row of the prediction: the RMS position error [m] under each applicable law.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Row {
    /// Duration [s].
    pub t_s: f64,
    /// Samples integrated, `t * fs` (the trapezoid uses `n` steps, `n + 1` samples).
    pub n: u64,
    /// Eq (2), bias: `|A| T^2 / 2`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub eq2_m: Option<f64>,
    /// Eq (23), white noise, retrospective estimator.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub eq23_m: Option<f64>,
    /// Eq (27), white noise, continuous double integration.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub eq27_m: Option<f64>,
    /// REFERENCE (c)(i), white noise, exact Euler.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub euler_m: Option<f64>,
    /// REFERENCE (c)(ii), white noise, exact trapezoid.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub trapezoid_m: Option<f64>,
    /// Eq (32), filtered noise, retrospective estimator.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub eq32_m: Option<f64>,
    /// REFERENCE (c)(iii), filtered (AR(1)) noise, exact Euler, `r0` from eq (31).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ar1_euler_m: Option<f64>,
    /// Bias and white noise together through the exact trapezoid: `sqrt(eq2^2 +
    /// trapezoid^2)`. The trapezoid integrates a constant exactly (eq 2) and the noise's
    /// error has zero mean, so the two add in mean square, whether the bias is fixed or drawn
    /// with that rms. Needs `bias` and `sigma_d`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub trapezoid_bias_m: Option<f64>,
}

/// Validates `inputs` and evaluates every applicable law at each duration.
///
/// # Errors
/// The first invalid input, as a [`PredictError`] naming it.
pub fn predict(inputs: &Inputs) -> Result<Vec<Row>, PredictError> {
    let fs = inputs.fs;
    if !(fs.is_finite() && fs > 0.0) {
        return Err(PredictError::Fs(fs));
    }
    for (name, v) in [("sigma-d", inputs.sigma_d), ("sigma-c", inputs.sigma_c)] {
        if let Some(value) = v.filter(|v| !(v.is_finite() && *v >= 0.0)) {
            return Err(PredictError::Noise { name, value });
        }
    }
    if let Some(b) = inputs.bias.filter(|b| !b.is_finite()) {
        return Err(PredictError::Bias(b));
    }
    let filtered = match (inputs.sigma_c, inputs.fc) {
        (None, None) => None,
        (Some(sigma_c), Some(fc)) => {
            if !(fc > 0.0 && fc <= fs / 2.0) {
                return Err(PredictError::Cutoff { fc, half: fs / 2.0 });
            }
            Some((sigma_c, fc))
        }
        _ => return Err(PredictError::FilterPair),
    };
    if inputs.sigma_d.is_none() && filtered.is_none() && inputs.bias.is_none() {
        return Err(PredictError::NoSource);
    }
    if inputs.t.is_empty() {
        return Err(PredictError::NoDuration);
    }
    inputs
        .t
        .iter()
        .map(|&t| {
            let n = whole_samples(t, fs)?;
            let nf = n as f64;
            let white = inputs.sigma_d;
            let eq2 = inputs.bias.map(|b| r::eq2_bias(b, t));
            let trapezoid = white.map(|s| r::trapezoid_white(s, fs, n));
            Ok(Row {
                t_s: t,
                n,
                eq2_m: eq2,
                eq23_m: white.map(|s| r::eq23_retrospective(s, fs, nf / fs)),
                eq27_m: white.map(|s| r::eq27_continuous(s, fs, nf / fs)),
                euler_m: white.map(|s| r::euler_white(s, fs, n)),
                trapezoid_m: trapezoid,
                eq32_m: filtered.map(|(sc, fc)| r::eq32_filtered_retrospective(sc, fc, fs, nf)),
                ar1_euler_m: filtered.map(|(sc, fc)| {
                    let a = r::alpha(fc, fs);
                    r::ar1_euler(r::eq31_sigma_f2(sc, a, fs), a, fs, nf)
                }),
                trapezoid_bias_m: eq2.zip(trapezoid).map(|(b, w)| b.hypot(w)),
            })
        })
        .collect()
}

/// `t * fs` as a whole number of samples, allowing the float error of forming the product
/// (1e-9 relative: `0.1 * 3000` is `300.00000000000006`).
fn whole_samples(t: f64, fs: f64) -> Result<u64, PredictError> {
    if !(t.is_finite() && t > 0.0) {
        return Err(PredictError::Duration(t));
    }
    let n = t * fs;
    if n > N_MAX {
        return Err(PredictError::TooLong { t, fs, n });
    }
    let whole = n.round();
    if whole < 1.0 || (n - whole).abs() > 1e-9 * whole {
        return Err(PredictError::NotWhole { t, fs, n });
    }
    Ok(whole as u64)
}

/// The rows as a fixed-width text table, one column per law present.
pub fn table(rows: &[Row]) -> String {
    type Col = (&'static str, fn(&Row) -> Option<f64>);
    let cols: [Col; 8] = [
        ("eq2 bias", |r| r.eq2_m),
        ("eq23 retro", |r| r.eq23_m),
        ("eq27 cont", |r| r.eq27_m),
        ("euler exact", |r| r.euler_m),
        ("trapezoid", |r| r.trapezoid_m),
        ("eq32 filt", |r| r.eq32_m),
        ("ar1 euler", |r| r.ar1_euler_m),
        ("trap + bias", |r| r.trapezoid_bias_m),
    ];
    let present: Vec<&Col> = cols
        .iter()
        .filter(|(_, get)| rows.iter().any(|r| get(r).is_some()))
        .collect();
    let mut out = format!("{:>12} {:>14}", "t [s]", "N");
    for (name, _) in &present {
        out += &format!(" {name:>12}");
    }
    out += "\n";
    for row in rows {
        out += &format!("{:>12} {:>14}", row.t_s, row.n);
        for (_, get) in &present {
            out += &format!(" {:>12.4e}", get(row).unwrap_or(f64::NAN));
        }
        out += "\n";
    }
    out += "RMS position error [m]. Trapezoid: N steps on N + 1 samples.\n";
    out
}

/// `v` as given: exponent form outside 1e-6..1e9 (so `--fs 1e300` is not quoted as 301
/// digits; the oracle keeps its own, sharing nothing with the lab's formats).
fn short(v: f64) -> String {
    let a = v.abs();
    if v != 0.0 && a.is_finite() && !(1e-6..1e9).contains(&a) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}
