//! `cargo lab mouse`, the pointing scenes: what a mouse is mostly used for. Slow and small
//! strokes, continuous motion, lifting it onto a tilted surface, knocks on the desk, long
//! rests over many seeds, and the map of which strokes it carries.
//!
//! # The world
//! One ADXL335 on a 12-bit ADC at 3 kHz (as the desk scene): per axis 300 ug/sqrt(Hz)
//! through its 50 Hz RC pole and a 20 ug/sqrt(s) bias walk. Gravity is in it: the sensor
//! reads `g sin(tilt)` on X and Y and `g cos(tilt)` on Z (the device is calibrated flat).
//! Every trial starts from one device, calibrated and then at rest for 10 s (a copy of the
//! tracker and the sensor's state) with a fresh noise realisation: trials are independent
//! and cost no calibration each.
//!
//! # The targets (issue 10)
//! - strokes of 5 mm to 30 cm over 0.2 to 2 s: at least 90 % within
//!   `max(5 % of D, 3 ND T^1.5 / sqrt 6)` (the noise floor of REFERENCE (i));
//! - continuous circles and figure eights of 1 to 5 s: the cursor's path closes within 5 %
//!   of the path's length (median), and travels its length within 10 %;
//! - lifted and set down on a surface tilted by up to 5 degrees, and back: at most 5 mm of
//!   cursor motion per re-placement; with or without a lift, the cursor stops within 0.5 s
//!   of the device coming to rest and stays still;
//! - knocks of 0.05 to 0.5 g: at most 10 counts (0.3 mm) per knock, median;
//! - 0 counts over each rest of every seed.

use imu_core::{Config, Drift, Event, Tracker};
use rayon::prelude::*;
use serde::Serialize;

use crate::stats::{spread, Spread};
use crate::world::desk::{Sensor, FS};
use crate::world::noise::{self, SimRng};
use crate::world::scene::min_jerk_accel;

use super::CPI;

const G: f64 = 9.806_65;
/// The ADXL335's noise density [m/s^2/sqrt(Hz)].
pub const ND: f64 = 300e-6 * G;
const M_PER_COUNT: f64 = 0.0254 / CPI;

/// The noise floor of a stroke of duration `t` [s]: `ND t^1.5 / sqrt 6` [m] per axis
/// (REFERENCE (i)).
pub fn floor_m(t: f64) -> f64 {
    ND * t.powf(1.5) / 6f64.sqrt()
}

/// The gravity the sensor reads at a tilt `(about Y, about X)` [rad], flat = Z up:
/// `g sin` leaks into X and Y.
fn gravity(tilt: [f64; 2]) -> [f64; 3] {
    [
        G * tilt[0].sin(),
        G * tilt[1].sin(),
        G * tilt[0].cos() * tilt[1].cos(),
    ]
}

/// What the hand and the world do at one sample.
#[derive(Clone, Copy, Debug, Default)]
struct Input {
    accel: [f64; 3],
    tilt: [f64; 2],
    edge: bool,
}

/// A device on the desk: the tracker and the sensor, calibrated flat and then at rest for
/// `REST_BEFORE_S` (its bias tracked, its noise learnt), as a mouse is between uses.
#[derive(Clone)]
struct Device {
    tracker: Tracker,
    sensor: Sensor,
}

/// Rest before the trials [s]: a few bias time constants.
const REST_BEFORE_S: f64 = 10.0;

fn calibrated(drift: Option<Drift>, seed: u64) -> Device {
    let mut rng = noise::rng(seed ^ 0xCA11);
    let mut sensor = Sensor::new(&mut rng);
    let mut t = Tracker::new(&Config {
        drift,
        ..Config::default()
    })
    .expect("valid config");
    loop {
        let c = sensor.codes([0.0; 3], gravity([0.0; 2]), &mut rng);
        if let Some(Event::Calibrated(_)) = t.feed(&[c]) {
            break;
        }
    }
    for _ in 0..samples(REST_BEFORE_S) {
        t.feed(&[sensor.codes([0.0; 3], gravity([0.0; 2]), &mut rng)]);
    }
    t.take_counts();
    Device { tracker: t, sensor }
}

