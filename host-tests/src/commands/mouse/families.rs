//! `cargo lab mouse`, the hand model's families (issue 22): motions nobody scripted, drawn
//! at random from stated ranges, each judged against its target with its physical floor
//! beside the measured error.
//!
//! # Method
//! A family is a generator of randomised [`Scenario`]s ([`crate::world::hand`]) and a
//! measurement of each. Every trial of a family starts from one device of the family's
//! sensor, calibrated flat and then at rest for [`REST_BEFORE_S`] (a copy of the tracker and
//! the sensor's state), with a fresh noise realisation; the cursor is read every 1 ms (a USB
//! poll) and kept in metres at the configured counts per inch.
//!
//! # Floors (REFERENCE (i), (j))
//! - a stroke of duration `T` from a zero-velocity update: `ND T^1.5 / sqrt 6` per axis;
//! - with the zero's own uncertainty (the bias floor): `sqrt(ND^2 T^3 / 6 + sd(b)^2 T^4 / 4)`,
//!   `sd(b) = ND / sqrt(2 T_rest)`, `T_rest` the rest the device averaged before the motion,
//!   at most its averaging time (drift control's bias time constant).

use imu_core::{Config, Drift, DriftState, Event, Tracker};
use rayon::prelude::*;
use serde::Serialize;

use crate::stats::{spread, Spread};
use crate::world::hand::{self, log_uniform, tilt_of, uniform, Motion, Scenario, SensorSpec, G};
use crate::world::noise::{self, SimRng};

/// Rest before every trial [s]: the device calibrated, then at rest this long.
pub const REST_BEFORE_S: f64 = 10.0;
/// Rest before the motion of a trial [s].
const LEAD_S: f64 = 0.4;
/// Rest after the motion of a trial [s].
const TAIL_S: f64 = 0.6;

/// The white-noise floor `ND T^1.5 / sqrt 6` [m] of a motion of `t` [s].
pub fn floor_m(nd: f64, t: f64) -> f64 {
    nd * t.powf(1.5) / 6f64.sqrt()
}

/// The bias floor `sqrt(ND^2 T^3 / 6 + sd(b)^2 T^4 / 4)` [m], `sd(b) = ND / sqrt(2 T_rest)`.
pub fn bias_floor_m(nd: f64, t: f64, t_rest: f64) -> f64 {
    let sb2 = nd * nd / (2.0 * t_rest);
    (nd * nd * t.powi(3) / 6.0 + sb2 * t.powi(4) / 4.0).sqrt()
}

/// The tracker's configuration for `spec`: its rate, scale and resolution, the rest of
/// `base`.
pub fn config_for(spec: SensorSpec, base: Config) -> Config {
    Config {
        fs_hz: spec.fs.round() as u32,
        m_s2_per_lsb: spec.lsb(),
        adc_bits: spec.bits,
        ..base
    }
}

/// A device at rest: its tracker and its sensor.
#[derive(Clone)]
pub struct Device {
    tracker: Tracker,
    sensor: hand::Sensor,
    cpi: f64,
}

impl Device {
    /// A device of `spec` with `config` (rate, scale and resolution from `spec`), calibrated
    /// flat and at rest for [`REST_BEFORE_S`], from `seed`.
    ///
    /// # Panics
    /// If `config` with the sensor's rate, scale and bits does not validate, or the device
    /// never calibrates in 60 s (a scene error, not an input).
    pub fn calibrated(spec: SensorSpec, config: Config, seed: u64) -> Self {
        let mut rng = noise::rng(seed ^ 0xCA11);
        let mut sensor = hand::Sensor::new(spec, &mut rng);
        let config = config_for(spec, config);
        let mut t = Tracker::new(&config).expect("the family's configuration is valid");
        let mut calibrated = false;
        for _ in 0..(60.0 * spec.fs) as usize {
            let c = sensor.codes([0.0; 3], [0.0; 3], [0.0; 2], &mut rng);
            if let Some(Event::Calibrated(_)) = t.feed(&[c]) {
                calibrated = true;
                break;
            }
        }
        assert!(calibrated, "{spec:?} never calibrated at rest");
        for _ in 0..(REST_BEFORE_S * spec.fs) as usize {
            t.feed(&[sensor.codes([0.0; 3], [0.0; 3], [0.0; 2], &mut rng)]);
        }
        t.take_counts();
        Self {
            tracker: t,
            sensor,
            cpi: f64::from(config.counts_per_inch),
        }
    }

