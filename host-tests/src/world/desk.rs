//! The desk scene: a hand making strokes, rests and clicks, and the ADXL335 that feels it.
//!
//! Each axis: ADXL335 noise (300 ug/sqrt(Hz) into its 50 Hz RC pole), a bias random walk of
//! 20 ug/sqrt(s) (slow temperature drift), a 12-bit ADC at 3 kHz. The hand makes minimum-jerk
//! strokes of 1 to 30 cm (log-uniform) in uniformly random directions, lasting
//! `0.25 + 0.9 sqrt(D / 0.3 m)` s (peak speeds 0.05 to 0.5 m/s), separated by rests of 0.3 to
//! 2 s; in every other rest the finger clicks (a press and a release 100 ms apart), each edge
//! with a 30 ms jolt of +-0.5 m/s^2 along a random direction.
//!
//! `cargo lab mouse` measures the cursor against this hand; `cargo lab twin` plays it to the
//! device in real time ([`stream`]).

use crate::world::noise::{self, SimRng};
use crate::world::scene::{min_jerk_accel, ADXL335_LSB};

/// The scene's sampling rate [Hz] (the firmware's default).
pub const FS: f64 = 3000.0;
/// Standard gravity [m/s^2].
const G: f64 = 9.806_65;

/// One stroke of the hand.
#[derive(Clone, Copy, Debug)]
pub struct Stroke {
    /// First sample.
    pub start: usize,
    /// Length [samples].
    pub len: usize,
    /// Distance travelled [m].
    pub distance_m: f64,
    /// Direction [rad] from the sensor's X towards its Y.
    pub dir: f64,
}

/// A click: press and release sample indices, jolt directions [rad].
#[derive(Clone, Copy, Debug)]
pub struct Click {
    /// Sample at which the finger presses.
    pub press: usize,
    /// Sample at which it releases (100 ms later).
    pub release: usize,
    /// Directions of the press's and the release's jolts [rad].
    pub dirs: [f64; 2],
}

/// The hand's plan for a scene: 1 s of calibration and 0.5 s of rest, then the strokes with
/// their rests and clicks, then 0.5 s of rest.
pub struct Plan {
    /// Length of the scene [samples].
    pub n: usize,
    /// The strokes, in order.
    pub strokes: Vec<Stroke>,
    /// The clicks, in order.
    pub clicks: Vec<Click>,
}

impl Plan {
    /// The plan of `strokes` strokes drawn from `seed` (its own stream, apart from the
    /// sensor's noise, so that the same seed gives the same hand with any sensor).
    pub fn new(strokes: usize, seed: u64) -> Self {
        use rand::Rng;
        let mut rng = noise::rng(seed ^ 0xA11CE);
        let mut t = (1.5 * FS) as usize; // 1 s calibration + 0.5 s rest
        let (mut ss, mut cs) = (vec![], vec![]);
        for k in 0..strokes {
            let d = 0.01 * 30f64.powf(rng.random::<f64>());
            let dur = 0.25 + 0.9 * (d / 0.3).sqrt();
            let len = (dur * FS) as usize;
            ss.push(Stroke {
                start: t,
                len,
                distance_m: d,
                dir: rng.random::<f64>() * std::f64::consts::TAU,
            });
            t += len;
            let rest = ((0.3 + 1.7 * rng.random::<f64>()) * FS) as usize;
            if k % 2 == 1 && rest > (0.6 * FS) as usize {
                let press = t + (0.1 * FS) as usize;
                cs.push(Click {
                    press,
                    release: press + (0.1 * FS) as usize,
                    dirs: [
                        rng.random::<f64>() * std::f64::consts::TAU,
                        rng.random::<f64>() * std::f64::consts::TAU,
                    ],
                });
            }
            t += rest;
        }
        Plan {
            n: t + (0.5 * FS) as usize,
            strokes: ss,
            clicks: cs,
        }
    }

    /// The hand's acceleration [m/s^2] (x, y) at sample `i`.
    pub fn accel(&self, i: usize) -> (f64, f64) {
        let (mut ax, mut ay) = (0.0, 0.0);
        for s in &self.strokes {
            if i >= s.start && i < s.start + s.len {
                let a = min_jerk_accel((i - s.start) as f64 / FS, s.len as f64 / FS, s.distance_m);
                ax += a * s.dir.cos();
                ay += a * s.dir.sin();
            }
        }
        for c in &self.clicks {
            for (edge, dir) in [c.press, c.release].iter().zip(c.dirs) {
                let jolt = (0.03 * FS) as usize;
                if i >= *edge && i < edge + jolt {
                    // +0.5 then -0.5 m/s^2: the finger's push and the hand's recoil.
                    let a = if i - edge < jolt / 2 { 0.5 } else { -0.5 };
                    ax += a * dir.cos();
                    ay += a * dir.sin();
                }
            }
        }
        (ax, ay)
    }