/// Runs `n` samples of `input(i)` through a copy of `device` with noise from `seed`;
/// returns the cursor `(x, y)` [m] after each 1 ms poll (every third sample).
fn run(device: &Device, seed: u64, n: usize, input: impl Fn(usize) -> Input) -> Vec<[f64; 2]> {
    let mut t = device.tracker;
    let mut sensor = device.sensor.clone();
    let mut rng = noise::rng(seed);
    let mut pos = [0i64; 2];
    let mut out = Vec::with_capacity(n / 3 + 1);
    for i in 0..n {
        let x = input(i);
        if x.edge {
            t.button_edge();
        }
        t.feed(&[sensor.codes(x.accel, gravity(x.tilt), &mut rng)]);
        if i % 3 == 2 {
            let c = t.take_counts();
            pos[0] += i64::from(c[0]);
            pos[1] += i64::from(c[1]);
            out.push(pos.map(|p| p as f64 * M_PER_COUNT));
        }
    }
    out
}

fn at(path: &[[f64; 2]], sample: usize) -> [f64; 2] {
    path[(sample / 3).min(path.len() - 1)]
}

/// Cursor path length [m] between two samples.
fn travel(path: &[[f64; 2]], from: usize, to: usize) -> f64 {
    let (a, b) = (from / 3, (to / 3).min(path.len() - 1));
    path[a..=b]
        .windows(2)
        .map(|w| (w[1][0] - w[0][0]).abs() + (w[1][1] - w[0][1]).abs())
        .sum()
}

fn samples(s: f64) -> usize {
    (s * FS).round() as usize
}

fn uniform(rng: &mut SimRng, lo: f64, hi: f64) -> f64 {
    use rand::Rng;
    lo + (hi - lo) * rng.random::<f64>()
}

fn log_uniform(rng: &mut SimRng, lo: f64, hi: f64) -> f64 {
    (uniform(rng, lo.ln(), hi.ln())).exp()
}

/// One stroke's result.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct StrokeResult {
    /// Length [m].
    pub distance_m: f64,
    /// Duration [s].
    pub duration_s: f64,
    /// |cursor - hand| at the end [m].
    pub error_m: f64,
    /// `max(5 % of D, 3 floor(T))` [m].
    pub allowed_m: f64,
}

/// One minimum-jerk stroke of `d` over `dur` in direction `dir` from a rest of 0.4 s, and
/// 0.6 s of rest after: its vector error.
fn stroke(device: &Device, seed: u64, d: f64, dur: f64, dir: f64) -> StrokeResult {
    let start = samples(0.4);
    let len = samples(dur);
    let n = start + len + samples(0.6);
    let path = run(device, seed, n, |i| {
        let a = min_jerk_accel((i as f64 - start as f64) / FS, dur, d);
        Input {
            accel: [a * dir.cos(), a * dir.sin(), 0.0],
            ..Input::default()
        }
    });
    let (p0, p1) = (at(&path, start), at(&path, n - 1));
    let e = [p1[0] - p0[0] - d * dir.cos(), p1[1] - p0[1] - d * dir.sin()];
    StrokeResult {
        distance_m: d,
        duration_s: dur,
        error_m: e[0].hypot(e[1]),
        allowed_m: (0.05 * d).max(3.0 * floor_m(dur)),
    }
}

/// Target 1: strokes of 5 mm to 30 cm over 0.2 to 2 s (both log-uniform), any direction.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Strokes {
    /// Strokes made.
    pub strokes: usize,
    /// Fraction within `max(5 % of D, 3 ND T^1.5 / sqrt 6)`.
    pub within: f64,
    /// Vector error / length [%].
    pub error_pct: Spread,
    /// Vector error / noise floor `ND T^1.5 / sqrt 6`.
    pub error_over_floor: Spread,
    /// Every stroke.
    pub results: Vec<StrokeResult>,
}

/// Runs target 1's scene.
pub fn strokes(drift: Option<Drift>, n: usize, seed: u64) -> Strokes {
    let device = calibrated(drift, seed);
    let mut rng = noise::rng(seed ^ 0x57);
    let plan: Vec<(f64, f64, f64)> = (0..n)
        .map(|_| {
            (
                log_uniform(&mut rng, 0.005, 0.3),
                log_uniform(&mut rng, 0.2, 2.0),
                uniform(&mut rng, 0.0, std::f64::consts::TAU),
            )
        })
        .collect();
    let results: Vec<StrokeResult> = plan
        .par_iter()
        .enumerate()
        .map(|(k, &(d, t, dir))| stroke(&device, seed.wrapping_mul(1000) + k as u64, d, t, dir))
        .collect();
    Strokes {
        strokes: n,
        within: results.iter().filter(|r| r.error_m <= r.allowed_m).count() as f64 / n as f64,
        error_pct: spread(
            results
                .iter()
                .map(|r| r.error_m / r.distance_m * 100.0)
                .collect(),
        ),
        error_over_floor: spread(
            results
                .iter()
                .map(|r| r.error_m / floor_m(r.duration_s))
                .collect(),
        ),
        results,
    }
}

