//! The hand model: a hand, a desk and a machine nearby, composed from small motions, felt
//! by a configurable accelerometer on a configurable ADC at any rate.
//!
//! # Design
//! "Model only what a scene needs": a [`Scenario`] is a list of [`Motion`]s, each a small
//! type that adds a world-frame acceleration and a device tilt at time `t`, plus the button's
//! edges; a [`Sensor`] turns the sum into ADC codes. Families of randomised scenarios (the
//! `cargo lab mouse` families) draw their parameters from the ranges in docs/drift-control.md and compose
//! only the motions they study.
//!
//! | motion | type | model |
//! |---|---|---|
//! | pointing stroke | [`Motion::Stroke`] | minimum jerk, `a = D/T^2 (60 u - 180 u^2 + 120 u^3)` |
//! | drag | [`Motion::Drag`] | velocity `V s(t / ramp)` up, a glide at `V`, the mirror image down; `s` the minimum-jerk step (jerk-limited ramps) |
//! | lift and set-down | [`Motion::Lift`] | a minimum-jerk rise of `h`, time in the air, a minimum-jerk fall; the tilt changes in the air or as it lands, or the hand tilts the device in the air and back as it sets it down, perhaps holding it still there first; a minimum-jerk carry along the desk through the air |
//! | pad tilt | [`Motion::Tilt`] | the angle from `from` to `to` along a minimum-jerk step |
//! | knock | [`Motion::Knock`] | a desk-top flex that returns (a raised-cosine dip of `flex`) and a ring at `f` decaying over a few periods, with zero net velocity and displacement |
//! | machine vibration | [`Motion::Vibration`] | a sinusoid ramped in over 0.2 s, on Z or on every axis |
//!
//! The sensor (REFERENCE (i), (j)): per axis white noise of one-sided density `ND` through
//! the sensor's single output pole (the ADXL335's 50 Hz RC: AR(1), eq 31), a bias random walk,
//! gravity through the tilt (`g sin` into X and Y, `g cos cos` on Z), the hand's motion and
//! gravity through the pole too (the RC filter is at the sensor's output; below 10 Hz it only
//! delays them by 3.2 ms), a zero-g code off mid-scale by a fraction of an LSB drawn per
//! device (so that sub-LSB noise meets the code grid anywhere), and an ideal ADC of `bits`
//! over +-5 g. Knocks and vibration are given as the sensor reads them (their amplitudes are
//! readings, after the pole): the harder case for a detector, which sees them whole.

use crate::world::noise::{self, SimRng};
use crate::world::scene::min_jerk_accel;

/// Standard gravity [m/s^2].
pub const G: f64 = 9.806_65;

/// The minimum-jerk step `s(u) = 10 u^3 - 15 u^4 + 6 u^5` on `0..=1`, clamped outside.
pub fn step(u: f64) -> f64 {
    let u = u.clamp(0.0, 1.0);
    u * u * u * (10.0 - 15.0 * u + 6.0 * u * u)
}

/// `ds/du` of [`step`]: `30 u^2 (1 - u)^2`, zero outside `0..1`.
pub fn step_rate(u: f64) -> f64 {
    if !(0.0..=1.0).contains(&u) {
        return 0.0;
    }
    30.0 * u * u * (1.0 - u) * (1.0 - u)
}

/// `d^2 s/du^2` of [`step`]: `60 u - 180 u^2 + 120 u^3`, zero outside `0..1`.
pub fn step_accel(u: f64) -> f64 {
    if !(0.0..=1.0).contains(&u) {
        return 0.0;
    }
    60.0 * u - 180.0 * u * u + 120.0 * u * u * u
}

/// What an accelerometer and its ADC are.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SensorSpec {
    /// One-sided noise density [ug/sqrt(Hz)].
    pub nd_ug: f64,
    /// The sensor's output pole [Hz] (the ADXL335's RC filter), or `None` for none (white
    /// noise up to Nyquist).
    pub pole_hz: Option<f64>,
    /// Bias random walk [ug/sqrt(s)].
    pub walk_ug: f64,
    /// ADC resolution [bits]; the ADC spans +-5 g.
    pub bits: u8,
    /// Sampling rate [Hz].
    pub fs: f64,
}