    /// The sensor's rate [Hz].
    pub fn fs(&self) -> f64 {
        self.sensor.spec().fs
    }
}

/// The cursor through one trial, one entry per 1 ms poll.
#[derive(Clone, Debug, Default)]
pub struct Path {
    /// Time of each poll [s].
    pub t: Vec<f64>,
    /// Cursor position after it [m].
    pub pos: Vec<[f64; 2]>,
    /// Whether tracking was suspended (drift control's Lifted state) at it.
    pub suspended: Vec<bool>,
}

impl Path {
    /// Index of the first poll at or after `t`.
    fn index(&self, t: f64) -> usize {
        self.t.partition_point(|&x| x < t).min(self.t.len() - 1)
    }

    /// The cursor at `t` [m].
    pub fn at(&self, t: f64) -> [f64; 2] {
        self.pos[self.index(t)]
    }

    /// Cursor travel (`sum |dx| + |dy|`) over `from..to` [m].
    pub fn travel(&self, from: f64, to: f64) -> f64 {
        let (a, b) = (self.index(from), self.index(to));
        self.pos[a..=b.max(a)]
            .windows(2)
            .map(|w| (w[1][0] - w[0][0]).abs() + (w[1][1] - w[0][1]).abs())
            .sum()
    }

    /// The time of the last poll in `from..to` that moved the cursor, if any.
    pub fn last_move(&self, from: f64, to: f64) -> Option<f64> {
        let (a, b) = (self.index(from).max(1), self.index(to));
        (a..=b)
            .rev()
            .find(|&i| self.pos[i] != self.pos[i - 1])
            .map(|i| self.t[i])
    }

    /// The largest retreat against direction `dir` over `from..to` [m]: how far the cursor's
    /// projection on `dir` ever falls below its running maximum.
    pub fn max_back(&self, from: f64, to: f64, dir: f64) -> f64 {
        let (a, b) = (self.index(from), self.index(to));
        let (c, s) = (dir.cos(), dir.sin());
        let mut best = f64::MIN;
        let mut back = 0.0f64;
        for p in &self.pos[a..=b.max(a)] {
            let x = p[0] * c + p[1] * s;
            best = best.max(x);
            back = back.max(best - x);
        }
        back
    }
}

/// Runs `sc` through a copy of `device` with noise from `seed`.
pub fn run(device: &Device, sc: &Scenario, seed: u64) -> Path {
    let mut t = device.tracker;
    let mut sensor = device.sensor.clone();
    let mut rng = noise::rng(seed);
    let fs = device.fs();
    let n = (sc.seconds * fs).round() as usize;
    let m_per_count = 0.0254 / device.cpi;
    let mut edges = sc.edges.clone();
    edges.sort_by(f64::total_cmp);
    let mut next_edge = 0;
    let mut pos = [0i64; 2];
    let mut path = Path::default();
    let mut poll_ms = 0u64;
    for i in 0..n {
        let time = i as f64 / fs;
        while next_edge < edges.len() && edges[next_edge] <= time {
            t.button_edge();
            next_edge += 1;
        }
        let (a, read, tilt) = sc.at(time);
        t.feed(&[sensor.codes(a, read, tilt, &mut rng)]);
        // A poll every millisecond of sample time (every sample below 1 kHz).
        let ms = ((i + 1) as f64 / fs * 1000.0).floor() as u64;
        if ms > poll_ms || fs <= 1000.0 {
            poll_ms = ms;
            let c = t.take_counts();
            pos[0] += i64::from(c[0]);
            pos[1] += i64::from(c[1]);
            path.t.push(time);
            path.pos.push(pos.map(|p| p as f64 * m_per_count));
            path.suspended
                .push(t.drift_state() == Some(DriftState::Lifted));
        }
    }
    path
}