/// `n` strokes of `d` [m] over `t` [s] in `n` evenly spread directions.
pub fn strokes_of(drift: Option<Drift>, d: f64, t: f64, n: usize, seed: u64) -> Vec<StrokeResult> {
    let device = calibrated(drift, seed);
    (0..n)
        .into_par_iter()
        .map(|k| {
            let dir = std::f64::consts::TAU * k as f64 / n as f64;
            stroke(&device, seed.wrapping_mul(1000) + k as u64, d, t, dir)
        })
        .collect()
}

/// Target 2: circles and figure eights without a rest.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Continuous {
    /// Figures drawn.
    pub figures: usize,
    /// |cursor end - cursor start| / path length [%].
    pub closure_pct: Spread,
    /// Cursor travel / path length.
    pub travel_ratio: Spread,
}

/// A figure: its position `p(phi)` and the derivatives `p'`, `p''` in `phi`, for a circle
/// or a figure eight of radius `r`.
fn figure(eight: bool, r: f64, phi: f64) -> [[f64; 2]; 3] {
    if eight {
        // Gerono's lemniscate: (sin phi, sin 2 phi / 2).
        let (s, c, s2, c2) = (phi.sin(), phi.cos(), (2.0 * phi).sin(), (2.0 * phi).cos());
        [
            [r * s, r * s2 / 2.0],
            [r * c, r * c2],
            [-r * s, -2.0 * r * s2],
        ]
    } else {
        // From the start point: (cos phi - 1, sin phi).
        let (s, c) = (phi.sin(), phi.cos());
        [[r * (c - 1.0), r * s], [-r * s, r * c], [-r * c, -r * s]]
    }
}

/// A figure's length along its path and in the L1 sense (`sum |dx| + |dy|`) [m], from
/// 20 000 chords.
fn figure_length(eight: bool, r: f64, total: f64) -> (f64, f64) {
    let steps = 20_000u32;
    let p = |j: u32| figure(eight, r, total * f64::from(j) / f64::from(steps))[0];
    (0..steps).fold((0.0, 0.0), |(l2, l1), j| {
        let (a, b) = (p(j), p(j + 1));
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        (l2 + dx.hypot(dy), l1 + dx.abs() + dy.abs())
    })
}

/// Runs target 2's scene.
pub fn continuous(drift: Option<Drift>, n: usize, seed: u64) -> Continuous {
    let device = calibrated(drift, seed);
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
            let total = std::f64::consts::TAU * turns;
            let (length, l1) = figure_length(eight, r, total);
            // About 0.3 m/s on average, within 1..5 s.
            let dur = (length / 0.3).clamp(1.0, 5.0);
            let start = samples(0.4);
            let n = start + samples(dur) + samples(0.6);
            let path = run(&device, seed.wrapping_mul(1000) + k as u64, n, |i| {
                let u = (i as f64 - start as f64) / FS / dur;
                if !(0.0..=1.0).contains(&u) {
                    return Input::default();
                }
                // Angle along a minimum-jerk profile: phi = total s(u).
                let s1 = 30.0 * u * u * (1.0 - u) * (1.0 - u) / dur;
                let s2 = (60.0 * u - 180.0 * u * u + 120.0 * u * u * u) / (dur * dur);
                let [_, d1, d2] = figure(
                    eight,
                    r,
                    total * (10.0 * u.powi(3) - 15.0 * u.powi(4) + 6.0 * u.powi(5)),
                );
                let (w, al) = (total * s1, total * s2);
                Input {
                    accel: [d2[0] * w * w + d1[0] * al, d2[1] * w * w + d1[1] * al, 0.0],
                    ..Input::default()
                }
            });
            let (p0, p1) = (at(&path, start), at(&path, n - 1));
            let closure = (p1[0] - p0[0]).hypot(p1[1] - p0[1]) / length * 100.0;
            // Travel in the L1 sense (as `travel` counts) against the figure's L1 length.
            (closure, travel(&path, start, n - 1) / l1)
        })
        .collect();
    Continuous {
        figures: n,
        closure_pct: spread(res.iter().map(|r| r.0).collect()),
        travel_ratio: spread(res.iter().map(|r| r.1).collect()),
    }
}