impl SensorSpec {
    /// The board's: an ADXL335 (300 ug/sqrt(Hz), 50 Hz RC pole, 20 ug/sqrt(s) bias walk) on a
    /// 12-bit ratiometric ADC at 3 kHz.
    pub const ADXL335: Self = Self {
        nd_ug: 300.0,
        pole_hz: Some(50.0),
        walk_ug: 20.0,
        bits: 12,
        fs: 3000.0,
    };

    /// Noise density [m/s^2/sqrt(Hz)].
    pub fn nd(&self) -> f64 {
        self.nd_ug * 1e-6 * G
    }

    /// Acceleration per code [m/s^2]: 10 g over `2^bits` codes.
    pub fn lsb(&self) -> f64 {
        G * 10.0 / f64::from(1u32 << self.bits)
    }
}

/// One device's sensor: noise, bias walk, the output pole, the ADC.
#[derive(Clone, Debug)]
pub struct Sensor {
    spec: SensorSpec,
    noise: [noise::Ar1; 3],
    white_sd: f64,
    walk: [f64; 3],
    walk_sd: f64,
    /// The pole's state per axis [m/s^2] and its coefficient `1 - exp(-2 pi fc / fs)`.
    pole: [f64; 3],
    pole_k: f64,
    /// Zero-g code of each axis [LSB, fractional].
    zero: [f64; 3],
}

impl Sensor {
    /// A sensor with its noise in its stationary state, its pole settled flat at rest, and
    /// zero-g codes drawn within half an LSB of mid-scale, all from `rng`.
    pub fn new(spec: SensorSpec, rng: &mut SimRng) -> Self {
        use rand::Rng;
        let nd = spec.nd();
        let (noise, white_sd) = match spec.pole_hz {
            Some(fc) => {
                let alpha = std::f64::consts::TAU * fc / spec.fs;
                let r0 = nd * nd * std::f64::consts::PI * fc / 2.0;
                (
                    core::array::from_fn(|_| noise::Ar1::new(r0, alpha, rng)),
                    0.0,
                )
            }
            None => (
                core::array::from_fn(|_| noise::Ar1::new(0.0, 1.0, rng)),
                nd * (spec.fs / 2.0).sqrt(),
            ),
        };
        let pole_k = spec
            .pole_hz
            .map_or(1.0, |fc| -(-std::f64::consts::TAU * fc / spec.fs).exp_m1());
        let mid = f64::from(1u32 << (spec.bits - 1));
        Self {
            spec,
            noise,
            white_sd,
            walk: [0.0; 3],
            walk_sd: spec.walk_ug * 1e-6 * G / spec.fs.sqrt(),
            pole: gravity([0.0; 2]),
            pole_k,
            zero: core::array::from_fn(|_| mid + rng.random::<f64>() - 0.5),
        }
    }

    /// What it is.
    pub fn spec(&self) -> &SensorSpec {
        &self.spec
    }

    /// Each axis's zero-g code [LSB, fractional]: flat, with no bias walk, its codes average
    /// to it (on X and Y; Z adds 1 g) wherever the noise spans a few codes.
    pub fn zero_codes(&self) -> [f64; 3] {
        self.zero
    }

    /// The codes for a world-frame acceleration `a` [m/s^2] of the hand (through the pole),
    /// `read` as read at the output (knocks, vibration), at a tilt `tilt` [rad] (about Y,
    /// about X).
    pub fn codes(
        &mut self,
        a: [f64; 3],
        read: [f64; 3],
        tilt: [f64; 2],
        rng: &mut SimRng,
    ) -> [u16; 3] {
        let g = gravity(tilt);
        let lsb = self.spec.lsb();
        let adc = noise::Adc {
            bits: self.spec.bits,
        };
        core::array::from_fn(|k| {
            self.walk[k] += self.walk_sd * noise::normal(rng);
            self.pole[k] += self.pole_k * (a[k] + g[k] - self.pole[k]);
            let n = self.noise[k].next(rng) + self.white_sd * noise::normal(rng);
            adc.code(self.zero[k] + (self.pole[k] + read[k] + n + self.walk[k]) / lsb)
        })
    }
}

/// The gravity the sensor reads at a tilt `(about Y, about X)` [rad], flat = Z up.
pub fn gravity(tilt: [f64; 2]) -> [f64; 3] {
    [
        G * tilt[0].sin(),
        G * tilt[1].sin(),
        G * tilt[0].cos() * tilt[1].cos(),
    ]
}

