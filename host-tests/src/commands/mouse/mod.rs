//! `cargo lab mouse`: the mouse on a desk. Strokes, rests and clicks of a simulated hand go
//! through the whole device (`imu_core::Tracker` with and without drift control) and the
//! cursor is compared with the hand.
//!
//! The scene is [`crate::world::desk`]: ADXL335 noise and bias walk on a 12-bit ADC at
//! 3 kHz, minimum-jerk strokes of 1 to 30 cm, rests and clicks with their jolts.
//!
//! # Metrics
//! - stroke length and direction: the cursor's displacement from one stroke's start to the
//!   next stroke's start, against the stroke's;
//! - latency: from a stroke's start to the first count it moves, and from its end to the
//!   last count before the next stroke;
//! - click drag: counts moved from a click's press to 300 ms after its release, with the
//!   button edge reaching the tracker [`EDGE_LATE_S`] after the finger (as the firmware's
//!   debounce delivers it);
//! - stationary wander: counts moved in a separate scene of the hand at rest.

use imu_core::hid::screen_motion;
use imu_core::{Config, Drift, Tracker};
use serde::Serialize;

use crate::stats::{spread, Spread};
use crate::world::desk::{Plan, Sensor, FS};
use crate::world::hand::SensorSpec;
use crate::world::noise;

pub mod families;
pub mod pointing;

/// The device's counts per inch (the default configuration).
const CPI: f64 = 800.0;
/// How late a button edge reaches the tracker [s]: the firmware's 5 ms debounce and its
/// 1 ms housekeeping period.
pub const EDGE_LATE_S: f64 = 0.006;

/// Latencies [ms].
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Latency {
    /// From a stroke's start to its first count: median.
    pub start_median: f64,
    /// The same, 90th percentile.
    pub start_p90: f64,
    /// From a stroke's end to its last count: median.
    pub stop_median: f64,
    /// The same, 90th percentile.
    pub stop_p90: f64,
}

/// The metrics of one configuration.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Metrics {
    /// Length of the at-rest scene [min].
    pub stationary_minutes: f64,
    /// Counts moved in it (|x| + |y| summed over every report).
    pub stationary_wander_counts: i64,
    /// Strokes measured.
    pub strokes: usize,
    /// |cursor length - stroke length| / stroke length [%].
    pub stroke_length_error_pct: Spread,
    /// Angle between cursor and stroke [degrees].
    pub direction_error_deg: Spread,
    /// Counts moved around clicks (|x| + |y|), all clicks.
    pub click_drag_counts: i64,
    /// Clicks made.
    pub clicks: usize,
    /// Latencies.
    pub latency_ms: Latency,
}

/// Both configurations.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Report {
    /// With drift control (the device's default).
    #[serde(flatten)]
    pub drift_control: Metrics,
    /// Pure double integration, the same scenes.
    pub pure_integration: Metrics,
    /// Seed.
    pub seed: u64,
}

/// A cursor trace: position [counts] after each 1 ms poll, and the counts moved per poll.
struct Trace {
    pos: Vec<(i64, i64)>,
    moved: Vec<i64>,
}

fn simulate(drift: Option<Drift>, n: usize, seed: u64, p: Option<&Plan>, late: usize) -> Trace {
    let mut rng = noise::rng(seed);
    let mut sensor = Sensor::new(&mut rng);
    let mut t = Tracker::new(&Config {
        drift,
        ..Config::default()
    })
    .expect("valid default config");
    let (mut x, mut y) = (0i64, 0i64);
    let mut tr = Trace {
        pos: Vec::with_capacity(n / 3 + 1),
        moved: Vec::with_capacity(n / 3 + 1),
    };
    for i in 0..n {
        let (ax, ay) = p.map_or((0.0, 0.0), |p| p.accel(i));
        if let Some(p) = p {
            if p.clicks
                .iter()
                .any(|c| c.press + late == i || c.release + late == i)
            {
                t.button_edge();
            }
        }
        // Sensor y points away from the user: screen_motion maps it to cursor up.
        let codes = sensor.codes([ax, ay, 0.0], [0.0; 3], &mut rng);
        t.feed(&[codes]);
        if i % 3 == 2 {
            let (dx, dy) = screen_motion(t.take_counts());
            x += i64::from(dx);
            y -= i64::from(dy); // back to the sensor's frame: y away from the user
            tr.pos.push((x, y));
            tr.moved.push(i64::from(dx).abs() + i64::from(dy).abs());
        }
    }
    tr
}

