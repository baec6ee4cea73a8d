//! `cargo lab mouse`, the pointing scenes the hand model's families do not cover: continuous
//! circles and figure eights (target 7: they close within 5 %), and the map of
//! which strokes the mouse carries over length and duration.
//!
//! Both run on the families' device ([`super::families::Device`]): the board's ADXL335 at
//! 3 kHz, calibrated flat and at rest for 10 s, a fresh noise realisation per trial.

use imu_core::Drift;
use rayon::prelude::*;
use serde::Serialize;

use super::families::{self, floor_m, Device};
use crate::stats::{spread, Spread};
use crate::world::hand::{uniform, Motion, Scenario, SensorSpec};
use crate::world::noise;

/// Time before and after a figure or a stroke [s].
const LEAD_S: f64 = 0.4;
const TAIL_S: f64 = 0.6;

/// A run of `sc` on a copy of `device`, its cursor path [m] per 1 ms poll.
fn path(device: &Device, sc: &Scenario, seed: u64) -> families::Path {
    families::run(device, sc, seed)
}

/// Target 7: circles and figure eights without a rest.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Continuous {
    /// Figures drawn.
    pub figures: usize,
    /// |cursor end - cursor start| / path length [%].
    pub closure_pct: Spread,
    /// Cursor travel / path length (L1).
    pub travel_ratio: Spread,
}

/// A figure's length along its path and in the L1 sense (`sum |dx| + |dy|`) [m], from
/// 20 000 chords.
fn figure_length(eight: bool, r: f64, total: f64) -> (f64, f64) {
    let steps = 20_000u32;
    let p =
        |j: u32| crate::world::hand::figure(eight, r, total * f64::from(j) / f64::from(steps))[0];
    (0..steps).fold((0.0, 0.0), |(l2, l1), j| {
        let (a, b) = (p(j), p(j + 1));
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        (l2 + dx.hypot(dy), l1 + dx.abs() + dy.abs())
    })
}

/// Runs target 7's scene: `n` figures (circles and figure eights in turn) of radius 2-5 cm,
/// 1-3 turns (1-2 for an eight), at about 0.3 m/s within 1-5 s.
pub fn continuous(drift: Option<Drift>, n: usize, seed: u64) -> Continuous {
    let device = families::board_device(drift, seed);
    let mut rng = noise::rng(seed ^ 0xC1);
    let plan: Vec<(bool, f64, f64)> = (0..n)
        .map(|k| {
            let eight = k % 2 == 1;
            let r = uniform(&mut rng, 0.02, 0.05);
            let turns = if eight {
                uniform(&mut rng, 1.0, 2.0).round()
            } else {
                uniform(&mut rng, 1.0, 3.0).round()
            };
            (eight, r, turns)
        })
        .collect();
    let res: Vec<(f64, f64)> = plan
        .par_iter()
        .enumerate()
        .map(|(k, &(eight, r, turns))| {
            let (length, l1) = figure_length(eight, r, std::f64::consts::TAU * turns);
            let dur = (length / 0.3).clamp(1.0, 5.0);
            let m = Motion::Figure {
                t0: LEAD_S,
                dur,
                eight,
                r,
                turns,
            };
            let sc = Scenario {
                seconds: LEAD_S + dur + TAIL_S,
                edges: vec![],
                motions: vec![m],
            };
            let p = path(&device, &sc, seed.wrapping_mul(1000) + k as u64);
            let (p0, p1) = (p.at(LEAD_S - 0.003), p.at(sc.seconds));
            let closure = (p1[0] - p0[0]).hypot(p1[1] - p0[1]) / length * 100.0;
            (closure, p.travel(LEAD_S - 0.003, sc.seconds) / l1)
        })
        .collect();
    Continuous {
        figures: n,
        closure_pct: spread(res.iter().map(|r| r.0).collect()),
        travel_ratio: spread(res.iter().map(|r| r.1).collect()),
    }
}

/// The detectability map: median vector error over a grid of stroke length and duration.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Map {
    /// Stroke lengths [m].
    pub lengths_m: Vec<f64>,
    /// Durations [s].
    pub durations_s: Vec<f64>,
    /// Median vector error / length [%], `[length][duration]`.
    pub error_pct: Vec<Vec<f64>>,
    /// Strokes per cell.
    pub trials: usize,
}

/// Runs the map: `lengths` x `durations` cells, log-spaced over 1 mm..30 cm and 0.1..3 s.
pub fn map(
    drift: Option<Drift>,
    lengths: usize,
    durations: usize,
    trials: usize,
    seed: u64,
) -> Map {
    let device = families::board_device(drift, seed);
    let grid = |n: usize, lo: f64, hi: f64| -> Vec<f64> {
        (0..n)
            .map(|i| (lo.ln() + (hi.ln() - lo.ln()) * i as f64 / (n - 1) as f64).exp())
            .collect()
    };
    let ls = grid(lengths, 0.001, 0.3);
    let ds = grid(durations, 0.1, 3.0);
    let cells: Vec<(usize, usize)> = (0..lengths)
        .flat_map(|i| (0..durations).map(move |j| (i, j)))
        .collect();
    let med: Vec<f64> = cells
        .par_iter()
        .map(|&(i, j)| {
            let errs = (0..trials)
                .map(|k| {
                    let s =
                        seed.wrapping_mul(1_000_003) + ((i * durations + j) * trials + k) as u64;
                    let dir = std::f64::consts::TAU * (k as f64 + 0.5) / trials as f64;
                    let m = Motion::Stroke {
                        t0: LEAD_S,
                        dur: ds[j],
                        d: ls[i],
                        dir,
                    };
                    let sc = Scenario {
                        seconds: LEAD_S + ds[j] + TAIL_S,
                        edges: vec![],
                        motions: vec![m],
                    };
                    let p = path(&device, &sc, s);
                    let (a, b) = (p.at(LEAD_S - 0.003), p.at(sc.seconds));
                    let t = m.displacement();
                    (b[0] - a[0] - t[0]).hypot(b[1] - a[1] - t[1]) / ls[i] * 100.0
                })
                .collect();
            spread(errs).median
        })
        .collect();
    Map {
        error_pct: (0..lengths)
            .map(|i| med[i * durations..(i + 1) * durations].to_vec())
            .collect(),
        lengths_m: ls,
        durations_s: ds,
        trials,
    }
}