/// The result of one trial that ends in a measured displacement.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Trial {
    /// The motion's length [m] (0 for what should not move the cursor).
    pub length_m: f64,
    /// The motion's duration [s].
    pub duration_s: f64,
    /// The measured error [m]: the vector error of a displacement, or the cursor travel of
    /// what should not move it.
    pub error_m: f64,
    /// The error the target allows [m].
    pub allowed_m: f64,
    /// The floor beside it [m].
    pub floor_m: f64,
}

/// One family's summary.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Family {
    /// Name (`strokes`, `drags`, ...).
    pub name: String,
    /// Which target of issue 22 it checks.
    pub target: &'static str,
    /// Trials.
    pub trials: usize,
    /// Fraction of trials within what the target allows.
    pub within: f64,
    /// The error [mm].
    pub error_mm: Spread,
    /// The floor [mm].
    pub floor_mm: Spread,
    /// Extra figures of the family (name, value), e.g. the largest retreat of a drag.
    pub extra: Vec<(String, f64)>,
    /// Whether the family meets its target.
    pub pass: bool,
    /// What the target asks, in words.
    pub asks: String,
}

fn summarise(
    name: impl Into<String>,
    target: &'static str,
    trials: &[Trial],
    need_within: Option<f64>,
) -> Family {
    let within = trials.iter().filter(|r| r.error_m <= r.allowed_m).count() as f64
        / trials.len().max(1) as f64;
    let error_mm = spread(trials.iter().map(|r| r.error_m * 1e3).collect());
    Family {
        name: name.into(),
        target,
        trials: trials.len(),
        within,
        error_mm,
        floor_mm: spread(trials.iter().map(|r| r.floor_m * 1e3).collect()),
        extra: vec![],
        pass: need_within.is_none_or(|w| within >= w),
        asks: need_within.map_or(String::new(), |w| format!(">= {:.0} % within", w * 100.0)),
    }
}

/// The vector error of the cursor's displacement over `from..to` against `truth` [m].
fn vector_error(p: &Path, from: f64, to: f64, truth: [f64; 2]) -> f64 {
    let (a, b) = (p.at(from), p.at(to));
    (b[0] - a[0] - truth[0]).hypot(b[1] - a[1] - truth[1])
}

/// Strokes of target 1 (5 mm-30 cm over 0.2-2 s, both log-uniform, any direction) on
/// `device`, with motions `compose(rng, duration)` puts around each (knocks, vibration, a
/// tilt before) and the stroke's start; its `t_rest` is `None` for the plain floor, or the
/// rest the zero was averaged over for the bias floor.
fn strokes_with(
    device: &Device,
    nd: f64,
    n: usize,
    seed: u64,
    compose: impl Fn(&mut SimRng, f64) -> (Vec<Motion>, f64, Option<f64>) + Sync,
) -> Vec<Trial> {
    (0..n)
        .into_par_iter()
        .map(|k| {
            let mut rng = noise::rng(seed.wrapping_mul(7919).wrapping_add(k as u64));
            let (dur, d, dir) = (
                log_uniform(&mut rng, 0.2, 2.0),
                log_uniform(&mut rng, 0.005, 0.3),
                uniform(&mut rng, 0.0, std::f64::consts::TAU),
            );
            let (mut motions, t0, t_rest) = compose(&mut rng, dur);
            let stroke = Motion::Stroke { t0, dur, d, dir };
            motions.push(stroke);
            let sc = Scenario {
                seconds: t0 + dur + TAIL_S,
                edges: vec![],
                motions,
            };
            let p = run(device, &sc, rng_seed(&mut rng));
            let e = vector_error(&p, t0 - 0.003, sc.seconds, stroke.displacement());
            let floor = match t_rest {
                None => floor_m(nd, dur),
                Some(r) => bias_floor_m(nd, dur, r),
            };
            Trial {
                length_m: d,
                duration_s: dur,
                error_m: e,
                allowed_m: (0.05 * d).max(3.0 * floor),
                floor_m: floor,
            }
        })
        .collect()
}

