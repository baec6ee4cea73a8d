//! `cargo lab reproduce`: the paper's laws, reproduced by Monte Carlo through the real
//! fixed-point core, with a table row per point and a log-log plot per law.
//!
//! # Design
//! Five sweeps answer the paper's two questions (how does the error grow with T, and what
//! does fs change?):
//!
//! | sweep | scene | laws |
//! |---|---|---|
//! | `white_vs_t` | white noise, fs = 100 Hz | exact Euler, eq 27 (large N), eq 23 (retrospective) |
//! | `white_vs_fs` | white noise, T = 2 s | exact Euler: rms falls as fs^-1/2 |
//! | `filtered_vs_fs` | fixed 5 Hz analog filter, T = 2 s | AR(1) Euler: rms stops depending on fs (REFERENCE (b) caveat 4) |
//! | `filtered_vs_t` | 1 Hz analog filter, fs = 100 Hz | eq 32 (retrospective) and AR(1) Euler, T^2 -> T^1.5 at 1/(pi fc) |
//! | `bias_vs_t` | a constant bias per trial, trapezoid | eq 2: A T^2 / 2 |
//!
//! Every trial is one seeded trajectory (seed, sweep and trial index fix it, whatever the
//! thread count) whose position is read at several checkpoints, so one run gives every T.
//! Each row's `predicted_m` is computed by [`crate::oracle::predict`] from exactly the inputs in its
//! `params`, so `cargo lab predict` with those inputs prints the same number.
//!
//! A row holds when `|z| < z_crit`, with `z_crit` chosen so that the whole table has a 1 %
//! chance of a false failure (Bonferroni over the non-control rows). Control rows apply a
//! wrong law and pass when they are rejected (`|z| >= z_crit`).

use imu_core::{AdcCode, Axis, Config, Scheme, Settings};
use indicatif::ProgressBar;
use rayon::prelude::*;
use serde::Serialize;

use crate::formats::plot::{Line, Plot, Points};
use crate::oracle::predict::{self, Inputs};
use crate::stats::MeanSquare;
use crate::world::noise::{self, SimRng};
use crate::world::scene::{Adc, Scene, Source, ADXL335_LSB};

/// The inputs of `cargo lab predict` that reproduce a row's prediction.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Params {
    /// Sampling rate [Hz].
    pub fs: f64,
    /// Duration [s].
    pub t: f64,
    /// Per-sample white noise [m/s^2].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sigma_d: Option<f64>,
    /// One-sided density into a single-pole filter [m/s^2/sqrt(Hz)].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sigma_c: Option<f64>,
    /// The filter's cut-off [Hz].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fc: Option<f64>,
    /// Constant bias [m/s^2].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bias: Option<f64>,
}

impl Params {
    /// White noise of per-sample std `sigma_d` [m/s^2].
    pub fn white(fs: f64, t: f64, sigma_d: f64) -> Self {
        Self {
            fs,
            t,
            sigma_d: Some(sigma_d),
            ..Self::default()
        }
    }
    /// Density `sigma_c` [m/s^2/sqrt(Hz)] into a single pole at `fc` [Hz].
    pub fn filtered(fs: f64, t: f64, sigma_c: f64, fc: f64) -> Self {
        Self {
            fs,
            t,
            sigma_c: Some(sigma_c),
            fc: Some(fc),
            ..Self::default()
        }
    }
    /// The same as `cargo lab predict` inputs.
    pub fn inputs(&self) -> Inputs {
        Inputs {
            fs: self.fs,
            t: vec![self.t],
            sigma_d: self.sigma_d,
            sigma_c: self.sigma_c,
            fc: self.fc,
            bias: self.bias,
        }
    }
    /// A constant bias [m/s^2].
    pub fn bias(fs: f64, t: f64, bias: f64) -> Self {
        Self {
            fs,
            t,
            bias: Some(bias),
            ..Self::default()
        }
    }
}