    /// Whether the finger holds the button at sample `i`.
    pub fn held(&self, i: usize) -> bool {
        self.clicks
            .iter()
            .any(|c| (c.press..c.release).contains(&i))
    }
}

/// The sensor on three axes: ADXL335 noise through its 50 Hz pole, a 20 ug/sqrt(s) bias
/// walk, a 12-bit ADC at 3 kHz. The pointing scenes use it too, with gravity.
#[derive(Clone)]
pub struct Sensor {
    ar: [noise::Ar1; 3],
    walk: [f64; 3],
    walk_sd: f64,
}

impl Sensor {
    /// A sensor whose filtered noise starts in its stationary state, drawn from `rng`.
    pub fn new(rng: &mut SimRng) -> Self {
        let alpha = std::f64::consts::TAU * 50.0 / FS;
        let sigma_c = 300e-6 * G;
        let r0 = sigma_c * sigma_c * std::f64::consts::PI * 50.0 / 2.0;
        Self {
            ar: core::array::from_fn(|_| noise::Ar1::new(r0, alpha, rng)),
            walk: [0.0; 3],
            walk_sd: 20e-6 * G / FS.sqrt(),
        }
    }

    /// Codes for a hand acceleration `a` and the gravity `g` the sensor reads [m/s^2]
    /// (sensor frame; the desk scene has none, the pointing scenes tilt it).
    pub fn codes(&mut self, a: [f64; 3], g: [f64; 3], rng: &mut SimRng) -> [u16; 3] {
        let adc = noise::Adc { bits: 12 };
        core::array::from_fn(|k| {
            self.walk[k] += self.walk_sd * noise::normal(rng);
            let x = a[k] + g[k] + self.ar[k].next(rng) + self.walk[k];
            adc.code(2048.0 + x / ADXL335_LSB)
        })
    }
}

/// The desk scene as the device's inputs: ADC codes `[x, y, z]` at 3 kHz and whether the
/// finger holds the button at each sample (the device's debounce adds its own delay). With
/// `strokes == 0` the hand rests (after the same 1.5 s of calibration and rest).
pub fn stream(strokes: usize, seed: u64) -> (Vec<[u16; 3]>, Vec<bool>) {
    let p = Plan::new(strokes, seed);
    let mut rng = noise::rng(seed);
    let mut sensor = Sensor::new(&mut rng);
    let codes = (0..p.n)
        .map(|i| {
            let (ax, ay) = p.accel(i);
            sensor.codes([ax, ay, 0.0], [0.0; 3], &mut rng)
        })
        .collect();
    let held = (0..p.n).map(|i| p.held(i)).collect();
    (codes, held)
}

/// The hand resting on the desk for `seconds` [s]: ADC codes at 3 kHz of the desk's sensor
/// with no motion, and the button never held.
pub fn rest(seconds: f64, seed: u64) -> (Vec<[u16; 3]>, Vec<bool>) {
    let mut rng = noise::rng(seed);
    let mut sensor = Sensor::new(&mut rng);
    let n = (seconds.max(0.0) * FS) as usize;
    let codes = (0..n)
        .map(|_| sensor.codes([0.0; 3], [0.0; 3], &mut rng))
        .collect();
    (codes, vec![false; n])
}

/// When the check scene's strokes start [s]: right along sensor X, then away along sensor Y.
pub const CHECK_STROKES_S: [f64; 2] = [6.5, 11.5];
/// The check scene's length [s].
pub const CHECK_S: f64 = 15.0;

/// The scene `cargo lab device check` is tried on in CI: the board flat on the desk (gravity
/// +1 g on sensor Z), at rest, then a 10 cm stroke right (sensor +X) in 0.5 s at
/// [`CHECK_STROKES_S`]`[0]` and one away (sensor +Y) at `[1]`, then rest to [`CHECK_S`]. The
/// check's steps (4 s at rest, then 5 s for each move) find each stroke inside its window
/// with a second or more to spare either side.
pub fn check(seed: u64) -> (Vec<[u16; 3]>, Vec<bool>) {
    let mut rng = noise::rng(seed);
    let mut sensor = Sensor::new(&mut rng);
    let n = (CHECK_S * FS) as usize;
    let codes = (0..n)
        .map(|i| {
            let t = i as f64 / FS;
            let [right, away] = CHECK_STROKES_S.map(|s| min_jerk_accel(t - s, 0.5, 0.1));
            sensor.codes([right, away, 0.0], [0.0, 0.0, G], &mut rng)
        })
        .collect();
    (codes, vec![false; n])
}