fn rng_seed(rng: &mut SimRng) -> u64 {
    use rand::Rng;
    rng.random()
}

/// What the families are run with.
#[derive(Clone, Copy, Debug)]
pub struct Sizes {
    /// Trials per family.
    pub trials: usize,
    /// Trials per rate and per sensor of the sweeps.
    pub sweep_trials: usize,
    /// Devices and minutes of the rest family.
    pub rest: (usize, f64),
}

impl Sizes {
    /// The full run: 200 trials a family (issue 22), 100 per rate and sensor.
    pub const FULL: Self = Self {
        trials: 200,
        sweep_trials: 100,
        rest: (20, 10.0),
    };
    /// A quick run (CI).
    pub const QUICK: Self = Self {
        trials: 40,
        sweep_trials: 20,
        rest: (4, 2.0),
    };
}

/// The rates the sweep visits: the firmware's bounds, the default and rates between, each
/// dividing 96 MHz (the firmware accepts those).
pub const RATES: [u32; 9] = [100, 250, 500, 1000, 2000, 3000, 6000, 12_000, 20_000];

/// The sensors the sweep visits: noise density [ug/sqrt(Hz)] and ADC bits.
pub const SENSORS: [(f64, u8); 8] = [
    (100.0, 12),
    (100.0, 16),
    (300.0, 10),
    (300.0, 14),
    (300.0, 16),
    (1000.0, 10),
    (1000.0, 12),
    (1000.0, 16),
];

