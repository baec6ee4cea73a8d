//! Scenes: a sensor and what happens to it, composed from small effects, producing ADC codes
//! exactly as the device's ADC would.
//!
//! # Design
//! "Model only what a scene needs": a [`Scene`] is a list of [`Source`]s (each adds an
//! acceleration in m/s^2 per sample) and one [`Adc`] that quantises and clips the sum into
//! codes. Each effect is a small type:
//!
//! | effect | type | model |
//! |---|---|---|
//! | white noise | [`Source::White`] | independent N(0, sigma_d^2) per sample |
//! | single-pole analog filter over white noise | [`Source::Filtered`] | the filter's sampled output, exactly: stationary AR(1), `r0 = sigma_c^2 pi fc / 2` (eq 31), pole `exp(-2 pi fc / fs)` (REFERENCE (b)) |
//! | DC bias | [`Source::Bias`] | a constant |
//! | bias random walk (drift) | [`Source::BiasWalk`] | `b[n] = b[n-1] + N(0, k^2 / fs)`, `k` in m/s^2/sqrt(s) |
//! | hand motion | [`Source::Stroke`] | minimum-jerk strokes (below) |
//! | ADC quantisation and clipping | [`Adc`] | round to the nearest code, clip to the rails |
//!
//! The analog filter is applied to the sensor noise only: a bias and hand motion (below 10 Hz)
//! pass a filter at tens of Hz unchanged, so filtering them would model nothing.

use crate::world::noise::{self, SimRng};

/// One additive effect, in m/s^2.
#[derive(Clone, Debug)]
pub enum Source {
    /// White noise, per-sample std `sigma_d` [m/s^2].
    White {
        /// Per-sample std [m/s^2].
        sigma_d: f64,
    },
    /// White noise of one-sided density `sigma_c` [m/s^2/sqrt(Hz)] through a single-pole
    /// filter at `fc` [Hz], sampled at the scene's rate.
    Filtered {
        /// Input noise density, one-sided [m/s^2/sqrt(Hz)].
        sigma_c: f64,
        /// Cut-off [Hz].
        fc: f64,
    },
    /// A constant bias [m/s^2].
    Bias {
        /// The bias [m/s^2].
        value: f64,
    },
    /// A bias that random-walks: `k` [m/s^2/sqrt(s)] (the acceleration random walk).
    BiasWalk {
        /// Random-walk coefficient [m/s^2/sqrt(s)].
        k: f64,
    },
    /// A minimum-jerk stroke of `distance_m` [m] lasting `duration_s` [s], starting at
    /// `start_s` [s]: `a(t) = D/T^2 * (60 u - 180 u^2 + 120 u^3)`, `u = t / T`.
    Stroke {
        /// Start time [s].
        start_s: f64,
        /// Duration [s].
        duration_s: f64,
        /// Distance [m] (signed).
        distance_m: f64,
    },
}

/// A source with its running state.
#[derive(Clone, Debug)]
enum Running {
    White(f64),
    Filtered(noise::Ar1),
    Bias(f64),
    BiasWalk {
        step_sd: f64,
        b: f64,
    },
    Stroke {
        start_s: f64,
        duration_s: f64,
        distance_m: f64,
    },
}

/// The ADC: a reference that maps `m_s2_per_lsb` per code around `mid`, `bits` of
/// resolution, rounding to the nearest code and clipping at the rails.
#[derive(Clone, Copy, Debug)]
pub struct Adc {
    /// Resolution [bits].
    pub bits: u8,
    /// Code of zero acceleration (the sensor's zero-g output).
    pub mid: f64,
    /// Acceleration per code [m/s^2].
    pub m_s2_per_lsb: f64,
}

impl Adc {
    /// The code for an acceleration `a` [m/s^2].
    pub fn code(&self, a: f64) -> u16 {
        noise::Adc { bits: self.bits }.code(self.mid + a / self.m_s2_per_lsb)
    }
}

/// A sensor at `fs` with its effects.
#[derive(Clone, Debug)]
pub struct Scene {
    /// Scene name.
    pub name: &'static str,
    /// What it models, and where its numbers come from.
    pub about: &'static str,
    /// Sampling rate [Hz].
    pub fs: f64,
    /// The effects.
    pub sources: Vec<Source>,
    /// The converter.
    pub adc: Adc,
}

/// A scene's running state for one trial.
pub struct Run<'a> {
    scene: &'a Scene,
    running: Vec<Running>,
    n: u64,
}

