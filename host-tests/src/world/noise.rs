//! Simulated sensor noise, quantised to ADC codes exactly as the device's ADC would.
//!
//! Each effect is a small type; a test or scene composes only what it studies.

use rand::{Rng, SeedableRng};
use rand_distr::StandardNormal;
use rand_pcg::Pcg64Mcg;

/// The project's seeded generator (PCG, 128-bit state): identical streams on every machine.
pub type SimRng = Pcg64Mcg;

/// A generator from a seed.
pub fn rng(seed: u64) -> SimRng {
    SimRng::seed_from_u64(seed)
}

/// One standard normal draw.
pub fn normal(rng: &mut SimRng) -> f64 {
    rng.sample(StandardNormal)
}

/// Stationary AR(1) noise `x[n] = q x[n-1] + e[n]` with variance `r0` and pole
/// `q = exp(-alpha)`: single-pole-filtered white noise sampled at fs (REFERENCE (b)).
#[derive(Clone, Debug)]
pub struct Ar1 {
    q: f64,
    innovation_sd: f64,
    x: f64,
}

impl Ar1 {
    /// A process with variance `r0` [unit^2] and `alpha = 2 pi fc / fs`, started in its
    /// stationary distribution (no transient).
    pub fn new(r0: f64, alpha: f64, rng: &mut SimRng) -> Self {
        let q = (-alpha).exp();
        // 1 - q^2 = -expm1(-2 alpha), stable for small alpha.
        let innovation_sd = (r0 * -(-2.0 * alpha).exp_m1()).sqrt();
        Self {
            q,
            innovation_sd,
            x: r0.sqrt() * normal(rng),
        }
    }

    /// The next sample.
    pub fn next(&mut self, rng: &mut SimRng) -> f64 {
        self.x = self.q * self.x + self.innovation_sd * normal(rng);
        self.x
    }
}

/// An ideal ADC: rounds `volts_lsb` (the input in LSB, i.e. the exact code it would read
/// with infinite resolution) to the nearest code and clips at `0` and `2^bits - 1`.
#[derive(Clone, Copy, Debug)]
pub struct Adc {
    /// Resolution [bits], `1..=16`.
    pub bits: u8,
}

impl Adc {
    /// The code for an input of `x` LSB.
    pub fn code(self, x: f64) -> u16 {
        let full = f64::from((1u32 << self.bits) - 1);
        x.round().clamp(0.0, full) as u16
    }
}

/// Variance [LSB^2] of `round(mid + sigma Z)`, `Z` standard normal, summed exactly over the
/// code lattice. Equals `sigma^2 + 1/12` (Sheppard) only while `sigma >~ 0.5`; for sub-LSB
/// noise it is what a quantised white process really has.
pub fn quantised_variance(mid: f64, sigma: f64) -> f64 {
    let lo = (mid - 12.0 * sigma).floor() as i64 - 1;
    let hi = (mid + 12.0 * sigma).ceil() as i64 + 1;
    let cdf = |x: f64| 0.5 * libm::erfc(-(x - mid) / (sigma * std::f64::consts::SQRT_2));
    let (mut m0, mut m1, mut m2) = (0.0, 0.0, 0.0);
    for k in lo..=hi {
        let p = cdf(k as f64 + 0.5) - cdf(k as f64 - 0.5);
        let d = k as f64 - mid;
        m0 += p;
        m1 += p * d;
        m2 += p * d * d;
    }
    m2 / m0 - (m1 / m0).powi(2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantised_variance_is_sheppard_for_dithering_noise_only() {
        let v = quantised_variance(2048.0, 4.0);
        // Sheppard's correction is exact up to terms in exp(-2 pi^2 sigma^2) = 1e-137.
        assert!((v - (16.0 + 1.0 / 12.0)).abs() < 1e-12, "{v}");
        // sigma = 0.2 LSB centred on a code: almost always the same code.
        let v = quantised_variance(2048.0, 0.2);
        assert!(v < 0.02, "{v}");
    }

    #[test]
    fn adc_rounds_and_clips() {
        let adc = Adc { bits: 12 };
        assert_eq!(adc.code(2047.5), 2048);
        assert_eq!(adc.code(-3.0), 0);
        assert_eq!(adc.code(5000.0), 4095);
    }
}