/// Every family with `drift` (and the device's default configuration otherwise).
pub fn all(drift: Option<Drift>, z: Sizes, seed: u64) -> Vec<Family> {
    let base = Config {
        drift,
        ..Config::default()
    };
    let spec = SensorSpec::ADXL335;
    let nd = spec.nd();
    let avg_s = drift.and_then(|d| d.bias_tau_s).unwrap_or(1.0);
    let t_rest = |rest: f64| rest.min(avg_s);
    let dev = Device::calibrated(spec, base, seed);
    let n = z.trials;
    let mut out = vec![];

    // Target 1: strokes from rest.
    let t = strokes_with(&dev, nd, n, seed ^ 1, |_, _| (vec![], LEAD_S, None));
    out.push(summarise("strokes", "1", &t, Some(0.9)));

    // Target 2: drags.
    out.push(drags(&dev, nd, n, seed ^ 2, t_rest(REST_BEFORE_S)));

    // Target 3: lifts, pad tilts, strokes after either.
    out.push(lifts(&dev, n, seed ^ 3));
    out.push(pad_tilts(&dev, n, seed ^ 4));
    let t = strokes_with(&dev, nd, n, seed ^ 5, |rng, _| {
        let deg = uniform(rng, 0.5, 5.0);
        let to = tilt_of(rng, deg);
        let m = if rng_seed(rng).is_multiple_of(2) {
            let dur = uniform(rng, 0.3, 2.0);
            Motion::Tilt {
                t0: LEAD_S,
                dur,
                from: [0.0; 2],
                to,
            }
        } else {
            lift_motion(rng, LEAD_S, [0.0; 2], to)
        };
        let gap = uniform(rng, 0.1, 2.0);
        (vec![m], m.end() + gap, Some(t_rest(gap)))
    });
    out.push(summarise("strokes after a tilt", "3", &t, Some(0.9)));

    // Target 4: knocks alone, and strokes with knocks before or during them.
    out.push(knocks(&dev, n, seed ^ 6));
    let t = strokes_with(&dev, nd, n, seed ^ 7, |rng, dur| {
        let t0 = LEAD_S + 0.3;
        let mut m = vec![];
        let where_ = rng_seed(rng) % 3;
        if where_ != 1 {
            let at = t0 - uniform(rng, 0.05, 0.3);
            m.push(random_knock(rng, at));
        }
        if where_ != 0 {
            let at = t0 + uniform(rng, 0.0, dur);
            m.push(random_knock(rng, at));
        }
        (m, t0, None)
    });
    out.push(summarise("strokes with knocks", "4", &t, Some(0.9)));

    // Target 5: vibration.
    let vib = |rng: &mut SimRng, all: bool| Motion::Vibration {
        t0: 0.0,
        f: uniform(rng, 30.0, 100.0),
        amp: log_uniform(rng, 0.005, 0.05) * G,
        all,
        phase: core::array::from_fn(|_| uniform(rng, 0.0, std::f64::consts::TAU)),
    };
    for all in [false, true] {
        let t = strokes_with(&dev, nd, n, seed ^ (8 + u64::from(all)), |rng, _| {
            (vec![vib(rng, all)], LEAD_S + 0.6, None)
        });
        let name = if all {
            "strokes, vibration on every axis"
        } else {
            "strokes, vibration on Z"
        };
        out.push(summarise(name, "5", &t, Some(0.9)));
    }
    out.push(vibration_rest(&dev, z.rest.0.max(4), seed ^ 10, vib));

    // Target 6: rest.
    out.push(rests(spec, base, z.rest.0, z.rest.1, seed ^ 11));

    // Target 1 at every rate of the sweep and on every sensor.
    for &fs in &RATES {
        let spec = SensorSpec {
            fs: f64::from(fs),
            ..SensorSpec::ADXL335
        };
        let dev = Device::calibrated(spec, base, seed ^ u64::from(fs));
        let t = strokes_with(
            &dev,
            nd,
            z.sweep_trials,
            seed ^ 12 ^ u64::from(fs),
            |_, _| (vec![], LEAD_S, None),
        );
        out.push(summarise(format!("strokes at {fs} Hz"), "1", &t, Some(0.9)));
    }
    for &(nd_ug, bits) in &SENSORS {
        let spec = SensorSpec {
            nd_ug,
            bits,
            ..SensorSpec::ADXL335
        };
        let dev = Device::calibrated(spec, base, seed ^ (nd_ug as u64) ^ u64::from(bits));
        let t = strokes_with(&dev, spec.nd(), z.sweep_trials, seed ^ 13, |_, _| {
            (vec![], LEAD_S, None)
        });
        // Issue 22 asks 12 to 16 bits to meet target 1; 10 bits are reported.
        let need = (bits >= 12).then_some(0.9);
        out.push(summarise(
            format!("strokes, {nd_ug:.0} ug/sqrt(Hz), {bits} bits"),
            "1",
            &t,
            need,
        ));
    }
    out
}

/// A random lift of 3-20 mm rising in 0.15-0.5 s from tilt `from` onto `to`, tilting in
/// the air or as it lands, from `t0`.
fn lift_motion(rng: &mut SimRng, t0: f64, from: [f64; 2], to: [f64; 2]) -> Motion {
    let rise = uniform(rng, 0.15, 0.5);
    Motion::Lift {
        t0,
        h: log_uniform(rng, 0.003, 0.02),
        rise,
        air: uniform(rng, 0.1, 0.5),
        fall: rise * uniform(rng, 0.8, 1.25),
        from,
        to,
        in_air: rng_seed(rng).is_multiple_of(2),
    }
}