/// The desk scene's metrics for `drift`, with button edges `edge_late_s` after the finger.
pub fn desk(
    drift: Option<Drift>,
    strokes: usize,
    rest_minutes: f64,
    seed: u64,
    edge_late_s: f64,
) -> Metrics {
    let p = Plan::new(strokes, seed);
    let late = (edge_late_s * FS).round() as usize;
    let tr = simulate(drift, p.n, seed, Some(&p), late);
    let at = |i: usize| tr.pos[(i / 3).min(tr.pos.len() - 1)];
    let counts_per_m = CPI / 0.0254;
    let (mut len_err, mut dir_err, mut start_lat, mut stop_lat) = (vec![], vec![], vec![], vec![]);
    for (k, s) in p.strokes.iter().enumerate() {
        let end = p.strokes.get(k + 1).map_or(p.n - 1, |n| n.start);
        let (x0, y0) = at(s.start.saturating_sub(3));
        let (x1, y1) = at(end - 3);
        let (dx, dy) = ((x1 - x0) as f64, (y1 - y0) as f64);
        let truth = s.distance_m * counts_per_m;
        len_err.push(((dx.hypot(dy) - truth) / truth * 100.0).abs());
        let d = (dy.atan2(dx) - s.dir).rem_euclid(std::f64::consts::TAU);
        dir_err.push(d.min(std::f64::consts::TAU - d).to_degrees());
        let polls = (s.start / 3)..(end / 3);
        if let Some(first) = polls.clone().find(|&q| tr.moved[q] > 0) {
            start_lat.push((first * 3).saturating_sub(s.start) as f64 / FS * 1e3);
        }
        if let Some(last) = polls.rev().find(|&q| tr.moved[q] > 0) {
            let stroke_end = s.start + s.len;
            stop_lat.push((last * 3).saturating_sub(stroke_end) as f64 / FS * 1e3);
        }
    }
    let drag: i64 = p
        .clicks
        .iter()
        .map(|c| {
            tr.moved[c.press / 3..((c.release + (0.3 * FS) as usize) / 3).min(tr.moved.len())]
                .iter()
                .sum::<i64>()
        })
        .sum();
    let rest_n = (1.0 + rest_minutes * 60.0) as usize * FS as usize;
    let rest = simulate(drift, rest_n, seed ^ 0x5EA7, None, 0);
    let s = spread(start_lat);
    let e = spread(stop_lat);
    Metrics {
        stationary_minutes: rest_minutes,
        stationary_wander_counts: rest.moved.iter().sum(),
        strokes: p.strokes.len(),
        stroke_length_error_pct: spread(len_err),
        direction_error_deg: spread(dir_err),
        click_drag_counts: drag,
        clicks: p.clicks.len(),
        latency_ms: Latency {
            start_median: s.median,
            start_p90: s.p90,
            stop_median: e.median,
            stop_p90: e.p90,
        },
    }
}

/// Runs the desk scenes with and without drift control.
pub fn compare(strokes: usize, rest_minutes: f64, seed: u64) -> Report {
    let (on, off) = rayon::join(
        || {
            desk(
                Some(Drift::default()),
                strokes,
                rest_minutes,
                seed,
                EDGE_LATE_S,
            )
        },
        || desk(None, strokes, rest_minutes, seed, EDGE_LATE_S),
    );
    Report {
        drift_control: on,
        pure_integration: off,
        seed,
    }
}

/// The report as a table.
pub fn table(r: &Report) -> String {
    let row = |name: &str, m: &Metrics| {
        format!(
            "{:<20} {:>9} {:>8.2} {:>8.2} {:>8.2} {:>8.2} {:>8} {:>8.1} {:>8.1} {:>8.1} {:>8.1}\n",
            name,
            m.stationary_wander_counts,
            m.stroke_length_error_pct.median,
            m.stroke_length_error_pct.p90,
            m.direction_error_deg.median,
            m.direction_error_deg.p90,
            m.click_drag_counts,
            m.latency_ms.start_median,
            m.latency_ms.start_p90,
            m.latency_ms.stop_median,
            m.latency_ms.stop_p90
        )
    };
    let m = &r.drift_control;
    format!(
        "{} strokes, {} clicks, {} min at rest (seed {})\n{:<20} {:>9} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8}\n{}{}",
        m.strokes,
        m.clicks,
        m.stationary_minutes,
        r.seed,
        "",
        "wander",
        "len% med",
        "len% p90",
        "dir° med",
        "dir° p90",
        "drag",
        "start ms",
        "p90",
        "stop ms",
        "p90",
        row("drift control", &r.drift_control),
        row("pure integration", &r.pure_integration)
    )
}