impl Scene {
    /// Starts a trial: filters in their stationary state, walks at zero.
    pub fn start(&self, rng: &mut SimRng) -> Run<'_> {
        let running = self
            .sources
            .iter()
            .map(|s| match *s {
                Source::White { sigma_d } => Running::White(sigma_d),
                Source::Filtered { sigma_c, fc } => {
                    let alpha = 2.0 * std::f64::consts::PI * fc / self.fs;
                    let r0 = sigma_c * sigma_c * std::f64::consts::PI * fc / 2.0;
                    Running::Filtered(noise::Ar1::new(r0, alpha, rng))
                }
                Source::Bias { value } => Running::Bias(value),
                Source::BiasWalk { k } => Running::BiasWalk {
                    step_sd: k / self.fs.sqrt(),
                    b: 0.0,
                },
                Source::Stroke {
                    start_s,
                    duration_s,
                    distance_m,
                } => Running::Stroke {
                    start_s,
                    duration_s,
                    distance_m,
                },
            })
            .collect();
        Run {
            scene: self,
            running,
            n: 0,
        }
    }
}

impl Run<'_> {
    /// The true acceleration of the next sample [m/s^2] (before the ADC).
    pub fn next_accel(&mut self, rng: &mut SimRng) -> f64 {
        let t = self.n as f64 / self.scene.fs;
        self.n += 1;
        self.running
            .iter_mut()
            .map(|r| match r {
                Running::White(sd) => *sd * noise::normal(rng),
                Running::Filtered(ar) => ar.next(rng),
                Running::Bias(b) => *b,
                Running::BiasWalk { step_sd, b } => {
                    *b += *step_sd * noise::normal(rng);
                    *b
                }
                Running::Stroke {
                    start_s,
                    duration_s,
                    distance_m,
                } => min_jerk_accel(t - *start_s, *duration_s, *distance_m),
            })
            .sum()
    }

    /// The next ADC code.
    pub fn next_code(&mut self, rng: &mut SimRng) -> u16 {
        let a = self.next_accel(rng);
        self.scene.adc.code(a)
    }
}

impl Scene {
    /// `seconds` of `[x, y, z]` codes: X is this scene; Y and Z are the same sensor at rest
    /// (the scene without its strokes), each axis with its own random stream from `seed`.
    pub fn three_axes(&self, seconds: f64, seed: u64) -> Vec<[u16; 3]> {
        let n = (seconds * self.fs).round() as usize;
        let rest = Scene {
            sources: self
                .sources
                .iter()
                .filter(|s| !matches!(s, Source::Stroke { .. }))
                .cloned()
                .collect(),
            ..self.clone()
        };
        let mut rngs: Vec<SimRng> = (0..3)
            .map(|k| noise::rng(seed.wrapping_mul(3).wrapping_add(k)))
            .collect();
        let mut runs: Vec<Run<'_>> = [self, &rest, &rest]
            .iter()
            .zip(rngs.iter_mut())
            .map(|(sc, r)| sc.start(r))
            .collect();
        (0..n)
            .map(|_| {
                let mut s = [0u16; 3];
                for (k, (run, rng)) in runs.iter_mut().zip(rngs.iter_mut()).enumerate() {
                    s[k] = run.next_code(rng);
                }
                s
            })
            .collect()
    }

    /// Per-sample rms of the scene's noise after the ADC [m/s^2]: white and filtered noise
    /// (eq 31) plus the ADC's LSB^2/12; biases and strokes are not noise.
    pub fn noise_rms_m_s2(&self) -> f64 {
        let var: f64 = self
            .sources
            .iter()
            .map(|s| match *s {
                Source::White { sigma_d } => sigma_d * sigma_d,
                Source::Filtered { sigma_c, fc } => {
                    sigma_c * sigma_c * std::f64::consts::PI * fc / 2.0
                }
                _ => 0.0,
            })
            .sum();
        (var + self.adc.m_s2_per_lsb.powi(2) / 12.0).sqrt()
    }

    /// The total distance of this scene's strokes [m] (the true displacement along X).
    pub fn stroke_distance_m(&self) -> f64 {
        self.sources
            .iter()
            .map(|s| match s {
                Source::Stroke { distance_m, .. } => *distance_m,
                _ => 0.0,
            })
            .sum()
    }
}