/// A random knock at `t0`: 0.05-0.5 g (log-uniform) ringing at 20-60 Hz for 1-3 periods,
/// a flex of 20-200 um, up to a third of it horizontal.
fn random_knock(rng: &mut SimRng, t0: f64) -> Motion {
    Motion::Knock {
        t0,
        peak: log_uniform(rng, 0.05, 0.5) * G,
        f: uniform(rng, 20.0, 60.0),
        periods: uniform(rng, 1.0, 3.0),
        flex: log_uniform(rng, 20e-6, 200e-6),
        share: uniform(rng, 0.0, 1.0 / 3.0),
        dir: uniform(rng, 0.0, std::f64::consts::TAU),
    }
}

/// Target 2: drags with jerk-limited ramps of 0.1-0.3 s and glides of 0.5-4 s at 10-100
/// mm/s, within `max(10 %, 3 bias floors)`; and the largest retreat against the drag's
/// direction (at most 2 mm, ever).
fn drags(dev: &Device, nd: f64, n: usize, seed: u64, t_rest: f64) -> Family {
    let res: Vec<(Trial, f64)> = (0..n)
        .into_par_iter()
        .map(|k| {
            let mut rng = noise::rng(seed.wrapping_mul(104_729).wrapping_add(k as u64));
            let m = Motion::Drag {
                t0: LEAD_S,
                ramp_up: uniform(&mut rng, 0.1, 0.3),
                glide: uniform(&mut rng, 0.5, 4.0),
                ramp_down: uniform(&mut rng, 0.1, 0.3),
                v: log_uniform(&mut rng, 0.01, 0.1),
                dir: uniform(&mut rng, 0.0, std::f64::consts::TAU),
            };
            let Motion::Drag { dir, .. } = m else {
                unreachable!("a drag")
            };
            let sc = Scenario {
                seconds: m.end() + TAIL_S,
                edges: vec![],
                motions: vec![m],
            };
            let p = run(dev, &sc, rng_seed(&mut rng));
            let d = m.displacement();
            let len = d[0].hypot(d[1]);
            let dur = m.end() - LEAD_S;
            let floor = bias_floor_m(nd, dur, t_rest);
            let trial = Trial {
                length_m: len,
                duration_s: dur,
                error_m: vector_error(&p, LEAD_S - 0.003, sc.seconds, d),
                allowed_m: (0.1 * len).max(3.0 * floor),
                floor_m: floor,
            };
            (trial, p.max_back(LEAD_S, sc.seconds, dir))
        })
        .collect();
    let trials: Vec<Trial> = res.iter().map(|r| r.0).collect();
    let mut f = summarise("drags", "2", &trials, Some(0.9));
    let back = spread(res.iter().map(|r| r.1 * 1e3).collect());
    f.extra.push(("retreat_mm_max".into(), back.max));
    f.extra.push(("retreat_mm_median".into(), back.median));
    f.pass &= back.max <= 2.0;
    f.asks = ">= 90 % within max(10 %, 3 bias floors); retreat <= 2 mm".into();
    f
}

/// Target 3: a lift onto a slope and back (two re-placements a trial): cursor travel per
/// re-placement from the lift to 2 s after the set-down, at most 5 mm.
fn lifts(dev: &Device, n: usize, seed: u64) -> Family {
    let trials: Vec<Trial> = (0..n)
        .into_par_iter()
        .flat_map(|k| {
            let mut rng = noise::rng(seed.wrapping_mul(15_485_863).wrapping_add(k as u64));
            let deg = uniform(&mut rng, 0.5, 5.0);
            let slope = tilt_of(&mut rng, deg);
            let away = lift_motion(&mut rng, LEAD_S, [0.0; 2], slope);
            let back_at = away.end() + 2.0;
            let back = lift_motion(&mut rng, back_at, slope, [0.0; 2]);
            let sc = Scenario {
                seconds: back.end() + 2.0,
                edges: vec![],
                motions: vec![away, back],
            };
            let p = run(dev, &sc, rng_seed(&mut rng));
            [(LEAD_S, back_at), (back_at, sc.seconds)]
                .map(|(a, b)| Trial {
                    length_m: 0.0,
                    duration_s: b - a,
                    error_m: p.travel(a, b),
                    allowed_m: 0.005,
                    floor_m: 0.0,
                })
                .to_vec()
        })
        .collect();
    let mut f = summarise("lifts onto a slope", "3", &trials, None);
    f.pass = f.error_mm.max <= 5.0;
    f.asks = "<= 5 mm per re-placement".into();
    f
}