/// Target 3: re-placements and tilts.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Tilts {
    /// Re-placements (lift, tilt in the air, set down; each trial does one away and one
    /// back).
    pub replacements: usize,
    /// Cursor travel per re-placement, from the lift to the end of the rest after it [mm].
    pub replacement_mm: Spread,
    /// Tilts without a lift (the surface tilts under the device within 0.3 s).
    pub tilts: usize,
    /// Cursor travel per tilt [mm].
    pub tilt_mm: Spread,
    /// From the device coming to rest to its last count, over both kinds [s].
    pub stop_s: Spread,
    /// Counts moved later than 0.5 s into a rest, over every rest (must be 0).
    pub late_counts: i64,
}

/// A lift 2 cm up and down (0.3 s each, 0.2 s in the air), tilting from `from` to `to`
/// while in the air, and a landing ring of 0.3 g on Z.
fn lift_input(i: usize, at: usize, from: [f64; 2], to: [f64; 2]) -> Input {
    let t = (i as f64 - at as f64) / FS;
    let (up, air, down) = (0.3, 0.2, 0.3);
    let mut z = min_jerk_accel(t, up, 0.02) + min_jerk_accel(t - up - air, down, -0.02);
    let land = t - (up + air + down);
    if land >= 0.0 {
        // A damped ring with zero net velocity: displacement D (1 - cos wt) e^(-t/tau).
        z += knock_accel(land, 0.3 * G);
    }
    let f = (t / (up + air + down)).clamp(0.0, 1.0);
    let s = 10.0 * f.powi(3) - 15.0 * f.powi(4) + 6.0 * f.powi(5);
    Input {
        accel: [0.0, 0.0, z],
        tilt: [
            from[0] + (to[0] - from[0]) * s,
            from[1] + (to[1] - from[1]) * s,
        ],
        edge: false,
    }
}

/// A knock's acceleration `peak` [m/s^2] at `t` [s] after it: the desk rings at 80 Hz and
/// decays in 15 ms, and returns to where it was (displacement `D (1 - cos wt) e^(-t/tau)`:
/// zero net velocity and displacement, REFERENCE (i)).
fn knock_accel(t: f64, peak: f64) -> f64 {
    if t < 0.0 {
        return 0.0;
    }
    let (w, tau) = (std::f64::consts::TAU * 80.0, 0.015);
    let d = peak / (w * w);
    let g = (-t / tau).exp();
    let (f, f1, f2) = (
        1.0 - (w * t).cos(),
        w * (w * t).sin(),
        w * w * (w * t).cos(),
    );
    d * (f2 * g - 2.0 * f1 * g / tau + f * g / (tau * tau))
}

/// Runs target 3's scene: `n` re-placement trials and `n` tilt trials.
pub fn tilts(drift: Option<Drift>, n: usize, seed: u64) -> Tilts {
    let device = calibrated(drift, seed);
    let mut rng = noise::rng(seed ^ 0x717);
    let angles: Vec<[f64; 2]> = (0..n)
        .map(|_| {
            let (th, az) = (
                uniform(&mut rng, 0.5, 5.0).to_radians(),
                uniform(&mut rng, 0.0, std::f64::consts::TAU),
            );
            [th * az.cos(), th * az.sin()]
        })
        .collect();
    let rest = samples(2.5);
    let res: Vec<(bool, f64, Vec<f64>, i64)> = angles
        .par_iter()
        .enumerate()
        .flat_map(|(k, &tilt)| {
            let mut out = vec![];
            for lifted in [true, false] {
                // Rest 0.5 s, away (lift or tilt), rest, back, rest.
                let away = samples(0.5);
                let motion = if lifted { samples(0.8) } else { samples(0.3) };
                let back = away + motion + rest;
                let n = back + motion + rest;
                let input = |i: usize| {
                    if lifted {
                        if i < back {
                            lift_input(i, away, [0.0; 2], tilt)
                        } else {
                            lift_input(i, back, tilt, [0.0; 2])
                        }
                    } else {
                        let f =
                            |at: usize| ((i as f64 - at as f64) / motion as f64).clamp(0.0, 1.0);
                        let s = |f: f64| 10.0 * f.powi(3) - 15.0 * f.powi(4) + 6.0 * f.powi(5);
                        let w = s(f(away)) - s(f(back));
                        Input {
                            tilt: [tilt[0] * w, tilt[1] * w],
                            ..Input::default()
                        }
                    }
                };
                let path = run(
                    &device,
                    seed.wrapping_mul(1000) + 2 * k as u64 + u64::from(lifted),
                    n,
                    input,
                );
                let mut stops = vec![];
                let mut late = 0i64;
                let mut moved = 0.0;
                for at_rest in [away + motion, back + motion] {
                    let end = at_rest + rest;
                    moved += travel(&path, at_rest - motion - 3, end - 3);
                    // The last poll that moved, from the rest's start.
                    let polls = at_rest / 3..(end / 3).min(path.len() - 1);
                    let last = polls
                        .clone()
                        .rev()
                        .find(|&q| path[q] != path[q - 1])
                        .map_or(0.0, |q| (q * 3).saturating_sub(at_rest) as f64 / FS);
                    stops.push(last);
                    let late_from = at_rest + samples(0.5);
                    late += (travel(&path, late_from, end - 3) / M_PER_COUNT).round() as i64;
                }
                out.push((lifted, moved / 2.0 * 1e3, stops, late));
            }
            out
        })
        .collect();
    let pick = |l: bool| spread(res.iter().filter(|r| r.0 == l).map(|r| r.1).collect());
    Tilts {
        replacements: 2 * n,
        replacement_mm: pick(true),
        tilts: 2 * n,
        tilt_mm: pick(false),
        stop_s: spread(res.iter().flat_map(|r| r.2.clone()).collect()),
        late_counts: res.iter().map(|r| r.3).sum(),
    }
}