/// One thing the hand, the desk or a machine does. Times in s, lengths in m, angles in rad,
/// directions in rad from the sensor's X towards its Y.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Motion {
    /// A minimum-jerk stroke of `d` over `dur` from `t0`.
    Stroke {
        /// Start [s].
        t0: f64,
        /// Duration [s].
        dur: f64,
        /// Length [m].
        d: f64,
        /// Direction [rad].
        dir: f64,
    },
    /// A drag: speed up to `v` over `ramp_up`, glide for `glide`, slow down over `ramp_down`.
    Drag {
        /// Start [s].
        t0: f64,
        /// Ramp up [s].
        ramp_up: f64,
        /// Glide [s].
        glide: f64,
        /// Ramp down [s].
        ramp_down: f64,
        /// Glide speed [m/s].
        v: f64,
        /// Direction [rad].
        dir: f64,
    },
    /// A lift of `h` over `rise`, `air` in the air, set down over `fall`; the tilt goes from
    /// `from` to `to` in the air (`in_air`) or over the last half of the fall (landing on
    /// one edge first); or, with a `wobble`, the hand tilts the device to it over the rise and
    /// the first half of the air, and to `to` over the rest of the air and the fall. With a
    /// `hover`, the hand holds it still in the air for that long first (tilted to the wobble
    /// over the rise and back to `to` over the fall, if it wobbles); with a `carry`, it
    /// carries it that far along the desk (minimum jerk, the device's axes) from the rise's
    /// middle (or the hover's end) to the fall's middle.
    Lift {
        /// Start [s].
        t0: f64,
        /// Height [m].
        h: f64,
        /// Rise [s].
        rise: f64,
        /// In the air [s].
        air: f64,
        /// Fall [s].
        fall: f64,
        /// Tilt before [rad].
        from: [f64; 2],
        /// Tilt after [rad].
        to: [f64; 2],
        /// Whether it tilts in the air.
        in_air: bool,
        /// The tilt the hand gives it in the air [rad], if it wobbles.
        wobble: Option<[f64; 2]>,
        /// Held still in the air at its start [s], 0 for none (part of `air`).
        hover: f64,
        /// Carried in the air [m, X and Y], zero for none.
        carry: [f64; 2],
    },
    /// The pad under the device tilts from `from` to `to` over `dur`.
    Tilt {
        /// Start [s].
        t0: f64,
        /// Duration [s].
        dur: f64,
        /// Tilt before [rad].
        from: [f64; 2],
        /// Tilt after [rad].
        to: [f64; 2],
    },
    /// A knock on the desk: a ring of peak `peak` [m/s^2] at `f` decaying over `periods`
    /// periods, and a flex of `flex` that returns over two periods; a `share` of both goes
    /// horizontal along `dir`.
    Knock {
        /// Time [s].
        t0: f64,
        /// Peak acceleration of the ring [m/s^2].
        peak: f64,
        /// Ring frequency [Hz].
        f: f64,
        /// Decay time constant [periods].
        periods: f64,
        /// Flex depth [m].
        flex: f64,
        /// Horizontal share.
        share: f64,
        /// Horizontal direction [rad].
        dir: f64,
    },
    /// A continuous figure from `t0` over `dur`: `turns` turns of a circle of radius `r`
    /// (from its start point, `(cos phi - 1, sin phi) r`) or of a figure eight (Gerono's
    /// lemniscate, `(sin phi, sin 2 phi / 2) r`), the angle `phi` along a minimum-jerk step.
    Figure {
        /// Start [s].
        t0: f64,
        /// Duration [s].
        dur: f64,
        /// A figure eight, or a circle.
        eight: bool,
        /// Radius [m].
        r: f64,
        /// Turns.
        turns: f64,
    },
    /// A machine's vibration of `amp` [m/s^2] at `f` from `t0`, on Z (`all` false) or on
    /// every axis with phases `phase`.
    Vibration {
        /// Start [s].
        t0: f64,
        /// Frequency [Hz].
        f: f64,
        /// Amplitude [m/s^2].
        amp: f64,
        /// On every axis, or on Z only.
        all: bool,
        /// Phase per axis [rad].
        phase: [f64; 3],
    },
}