/// Target 3: the pad tilts 0.5-5 degrees under the device over 0.3-2 s, no lift: cursor
/// travel (median <= 25 mm), the last count within 0.5 s of the pad's rest, nothing later.
fn pad_tilts(dev: &Device, n: usize, seed: u64) -> Family {
    let res: Vec<(Trial, f64, f64)> = (0..n)
        .into_par_iter()
        .map(|k| {
            let mut rng = noise::rng(seed.wrapping_mul(32_452_843).wrapping_add(k as u64));
            let deg = uniform(&mut rng, 0.5, 5.0);
            let m = Motion::Tilt {
                t0: LEAD_S,
                dur: uniform(&mut rng, 0.3, 2.0),
                from: [0.0; 2],
                to: tilt_of(&mut rng, deg),
            };
            let rest = m.end();
            let sc = Scenario {
                seconds: rest + 2.5,
                edges: vec![],
                motions: vec![m],
            };
            let p = run(dev, &sc, rng_seed(&mut rng));
            let stop = p
                .last_move(rest, sc.seconds)
                .map_or(0.0, |t| (t - rest).max(0.0));
            let late = p.travel(rest + 0.5, sc.seconds);
            let trial = Trial {
                length_m: 0.0,
                duration_s: rest - LEAD_S,
                error_m: p.travel(LEAD_S, sc.seconds),
                allowed_m: 0.025,
                floor_m: 0.0,
            };
            (trial, stop, late)
        })
        .collect();
    let trials: Vec<Trial> = res.iter().map(|r| r.0).collect();
    let mut f = summarise("pad tilts", "3", &trials, None);
    let stop = spread(res.iter().map(|r| r.1).collect());
    let late: f64 = res.iter().map(|r| r.2).sum();
    f.extra.push(("stop_s_median".into(), stop.median));
    f.extra.push(("stop_s_max".into(), stop.max));
    f.extra.push(("late_mm".into(), late * 1e3));
    f.pass = f.error_mm.median <= 25.0 && stop.max <= 0.5 && late == 0.0;
    f.asks = "<= 25 mm median; stops within 0.5 s of the pad's rest; nothing later".into();
    f
}

/// Target 4: a knock alone at rest: cursor travel per knock, median <= 0.3 mm.
fn knocks(dev: &Device, n: usize, seed: u64) -> Family {
    let trials: Vec<Trial> = (0..n)
        .into_par_iter()
        .map(|k| {
            let mut rng = noise::rng(seed.wrapping_mul(49_979_687).wrapping_add(k as u64));
            let m = random_knock(&mut rng, LEAD_S);
            let sc = Scenario {
                seconds: LEAD_S + 1.5,
                edges: vec![],
                motions: vec![m],
            };
            let p = run(dev, &sc, rng_seed(&mut rng));
            Trial {
                length_m: 0.0,
                duration_s: 1.5,
                error_m: p.travel(LEAD_S, sc.seconds),
                allowed_m: 0.3e-3,
                floor_m: 0.0,
            }
        })
        .collect();
    let mut f = summarise("knocks", "4", &trials, None);
    f.pass = f.error_mm.median <= 0.3;
    f.asks = "<= 0.3 mm per knock, median".into();
    f
}

