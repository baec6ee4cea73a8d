//! Monte Carlo through the real fixed-point core: simulated ADC codes go through
//! `imu_core::Axis` exactly as on the device, and the integrator's state is read out in
//! metres.

use imu_core::{AdcCode, Axis, Config, Scheme, Settings};

use crate::stats::MeanSquare;
use crate::world::noise::SimRng;

/// ADC mid-scale code of a 12-bit converter: the zero-acceleration point of the simulations.
pub const MID: u16 = 2048;

/// Settings for a Monte Carlo run: `fs` [Hz], optional digital low-pass `fc` [Hz], scheme,
/// and the project's default ADXL335-class scale (0.023942 m/s^2 per LSB).
///
/// # Panics
/// If the configuration is invalid (a bug in the calling test, not an input).
pub fn settings(fs_hz: u32, lowpass_fc_hz: Option<f64>, scheme: Scheme) -> Settings {
    Config {
        fs_hz,
        lowpass_fc_hz,
        scheme,
        drift: None, // Monte Carlo studies pure integration; any fs up to 100 kHz
        ..Config::default()
    }
    .validate()
    .expect("Monte Carlo settings are valid")
}

/// The outcome of one trial.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trial {
    /// Sample-by-sample double integral [m] (the device's estimate).
    pub position_m: f64,
    /// The retrospective estimate `D_N T^2 / 2` of eq (23)/(32) [m], from the integrator's
    /// velocity sum (Euler: `V = sum c`, so `D_N = V / N`).
    pub retrospective_m: f64,
}

/// Runs one trial: `burn_in` codes settle the filter (integrator then reset), then `n` codes
/// are integrated. `bias_q16` is the bias the core subtracts [Q16 counts].
pub fn trial(
    settings: &Settings,
    bias_q16: i64,
    burn_in: usize,
    n: usize,
    mut code: impl FnMut() -> u16,
) -> Trial {
    let mut axis = Axis::new(bias_q16);
    for _ in 0..burn_in {
        axis.update(settings, AdcCode(code()));
    }
    axis.stop();
    for _ in 0..n {
        axis.update(settings, AdcCode(code()));
    }
    let m_per_unit = settings.metres_per_position_unit();
    let w = axis.integrator().velocity() as f64; // 2 V in Q16 counts * samples
    Trial {
        position_m: axis.integrator().position() as f64 * m_per_unit,
        // D_N T^2 / 2 = (W / 2 / N) 2^-16 LSB (N / fs)^2 / 2 = W N LSB / (4 2^16 fs^2),
        // which is W N position units.
        retrospective_m: w * n as f64 * m_per_unit,
    }
}

/// Both estimates' mean squares over `trials` trials of `one`, which draws its codes from a
/// generator seeded with `seed` (the same seed gives the same numbers on every machine).
pub fn run(
    trials: usize,
    seed: u64,
    mut one: impl FnMut(&mut SimRng) -> Trial,
) -> (MeanSquare, MeanSquare) {
    let mut rng = crate::world::noise::rng(seed);
    let results: Vec<Trial> = (0..trials).map(|_| one(&mut rng)).collect();
    let pos: Vec<f64> = results.iter().map(|t| t.position_m).collect();
    let retro: Vec<f64> = results.iter().map(|t| t.retrospective_m).collect();
    (MeanSquare::of(&pos), MeanSquare::of(&retro))
}