/// Acceleration of a minimum-jerk stroke of `d` [m] over `dur` [s] at time `t` into it.
pub fn min_jerk_accel(t: f64, dur: f64, d: f64) -> f64 {
    if t < 0.0 || t > dur {
        return 0.0;
    }
    let u = t / dur;
    d / (dur * dur) * (60.0 * u - 180.0 * u * u + 120.0 * u * u * u)
}

/// ADC scale of an ADXL335 on a 12-bit ratiometric ADC (REFERENCE (g)) [m/s^2 per LSB].
pub const ADXL335_LSB: f64 = 9.806_65 * 10.0 / 4096.0;

/// The scenes `cargo lab simulate` knows.
pub fn catalogue() -> Vec<Scene> {
    let g = 9.806_65;
    vec![
        Scene {
            name: "adxl335-rest",
            about: "ADXL335 at rest (REFERENCE (g)): 300 ug/sqrt(Hz) into its 50 Hz RC filter, \
                    12-bit ratiometric ADC at 3 kHz, 2 mg bias",
            fs: 3000.0,
            sources: vec![
                Source::Filtered {
                    sigma_c: 300e-6 * g,
                    fc: 50.0,
                },
                Source::Bias { value: 2e-3 * g },
            ],
            adc: Adc {
                bits: 12,
                mid: 2048.0,
                m_s2_per_lsb: ADXL335_LSB,
            },
        },
        Scene {
            name: "adxl250-rest",
            about: "noise-dominated, like the paper's ADXL250: 1 mg/sqrt(Hz) typical (ADXL150/ADXL250 \
                    data sheet, Analog Devices), 38 mV/g ratiometric at 5 V read by a 12-bit ADC \
                    (32 mg per LSB), here through a 100 Hz single-pole filter at 1 kHz",
            fs: 1000.0,
            sources: vec![Source::Filtered {
                sigma_c: 1e-3 * g,
                fc: 100.0,
            }],
            adc: Adc {
                bits: 12,
                mid: 2048.0,
                m_s2_per_lsb: 5.0 / 4096.0 / 0.038 * g,
            },
        },
        Scene {
            name: "cxl-drift",
            about: "drift-dominated, in the manner of the paper's Crossbow CXL01F3 (+-1 g, 2 V/g). \
                    ILLUSTRATIVE values, not checked against a data sheet here: 0.2 mg/sqrt(Hz) \
                    into a 50 Hz filter, 1 mg bias and a 20 ug/sqrt(s) bias random walk, 12-bit ADC \
                    over 0-5 V (1.2 mg per LSB) at 1 kHz",
            fs: 1000.0,
            sources: vec![
                Source::Filtered {
                    sigma_c: 0.2e-3 * g,
                    fc: 50.0,
                },
                Source::Bias { value: 1e-3 * g },
                Source::BiasWalk { k: 20e-6 * g },
            ],
            adc: Adc {
                bits: 12,
                mid: 2048.0,
                m_s2_per_lsb: 5.0 / 4096.0 / 2.0 * g,
            },
        },
        Scene {
            name: "adxl335-stroke",
            about: "ADXL335 as in adxl335-rest, moved 10 cm in a 0.5 s minimum-jerk stroke after \
                    1.5 s at rest",
            fs: 3000.0,
            sources: vec![
                Source::Filtered {
                    sigma_c: 300e-6 * g,
                    fc: 50.0,
                },
                Source::Stroke {
                    start_s: 1.5,
                    duration_s: 0.5,
                    distance_m: 0.10,
                },
            ],
            adc: Adc {
                bits: 12,
                mid: 2048.0,
                m_s2_per_lsb: ADXL335_LSB,
            },
        },
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn min_jerk_stroke_integrates_to_its_distance_and_stops() {
        // Double integral of the acceleration over the stroke = D, final velocity 0.
        let (dur, d, n) = (0.5, 0.1, 100_000u32);
        let dt = dur / f64::from(n);
        let (mut v, mut s) = (0.0, 0.0);
        for i in 0..n {
            let a = min_jerk_accel((f64::from(i) + 0.5) * dt, dur, d);
            s += v * dt + 0.5 * a * dt * dt;
            v += a * dt;
        }
        assert!(v.abs() < 1e-9, "{v}");
        assert!((s - d).abs() < 1e-9, "{s}");
    }

    #[test]
    fn catalogue_names_are_unique() {
        let c = catalogue();
        for (i, a) in c.iter().enumerate() {
            assert!(c[i + 1..].iter().all(|b| b.name != a.name));
        }
    }
}