/// Target 5: a minute at rest with a machine's vibration (30-100 Hz, 5-50 mg, on Z or on
/// every axis), per trial: counts per minute (at most 1) and time suspended (none).
fn vibration_rest(
    dev: &Device,
    n: usize,
    seed: u64,
    vib: impl Fn(&mut SimRng, bool) -> Motion + Sync,
) -> Family {
    let res: Vec<(Trial, f64)> = (0..n)
        .into_par_iter()
        .map(|k| {
            let mut rng = noise::rng(seed.wrapping_mul(67_867_967).wrapping_add(k as u64));
            let m = vib(&mut rng, k % 2 == 1);
            let sc = Scenario {
                seconds: 60.0,
                edges: vec![],
                motions: vec![m],
            };
            let p = run(dev, &sc, rng_seed(&mut rng));
            let count = 0.0254 / dev.cpi;
            let suspended =
                p.suspended.iter().filter(|&&s| s).count() as f64 / p.suspended.len() as f64;
            let trial = Trial {
                length_m: 0.0,
                duration_s: 60.0,
                error_m: p.travel(0.0, 60.0),
                allowed_m: count,
                floor_m: 0.0,
            };
            (trial, suspended)
        })
        .collect();
    let trials: Vec<Trial> = res.iter().map(|r| r.0).collect();
    let mut f = summarise("rest, vibration", "5", &trials, None);
    let susp = res.iter().map(|r| r.1).fold(0.0, f64::max);
    let counts = spread(
        trials
            .iter()
            .map(|t| t.error_m / (0.0254 / dev.cpi))
            .collect(),
    );
    f.extra.push(("counts_per_min_max".into(), counts.max));
    f.extra.push(("suspended_fraction_max".into(), susp));
    f.pass = counts.max <= 1.0 && susp == 0.0;
    f.asks = "<= 1 count per minute; never suspended".into();
    f
}

/// Target 6 (short form): `devices` devices at rest for `minutes` each: counts moved.
fn rests(spec: SensorSpec, base: Config, devices: usize, minutes: f64, seed: u64) -> Family {
    let counts: Vec<f64> = (0..devices as u64)
        .into_par_iter()
        .map(|k| {
            let dev = Device::calibrated(spec, base, seed.wrapping_mul(31).wrapping_add(k));
            let sc = Scenario {
                seconds: minutes * 60.0,
                ..Scenario::default()
            };
            let p = run(&dev, &sc, seed ^ k ^ 0x5EA7);
            (p.travel(0.0, sc.seconds) / (0.0254 / dev.cpi)).round()
        })
        .collect();
    let trials: Vec<Trial> = counts
        .iter()
        .map(|&c| Trial {
            length_m: 0.0,
            duration_s: minutes * 60.0,
            error_m: c * 0.0254 / 800.0,
            allowed_m: 0.0,
            floor_m: 0.0,
        })
        .collect();
    let mut f = summarise(
        format!("rest, {devices} devices x {minutes} min"),
        "6",
        &trials,
        None,
    );
    let moved = counts.iter().filter(|&&c| c > 0.0).count();
    f.extra.push(("devices_moved".into(), moved as f64));
    f.extra.push(("counts".into(), counts.iter().sum()));
    f.pass = moved == 0;
    f.asks = "0 counts".into();
    f
}

/// The families as a table.
pub fn table(fams: &[Family]) -> String {
    let mut out = format!(
        "{:<40} {:>3} {:>5} {:>8} {:>9} {:>9} {:>9}  {:<4} {}\n",
        "family (target)", "n", "T", "within", "err med", "err p90", "floor med", "ok", "extra"
    );
    for f in fams {
        let extra = f
            .extra
            .iter()
            .map(|(k, v)| format!("{k} {v:.3}"))
            .collect::<Vec<_>>()
            .join(", ");
        out += &format!(
            "{:<40} {:>3} {:>5} {:>7.1}% {:>7.2}mm {:>7.2}mm {:>7.2}mm  {:<4} {}\n",
            f.name,
            f.trials,
            f.target,
            f.within * 100.0,
            f.error_mm.median,
            f.error_mm.p90,
            f.floor_mm.median,
            if f.pass { "yes" } else { "NO" },
            extra
        );
    }
    out
}