impl std::fmt::Display for Motion {
    /// One line a person reads: the motion's start, its sizes in mm, mm/s, ms, degrees and g.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let deg = |r: f64| r.to_degrees();
        let tilt = |t: [f64; 2]| format!("({:.2}, {:.2}) deg", deg(t[0]), deg(t[1]));
        match *self {
            Motion::Stroke { t0, dur, d, dir } => write!(
                f,
                "at {t0:.3} s a stroke of {:.1} mm over {:.0} ms, direction {:.0} deg",
                d * 1e3,
                dur * 1e3,
                deg(dir)
            ),
            Motion::Drag {
                t0,
                ramp_up,
                glide,
                ramp_down,
                v,
                dir,
            } => write!(
                f,
                "at {t0:.3} s a drag: up over {:.0} ms, a glide of {glide:.2} s at {:.1} mm/s, \
                 down over {:.0} ms, direction {:.0} deg",
                ramp_up * 1e3,
                v * 1e3,
                ramp_down * 1e3,
                deg(dir)
            ),
            Motion::Lift {
                t0,
                h,
                rise,
                air,
                fall,
                from,
                to,
                in_air,
                wobble,
                hover,
                carry,
            } => write!(
                f,
                "at {t0:.3} s a lift of {:.1} mm: up over {:.0} ms, {:.0} ms in the air{}, down \
                 over {:.0} ms{}; tilt {} to {} {}",
                h * 1e3,
                rise * 1e3,
                air * 1e3,
                if hover > 0.0 {
                    format!(" ({:.0} ms of it held still)", hover * 1e3)
                } else {
                    String::new()
                },
                fall * 1e3,
                if carry == [0.0; 2] {
                    String::new()
                } else {
                    format!(
                        ", carried {:.1} mm at {:.0} deg",
                        carry[0].hypot(carry[1]) * 1e3,
                        deg(carry[1].atan2(carry[0]))
                    )
                },
                tilt(from),
                tilt(to),
                match wobble {
                    Some(w) => format!("by way of {} in the air", tilt(w)),
                    None if in_air => "in the air".to_string(),
                    None => "as it lands".to_string(),
                }
            ),
            Motion::Tilt { t0, dur, from, to } => write!(
                f,
                "at {t0:.3} s the pad tilts from {} to {} over {:.0} ms",
                tilt(from),
                tilt(to),
                dur * 1e3
            ),
            Motion::Knock {
                t0,
                peak,
                f: hz,
                flex,
                share,
                ..
            } => write!(
                f,
                "at {t0:.3} s a knock of {:.2} g ringing at {hz:.0} Hz, the desk flexing \
                 {:.0} um, {:.0} % of it horizontal",
                peak / G,
                flex * 1e6,
                share * 100.0
            ),
            Motion::Figure {
                t0,
                dur,
                eight,
                r,
                turns,
            } => write!(
                f,
                "at {t0:.3} s {turns} turn(s) of a {} of radius {:.1} mm over {dur:.2} s",
                if eight { "figure eight" } else { "circle" },
                r * 1e3
            ),
            Motion::Vibration {
                t0,
                f: hz,
                amp,
                all,
                ..
            } => write!(
                f,
                "from {t0:.3} s a machine's vibration of {:.1} mg at {hz:.0} Hz on {}",
                amp / G * 1e3,
                if all { "every axis" } else { "Z" }
            ),
        }
    }
}

/// A knock's ring: displacement `A (1 - cos w t) e^(-t/tau)` with `A = peak / w^2`, which
/// starts and ends at rest; its acceleration at `t`.
fn ring_accel(t: f64, peak: f64, f: f64, tau: f64) -> f64 {
    if t < 0.0 {
        return 0.0;
    }
    let w = std::f64::consts::TAU * f;
    let d = peak / (w * w);
    let e = (-t / tau).exp();
    let (c, s) = ((w * t).cos(), (w * t).sin());
    d * e * (w * w * c - 2.0 * w * s / tau + (1.0 - c) / (tau * tau))
}

/// A raised-cosine dip of depth `flex` over `dur`: its acceleration at `t` (it starts and
/// ends with zero velocity and displacement).
fn flex_accel(t: f64, flex: f64, dur: f64) -> f64 {
    if !(0.0..=dur).contains(&t) {
        return 0.0;
    }
    let w = std::f64::consts::TAU / dur;
    -flex / 2.0 * w * w * (w * t).cos()
}

