//! Fixed-point error budgets: each core stage against its f64 twin, with the bound that the
//! Q formats imply. `tests/budget.rs` asserts them; `cargo lab budget` prints the table.
//!
//! Derived bounds (LSB = one ADC code):
//! - low-pass output: rounded half-up from Q32 to Q16, so `|err| <= 2^-17` LSB, plus the
//!   state's own rounding to Q32 (`2^-33` in the recursion, `2^-33` in the output); for
//!   noise-like input the error is uniform: rms `2^-16 / sqrt(12)`. The f64 twin's own error
//!   (`<= ulp(4096) / k`, the rounding of each step summed through the contraction `1 - k`)
//!   is added to the max bound.
//! - calibration: bias `|err| <= 2^-17` LSB (rounded once); noise rms `err in (-2^-16, 0]`
//!   (square root floored).
//! - integrator: exact; bound 0.
//! - read-out: the sum of counts is the position times the realised scale `M / 2^P`,
//!   rounded: `|err| <= 0.5` count plus `s K 2^-32` of scale rounding.
//! - pipeline (filter + calibrated bias + Euler): the residual bias `|db| <= 2^-17` LSB
//!   integrates to `db N (N + 1) / 2`, and the output rounding `e_k` (uniform, `|e| <= 2^-17`)
//!   to `sum (N - k + 1) e_k`. Max bound `2^-16 N (N + 1) / 2`; rms bound
//!   `sqrt((2^-17 / sqrt 3)^2 (N (N+1) / 2)^2 + (2^-16 / sqrt 12)^2 N (N+1) (2N+1) / 6)`,
//!   times `LSB / fs^2` for metres.

use imu_core::{AdcCode, Config, Lowpass, LowpassState, Scheme, Tracker};
use serde::Serialize;

use crate::oracle::reference as r;
use crate::oracle::twin;
use crate::world::noise::{self, Adc};

const Q16: f64 = 65_536.0;
const HALF_Q16_LSB: f64 = 1.0 / 131_072.0; // 2^-17 LSB

/// One stage's measured error against its f64 twin, with the derived bounds.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Row {
    /// What was measured.
    pub stage: String,
    /// Unit of the errors.
    pub unit: &'static str,
    /// Samples (or trials) measured.
    pub samples: u64,
    /// Largest absolute error seen.
    pub max_err: f64,
    /// RMS error.
    pub rms_err: f64,
    /// Derived bound on the largest error.
    pub max_bound: f64,
    /// Derived expected RMS error (`None` where the error is exactly zero or not random).
    pub rms_bound: Option<f64>,
}

impl Row {
    /// The row of `errs`, the errors of `samples` samples (or trials) in `unit`, against the
    /// derived bounds.
    fn measured(
        stage: String,
        unit: &'static str,
        samples: u64,
        errs: &[f64],
        max_bound: f64,
        rms_bound: Option<f64>,
    ) -> Self {
        Self {
            stage,
            unit,
            samples,
            max_err: max_abs(errs),
            rms_err: rms(errs),
            max_bound,
            rms_bound,
        }
    }
}

fn rms(v: &[f64]) -> f64 {
    (v.iter().map(|e| e * e).sum::<f64>() / v.len() as f64).sqrt()
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, e| m.max(e.abs()))
}

/// Codes of white noise `sigma` LSB around `mid`, quantised by a 12-bit ADC.
fn noise_codes(n: usize, mid: f64, sigma: f64, seed: u64) -> Vec<u16> {
    let mut rng = noise::rng(seed);
    let adc = Adc { bits: 12 };
    (0..n)
        .map(|_| adc.code(mid + sigma * noise::normal(&mut rng)))
        .collect()
}

/// The low-pass at `fc / fs = ratio`, over `n` samples of 50 LSB white noise.
pub fn lowpass(ratio: f64, n: usize, seed: u64) -> Row {
    let lp = Lowpass::from_ratio(ratio).expect("ratio within the core's range");
    let mut state = LowpassState::settled_q16(2048 << 16);
    let mut f = twin::Lowpass::realised(lp.k_q32(), 2048.0);
    let errs: Vec<f64> = noise_codes(n, 2048.0, 50.0, seed)
        .into_iter()
        .map(|c| lp.process(&mut state, AdcCode(c)) as f64 / Q16 - f.process(f64::from(c)))
        .collect();
    let twin_err = 2.0 * f64::EPSILON * 4096.0 / f.k;
    Row::measured(
        format!("low-pass output, fc/fs = {ratio:.6}"),
        "LSB",
        n as u64,
        &errs,
        HALF_Q16_LSB + 2f64.powi(-32) + twin_err,
        Some(1.0 / Q16 / 12f64.sqrt() + twin_err),
    )
}