/// Target 4: knocks on the desk.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Knocks {
    /// Knocks.
    pub knocks: usize,
    /// Counts moved per knock (|x| + |y|).
    pub counts: Spread,
}

/// Runs target 4's scene: knocks of 0.05 to 0.5 g (log-uniform), vertical with a random
/// horizontal share of up to 1/2.
pub fn knocks(drift: Option<Drift>, n: usize, seed: u64) -> Knocks {
    let device = calibrated(drift, seed);
    let mut rng = noise::rng(seed ^ 0x4B);
    let plan: Vec<(f64, f64, f64)> = (0..n)
        .map(|_| {
            (
                log_uniform(&mut rng, 0.05, 0.5) * G,
                uniform(&mut rng, 0.0, 0.5),
                uniform(&mut rng, 0.0, std::f64::consts::TAU),
            )
        })
        .collect();
    let counts: Vec<f64> = plan
        .par_iter()
        .enumerate()
        .map(|(k, &(peak, share, dir))| {
            let at = samples(0.5);
            let n = at + samples(1.0);
            let path = run(&device, seed.wrapping_mul(1000) + k as u64, n, |i| {
                let a = knock_accel((i as f64 - at as f64) / FS, peak);
                Input {
                    accel: [a * share * dir.cos(), a * share * dir.sin(), a],
                    ..Input::default()
                }
            });
            (travel(&path, at, n - 1) / M_PER_COUNT).round()
        })
        .collect();
    Knocks {
        knocks: n,
        counts: spread(counts),
    }
}

/// Target 5: rests, one per seed.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Rests {
    /// Seeds (one device and one rest each).
    pub seeds: usize,
    /// Length of each rest [min].
    pub minutes: f64,
    /// Counts moved in each rest.
    pub wander_counts: Vec<i64>,
}