impl Motion {
    /// The world-frame acceleration [m/s^2] this motion adds at `t` [s].
    pub fn accel(&self, t: f64) -> [f64; 3] {
        match *self {
            Motion::Stroke { t0, dur, d, dir } => {
                let a = min_jerk_accel(t - t0, dur, d);
                [a * dir.cos(), a * dir.sin(), 0.0]
            }
            Motion::Drag {
                t0,
                ramp_up,
                glide,
                ramp_down,
                v,
                dir,
            } => {
                let u = t - t0;
                let down = ramp_up + glide;
                let a = v / ramp_up * step_rate(u / ramp_up)
                    - v / ramp_down * step_rate((u - down) / ramp_down);
                [a * dir.cos(), a * dir.sin(), 0.0]
            }
            Motion::Lift {
                t0,
                h,
                rise,
                air,
                fall,
                hover,
                carry,
                ..
            } => {
                let u = t - t0;
                let z = h / (rise * rise) * step_accel(u / rise)
                    - h / (fall * fall) * step_accel((u - rise - air) / fall);
                let (from, to) = carry_span(rise, air, fall, hover);
                let dur = to - from;
                let c = step_accel((u - from) / dur) / (dur * dur);
                [carry[0] * c, carry[1] * c, z]
            }
            Motion::Tilt { .. } => [0.0; 3],
            Motion::Figure {
                t0,
                dur,
                eight,
                r,
                turns,
            } => {
                let u = (t - t0) / dur;
                if !(0.0..=1.0).contains(&u) {
                    return [0.0; 3];
                }
                let total = std::f64::consts::TAU * turns;
                // phi = total step(u): phi' = total step'(u) / dur, phi'' = total step''(u) / dur^2.
                let (w, al) = (
                    total * step_rate(u) / dur,
                    total * step_accel(u) / (dur * dur),
                );
                let [_, d1, d2] = figure(eight, r, total * step(u));
                [d2[0] * w * w + d1[0] * al, d2[1] * w * w + d1[1] * al, 0.0]
            }
            Motion::Knock {
                t0,
                peak,
                f,
                periods,
                flex,
                share,
                dir,
            } => {
                let u = t - t0;
                let a = ring_accel(u, peak, f, periods / f) + flex_accel(u, flex, 2.0 / f);
                [a * share * dir.cos(), a * share * dir.sin(), a]
            }
            Motion::Vibration {
                t0,
                f,
                amp,
                all,
                phase,
            } => {
                if t < t0 {
                    return [0.0; 3];
                }
                let ramp = ((t - t0) / 0.2).min(1.0);
                let w = std::f64::consts::TAU * f * (t - t0);
                let s = |k: usize| amp * ramp * (w + phase[k]).sin();
                if all {
                    [s(0), s(1), s(2)]
                } else {
                    [0.0, 0.0, s(2)]
                }
            }
        }
    }

    /// The tilt [rad] this motion sets at `t`, if it sets one: a pad tilt or a lift from its
    /// start on (before its start the tilt is `from`).
    pub fn tilt(&self, t: f64) -> Option<[f64; 2]> {
        let lerp = |from: [f64; 2], to: [f64; 2], s: f64| {
            [
                from[0] + (to[0] - from[0]) * s,
                from[1] + (to[1] - from[1]) * s,
            ]
        };
        match *self {
            Motion::Tilt { t0, dur, from, to } => Some(lerp(from, to, step((t - t0) / dur))),
            Motion::Lift {
                t0,
                rise,
                air,
                fall,
                from,
                to,
                in_air,
                wobble,
                hover,
                ..
            } => {
                if let (Some(w), true) = (wobble, hover > 0.0) {
                    let down = t0 + rise + air;
                    return Some(if t < down {
                        lerp(from, w, step((t - t0) / rise))
                    } else {
                        lerp(w, to, step((t - down) / fall))
                    });
                }
                if let Some(w) = wobble {
                    let turn = t0 + rise + air / 2.0;
                    return Some(if t < turn {
                        lerp(from, w, step((t - t0) / (turn - t0)))
                    } else {
                        lerp(w, to, step((t - turn) / (air / 2.0 + fall)))
                    });
                }
                let (start, len) = if in_air {
                    (t0 + rise, air)
                } else {
                    (t0 + rise + air + fall / 2.0, fall / 2.0)
                };
                Some(lerp(from, to, step((t - start) / len)))
            }
            _ => None,
        }
    }