/// One scene's true path and cursor path, as an SVG (x right, y away from the user).
pub fn path_svg(strokes: usize, seed: u64) -> String {
    let p = Plan::new(strokes, seed);
    let late = (EDGE_LATE_S * FS).round() as usize;
    let on = simulate(Some(Drift::default()), p.n, seed, Some(&p), late);
    let off = simulate(None, p.n, seed, Some(&p), late);
    let counts_per_m = CPI / 0.0254;
    let mut truth = vec![(0.0, 0.0)];
    let (mut tx, mut ty) = (0.0, 0.0);
    for s in &p.strokes {
        tx += s.distance_m * counts_per_m * s.dir.cos();
        ty += s.distance_m * counts_per_m * s.dir.sin();
        truth.push((tx, ty));
    }
    let on_pts: Vec<(f64, f64)> = on
        .pos
        .iter()
        .step_by(10)
        .map(|&(x, y)| (x as f64, y as f64))
        .collect();
    let off_pts: Vec<(f64, f64)> = off
        .pos
        .iter()
        .step_by(10)
        .map(|&(x, y)| (x as f64, y as f64))
        .collect();
    let all = truth.iter().chain(&on_pts);
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in all {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    let span = (x1 - x0).max(y1 - y0).max(1.0) * 1.1;
    let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    let size = 560.0;
    let map = |x: f64, y: f64| {
        (
            40.0 + (x - cx + span / 2.0) / span * size,
            60.0 + (cy - y + span / 2.0) / span * size,
        )
    };
    let poly = |pts: &[(f64, f64)]| {
        pts.iter()
            .map(|&(x, y)| {
                let (a, b) = map(x, y);
                format!("{a:.1},{b:.1}")
            })
            .collect::<Vec<_>>()
            .join(" ")
    };
    // The pure integrator leaves the frame within seconds: draw what stays inside.
    let off_in: Vec<(f64, f64)> = off_pts
        .iter()
        .copied()
        .take_while(|&(x, y)| (x - cx).abs() < span / 2.0 && (y - cy).abs() < span / 2.0)
        .collect();
    format!(
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="640" height="680" viewBox="0 0 640 680" font-family="sans-serif" font-size="12">
<rect width="640" height="680" fill="white"/>
<text x="320" y="24" text-anchor="middle" font-size="15" font-weight="bold">{} strokes on a desk: the hand, and the cursor</text>
<text x="320" y="44" text-anchor="middle">square frame {:.0} mm wide; counts at {} cpi</text>
<rect x="40" y="60" width="{size}" height="{size}" fill="none" stroke="#333"/>
<polyline points="{}" fill="none" stroke="#999" stroke-width="3"/>
<polyline points="{}" fill="none" stroke="#d62728" stroke-width="1.2" stroke-dasharray="4,3"/>
<polyline points="{}" fill="none" stroke="#1f77b4" stroke-width="1.5"/>
<line x1="60" y1="640" x2="90" y2="640" stroke="#999" stroke-width="3"/><text x="96" y="644">hand (true strokes)</text>
<line x1="250" y1="640" x2="280" y2="640" stroke="#1f77b4" stroke-width="1.5"/><text x="286" y="644">cursor, drift control</text>
<line x1="440" y1="640" x2="470" y2="640" stroke="#d62728" stroke-dasharray="4,3"/><text x="476" y="644">pure integration</text>
</svg>
"##,
        p.strokes.len(),
        span / counts_per_m * 1e3,
        CPI,
        poly(&truth),
        poly(&off_in),
        poly(&on_pts)
    )
}

/// One example, for `cargo lab` alone.
pub const EXAMPLE: &str = "cargo lab mouse --quick --rest-minutes 2";

/// `cargo lab mouse`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Strokes in the desk scene.
    #[arg(long, default_value_t = 60)]
    pub strokes: usize,
    /// Length of the at-rest scene [min].
    #[arg(long, allow_negative_numbers = true, default_value_t = 10.0)]
    pub rest_minutes: f64,
    /// Seed of every random draw (the same seed, the same output).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Smaller pointing scenes (for CI).
    #[arg(long)]
    pub quick: bool,
    /// Directory for the path plot and the detectability map.
    #[arg(long, default_value = "target/lab/mouse")]
    pub out: std::path::PathBuf,
    /// Print JSON instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Only the hand model's families and the rate and sensor sweeps (no desk scene, circles
    /// or map).
    #[arg(long)]
    pub families: bool,
    /// Trace one trial of a family, `FAMILY:K` (e.g. `drags:17`, K below the full run's
    /// trials): every change of drift control's state, with the cursor and the velocity.
    #[arg(
        long,
        value_name = "FAMILY:K",
        conflicts_with_all = ["json", "families", "long_rest", "sensitivity"]
    )]
    pub trace: Option<String>,
    /// The traced device's sampling rate [Hz]: trial K of that rate's sweep row (`strokes`;
    /// the board's sensor and the family's own trial K without it, or at 3000).
    #[arg(long, requires = "trace", allow_negative_numbers = true)]
    pub fs: Option<u32>,
    /// The traced device's noise density [ug/sqrt(Hz)]; with `--bits`, trial K of that
    /// sensor's sweep row (`strokes`).
    #[arg(long, requires = "trace", allow_negative_numbers = true)]
    pub noise_ug: Option<f64>,
    /// The traced device's ADC resolution [bits]; with `--noise-ug`, trial K of that
    /// sensor's sweep row (`strokes`).
    #[arg(long, requires = "trace", allow_negative_numbers = true)]
    pub bits: Option<u8>,
    /// A trace line every this many milliseconds as well as at each decision, `1..=60000`.
    #[arg(long, requires = "trace", value_name = "MS")]
    pub every_ms: Option<u32>,
    /// The long-rest benchmark: this many device-hours at rest on each of three sensors
    /// (the ADXL335 with its bias walk, and 100 ug/sqrt(Hz) on 12 bits with that walk and
    /// without it), `0.01..=10000`.
    #[arg(long, value_name = "HOURS")]
    pub long_rest: Option<f64>,
    /// The sensitivity table: every target at half and at twice each constant.
    #[arg(long)]
    pub sensitivity: bool,
}