/// Calibration over `trials` windows of `window` samples: bias and noise estimates.
pub fn calibration(trials: usize, window: usize, seed: u64) -> [Row; 2] {
    let config = Config {
        calibration_s: window as f64 / 3000.0,
        ..Config::default()
    };
    let settings = config.validate().expect("valid budget config");
    let (mut bias_errs, mut noise_errs) = (vec![], vec![]);
    for t in 0..trials {
        let mid = 2000.0 + 0.37 * t as f64;
        let codes = noise_codes(window, mid, 1.5, seed + t as u64);
        let mut cal = settings.calibrator();
        codes.iter().for_each(|&c| cal.push(AdcCode(c)));
        let got = cal.finish().expect("at rest");
        let (mean, sd) = twin::calibrate(&codes);
        bias_errs.push(got.bias_q16 as f64 / Q16 - mean);
        noise_errs.push(got.noise_rms_q16 as f64 / Q16 - sd);
    }
    [
        Row::measured(
            format!("calibration bias, {window}-sample window"),
            "LSB",
            trials as u64,
            &bias_errs,
            HALF_Q16_LSB,
            Some(HALF_Q16_LSB / 3f64.sqrt()),
        ),
        Row::measured(
            format!("calibration noise rms, {window}-sample window"),
            "LSB",
            trials as u64,
            &noise_errs,
            1.0 / Q16,
            Some(1.0 / Q16 / 3f64.sqrt()),
        ),
    ]
}

/// The double integrator against f64 on integer inputs (exact in f64 below 2^53).
pub fn integrator(scheme: Scheme, n: usize, seed: u64) -> Row {
    let mut fixed = imu_core::IntegratorState::default();
    let mut f = twin::Integrator::new(match scheme {
        Scheme::Euler => twin::Scheme::Euler,
        Scheme::Trapezoid => twin::Scheme::Trapezoid,
    });
    let mut errs = vec![];
    for c in noise_codes(n, 2048.0, 300.0, seed) {
        let a = i64::from(c) - 2048;
        scheme.step(&mut fixed, a << 16);
        f.step(a as f64);
        errs.push(fixed.position() as f64 / 4.0 / Q16 - f.s);
    }
    Row::measured(
        format!("{scheme:?} double integration"),
        "LSB*samples^2",
        n as u64,
        &errs,
        0.0,
        None,
    )
}

/// Read-out: counts delivered at 1 kHz from a 3 kHz axis, against the f64 position.
pub fn readout(n: usize, seed: u64) -> Row {
    // Pure integration: the budget measures arithmetic, not drift control.
    let config = Config {
        drift: None,
        ..Config::default()
    };
    let mut tracker = Tracker::new(&config).expect("valid default");
    tracker.feed(&[[2048; 3]; 3000]);
    let settings = *tracker.settings();
    let k = settings.readout().counts_per_unit();
    let mut f = twin::Integrator::new(twin::Scheme::Euler);
    let (mut total, mut errs, mut worst_bound) = (0i64, vec![], 0.0f64);
    for (i, c) in noise_codes(n, 2048.0, 40.0, seed).into_iter().enumerate() {
        tracker.feed(&[[c, 2048, 2048]]);
        f.step(f64::from(c) - 2048.0);
        if i % 3 == 2 {
            total += i64::from(tracker.take_counts()[0]);
            let exact = f.s * 4.0 * Q16 * k; // the f64 position in counts
            errs.push(total as f64 - exact);
            worst_bound = worst_bound.max(0.5 + exact.abs() * 2f64.powi(-32));
        }
    }
    Row::measured(
        "read-out, counts taken at 1 kHz".into(),
        "counts",
        errs.len() as u64,
        &errs,
        worst_bound,
        Some(0.5 / 3f64.sqrt()),
    )
}