    /// When this motion is over [s]: the device (or the desk) at rest again; `INFINITY` for
    /// a vibration.
    pub fn end(&self) -> f64 {
        match *self {
            Motion::Stroke { t0, dur, .. } | Motion::Tilt { t0, dur, .. } => t0 + dur,
            Motion::Drag {
                t0,
                ramp_up,
                glide,
                ramp_down,
                ..
            } => t0 + ramp_up + glide + ramp_down,
            Motion::Lift {
                t0,
                rise,
                air,
                fall,
                ..
            } => t0 + rise + air + fall,
            Motion::Knock { t0, f, periods, .. } => t0 + (6.0 * periods).max(2.0) / f,
            Motion::Figure { t0, dur, .. } => t0 + dur,
            Motion::Vibration { .. } => f64::INFINITY,
        }
    }

    /// The horizontal displacement [m] this motion gives the device (X, Y): a stroke's or a
    /// drag's; zero for everything that returns or is not a translation.
    pub fn displacement(&self) -> [f64; 2] {
        match *self {
            Motion::Stroke { d, dir, .. } => [d * dir.cos(), d * dir.sin()],
            Motion::Drag {
                ramp_up,
                glide,
                ramp_down,
                v,
                dir,
                ..
            } => {
                let d = v * (ramp_up / 2.0 + glide + ramp_down / 2.0);
                [d * dir.cos(), d * dir.sin()]
            }
            _ => [0.0; 2],
        }
    }
}

/// When a lift's carry begins and ends [s after the lift's start]: from the rise's middle,
/// or from the end of a `hover` after the rise, to the fall's middle.
fn carry_span(rise: f64, air: f64, fall: f64, hover: f64) -> (f64, f64) {
    let from = if hover > 0.0 {
        rise + hover
    } else {
        rise / 2.0
    };
    (from, rise + air + fall / 2.0)
}

/// A figure's position `p(phi)` and its derivatives `p'`, `p''` in `phi` [m], for a circle
/// or a figure eight of radius `r` ([`Motion::Figure`]).
pub fn figure(eight: bool, r: f64, phi: f64) -> [[f64; 2]; 3] {
    if eight {
        let (s, c, s2, c2) = (phi.sin(), phi.cos(), (2.0 * phi).sin(), (2.0 * phi).cos());
        [
            [r * s, r * s2 / 2.0],
            [r * c, r * c2],
            [-r * s, -2.0 * r * s2],
        ]
    } else {
        let (s, c) = (phi.sin(), phi.cos());
        [[r * (c - 1.0), r * s], [-r * s, r * c], [-r * c, -r * s]]
    }
}

/// What happens to one device: motions, button edges, a length.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Scenario {
    /// The motions.
    pub motions: Vec<Motion>,
    /// Times of the button's edges as the tracker receives them [s].
    pub edges: Vec<f64>,
    /// Length [s].
    pub seconds: f64,
}

impl Scenario {
    /// The hand's world acceleration, what the sensor reads of knocks and vibration (both
    /// [m/s^2]) and the tilt at `t`: the tilt of the last motion that sets one and has begun,
    /// or the `from` of the first that sets one (flat if none does).
    pub fn at(&self, t: f64) -> ([f64; 3], [f64; 3], [f64; 2]) {
        let mut a = [0.0; 3];
        let mut read = [0.0; 3];
        let mut tilt = None;
        let mut first = None;
        for m in &self.motions {
            let x = m.accel(t);
            let to = if matches!(m, Motion::Knock { .. } | Motion::Vibration { .. }) {
                &mut read
            } else {
                &mut a
            };
            for k in 0..3 {
                to[k] += x[k];
            }
            if let Some(th) = m.tilt(t) {
                first = first.or(Some(th));
                let begun = match *m {
                    Motion::Tilt { t0, .. } | Motion::Lift { t0, .. } => t >= t0,
                    _ => false,
                };
                if begun {
                    tilt = Some(th);
                }
            }
        }
        (a, read, tilt.or(first).unwrap_or([0.0; 2]))
    }

    /// The true horizontal displacement of every motion [m].
    pub fn displacement(&self) -> [f64; 2] {
        self.motions.iter().fold([0.0; 2], |acc, m| {
            let d = m.displacement();
            [acc[0] + d[0], acc[1] + d[1]]
        })
    }
}

/// A uniform draw on `lo..hi`.
pub fn uniform(rng: &mut SimRng, lo: f64, hi: f64) -> f64 {
    use rand::Rng;
    lo + (hi - lo) * rng.random::<f64>()
}