/// The longest `--rest-minutes`.
const REST_MINUTES_MAX: f64 = 120.0;
/// The noisiest `--noise-ug` [ug/sqrt(Hz)]: through the sensor's 50 Hz pole the noise's rms
/// is `ND sqrt(pi/2 x 50 Hz)` = 8.9 ND, and the default rest bound of 1 m/s^2 rms is reached
/// at ND = 1 / 8.9 / 9.8e-6 = 11 500 ug/sqrt(Hz); at 5000 the rms is under half the bound, so
/// a window's estimate of it (a few per cent off) never reaches it.
const NOISE_UG_MAX: f64 = 5000.0;

/// Runs `cargo lab mouse`: the desk scene, the hand model's families, circles, the map; or
/// one of `--trace`, `--families`, `--long-rest`, `--sensitivity`.
///
/// # Errors
/// A bad argument; an unwritable `--out`.
pub fn run(a: &Args) -> super::Outcome {
    super::folder("out", &a.out)?;
    if a.strokes == 0 || a.strokes > 10_000 {
        return Err(super::Error::arg("strokes", a.strokes, "1..=10000"));
    }
    super::positive("rest-minutes", a.rest_minutes)?;
    if a.rest_minutes > REST_MINUTES_MAX {
        return Err(super::Error::arg(
            "rest-minutes",
            crate::formats::number::Num(a.rest_minutes),
            format!("at most {REST_MINUTES_MAX} (the rest is held in memory, about 1 MB a minute)"),
        ));
    }
    if let Some(fs) = a.fs {
        if !imu_app::device::rate_accepted(fs, 96_000_000) {
            return Err(super::Error::arg(
                "fs",
                fs,
                "the device's rates: 100..=20000 Hz, dividing its 96 MHz clock",
            ));
        }
    }
    if let Some(nd) = a.noise_ug {
        if !(nd.is_finite() && nd > 0.0 && nd <= NOISE_UG_MAX) {
            return Err(super::Error::arg(
                "noise-ug",
                crate::formats::number::Num(nd),
                format!(
                    "must be above 0 and at most {NOISE_UG_MAX} ug/sqrt(Hz): noisier, a window \
                     nears the 1 m/s^2 rest bound and calibration may never succeed"
                ),
            ));
        }
    }
    if let Some(b) = a.bits {
        if !(2..=16).contains(&b) {
            return Err(super::Error::arg(
                "bits",
                b,
                "the core's ADC resolutions: 2..=16",
            ));
        }
    }
    if let Some(t) = &a.trace {
        let bad = || {
            let names: Vec<&str> = families::Kind::ALL.iter().map(|k| k.name()).collect();
            super::Error::arg(
                "trace",
                t,
                format!("FAMILY:K, FAMILY one of {}", names.join(", ")),
            )
        };
        let (name, k) = t.split_once(':').ok_or_else(bad)?;
        let kind = families::Kind::from_name(name).ok_or_else(bad)?;
        // The full run's trials of the family (a sweep row has as many as a family).
        let full = families::Sizes::FULL;
        let n = if kind == families::Kind::VibrationRest {
            full.rest.0.max(4)
        } else {
            full.trials.max(full.sweep_trials)
        };
        let k = k.parse::<usize>().ok().filter(|&k| k < n).ok_or_else(|| {
            super::Error::arg(
                "trace",
                t,
                format!("K, the trial of {name}: 0..{n} (the full run's)"),
            )
        })?;
        let d = SensorSpec::ADXL335;
        let spec = SensorSpec {
            fs: a.fs.map_or(d.fs, f64::from),
            nd_ug: a.noise_ug.unwrap_or(d.nd_ug),
            bits: a.bits.unwrap_or(d.bits),
            ..d
        };
        if let Some(ms) = a.every_ms.filter(|ms| !(1..=60_000).contains(ms)) {
            return Err(super::Error::arg(
                "every-ms",
                ms,
                "1..=60000 ms between trace lines",
            ));
        }
        return Ok(families::trace(
            kind,
            Some(Drift::default()),
            spec,
            a.seed,
            k,
            a.every_ms,
        ));
    }
    let z = if a.quick {
        families::Sizes::QUICK
    } else {
        families::Sizes::FULL
    };
    if let Some(hours) = a.long_rest {
        if !(hours.is_finite() && (0.01..=10_000.0).contains(&hours)) {
            return Err(super::Error::arg(
                "long-rest",
                hours,
                "0.01..=10000 device-hours",
            ));
        }
        let bar = super::progress(0, a.json, "");
        bar.set_message("long rest");
        let r = families::long_rests(Some(Drift::default()), hours, a.seed);
        bar.finish_and_clear();
        if a.json {
            return super::json(&serde_json::to_value(&r)?);
        }
        return Ok(families::long_rest_table(&r));
    }
    if a.sensitivity {
        let bar = super::progress(0, a.json, "");
        bar.set_message("sensitivity");
        let r = families::sensitivity(z, a.seed);
        bar.finish_and_clear();
        if a.json {
            return super::json(&serde_json::to_value(&r)?);
        }
        return Ok(families::sensitivity_table(&r));
    }
    let bar = super::progress(0, a.json, "");
    bar.set_message("hand model families");
    let fams = families::all(Some(Drift::default()), z, a.seed);
    if a.families {
        bar.finish_and_clear();
        if a.json {
            return super::json(&serde_json::to_value(&fams)?);
        }
        return Ok(families::table(&fams));
    }
    bar.set_message("desk scene");
    let report = compare(a.strokes, a.rest_minutes, a.seed);
    bar.set_message("circles and the map");
    let p = if a.quick {
        pointing::Sizes::QUICK
    } else {
        pointing::Sizes::FULL
    };
    let circles = pointing::continuous(Some(Drift::default()), p.figures, a.seed);
    let (l, d, t) = p.map;
    let m = pointing::map(Some(Drift::default()), l, d, t, a.seed);
    bar.finish_and_clear();
    let path = super::write_out(&a.out, "path.svg", &path_svg(12, a.seed))?;
    let map = super::write_out(&a.out, "map.svg", &pointing::map_svg(&m))?;
    if a.json {
        let mut v = serde_json::to_value(&report)?;
        v["families"] = serde_json::to_value(&fams)?;
        v["circles"] = serde_json::to_value(&circles)?;
        v["map"] = serde_json::to_value(&m)?;
        return super::json(&v);
    }
    Ok(format!(
        "{}\n{}\ncircles and figure eights ({}): close within {:.2} % med ({:.2} % max); travel {:.3}x (target: <= 5 % med)\nplots: {}, {}",
        table(&report),
        families::table(&fams),
        circles.figures,
        circles.closure_pct.median,
        circles.closure_pct.max,
        circles.travel_ratio.median,
        path.display(),
        map.display()
    ))
}