/// One row of the reproduction table.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Row {
    /// What was measured.
    pub name: String,
    /// The law, as the predictor's key without `_m`: eq2, eq23, eq27, euler, trapezoid,
    /// eq32, ar1_euler or trapezoid_bias.
    pub law: &'static str,
    /// The predictor's inputs.
    pub params: Params,
    /// The law's RMS position error [m].
    pub predicted_m: f64,
    /// Monte Carlo RMS [m].
    pub measured_m: f64,
    /// Lower end of the 95 % interval of the RMS [m].
    pub ci_low_m: f64,
    /// Upper end [m].
    pub ci_high_m: f64,
    /// z-score of the prediction.
    pub z: f64,
    /// The row's power: the smallest error of a predicted RMS it rejects, in % of the
    /// measured RMS, `z_crit se / (2 mean)` to first order (an error this size is rejected
    /// half the time, one 1.5 times as large nearly always).
    pub detectable_pct: f64,
    /// Whether the row applies a deliberately wrong law.
    pub control: bool,
    /// Whether the row met its expectation: held (ordinary) or was rejected (control).
    pub pass: bool,
}

/// The whole reproduction.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// All rows.
    pub rows: Vec<Row>,
    /// Files written (SVG plots).
    pub plots: Vec<String>,
    /// Trials per sweep.
    pub trials: usize,
    /// The critical |z| used.
    pub z_crit: f64,
}

/// Which estimate a law is compared with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Estimate {
    /// The integrator's position (sample-by-sample double integration).
    Position,
    /// The retrospective estimate D_N T^2 / 2 from the velocity sum.
    Retrospective,
}

/// A check of one law at one checkpoint.
struct Check {
    law: &'static str,
    estimate: Estimate,
    params: Params,
    control: bool,
    note: &'static str,
}

/// The Monte Carlo result at one checkpoint.
struct Measured {
    position: MeanSquare,
    retrospective: MeanSquare,
}

/// Settings for the core: the project's ADXL335 scale at `fs`, no digital filter.
fn core_settings(fs: u32, scheme: Scheme) -> Settings {
    Config {
        fs_hz: fs,
        lowpass_fc_hz: None,
        scheme,
        drift: None, // the paper's pure double integration
        ..Config::default()
    }
    .validate()
    .expect("reproduce settings are valid")
}

/// The ADC of every reproduction scene: 12 bits, mid-scale zero, ADXL335 scale.
const ADC: Adc = Adc {
    bits: 12,
    mid: 2048.0,
    m_s2_per_lsb: ADXL335_LSB,
};