/// The whole pipeline of the default device with a 50 Hz digital low-pass: calibrate on a
/// 1 s window, then integrate `t_s` seconds of 1.5 LSB white noise, over `trials` trials.
/// Errors are the fixed-point position minus the f64 twin's [m].
pub fn pipeline(t_s: f64, trials: usize, seed: u64) -> Row {
    let config = Config {
        lowpass_fc_hz: Some(50.0),
        drift: None,
        ..Config::default()
    };
    let fs = f64::from(config.fs_hz);
    let n = (t_s * fs).round() as usize;
    let lsb = config.m_s2_per_lsb;
    let mut errs = vec![];
    for t in 0..trials {
        let mid = 2048.0 + 0.29 * t as f64;
        let window = noise_codes(3000, mid, 1.5, seed + 2 * t as u64);
        let mut tracker = Tracker::new(&config).expect("valid");
        let block: Vec<[u16; 3]> = window.iter().map(|&c| [c, 2048, 2048]).collect();
        tracker.feed(&block);
        let k_q32 = tracker.settings().lowpass_k_q32();
        let (mean, _) = twin::calibrate(&window);
        let mut f = twin::Axis {
            lowpass: Some(twin::Lowpass::realised(k_q32, mean)),
            bias: mean,
            integrator: twin::Integrator::new(twin::Scheme::Euler),
        };
        let mut rng = noise::rng(seed + 2 * t as u64 + 1);
        let adc = Adc { bits: 12 };
        let mut buf = Vec::with_capacity(4096);
        let mut left = n;
        while left > 0 {
            buf.clear();
            for _ in 0..left.min(4096) {
                let c = adc.code(mid + 1.5 * noise::normal(&mut rng));
                f.update(c);
                buf.push([c, 2048, 2048]);
            }
            tracker.feed(&buf);
            left -= buf.len();
        }
        let z = tracker.axes()[0].integrator().position() as f64;
        let fixed_m = z * tracker.settings().metres_per_position_unit();
        errs.push(fixed_m - f.position() * lsb / (fs * fs));
    }
    let nf = n as f64;
    let to_m = lsb / (fs * fs);
    let bias_part = HALF_Q16_LSB / 3f64.sqrt() * nf * (nf + 1.0) / 2.0;
    let round_part = 1.0 / Q16 / 12f64.sqrt() * r::euler_sum(n as u64).sqrt();
    Row::measured(
        format!("pipeline position, T = {t_s} s (3 kHz, 50 Hz low-pass)"),
        "m",
        trials as u64,
        &errs,
        2.0 * HALF_Q16_LSB * nf * (nf + 1.0) / 2.0 * to_m,
        Some((bias_part.powi(2) + round_part.powi(2)).sqrt() * to_m),
    )
}

/// Every budget row; `quick` runs fewer samples (the test suite's size).
pub fn all(quick: bool) -> Vec<Row> {
    let (n_lp, cal_trials, pipe_trials) = if quick {
        (100_000, 200, 8)
    } else {
        (2_000_000, 2000, 40)
    };
    let mut rows: Vec<Row> = [1e-6, 1e-3, 50.0 / 3000.0, 0.499_999]
        .iter()
        .map(|&ratio| lowpass(ratio, n_lp, 1))
        .collect();
    rows.extend(calibration(cal_trials, 3000, 2));
    rows.push(integrator(Scheme::Euler, 1000, 3));
    rows.push(integrator(Scheme::Trapezoid, 1000, 4));
    rows.push(readout(if quick { 30_000 } else { 300_000 }, 5));
    for t in [1.0, 60.0] {
        rows.push(pipeline(t, pipe_trials, 6));
    }
    if !quick {
        rows.push(pipeline(3600.0, 4, 7));
    }
    rows
}

/// The rows as a Markdown table.
pub fn table(rows: &[Row]) -> String {
    let mut out = String::from(
        "| stage | unit | n | max error | max bound | rms error | rms expected |\n|---|---|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        let rms_b = r
            .rms_bound
            .map_or("0 (exact)".into(), |b| format!("{b:.4e}"));
        out += &format!(
            "| {} | {} | {} | {:.5e} | {:.5e} | {:.4e} | {} |\n",
            r.stage, r.unit, r.samples, r.max_err, r.max_bound, r.rms_err, rms_b
        );
    }
    out
}

/// One example, for `cargo lab` alone.
pub const EXAMPLE: &str = "cargo lab budget --quick";

/// `cargo lab budget`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Fewer samples (the test suite's size) and no 1 h pipeline run.
    #[arg(long)]
    pub quick: bool,
    /// Print JSON rows instead of the Markdown table.
    #[arg(long)]
    pub json: bool,
}

/// Runs `cargo lab budget`.
///
/// # Errors
/// None in practice (JSON encoding).
pub fn run(a: &Args) -> super::Outcome {
    let rows = all(a.quick);
    if a.json {
        super::json(&rows)
    } else {
        Ok(table(&rows))
    }
}