/// Runs target 5's rests.
pub fn rests(drift: Option<Drift>, seeds: usize, minutes: f64, seed: u64) -> Rests {
    let wander = (0..seeds as u64)
        .into_par_iter()
        .map(|k| {
            let s = seed.wrapping_mul(7919) + k;
            let device = calibrated(drift, s);
            let path = run(&device, s ^ 0x5EA7, samples(minutes * 60.0), |_| {
                Input::default()
            });
            (travel(&path, 0, path.len() * 3 - 1) / M_PER_COUNT).round() as i64
        })
        .collect();
    Rests {
        seeds,
        minutes,
        wander_counts: wander,
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
    let device = calibrated(drift, seed);
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
                    let r = stroke(&device, s, ls[i], ds[j], dir);
                    r.error_m / r.distance_m * 100.0
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
            (t, 3.0 * floor_m(t))
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

/// Every pointing scene, as `cargo lab mouse` runs them.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Scenes {
    /// Target 1.
    pub strokes: Strokes,
    /// Target 2.
    pub continuous: Continuous,
    /// Target 3.
    pub tilts: Tilts,
    /// Target 4.
    pub knocks: Knocks,
    /// Target 5's rests.
    pub rests: Rests,
    /// Target 6.
    pub map: Map,
}

/// Sizes of the scenes.
#[derive(Clone, Copy, Debug)]
pub struct Sizes {
    /// Strokes of target 1.
    pub strokes: usize,
    /// Figures of target 2.
    pub figures: usize,
    /// Tilt trials of target 3 (each: a re-placement away and back, a tilt away and back).
    pub tilt_trials: usize,
    /// Knocks of target 4.
    pub knocks: usize,
    /// Seeds of target 5.
    pub rest_seeds: usize,
    /// Minutes of each rest.
    pub rest_minutes: f64,
    /// Map grid: lengths, durations, strokes per cell.
    pub map: (usize, usize, usize),
}

impl Sizes {
    /// The full run: 200 strokes, 20 figures, 20 x 2 re-placements and tilts, 50 knocks,
    /// 20 seeds, a 12 x 10 map with 5 strokes a cell.
    pub fn full(rest_minutes: f64) -> Self {
        Self {
            strokes: 200,
            figures: 20,
            tilt_trials: 20,
            knocks: 50,
            rest_seeds: 20,
            rest_minutes,
            map: (12, 10, 5),
        }
    }

    /// A quick run for CI.
    pub fn quick(rest_minutes: f64) -> Self {
        Self {
            strokes: 60,
            figures: 8,
            tilt_trials: 5,
            knocks: 20,
            rest_seeds: 4,
            rest_minutes,
            map: (6, 5, 2),
        }
    }
}

/// Runs every scene with `drift`.
pub fn scenes(drift: Option<Drift>, z: Sizes, seed: u64) -> Scenes {
    let (l, d, t) = z.map;
    Scenes {
        strokes: strokes(drift, z.strokes, seed),
        continuous: continuous(drift, z.figures, seed),
        tilts: tilts(drift, z.tilt_trials, seed),
        knocks: knocks(drift, z.knocks, seed),
        rests: rests(drift, z.rest_seeds, z.rest_minutes, seed),
        map: map(drift, l, d, t, seed),
    }
}

/// The scenes as a table: target, measured, required.
pub fn table(s: &Scenes) -> String {
    let st = &s.strokes;
    let c = &s.continuous;
    let t = &s.tilts;
    let moved = s.rests.wander_counts.iter().filter(|&&w| w != 0).count();
    let rows = [
        (
            format!("1 strokes 5 mm-30 cm, 0.2-2 s ({})", st.strokes),
            format!(
                "{:.1} % within; error {:.2} % med, {:.2}x floor med, {:.2}x p90",
                st.within * 100.0,
                st.error_pct.median,
                st.error_over_floor.median,
                st.error_over_floor.p90
            ),
            ">= 90 % within max(5 %, 3 floor)".to_string(),
        ),
        (
            format!("2 circles, figure eights ({})", c.figures),
            format!(
                "closes within {:.2} % med ({:.2} % max); travel {:.3}x",
                c.closure_pct.median, c.closure_pct.max, c.travel_ratio.median
            ),
            "<= 5 % med".to_string(),
        ),
        (
            format!("3 lift onto <= 5 deg tilt ({})", t.replacements),
            format!(
                "{:.2} mm med, {:.2} mm max per re-placement",
                t.replacement_mm.median, t.replacement_mm.max
            ),
            "<= 5 mm each".to_string(),
        ),
        (
            format!("3 tilt without a lift ({})", t.tilts),
            format!(
                "{:.1} mm med runaway; stops {:.3} s med, {:.3} s max; {} counts later",
                t.tilt_mm.median, t.stop_s.median, t.stop_s.max, t.late_counts
            ),
            "stops within 0.5 s, 0 later".to_string(),
        ),
        (
            format!("4 knocks 0.05-0.5 g ({})", s.knocks.knocks),
            format!(
                "{} counts med, {} max",
                s.knocks.counts.median, s.knocks.counts.max
            ),
            "<= 10 counts med".to_string(),
        ),
        (
            format!("5 rest {} min x {} seeds", s.rests.minutes, s.rests.seeds),
            format!(
                "{} seeds moved; {} counts in all",
                moved,
                s.rests.wander_counts.iter().sum::<i64>()
            ),
            "0 counts in each".to_string(),
        ),
    ];
    let mut out = format!("{:<36} {:<72} {}\n", "scene (n)", "measured", "target");
    for (a, b, c) in rows {
        out += &format!("{a:<36} {b:<72} {c}\n");
    }
    out
}