/// The map as an SVG heat map with the noise-floor line `D = 3 ND T^1.5 / sqrt 6`.
pub fn map_svg(m: &Map) -> String {
    let (w, h, x0, y0) = (560.0, 420.0, 80.0, 50.0);
    let (nl, nd) = (m.lengths_m.len(), m.durations_s.len());
    let (cw, ch) = (w / nd as f64, h / nl as f64);
    let lx = |t: f64| {
        let (a, b) = (m.durations_s[0].ln(), m.durations_s[nd - 1].ln());
        x0 + cw / 2.0 + (t.ln() - a) / (b - a) * (w - cw)
    };
    let ly = |d: f64| {
        let (a, b) = (m.lengths_m[0].ln(), m.lengths_m[nl - 1].ln());
        y0 + h - ch / 2.0 - (d.ln() - a) / (b - a) * (h - ch)
    };
    let colour = |e: f64| {
        if e <= 5.0 {
            "#2ca02c"
        } else if e <= 20.0 {
            "#bcbd22"
        } else if e <= 50.0 {
            "#ff7f0e"
        } else {
            "#d62728"
        }
    };
    let mut cells = String::new();
    for (i, row) in m.error_pct.iter().enumerate() {
        for (j, &e) in row.iter().enumerate() {
            let (x, y) = (x0 + j as f64 * cw, y0 + h - (i + 1) as f64 * ch);
            cells += &format!(
                "<rect x=\"{x:.1}\" y=\"{y:.1}\" width=\"{cw:.1}\" height=\"{ch:.1}\" fill=\"{}\" stroke=\"white\"/>\n<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\" font-size=\"10\">{}</text>\n",
                colour(e),
                x + cw / 2.0,
                y + ch / 2.0 + 4.0,
                if e < 100.0 { format!("{e:.0}") } else { ">99".into() }
            );
        }
    }
    let floor: Vec<String> = (0..=60)
        .map(|k| {
            let t = m.durations_s[0]
                * (m.durations_s[nd - 1] / m.durations_s[0]).powf(f64::from(k) / 60.0);
            (t, 3.0 * floor_m(SensorSpec::ADXL335.nd(), t))
        })
        .filter(|&(_, d)| d >= m.lengths_m[0] && d <= m.lengths_m[nl - 1])
        .map(|(t, d)| format!("{:.1},{:.1}", lx(t), ly(d)))
        .collect();
    let mut axes = String::new();
    for (j, t) in m.durations_s.iter().enumerate() {
        axes += &format!(
            "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{t:.2}</text>\n",
            x0 + (j as f64 + 0.5) * cw,
            y0 + h + 16.0
        );
    }
    for (i, d) in m.lengths_m.iter().enumerate() {
        axes += &format!(
            "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{:.1}</text>\n",
            x0 - 6.0,
            y0 + h - (i as f64 + 0.5) * ch + 4.0,
            d * 1e3
        );
    }
    format!(
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="700" height="545" viewBox="0 0 700 545" font-family="sans-serif" font-size="11">
<rect width="700" height="545" fill="white"/>
<text x="360" y="24" text-anchor="middle" font-size="15" font-weight="bold">Which strokes the mouse carries: median vector error [% of length]</text>
{cells}<polyline points="{}" fill="none" stroke="black" stroke-width="2" stroke-dasharray="6,3"/>
{axes}<text x="360" y="{:.0}" text-anchor="middle">stroke duration T [s]</text>
<text x="20" y="{:.0}" text-anchor="middle" transform="rotate(-90 20 {:.0})">stroke length D [mm]</text>
<text x="80" y="520">median of the strokes in a cell; green &lt;= 5 %, olive &lt;= 20 %, orange &lt;= 50 %, red &gt; 50 %</text>
<text x="80" y="535">dashed: D = 3 ND T^1.5 / sqrt 6, three noise floors (ADXL335): below it the sensor's noise is larger</text>
</svg>
"##,
        floor.join(" "),
        y0 + h + 34.0,
        y0 + h / 2.0,
        y0 + h / 2.0,
    )
}

/// Sizes of the scenes.
#[derive(Clone, Copy, Debug)]
pub struct Sizes {
    /// Figures of target 7.
    pub figures: usize,
    /// Map grid: lengths, durations, strokes per cell.
    pub map: (usize, usize, usize),
}

impl Sizes {
    /// The full run: 20 figures, a 12 x 10 map with 5 strokes a cell.
    pub const FULL: Self = Self {
        figures: 20,
        map: (12, 10, 5),
    };
    /// A quick run for CI.
    pub const QUICK: Self = Self {
        figures: 8,
        map: (6, 5, 2),
    };
}