/// A log-uniform draw on `lo..hi`.
pub fn log_uniform(rng: &mut SimRng, lo: f64, hi: f64) -> f64 {
    uniform(rng, lo.ln(), hi.ln()).exp()
}

/// A tilt of `deg` degrees about a random horizontal axis [rad] (about Y, about X).
pub fn tilt_of(rng: &mut SimRng, deg: f64) -> [f64; 2] {
    let az = uniform(rng, 0.0, std::f64::consts::TAU);
    let th = deg.to_radians();
    [th * az.cos(), th * az.sin()]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Double-integrates a motion's acceleration numerically: (velocity, displacement) at `t1`.
    fn integrate(m: &Motion, t1: f64, axis: usize) -> (f64, f64) {
        let n = 400_000;
        let dt = t1 / f64::from(n);
        let (mut v, mut s) = (0.0, 0.0);
        for i in 0..n {
            let a = m.accel((f64::from(i) + 0.5) * dt)[axis];
            s += v * dt + 0.5 * a * dt * dt;
            v += a * dt;
        }
        (v, s)
    }

    #[test]
    fn a_drag_ends_at_rest_having_travelled_its_length() {
        let m = Motion::Drag {
            t0: 0.1,
            ramp_up: 0.2,
            glide: 1.0,
            ramp_down: 0.3,
            v: 0.03,
            dir: 0.0,
        };
        let (v, s) = integrate(&m, 2.0, 0);
        assert!(v.abs() < 1e-9, "{v}");
        assert!((s - m.displacement()[0]).abs() < 1e-8, "{s}");
        // Mid-glide at the glide speed.
        let (v, _) = integrate(&m, 0.9, 0);
        assert!((v - 0.03).abs() < 1e-9, "{v}");
    }

    #[test]
    fn a_figure_closes_and_ends_at_rest() {
        for eight in [false, true] {
            let m = Motion::Figure {
                t0: 0.0,
                dur: 2.0,
                eight,
                r: 0.03,
                turns: 2.0,
            };
            for axis in 0..2 {
                let (v, s) = integrate(&m, 2.0, axis);
                assert!(v.abs() < 1e-7 && s.abs() < 1e-7, "{eight} {axis}: {v} {s}");
            }
            // Half way along a circle's first turn (phi = pi): 2 r to the left of the start.
            let half = Motion::Figure {
                t0: 0.0,
                dur: 2.0,
                eight: false,
                r: 0.03,
                turns: 1.0,
            };
            let (_, x) = integrate(&half, 1.0, 0);
            assert!((x + 0.06).abs() < 1e-6, "{x}");
        }
    }

    #[test]
    fn a_knock_and_a_lift_return_to_where_they_began() {
        let k = Motion::Knock {
            t0: 0.0,
            peak: 2.0,
            f: 30.0,
            periods: 2.0,
            flex: 150e-6,
            share: 0.3,
            dir: 1.0,
        };
        // The flex's acceleration jumps at its ends, which the midpoint rule (3.75 us steps)
        // places within a step: a residue of order 1e-7, against 150 um of flex.
        for axis in 0..3 {
            let (v, s) = integrate(&k, 1.5, axis);
            assert!(v.abs() < 1e-6 && s.abs() < 1e-6, "{axis}: {v} {s}");
        }
        let l = Motion::Lift {
            t0: 0.0,
            h: 0.005,
            rise: 0.25,
            air: 0.2,
            fall: 0.3,
            from: [0.0; 2],
            to: [0.05, 0.0],
            in_air: true,
            wobble: None,
            hover: 0.0,
            carry: [0.0; 2],
        };
        let (v, s) = integrate(&l, 1.0, 2);
        assert!(v.abs() < 1e-9 && s.abs() < 1e-9, "{v} {s}");
        let (_, top) = integrate(&l, 0.35, 2);
        assert!((top - 0.005).abs() < 1e-9, "{top}");
    }

    #[test]
    fn a_wobbling_lift_tilts_in_the_air_and_lands_at_its_slope() {
        let l = Motion::Lift {
            t0: 1.0,
            h: 0.005,
            rise: 0.2,
            air: 0.4,
            fall: 0.2,
            from: [0.01, 0.0],
            to: [0.0, 0.05],
            in_air: false,
            wobble: Some([-0.15, 0.1]),
            hover: 0.0,
            carry: [0.0; 2],
        };
        let at = |t: f64| l.tilt(t).expect("a lift tilts");
        assert_eq!(at(0.5), [0.01, 0.0]);
        // At its widest half-way through the air, then down to the slope as it touches.
        assert_eq!(at(1.4), [-0.15, 0.1]);
        let [x, y] = at(1.6);
        assert!(x > -0.15 && x < 0.0 && y < 0.1 && y > 0.05, "{x} {y}");
        assert_eq!(at(1.8), [0.0, 0.05]);
        assert_eq!(at(3.0), [0.0, 0.05]);
    }

    #[test]
    fn a_hover_holds_its_tilt_still_in_the_air_and_a_carry_ends_at_rest_where_it_went() {
        // Up over 0.2 s, 0.9 s in the air of which 0.5 s held still, down over 0.2 s; carried
        // 40 mm along X and 30 along -Y from the hover's end to the fall's middle.
        let l = Motion::Lift {
            t0: 1.0,
            h: 0.005,
            rise: 0.2,
            air: 0.9,
            fall: 0.2,
            from: [0.0; 2],
            to: [0.02, 0.0],
            in_air: false,
            wobble: Some([0.1, -0.05]),
            hover: 0.5,
            carry: [0.04, -0.03],
        };
        let at = |t: f64, want: [f64; 2]| {
            let got = l.tilt(t).expect("a lift tilts");
            assert!(
                (0..2).all(|j| (got[j] - want[j]).abs() < 1e-12),
                "{t}: {got:?}"
            );
        };
        // Tilted over the rise, held through the air, onto the slope over the fall.
        at(1.2, [0.1, -0.05]);
        at(2.0, [0.1, -0.05]);
        at(2.4, [0.02, 0.0]);
        // Still while it hovers: no acceleration from 1.2 to 1.7 s.
        assert!((1..50).all(|i| l.accel(1.2 + f64::from(i) * 0.01) == [0.0; 3]));
        for (axis, d) in [(0, 0.04), (1, -0.03)] {
            let (v, s) = integrate(&l, 3.0, axis);
            assert!(v.abs() < 1e-9 && (s - d).abs() < 1e-9, "{axis}: {v} {s}");
        }
        assert_eq!(l.displacement(), [0.0; 2], "a carry is no stroke");
    }

    #[test]
    fn before_a_tilt_begins_the_device_lies_as_the_first_motion_found_it() {
        let away = Motion::Lift {
            t0: 1.0,
            h: 0.005,
            rise: 0.2,
            air: 0.2,
            fall: 0.2,
            from: [0.0; 2],
            to: [0.05, 0.0],
            in_air: true,
            wobble: None,
            hover: 0.0,
            carry: [0.0; 2],
        };
        let back = Motion::Lift {
            t0: 3.0,
            h: 0.005,
            rise: 0.2,
            air: 0.2,
            fall: 0.2,
            from: [0.05, 0.0],
            to: [0.0; 2],
            in_air: true,
            wobble: None,
            hover: 0.0,
            carry: [0.0; 2],
        };
        let sc = Scenario {
            motions: vec![away, back],
            edges: vec![],
            seconds: 4.0,
        };
        assert_eq!(sc.at(0.5).2, [0.0; 2], "flat before the first lift");
        assert_eq!(sc.at(2.0).2, [0.05, 0.0], "on the slope between");
        assert_eq!(sc.at(3.9).2, [0.0; 2], "flat again");
    }

    #[test]
    fn the_sensor_reads_gravity_through_a_tilt_at_its_scale() {
        let spec = SensorSpec {
            nd_ug: 1e-3,
            walk_ug: 0.0,
            ..SensorSpec::ADXL335
        };
        let mut rng = noise::rng(1);
        let mut s = Sensor::new(spec, &mut rng);
        let tilt = [2f64.to_radians(), 0.0];
        let mut c = [0u16; 3];
        for _ in 0..3000 {
            c = s.codes([0.0; 3], [0.0; 3], tilt, &mut rng);
        }
        let want = G * 2f64.to_radians().sin() / spec.lsb();
        assert!((f64::from(c[0]) - 2048.0 - want).abs() <= 1.0, "{c:?}");
        assert!(
            (f64::from(c[2]) - 2048.0 - G / spec.lsb()).abs() <= 1.5,
            "{c:?}"
        );
    }
}