/// A seed for trial `i` of sweep `sweep`: independent of threads and order.
fn trial_seed(seed: u64, sweep: u64, i: usize) -> u64 {
    seed ^ sweep.wrapping_mul(0xA076_1D64_78BD_642F)
        ^ (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
}

/// Which simulation: the sweep's number (part of every trial's seed), the run's seed, the
/// trials, and the core's rate and scheme.
#[derive(Clone, Copy)]
struct RunSpec {
    sweep: u64,
    seed: u64,
    trials: usize,
    fs: u32,
    scheme: Scheme,
}

/// Runs the trials of `spec`, each with a `scene` built for it, through the core, reading
/// the position and the retrospective estimate after each checkpoint's number of steps.
fn simulate(
    spec: RunSpec,
    checkpoints: &[u64],
    scene: &(dyn Fn(&mut SimRng) -> Scene + Sync),
    bar: &ProgressBar,
) -> Vec<Measured> {
    let RunSpec {
        sweep,
        seed,
        trials,
        fs,
        scheme,
    } = spec;
    let settings = core_settings(fs, scheme);
    let m = settings.metres_per_position_unit();
    let last = *checkpoints.last().expect("at least one checkpoint");
    // The trapezoid's first sample only primes it: N steps take N + 1 samples.
    let extra = u64::from(scheme == Scheme::Trapezoid);
    let per_trial: Vec<Vec<(f64, f64)>> = (0..trials)
        .into_par_iter()
        .map(|i| {
            let mut rng = noise::rng(trial_seed(seed, sweep, i));
            let sc = scene(&mut rng);
            let mut source = sc.start(&mut rng);
            let mut axis = Axis::new(2048 << 16);
            let mut out = Vec::with_capacity(checkpoints.len());
            let mut next = checkpoints.iter().peekable();
            for k in 1..=last + extra {
                axis.update(&settings, AdcCode(source.next_code(&mut rng)));
                if next.peek().is_some_and(|&&n| n + extra == k) {
                    let n = next.next().copied().unwrap_or(0) as f64;
                    let pos = axis.integrator().position() as f64 * m;
                    let retro = axis.integrator().velocity() as f64 * n * m;
                    out.push((pos, retro));
                }
            }
            bar.inc(1);
            out
        })
        .collect();
    (0..checkpoints.len())
        .map(|c| {
            let pos: Vec<f64> = per_trial.iter().map(|t| t[c].0).collect();
            let retro: Vec<f64> = per_trial.iter().map(|t| t[c].1).collect();
            Measured {
                position: MeanSquare::of(&pos),
                retrospective: MeanSquare::of(&retro),
            }
        })
        .collect()
}

/// The predictor's value for `law` at `params`.
fn predicted(law: &str, p: &Params) -> f64 {
    let rows = predict::predict(&p.inputs()).expect("reproduce params are valid predictor inputs");
    let r = &rows[0];
    match law {
        "eq2" => r.eq2_m,
        "eq23" => r.eq23_m,
        "eq27" => r.eq27_m,
        "euler" => r.euler_m,
        "trapezoid" => r.trapezoid_m,
        "eq32" => r.eq32_m,
        "ar1_euler" => r.ar1_euler_m,
        "trapezoid_bias" => r.trapezoid_bias_m,
        _ => None,
    }
    .expect("the law applies to these inputs")
}

/// The predictor's value for a plot curve: `t` snapped to a whole number of samples at
/// `fs`, itself snapped to a whole number of Hz (a curve is drawn, not tested).
fn on_curve(law: &str, p: Params) -> f64 {
    let fs = p.fs.round();
    let t = (p.t * fs).round().max(1.0) / fs;
    predicted(law, &Params { fs, t, ..p })
}

fn row(name: String, check: Check, m: &Measured) -> Row {
    let ms = match check.estimate {
        Estimate::Position => m.position,
        Estimate::Retrospective => m.retrospective,
    };
    let p = predicted(check.law, &check.params);
    let (lo, hi) = ms.ci95();
    let name = if check.note.is_empty() {
        name
    } else {
        format!("{name}, {}", check.note)
    };
    Row {
        name,
        law: check.law,
        params: check.params,
        predicted_m: p,
        measured_m: ms.rms(),
        ci_low_m: lo,
        ci_high_m: hi,
        z: ms.z(p),
        detectable_pct: 100.0 * ms.se_ln_rms(), // times z_crit once it is known
        control: check.control,
        pass: false, // decided once z_crit is known
    }
}

/// Per-sample std after a 12-bit ADC of `sigma_lsb` LSB of white noise [m/s^2]
/// (Sheppard: exact while sigma >= 2 LSB).
fn white_eff(sigma_lsb: f64) -> f64 {
    (sigma_lsb * sigma_lsb + 1.0 / 12.0).sqrt() * ADXL335_LSB
}

fn white_scene(sigma_lsb: f64, fs: f64) -> impl Fn(&mut SimRng) -> Scene + Sync {
    move |_| Scene {
        name: "white",
        about: "white noise",
        fs,
        sources: vec![Source::White {
            sigma_d: sigma_lsb * ADXL335_LSB,
        }],
        adc: ADC,
    }
}

fn filtered_scene(sigma_c: f64, fc: f64, fs: f64) -> impl Fn(&mut SimRng) -> Scene + Sync {
    move |_| Scene {
        name: "filtered",
        about: "single-pole filtered noise",
        fs,
        sources: vec![Source::Filtered { sigma_c, fc }],
        adc: ADC,
    }
}

/// The output of one sweep: rows and a plot.
struct SweepOut {
    rows: Vec<Row>,
    plot: (String, Plot),
}

fn mc_points(label: &str, color: &'static str, xs: &[f64], ms: &[MeanSquare]) -> Points {
    Points {
        label: label.into(),
        color,
        pts: xs
            .iter()
            .zip(ms)
            .map(|(&x, m)| {
                let (lo, hi) = m.ci95();
                (x, m.rms(), lo, hi)
            })
            .collect(),
    }
}

fn curve(
    label: &str,
    color: &'static str,
    dashed: bool,
    xs: &[f64],
    f: impl Fn(f64) -> f64,
) -> Line {
    Line {
        label: label.into(),
        color,
        dashed,
        pts: xs.iter().map(|&x| (x, f(x))).collect(),
    }
}

/// About `n` log-spaced values from `a` to `b` on the grid `1/step` (whole samples when
/// `step` is fs, whole Hz when it is 1), without repeats, so a curve has no steps.
fn logspace(a: f64, b: f64, n: usize, step: f64) -> Vec<f64> {
    let mut v: Vec<f64> = (0..n)
        .map(|i| (a * (b / a).powf(i as f64 / (n - 1) as f64) * step).round() / step)
        .collect();
    v.dedup();
    v
}

fn white_vs_t(seed: u64, trials: usize, bar: &ProgressBar) -> SweepOut {
    let fs = 100u32;
    let ns = [5u64, 10, 30, 100, 300, 1000, 3000];
    let sd = white_eff(4.0);
    let m = simulate(
        RunSpec {
            sweep: 1,
            seed,
            trials,
            fs,
            scheme: Scheme::Euler,
        },
        &ns,
        &white_scene(4.0, 100.0),
        bar,
    );
    let white = |t: f64| Params::white(100.0, t, sd);
    let mut rows = vec![];
    for (i, &n) in ns.iter().enumerate() {
        let t = n as f64 / 100.0;
        let name = format!("white noise 4 LSB, fs 100 Hz, N = {n}");
        let mut checks = vec![
            Check {
                law: "euler",
                estimate: Estimate::Position,
                params: white(t),
                control: false,
                note: "sample-by-sample",
            },
            Check {
                law: "eq23",
                estimate: Estimate::Retrospective,
                params: white(t),
                control: false,
                note: "retrospective",
            },
        ];
        if n >= 300 {
            checks.push(Check {
                law: "eq27",
                estimate: Estimate::Position,
                params: white(t),
                control: false,
                note: "sample-by-sample",
            });
        }
        if n == 5 {
            checks.push(Check {
                law: "eq27",
                estimate: Estimate::Position,
                params: white(t),
                control: true,
                note: "eq 27 ignores the finite-N term",
            });
        }
        if n == 1000 {
            checks.push(Check {
                law: "eq23",
                estimate: Estimate::Position,
                params: white(t),
                control: true,
                note: "eq 23 applied to sample-by-sample",
            });
        }
        rows.extend(checks.into_iter().map(|c| row(name.clone(), c, &m[i])));
    }
    let ts: Vec<f64> = ns.iter().map(|&n| n as f64 / 100.0).collect();
    let fine = logspace(0.05, 30.0, 60, 100.0);
    let plot = Plot {
        title: "White noise: RMS position error vs T (fs = 100 Hz)".into(),
        x_label: "T [s]".into(),
        y_label: "RMS position error [m]".into(),
        lines: vec![
            curve(
                "eq 27, continuous: sd T^1.5 / sqrt(3 fs)",
                "#1f77b4",
                false,
                &fine,
                |t| on_curve("eq27", white(t)),
            ),
            curve(
                "eq 23, retrospective: sd T^1.5 / (2 sqrt(fs))",
                "#d62728",
                true,
                &fine,
                |t| on_curve("eq23", white(t)),
            ),
        ],
        points: vec![
            mc_points(
                "core, sample-by-sample (Euler)",
                "#1f77b4",
                &ts,
                &m.iter().map(|x| x.position).collect::<Vec<_>>(),
            ),
            mc_points(
                "core, retrospective D_N T^2 / 2",
                "#d62728",
                &ts,
                &m.iter().map(|x| x.retrospective).collect::<Vec<_>>(),
            ),
        ],
        marks: vec![],
    };
    SweepOut {
        rows,
        plot: ("white_vs_t".into(), plot),
    }
}

fn white_vs_fs(seed: u64, trials: usize, bar: &ProgressBar) -> SweepOut {
    let t = 2.0;
    let fss = [100u32, 200, 400, 800, 1600, 3200];
    let sd = white_eff(4.0);
    let mut rows = vec![];
    let mut ms = vec![];
    for (k, &fs) in fss.iter().enumerate() {
        let n = (t * f64::from(fs)) as u64;
        let m = simulate(
            RunSpec {
                sweep: 10 + k as u64,
                seed,
                trials,
                fs,
                scheme: Scheme::Euler,
            },
            &[n],
            &white_scene(4.0, f64::from(fs)),
            bar,
        );
        let p = Params::white(f64::from(fs), t, sd);
        let name = format!("white noise 4 LSB per sample, T = 2 s, fs {fs} Hz");
        rows.push(row(
            name.clone(),
            Check {
                law: "euler",
                estimate: Estimate::Position,
                params: p.clone(),
                control: false,
                note: "",
            },
            &m[0],
        ));
        if fs == 3200 {
            // Caveat: per-sample noise fixed, so faster sampling helps; a law without the
            // fs dependence (eq 27 at fs = 100 Hz) is wrong here.
            let wrong = Params { fs: 100.0, ..p };
            rows.push(row(
                name,
                Check {
                    law: "eq27",
                    estimate: Estimate::Position,
                    params: wrong,
                    control: true,
                    note: "the error at fs = 100 Hz (no fs^-1/2 gain)",
                },
                &m[0],
            ));
        }
        ms.push(m[0].position);
    }
    let xs: Vec<f64> = fss.iter().map(|&f| f64::from(f)).collect();
    let fine = logspace(100.0, 3200.0, 40, 1.0);
    let plot = Plot {
        title: "White noise of fixed per-sample std: RMS vs fs at T = 2 s".into(),
        x_label: "fs [Hz]".into(),
        y_label: "RMS position error [m]".into(),
        lines: vec![curve(
            "exact Euler (~ fs^-1/2)",
            "#1f77b4",
            false,
            &fine,
            |fs| on_curve("euler", Params::white(fs, t, sd)),
        )],
        points: vec![mc_points("core, Monte Carlo", "#1f77b4", &xs, &ms)],
        marks: vec![],
    };
    SweepOut {
        rows,
        plot: ("white_vs_fs".into(), plot),
    }
}

/// sigma_c [m/s^2/sqrt(Hz)] giving a filtered rms of `sigma_f_lsb` LSB at cut-off `fc` (eq 31).
fn sigma_c_for(sigma_f_lsb: f64, fc: f64) -> f64 {
    sigma_f_lsb * ADXL335_LSB / (std::f64::consts::PI * fc / 2.0).sqrt()
}

fn filtered_vs_fs(seed: u64, trials: usize, bar: &ProgressBar) -> SweepOut {
    let (t, fc) = (2.0, 5.0);
    let sc = sigma_c_for(20.0, fc);
    let fss = [50u32, 100, 200, 400, 800, 1600];
    let mut rows = vec![];
    let mut ms = vec![];
    for (k, &fs) in fss.iter().enumerate() {
        let n = (t * f64::from(fs)) as u64;
        let m = simulate(
            RunSpec {
                sweep: 20 + k as u64,
                seed,
                trials,
                fs,
                scheme: Scheme::Euler,
            },
            &[n],
            &filtered_scene(sc, fc, f64::from(fs)),
            bar,
        );
        let p = Params::filtered(f64::from(fs), t, sc, fc);
        let name = format!("5 Hz analog filter, sigma_f 20 LSB, T = 2 s, fs {fs} Hz");
        rows.push(row(
            name.clone(),
            Check {
                law: "ar1_euler",
                estimate: Estimate::Position,
                params: p,
                control: false,
                note: "",
            },
            &m[0],
        ));
        if fs == 1600 {
            // REFERENCE (b) caveat 4: treating the filtered samples as white (sigma_d = sigma_f)
            // predicts a 1/sqrt(fs) gain that a fixed analog filter does not give.
            let sigma_f = 20.0 * ADXL335_LSB;
            let wrong = Params::white(f64::from(fs), t, sigma_f);
            rows.push(row(
                name,
                Check {
                    law: "euler",
                    estimate: Estimate::Position,
                    params: wrong,
                    control: true,
                    note: "white law with sigma_d = sigma_f (caveat 4)",
                },
                &m[0],
            ));
        }
        ms.push(m[0].position);
    }
    let xs: Vec<f64> = fss.iter().map(|&f| f64::from(f)).collect();
    let fine = logspace(50.0, 1600.0, 40, 1.0);
    let sigma_f = 20.0 * ADXL335_LSB;
    let plot = Plot {
        title: "Fixed 5 Hz analog filter: RMS vs fs at T = 2 s (caveat 4)".into(),
        x_label: "fs [Hz]".into(),
        y_label: "RMS position error [m]".into(),
        lines: vec![
            curve(
                "AR(1) exact Euler (eq 31 r0)",
                "#2ca02c",
                false,
                &fine,
                |fs| on_curve("ar1_euler", Params::filtered(fs, t, sc, fc)),
            ),
            curve(
                "white law with sigma_d = sigma_f (wrong)",
                "#999999",
                true,
                &fine,
                |fs| on_curve("euler", Params::white(fs, t, sigma_f)),
            ),
        ],
        points: vec![mc_points("core, Monte Carlo", "#2ca02c", &xs, &ms)],
        marks: vec![],
    };
    SweepOut {
        rows,
        plot: ("filtered_vs_fs".into(), plot),
    }
}

fn filtered_vs_t(seed: u64, trials: usize, bar: &ProgressBar) -> SweepOut {
    let (fs, fc) = (100u32, 1.0);
    let sc = sigma_c_for(20.0, fc);
    let ns = [2u64, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 6000];
    let m = simulate(
        RunSpec {
            sweep: 30,
            seed,
            trials,
            fs,
            scheme: Scheme::Euler,
        },
        &ns,
        &filtered_scene(sc, fc, 100.0),
        bar,
    );
    let filt = |t: f64| Params::filtered(100.0, t, sc, fc);
    let sigma_f = 20.0 * ADXL335_LSB;
    let mut rows = vec![];
    for (i, &n) in ns.iter().enumerate() {
        let t = n as f64 / 100.0;
        let name = format!("1 Hz analog filter, sigma_f 20 LSB, fs 100 Hz, N = {n}");
        let mut checks = vec![
            Check {
                law: "eq32",
                estimate: Estimate::Retrospective,
                params: filt(t),
                control: false,
                note: "retrospective",
            },
            Check {
                law: "ar1_euler",
                estimate: Estimate::Position,
                params: filt(t),
                control: false,
                note: "sample-by-sample",
            },
        ];
        if n == 6000 {
            let wrong = Params::white(100.0, t, sigma_f);
            checks.push(Check {
                law: "eq23",
                estimate: Estimate::Retrospective,
                params: wrong,
                control: true,
                note: "eq 23 with sigma_d = sigma_f (caveat 4)",
            });
        }
        rows.extend(checks.into_iter().map(|c| row(name.clone(), c, &m[i])));
    }
    let ts: Vec<f64> = ns.iter().map(|&n| n as f64 / 100.0).collect();
    let fine = logspace(0.02, 60.0, 80, 100.0);
    let plot = Plot {
        title: "Filtered noise (fc = 1 Hz, fs = 100 Hz): T^2 turns into T^1.5 at 1/(pi fc)".into(),
        x_label: "T [s]".into(),
        y_label: "RMS position error [m]".into(),
        lines: vec![
            curve("eq 32, retrospective", "#d62728", false, &fine, |t| {
                on_curve("eq32", filt(t))
            }),
            curve("AR(1) exact Euler", "#2ca02c", false, &fine, |t| {
                on_curve("ar1_euler", filt(t))
            }),
            curve("small T: sigma_f T^2 / 2", "#555555", true, &fine, |t| {
                sigma_f * t * t / 2.0
            }),
            curve(
                "large T: sigma_c T^1.5 / (2 sqrt 2)",
                "#999999",
                true,
                &fine,
                |t| sc * t.powf(1.5) / 8f64.sqrt(),
            ),
        ],
        points: vec![
            mc_points(
                "core, retrospective",
                "#d62728",
                &ts,
                &m.iter().map(|x| x.retrospective).collect::<Vec<_>>(),
            ),
            mc_points(
                "core, sample-by-sample",
                "#2ca02c",
                &ts,
                &m.iter().map(|x| x.position).collect::<Vec<_>>(),
            ),
        ],
        marks: vec![(1.0 / (std::f64::consts::PI * fc), "T = 1/(pi fc)".into())],
    };
    SweepOut {
        rows,
        plot: ("filtered_vs_t".into(), plot),
    }
}

/// A bias drawn per trial (rms 0.3 LSB) under white noise of 4 LSB, through the trapezoid:
/// the noise's T^1.5 dominates below N = 240 samples, the bias's T^2 above. Every row tests
/// the sum of the two in mean square at a different mix (4 % bias at N = 10, 97 % at
/// N = 10 000); each law alone is rejected where the other dominates. (A bias alone is no
/// test: with the trapezoid its position is exactly A T^2 / 2, so every N would measure
/// only the spread of the drawn biases.)
fn bias_vs_t(seed: u64, trials: usize, bar: &ProgressBar) -> SweepOut {
    let fs = 100u32;
    let ns = [10u64, 100, 1000, 10_000];
    let (bias_lsb, noise_lsb) = (0.3, 4.0);
    // The noise dithers the ADC (4 LSB >> 1): the codes' mean is the bias exactly and their
    // variance sigma^2 + 1/12 (Sheppard), so the bias may take any value.
    let scene = move |rng: &mut SimRng| Scene {
        name: "bias",
        about: "a bias per trial under white noise",
        fs: 100.0,
        sources: vec![
            Source::Bias {
                value: bias_lsb * noise::normal(rng) * ADXL335_LSB,
            },
            Source::White {
                sigma_d: noise_lsb * ADXL335_LSB,
            },
        ],
        adc: ADC,
    };
    let m = simulate(
        RunSpec {
            sweep: 40,
            seed,
            trials,
            fs,
            scheme: Scheme::Trapezoid,
        },
        &ns,
        &scene,
        bar,
    );
    let bias = bias_lsb * ADXL335_LSB;
    let sd = white_eff(noise_lsb);
    let both = |t: f64| Params {
        bias: Some(bias),
        ..Params::white(100.0, t, sd)
    };
    let mut rows = vec![];
    for (i, &n) in ns.iter().enumerate() {
        let t = n as f64 / 100.0;
        let name = format!("bias rms {bias_lsb} LSB + white {noise_lsb} LSB, trapezoid, N = {n}");
        let mut checks = vec![Check {
            law: "trapezoid_bias",
            estimate: Estimate::Position,
            params: both(t),
            control: false,
            note: "",
        }];
        if n == 10 {
            checks.push(Check {
                law: "eq2",
                estimate: Estimate::Position,
                params: Params::bias(100.0, t, bias),
                control: true,
                note: "the bias alone (eq 2), where the noise dominates",
            });
        }
        if n == 10_000 {
            checks.push(Check {
                law: "trapezoid",
                estimate: Estimate::Position,
                params: Params::white(100.0, t, sd),
                control: true,
                note: "the noise alone (T^1.5), where the bias dominates",
            });
        }
        rows.extend(checks.into_iter().map(|c| row(name.clone(), c, &m[i])));
    }
    let ts: Vec<f64> = ns.iter().map(|&n| n as f64 / 100.0).collect();
    let fine = logspace(0.1, 100.0, 40, 100.0);
    let plot = Plot {
        title: "A bias under white noise: T^1.5 turns into T^2 (eq 2 + exact trapezoid)".into(),
        x_label: "T [s]".into(),
        y_label: "RMS position error [m]".into(),
        lines: vec![
            curve(
                "bias and noise in mean square",
                "#9467bd",
                false,
                &fine,
                |t| on_curve("trapezoid_bias", both(t)),
            ),
            curve(
                "eq 2: the bias alone, rms(A) T^2 / 2",
                "#555555",
                true,
                &fine,
                |t| on_curve("eq2", Params::bias(100.0, t, bias)),
            ),
            curve(
                "the noise alone, exact trapezoid",
                "#999999",
                true,
                &fine,
                |t| on_curve("trapezoid", Params::white(100.0, t, sd)),
            ),
        ],
        points: vec![mc_points(
            "core, trapezoid",
            "#9467bd",
            &ts,
            &m.iter().map(|x| x.position).collect::<Vec<_>>(),
        )],
        marks: vec![],
    };
    SweepOut {
        rows,
        plot: ("bias_vs_t".into(), plot),
    }
}

/// Two-sided critical z for a 1 % chance of any false failure among `k` rows (Bonferroni).
pub fn z_crit(k: usize) -> f64 {
    let p = 0.01 / (2.0 * k as f64);
    // Solve 0.5 erfc(z / sqrt 2) = p by bisection.
    let (mut lo, mut hi) = (0.0f64, 10.0f64);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if 0.5 * libm::erfc(mid / std::f64::consts::SQRT_2) > p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Simulations per trial over the five sweeps: white_vs_fs and filtered_vs_fs run six each.
const TRIAL_SETS: u64 = 1 + 6 + 6 + 1 + 1;

/// Runs every sweep with `trials` trials each; plots go to `out_dir` if given; `bar` counts
/// the simulations (`trials` times [`TRIAL_SETS`]; hidden or not, as the caller chose).
///
/// # Errors
/// A plot that cannot be written.
pub fn reproduce(
    trials: usize,
    seed: u64,
    out_dir: Option<&std::path::Path>,
    bar: &ProgressBar,
) -> Result<Report, super::Error> {
    let sweeps: [fn(u64, usize, &ProgressBar) -> SweepOut; 5] = [
        white_vs_t,
        white_vs_fs,
        filtered_vs_fs,
        filtered_vs_t,
        bias_vs_t,
    ];
    // Trials per sweep: white_vs_fs and filtered_vs_fs run six simulations each.
    let outs: Vec<SweepOut> = sweeps.iter().map(|f| f(seed, trials, bar)).collect();
    bar.finish_and_clear();
    let mut rows: Vec<Row> = outs.iter().flat_map(|o| o.rows.clone()).collect();
    let k = rows.iter().filter(|r| !r.control).count();
    let zc = z_crit(k);
    for r in &mut rows {
        r.pass = (r.z.abs() < zc) != r.control;
        r.detectable_pct *= zc;
    }
    let mut plots = vec![];
    if let Some(dir) = out_dir {
        for o in &outs {
            let path = super::write_out(dir, &format!("{}.svg", o.plot.0), &o.plot.1.to_svg())?;
            plots.push(path.display().to_string());
        }
    }
    Ok(Report {
        rows,
        plots,
        trials,
        z_crit: zc,
    })
}

/// The report as a readable table.
pub fn table(r: &Report) -> String {
    let mut out = format!(
        "{:<78} {:<14} {:>11} {:>11} {:>7} {:>8}  {}\n",
        "case", "law", "predicted", "measured", "z", "detects", "result"
    );
    for row in &r.rows {
        let result = match (row.control, row.pass) {
            (false, true) => "holds",
            (false, false) => "FAILS",
            (true, true) => "control, rejected",
            (true, false) => "CONTROL NOT REJECTED",
        };
        out += &format!(
            "{:<78} {:<14} {:>11.4e} {:>11.4e} {:>+7.2} {:>7.1}%  {}\n",
            row.name, row.law, row.predicted_m, row.measured_m, row.z, row.detectable_pct, result
        );
    }
    let bad = r.rows.iter().filter(|x| !x.pass).count();
    out += &format!(
        "{} rows, {} trials per sweep, |z| < {:.2} holds (1 % family-wise over {} rows); {}\n",
        r.rows.len(),
        r.trials,
        r.z_crit,
        r.rows.iter().filter(|x| !x.control).count(),
        if bad == 0 {
            "every row as expected".to_string()
        } else {
            format!("{bad} rows NOT as expected")
        }
    );
    let laws = r.rows.iter().filter(|x| !x.control);
    let (best, worst) = laws.fold((f64::INFINITY, 0.0f64), |(lo, hi), x| {
        (lo.min(x.detectable_pct), hi.max(x.detectable_pct))
    });
    out += &format!(
        "detects: the smallest error of a predicted RMS each row rejects ({best:.1} % to {worst:.1} % over the law rows)\n"
    );
    for p in &r.plots {
        out += &format!("plot: {p}\n");
    }
    out
}

/// One example, for `cargo lab` alone.
pub const EXAMPLE: &str = "cargo lab reproduce --quick";

/// `cargo lab reproduce`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// CI-sized run: 1000 trials per sweep instead of 10 000, the same rows.
    #[arg(long)]
    pub quick: bool,
    /// Trials per sweep (overrides --quick).
    #[arg(long)]
    pub trials: Option<usize>,
    /// Seed of every random draw (the same seed, the same output).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Directory for the SVG plots.
    #[arg(long, default_value = "target/lab/reproduce")]
    pub out: std::path::PathBuf,
    /// Print `{"rows": [..], "plots": [..], "trials": ..}` instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// Runs `cargo lab reproduce`.
///
/// # Errors
/// Too few trials; an unwritable `--out`; [`super::Error::Check`] when a row does not come
/// out as expected (a law rejected or a control accepted).
pub fn run(a: &Args) -> super::Outcome {
    super::folder("out", &a.out)?;
    let trials = a.trials.unwrap_or(if a.quick { 1000 } else { 10_000 });
    if trials < 100 {
        return Err(super::Error::arg(
            "trials",
            trials,
            "at least 100, or the normal approximation behind the z-scores fails",
        ));
    }
    let bar = super::progress(trials as u64 * TRIAL_SETS, a.json, "trials");
    let report = reproduce(trials, a.seed, Some(&a.out), &bar)?;
    let bad = report.rows.iter().filter(|r| !r.pass).count();
    let text = if a.json {
        serde_json::to_string_pretty(&report)?
    } else {
        table(&report)
    };
    if bad > 0 {
        return Err(super::Error::Check {
            report: text,
            why: format!("{bad} rows did not come out as expected"),
        });
    }
    Ok(text)
}
