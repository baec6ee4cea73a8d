//! Bias calibration over a window at rest: the mean with 16 fractional bits, and a noise
//! estimate that rejects a window with motion in it.
//!
//! # Design
//! The sums are exact integers (`u64` sum and sum of squares of `u16` codes, at most `2^24`
//! samples), so the mean and variance are exact rationals, rounded once:
//! - bias `= round(sum * 2^16 / n)` in Q16 counts (half up), within `2^-17` LSB of the mean;
//! - variance `= (n sum_sq - sum^2) / (n (n - 1))` [LSB^2] (unbiased), compared exactly with
//!   the configured bound; the reported rms is `floor(sqrt(variance) * 2^16)` in Q16 counts.
//!
//! - noise over time: the window is also cut into ticks of `D` samples (drift control's 5 ms
//!   ticks). From the tick sums `s[t]` come their variance `g0` and lag covariances `g1`,
//!   `g2`, `g3` (exact integer sums, rounded once): [`Calibration::tick_var_q32`] `= g0 / D`,
//!   [`Calibration::tick_lags_q32`] `= g_l / D`, and [`Calibration::long_run_var_q32`]
//!   `= (g0 + 2 g1 + 2 g2) / D`, the variance per sample of a long
//!   sum (`Var(sum of n samples) ~ q n` for `n >> D`; REFERENCE (i)). A sensor's RC filter
//!   correlates neighbouring samples, so `q` is several times the per-sample variance (19x
//!   for an ADXL335's 50 Hz pole at 3 kHz); ticks well past the filter's time constant keep
//!   `g2` and beyond negligible (the 50 Hz pole's correlation is 0.2 after one 5 ms tick,
//!   below 0.01 after two).
//!
//! # Motion: the window against its own noise
//! What spoils a zero is acceleration that does not average out over the window: the device
//! pushed, held in a hand, tilted part-way through. All of it is slow (a hand moves below
//! about 10 Hz, a tilt is a step), so it shows as **neighbouring means that agree more than
//! noise lets them**. The window is cut into blocks of a few ticks (the noise of an ADXL335
//! through its 50 Hz pole is correlated over about 3 ms, so block sums of noise are nearly
//! independent), and their von Neumann ratio
//!
//! ```text
//! eta = sum_{j>1} (B[j] - B[j-1])^2 / (2 sum_j (B[j] - mean B)^2)
//! ```
//!
//! is about 1 for noise of any size (`E eta = 1`, `Var eta = (k - 2) / ((k + 1)(k - 1))`
//! for `k` independent Gaussian blocks), and falls towards 0 as slow motion fills the
//! blocks: a block length finds the window **unsteady** when `eta` is below
//! `1 - z sqrt(Var eta)`, `z = 3.72` the normal quantile of [`FALSE_REFUSAL`] (in 1 s: 0.485
//! for the 50 blocks of 20 ms, 0.427 for the 40 of 25 ms, 0.372 for the 33 of 30 ms). So the
//! test needs no noise figure of the sensor: a sensor ten times noisier than the ADXL335
//! calibrates as readily, and a quiet one is held to its own noise.
//!
//! Block sums sample the window at the block rate, so a vibration near a multiple of it
//! aliases into sums that vary slowly, as a hand's would (50 mg at 45 Hz through 20 ms blocks
//! beats at 5 Hz, 5 mg of it left in the block means). A length is fooled within its alias
//! zone, where the beat's `1 - cos(2 pi f_beat T)` is under its bound: 8.5, 6.1 and 4.7 Hz
//! either side of each multiple of 50, 40 and 33 Hz. So there are three lengths,
//! [`BLOCK_TICKS`] (20, 25 and 30 ms at 5 ms ticks), whose zones first all meet at 200 Hz,
//! and a window is refused only when every length tested finds it unsteady.
//!
//! What it catches, for block means of sd `s` (1.5, 1.4 and 1.2 mg over 20, 25 and 30 ms for
//! the ADXL335 at 3 kHz): a step (a tilt part-way) of `2 sqrt(1 / eta_min - 1) s` at each
//! length, 3.2 mg or 0.19 degrees at most, where the old rms bound of 0.1 m/s^2 let a whole
//! degree through; motion below about 4.7 Hz (the 30 ms length's zone about 0) that carries
//! most of the blocks' variance. What it lets through, by design: a knock's ring or a
//! machine's vibration (20 to about 190 Hz, which averages out of the zero), a hand's tremor
//! of a few mg (as small as the noise, and zero-mean), and sway faster than 4.7 Hz (zero-mean
//! too: 20 mg at 5 Hz moves the mean of 1 s by 1.3 mg at most). Neighbouring blocks of a real
//! sensor's noise correlate a little (about 0.09 for the ADXL335's pole at 3 kHz), which
//! lowers `eta`'s mean by as much: the false-refusal rate is measured on the sensor model
//! (`host-tests/tests/calibration_motion.rs`). A length with fewer than
//! [`STEADY_BLOCKS_MIN`] blocks in the window is not tested.
//!
//! A window whose variance exceeds the configured rms bound (a broken or floating input, a
//! shaking hand) is rejected too, as a whole, never averaged in. A window that touches either
//! ADC rail (code `0` or `2^bits - 1`) is rejected as clipped: a clipped mean is not the bias.

use core::fmt;

use crate::math;
use crate::AdcCode;

/// Ticks in a block of each of the motion test's three block lengths [ticks]: 20, 25 and
/// 30 ms at 5 ms ticks (40, 50 and 60 ms at 100 Hz). Their rates, 50, 40 and 33 Hz, first
/// share a multiple at 200 Hz, and no frequency below it lies within each one's alias zone
/// (see the module docs): a vibration that beats slowly through one length's blocks does
/// not through all three.
pub const BLOCK_TICKS: [u32; 3] = [4, 5, 6];
/// Fewest blocks in a window for the motion test to run [blocks]: no window of `k` blocks
/// has a von Neumann ratio below `1 - cos(pi / k)` (a half cosine's), and from 13 blocks on
/// the bound at [`FALSE_REFUSAL`] lies above that (0.048 against 0.029; at 12 blocks 0.017
/// against 0.034), so below it the test could never refuse. A window under 13 blocks (260 ms
/// at 5 ms ticks) has only the rms bound.
pub const STEADY_BLOCKS_MIN: u32 = 13;
/// Probability that a window of independent Gaussian noise is refused as unsteady, per
/// calibration; it sets the motion test's `z` (3.72).
pub const FALSE_REFUSAL: f64 = 1e-4;

/// The motion test's bound on the von Neumann ratio for `blocks` blocks, in Q16
/// (`0..=65536`): `1 - z sqrt((k - 2) / ((k + 1)(k - 1)))` with `z` the normal quantile of
/// [`FALSE_REFUSAL`], floored at 0; 0 (no test) below [`STEADY_BLOCKS_MIN`] blocks.
pub fn steady_min_q16(blocks: u32) -> u32 {
    if blocks < STEADY_BLOCKS_MIN {
        return 0;
    }
    let k = f64::from(blocks);
    let sd = libm::sqrt((k - 2.0) / ((k + 1.0) * (k - 1.0)));
    let eta = 1.0 - crate::drift::z_of_tail(FALSE_REFUSAL) * sd;
    math::round_to_u64(eta.max(0.0) * 65_536.0) as u32
}

/// Result of a good calibration window for one axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Calibration {
    /// The bias (mean code at rest) in Q16 counts, `0..=65535 * 2^16`.
    pub bias_q16: i64,
    /// Per-sample rms noise at rest in Q16 counts (unbiased variance, square root floored).
    pub noise_rms_q16: u64,
    /// Number of samples averaged.
    pub samples: u32,
    /// Variance of a tick's sum divided by its length [LSB^2 per sample, Q32], floored at
    /// 1/4 LSB^2 (a noise-free sensor still flickers between two codes).
    pub tick_var_q32: u64,
    /// Long-run variance per sample, `q`, from the ticks' variance and lag-one covariance
    /// [LSB^2 per sample, Q32]: `Var(sum of n samples) ~ q n` for sums longer than a tick.
    /// Floored at 1/4 LSB^2 and at half of [`Self::tick_var_q32`].
    pub long_run_var_q32: u64,
    /// Lag-1, lag-2 and lag-3 covariances of the tick sums divided by the tick's length
    /// [LSB^2 per sample, Q32, signed, saturating at `±(2^63 - 1)`; 0 with fewer than 4
    /// ticks]: with
    /// [`Self::tick_var_q32`] they give the noise of any short linear combination of tick
    /// sums (drift control's disturbance estimate).
    pub tick_lags_q32: [i64; 3],
}

/// Why a calibration window was rejected.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum CalibrationError {
    /// The window's variance exceeded the at-rest bound: the device moved.
    Motion {
        /// The window's rms noise in Q16 counts.
        noise_rms_q16: u64,
    },
    /// The window's block means agreed more than its noise lets them, at every block length
    /// ([`BLOCK_TICKS`]) that was tested: slow motion or a step (see the module docs).
    Unsteady {
        /// The window's von Neumann ratio at each block length in Q16 (`65536` is 1, the
        /// value at rest); `u32::MAX` for a length not tested.
        eta_q16: [u32; 3],
        /// The bounds they fell below, in Q16 (0: not tested).
        min_q16: [u32; 3],
        /// The tick's length [us], for the blocks' lengths in the message.
        tick_us: u32,
    },
    /// A sample sat on an ADC rail (code 0 or full scale): clipped or disconnected sensor.
    Clipped {
        /// The rail code seen.
        code: u16,
    },
}

impl fmt::Display for CalibrationError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Motion { noise_rms_q16 } => write!(
                f,
                "too noisy to calibrate: rms {:.3} LSB is above the at-rest bound (rest_noise_max_m_s2; a shaking hand or a faulty input)",
                *noise_rms_q16 as f64 / 65_536.0
            ),
            Self::Unsteady {
                eta_q16,
                min_q16,
                tick_us,
            } => {
                f.write_str("motion during calibration: neighbouring means agree more than noise lets them (von Neumann ratio")?;
                for ((eta, min), ticks) in eta_q16.iter().zip(min_q16).zip(BLOCK_TICKS) {
                    if *min > 0 {
                        let ms = f64::from(ticks * tick_us) / 1000.0;
                        let (eta, min) = (f64::from(*eta) / 65_536.0, f64::from(*min) / 65_536.0);
                        write!(f, " {eta:.2} over {ms:.0} ms blocks, below {min:.2};")?;
                    }
                }
                f.write_str(" at rest about 1)")
            }
            Self::Clipped { code } => write!(
                f,
                "ADC code {code} is a rail: the sensor is clipped or disconnected"
            ),
        }
    }
}

/// Accumulates one axis's calibration window. Its window length and bound come from
/// [`crate::Settings::calibrator`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Calibrator {
    window: u32,
    var_max_q16: u64,
    rail: u16,
    tick: u32,
    n: u32,
    sum: u64,
    sum_sq: u64,
    clipped: Option<u16>,
    /// The current tick's sum so far.
    tick_sum: u64,
    /// The first three complete ticks' sums and the last three (oldest first).
    first_ticks: [u64; 3],
    last_ticks: [u64; 3],
    /// Complete ticks, their sum, and the sums of lag-0 (squares) to lag-3 products.
    ticks: u32,
    ticks_sum: u64,
    ticks_lag: [u128; 4],
    /// The motion test at each block length, and the tick's length [us] for its message.
    blocks: [Blocks; 3],
    tick_us: u32,
}

/// The motion test's sums at one block length: its bound (Q16, 0: no test), the current
/// block's sum, complete blocks, their sum, the first and the latest block, and the sums of
/// squares and of neighbours' products.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Blocks {
    ticks: u32,
    min_q16: u32,
    sum: u64,
    n: u32,
    total: u64,
    first: u64,
    last: u64,
    sq: u128,
    lag: u128,
}

impl Blocks {
    const fn new(ticks: u32, min_q16: u32) -> Self {
        Self {
            ticks,
            min_q16,
            sum: 0,
            n: 0,
            total: 0,
            first: 0,
            last: 0,
            sq: 0,
            lag: 0,
        }
    }

    /// Adds a tick's sum `t`, the window's `ticks`-th: a block ends every [`Self::ticks`].
    /// Each sum below `(n 2^16)^2 <= 2^80`.
    fn push_tick(&mut self, t: u64, ticks: u32) {
        self.sum += t; // <= 5 2^14 2^16 < 2^33
        if !ticks.is_multiple_of(self.ticks) {
            return;
        }
        let b = core::mem::take(&mut self.sum);
        if self.n == 0 {
            self.first = b;
        } else {
            self.lag += u128::from(b) * u128::from(self.last);
        }
        self.n += 1;
        self.total += b;
        self.sq += u128::from(b) * u128::from(b);
        self.last = b;
    }

    /// Whether the test runs on these blocks.
    const fn tested(&self) -> bool {
        self.min_q16 > 0 && self.n >= STEADY_BLOCKS_MIN
    }

    /// The von Neumann ratio (Q16), if the test runs and it is below the bound (see the
    /// module docs): computed exactly as `k D 2^16 < eta_min 2 (k S2 - S1^2)` with `D` the
    /// sum of squared neighbours' differences, `S1`, `S2` the blocks' sum and sum of squares
    /// (every term below `2^98`). A constant window has no spread: steady.
    fn unsteady(&self) -> Option<u32> {
        if !self.tested() {
            return None;
        }
        let k = u128::from(self.n);
        let s1 = u128::from(self.total);
        let spread = k * self.sq - s1 * s1; // k^2 times the blocks' variance, >= 0
        let ends = u128::from(self.first).pow(2) + u128::from(self.last).pow(2);
        let diffs = 2 * self.sq - ends - 2 * self.lag; // >= 0
        if spread == 0 {
            return None;
        }
        let lhs = (k * diffs) << 16;
        let rhs = 2 * u128::from(self.min_q16) * spread;
        (lhs < rhs).then(|| (lhs / (2 * spread)).min(u128::from(u32::MAX)) as u32)
    }
}

impl Calibrator {
    /// A calibrator for `window` samples (`2..=2^24`) that rejects a variance above
    /// `var_max_q16` (LSB^2 in Q16), any code at `0` or `2^adc_bits - 1`, and an unsteady
    /// window (its von Neumann ratio below `steady_min_q16` at every block length of
    /// [`BLOCK_TICKS`] tested, Q16; 0 for no test at that length, see [`steady_min_q16`]),
    /// and measures the noise over ticks of `tick` samples (`1..=2^14`) of `tick_us`
    /// microseconds.
    pub(crate) const fn new(
        window: u32,
        var_max_q16: u64,
        adc_bits: u8,
        (tick, tick_us): (u32, u32),
        steady_min_q16: [u32; 3],
    ) -> Self {
        Self {
            window,
            var_max_q16,
            rail: ((1u32 << adc_bits) - 1) as u16,
            tick,
            n: 0,
            sum: 0,
            sum_sq: 0,
            clipped: None,
            tick_sum: 0,
            first_ticks: [0; 3],
            last_ticks: [0; 3],
            ticks: 0,
            ticks_sum: 0,
            ticks_lag: [0; 4],
            blocks: [
                Blocks::new(BLOCK_TICKS[0], steady_min_q16[0]),
                Blocks::new(BLOCK_TICKS[1], steady_min_q16[1]),
                Blocks::new(BLOCK_TICKS[2], steady_min_q16[2]),
            ],
            tick_us,
        }
    }

    /// The motion test's bound at each block length of [`BLOCK_TICKS`] (Q16; 0: that length
    /// is not tested), as [`steady_min_q16`] gives it for the window's count of blocks.
    pub const fn steady_bounds_q16(&self) -> [u32; 3] {
        [
            self.blocks[0].min_q16,
            self.blocks[1].min_q16,
            self.blocks[2].min_q16,
        ]
    }

    /// Samples accumulated so far.
    pub const fn samples(&self) -> u32 {
        self.n
    }

    /// `true` once the window is full; further samples are ignored until [`Self::restart`].
    pub const fn is_full(&self) -> bool {
        self.n >= self.window
    }

    /// Adds one sample, unless the window is already full.
    #[inline]
    pub fn push(&mut self, x: AdcCode) {
        if self.is_full() {
            return;
        }
        if x.0 == 0 || x.0 >= self.rail {
            self.clipped.get_or_insert(x.0);
        }
        let v = u64::from(x.0);
        self.n += 1;
        self.sum += v; // <= 2^24 * 2^16: exact
        self.sum_sq += v * v; // <= 2^24 * 2^32: exact
        self.tick_sum += v;
        if self.n.is_multiple_of(self.tick) {
            let t = self.tick_sum;
            self.ticks_sum += t; // <= 2^40
                                 // Products with the ticks 0..=3 back: each <= 2^24 * 2^60 in all.
            self.ticks_lag[0] += u128::from(t) * u128::from(t);
            for lag in 1..=3usize {
                if self.ticks as usize >= lag {
                    let back = self.last_ticks[3 - lag];
                    self.ticks_lag[lag] += u128::from(t) * u128::from(back);
                }
            }
            if self.ticks < 3 {
                self.first_ticks[self.ticks as usize] = t;
            }
            self.ticks += 1;
            self.last_ticks = [self.last_ticks[1], self.last_ticks[2], t];
            self.tick_sum = 0;
            for b in &mut self.blocks {
                b.push_tick(t, self.ticks);
            }
        }
    }

    /// The motion test: `Some` with each length's ratio if every block length tested
    /// finds the window unsteady, and at least one is tested.
    fn unsteady(&self) -> Option<[u32; 3]> {
        let etas = self.blocks.map(|b| b.unsteady());
        let vetoed = self
            .blocks
            .iter()
            .zip(&etas)
            .any(|(b, e)| b.tested() && e.is_none());
        if vetoed || etas == [None; 3] {
            return None;
        }
        Some(etas.map(|e| e.unwrap_or(u32::MAX)))
    }

    /// Empties the window.
    pub fn restart(&mut self) {
        *self = Self::new(
            self.window,
            self.var_max_q16,
            self.rail.count_ones() as u8,
            (self.tick, self.tick_us),
            self.steady_bounds_q16(),
        );
    }

    /// The calibration from the samples so far (normally a full window; at least 2 samples).
    ///
    /// # Errors
    /// [`CalibrationError::Clipped`] if a sample sat on a rail, [`CalibrationError::Motion`]
    /// if the variance exceeds the bound, [`CalibrationError::Unsteady`] if the window fails
    /// the motion test.
    pub fn finish(&self) -> Result<Calibration, CalibrationError> {
        if let Some(code) = self.clipped {
            return Err(CalibrationError::Clipped { code });
        }
        let n = u128::from(self.n.max(2));
        let sum = u128::from(self.sum);
        // n * sum_sq - sum^2 >= 0 (Cauchy-Schwarz); < 2^24 * 2^56 = 2^80.
        let scatter = n * u128::from(self.sum_sq) - sum * sum;
        let dof = n * (n - 1);
        let noise_rms_q16 = math::isqrt_u128((scatter << 32) / dof) as u64;
        if scatter << 16 > u128::from(self.var_max_q16) * dof {
            return Err(CalibrationError::Motion { noise_rms_q16 });
        }
        if let Some(eta_q16) = self.unsteady() {
            return Err(CalibrationError::Unsteady {
                eta_q16,
                min_q16: self.blocks.map(|b| if b.tested() { b.min_q16 } else { 0 }),
                tick_us: self.tick_us,
            });
        }
        let bias_q16 = (((sum << 17) + n) / (2 * n)) as i64; // round half up of sum 2^16 / n
        let (tick_var_q32, long_run_var_q32) = self.tick_variances();
        Ok(Calibration {
            bias_q16,
            noise_rms_q16,
            samples: self.n,
            tick_var_q32,
            long_run_var_q32,
            tick_lags_q32: self.tick_lags(),
        })
    }

    /// The centred lag sums of the tick sums times `k^2`, `k^2 C_l` for `l = 0..=3`, exactly
    /// (`k` ticks, `m = s / k` their mean; the edge terms matter: `m` is thousands of times
    /// the deviations):
    ///
    /// ```text
    /// C_l = sum_{i > l} (t[i] - m)(t[i-l] - m)
    /// k^2 C_l = k^2 P_l - (k + l) s^2 + k s (F_l + L_l)
    /// ```
    ///
    /// with `P_l = sum t[i] t[i-l]`, `F_l` the sum of the first `l` ticks and `L_l` of the
    /// last `l`. Every term is below `2^110`. `None` with fewer than 4 ticks.
    #[inline(never)] // cold: once per calibration; inlined, it is copied per use
    fn centred_lags(&self) -> Option<[i128; 4]> {
        let k = i128::from(self.ticks);
        if k < 4 {
            return None;
        }
        let s = i128::from(self.ticks_sum);
        let s2 = s * s; // < 2^80
        let first = self.first_ticks.map(i128::from);
        let last = self.last_ticks.map(i128::from);
        Some(core::array::from_fn(|l| {
            let edges: i128 = first[..l].iter().sum::<i128>() + last[3 - l..].iter().sum::<i128>();
            let lag = l as i128;
            k * k * self.ticks_lag[l] as i128 - (k + lag) * s2 + k * s * edges
        }))
    }

    /// `floor(num 2^32 / (k^3 D))`, saturating at `u64::MAX`, for the centred lag sums:
    /// the quotient's whole part shifted, plus the remainder's fraction (rem < den = k^3 D
    /// <= 2^72, since k D <= 2^24, so rem 2^32 fits). Negative `num` gives 0.
    #[inline(never)] // cold: once per calibration; inlined, it is copied per use
    fn per_sample_q32(&self, num: i128) -> u64 {
        let k = i128::from(self.ticks);
        let den = k * k * k * i128::from(self.tick);
        let num = num.max(0);
        let whole = num / den;
        if whole >= 1 << 32 {
            return u64::MAX;
        }
        ((whole << 32) + ((num % den) << 32) / den) as u64
    }

    /// `(g0 / D, (g0 + 2 g1 + 2 g2) / D)` in LSB^2 per sample, Q32, floored (see
    /// [`Calibration`]), `g_l = C_l / k`. With fewer than 4 ticks, both are the floor.
    fn tick_variances(&self) -> (u64, u64) {
        const FLOOR: u64 = 1 << 30; // 1/4 LSB^2
        let Some([c0, c1, c2, _]) = self.centred_lags() else {
            return (FLOOR, FLOOR);
        };
        let g0 = self.per_sample_q32(c0);
        let long = self.per_sample_q32(c0 + 2 * c1 + 2 * c2);
        (g0.max(FLOOR), long.max(g0 / 2).max(FLOOR))
    }

    /// `g_l / D` for `l = 1, 2, 3` in LSB^2 per sample, Q32, signed, rounded toward zero and
    /// saturating at `±(2^63 - 1)`, not floored; zeros with fewer than 4 ticks.
    fn tick_lags(&self) -> [i64; 3] {
        let Some(c) = self.centred_lags() else {
            return [0; 3];
        };
        core::array::from_fn(|i| {
            let v = c[i + 1];
            let mag = self.per_sample_q32(v.abs()).min(i64::MAX as u64) as i64;
            mag * v.signum() as i64
        })
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::string::ToString;
    use std::vec::Vec;

    fn cal(window: u32, var_max_lsb2: u64) -> Calibrator {
        Calibrator::new(window, var_max_lsb2 << 16, 12, (2, 1000), [0, 0, 0])
    }

    #[test]
    fn mean_is_rounded_to_q16_and_variance_is_unbiased() {
        let mut c = cal(4, 100);
        for x in [2000, 2001, 2001, 2001] {
            c.push(AdcCode(x));
        }
        assert!(c.is_full());
        let r = c.finish().expect("at rest");
        // mean 2000.75 exactly; variance (4 * 16012003 - 8003^2) / 12 = 0.25 -> rms 0.5.
        assert_eq!(r.bias_q16, 2000 * 65_536 + 49_152);
        assert_eq!(r.noise_rms_q16, 32_768);
        assert_eq!(r.samples, 4);
    }

    #[test]
    fn variance_above_bound_is_motion_not_averaged_in() {
        let mut c = cal(4, 1);
        for x in [2000, 2004, 2000, 2004] {
            c.push(AdcCode(x)); // variance 16/3 > 1
        }
        assert!(matches!(c.finish(), Err(CalibrationError::Motion { .. })));
        c.restart();
        assert_eq!(c.samples(), 0);
    }

    #[test]
    fn tick_variances_separate_white_from_correlated_noise() {
        // Ticks of 2 samples. Alternating: tick sums 4000 +- 2 in turn (g1 = -g0, g2 = g0):
        // the long-run variance g0 - 2 g0 + 2 g0 = g0. Correlated: tick sums in runs of four
        // (g1 = g0 / 2, g2 = 0 in the limit): long-run = 2 g0.
        let mut c = Calibrator::new(4000, 100 << 16, 12, (2, 1000), [0, 0, 0]);
        for i in 0..4000 {
            c.push(AdcCode(if (i / 2) % 2 == 0 { 2001 } else { 1999 }));
        }
        let r = c.finish().expect("at rest");
        // Tick sums 4000 +- 2: g0 = 4 LSB^2 (divided by k), per sample half of it.
        let g0 = 2.0;
        assert!((r.tick_var_q32 as f64 / 2f64.powi(32) - g0).abs() < 1e-6);
        let ratio = r.long_run_var_q32 as f64 / r.tick_var_q32 as f64;
        assert!((ratio - 1.0).abs() < 0.01, "{ratio}");
        let mut c = Calibrator::new(4000, 100 << 16, 12, (2, 1000), [0, 0, 0]);
        for i in 0..4000 {
            c.push(AdcCode(if (i / 8) % 2 == 0 { 2001 } else { 1999 }));
        }
        let r = c.finish().expect("at rest");
        let ratio = r.long_run_var_q32 as f64 / r.tick_var_q32 as f64;
        assert!((ratio - 2.0).abs() < 0.01, "{ratio}");
    }

    /// The centred lag sums of `codes`' tick sums per sample in f64, from their definition
    /// (see [`Calibration`]): tick sums `t`, `C_l = sum (t[i] - m)(t[i-l] - m)` for `l = 0..=3`,
    /// over `k D`; `None` with fewer than 4 ticks.
    fn lags_f64(codes: &[u16], tick: usize) -> Option<[f64; 4]> {
        let t: Vec<f64> = codes
            .chunks_exact(tick)
            .map(|c| c.iter().map(|&x| f64::from(x)).sum())
            .collect();
        if t.len() < 4 {
            return None;
        }
        let k = t.len() as f64;
        let m = t.iter().sum::<f64>() / k;
        let per = k * tick as f64;
        Some(core::array::from_fn(|l| {
            (l..t.len())
                .map(|i| (t[i] - m) * (t[i - l] - m))
                .sum::<f64>()
                / per
        }))
    }

    /// The lag-`l` covariance per sample, `C_l / (k D)` (see
    /// [`Calibration::tick_lags_q32`]); 0 with fewer than 4 ticks.
    fn tick_lag_f64(codes: &[u16], tick: usize, l: usize) -> f64 {
        lags_f64(codes, tick).map_or(0.0, |c| c[l])
    }

    /// The tick variances `g0 / D` and `(g0 + 2 g1 + 2 g2) / D` in f64; floored at 1/4
    /// LSB^2, the long-run one also at half the tick one.
    fn tick_variances_f64(codes: &[u16], tick: usize) -> (f64, f64) {
        let Some(c) = lags_f64(codes, tick) else {
            return (0.25, 0.25);
        };
        let long = c[0] + 2.0 * c[1] + 2.0 * c[2];
        (c[0].max(0.25), long.max(c[0] / 2.0).max(0.25))
    }

    /// Marsaglia's xorshift64 from `state` (nonzero): the tests' random windows.
    fn xorshift(mut state: u64) -> impl FnMut() -> u64 {
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        }
    }

    /// The von Neumann ratio of the complete blocks of `tick * ticks` samples, in f64.
    fn eta_f64(codes: &[u16], tick: usize, ticks: u32) -> f64 {
        let b: Vec<f64> = codes
            .chunks_exact(tick * ticks as usize)
            .map(|c| c.iter().map(|&x| f64::from(x)).sum())
            .collect();
        let mean = b.iter().sum::<f64>() / b.len() as f64;
        let spread: f64 = b.iter().map(|x| (x - mean).powi(2)).sum();
        let diffs: f64 = b.windows(2).map(|w| (w[1] - w[0]).powi(2)).sum();
        diffs / (2.0 * spread)
    }

    #[test]
    fn the_motion_test_is_the_von_neumann_ratio_of_its_blocks() {
        // Random windows (tick 1 to 60, 20 to 419 blocks of 4 ticks and a partial one, so 13
        // or more of 5 and of 6; white and walking codes, quiet and full range): with every
        // bound at 4 every window is refused, and the ratio it reports at each length is the
        // f64 definition's, floored to Q16.
        let mut next = xorshift(0x9E37_79B9_7F4A_7C15u64);
        for case in 0..200 {
            let tick = 1 + (next() % 60) as usize;
            let blocks = 20 + (next() % 400) as usize;
            let n = tick * (BLOCK_TICKS[0] as usize * blocks + (next() % 4) as usize);
            let spread = [3, 40, 65_000][case % 3];
            let mut level = 30_000i64;
            let codes: Vec<u16> = (0..n)
                .map(|_| {
                    let d = (next() % spread) as i64 - spread as i64 / 2;
                    level = if case % 2 == 1 {
                        level + d / 8
                    } else {
                        30_000 + d
                    };
                    level = level.clamp(1, 65_534);
                    level as u16
                })
                .collect();
            let mut c = Calibrator::new(n as u32, u64::MAX, 16, (tick as u32, 1000), [4 << 16; 3]);
            codes.iter().for_each(|&x| c.push(AdcCode(x)));
            let want = BLOCK_TICKS.map(|ticks| eta_f64(&codes, tick, ticks));
            if want[0].is_nan() {
                assert!(c.finish().is_ok(), "case {case}: a constant window is rest");
                continue;
            }
            match c.finish() {
                Err(CalibrationError::Unsteady {
                    eta_q16, min_q16, ..
                }) => {
                    assert_eq!(min_q16, [4 << 16; 3]);
                    for (got, want) in eta_q16.iter().zip(want) {
                        let got = f64::from(*got) / 65_536.0;
                        assert!(
                            got <= want + 1e-9 && want - got < 1.0 / 65_536.0 + 1e-9,
                            "case {case}: {got} against {want}"
                        );
                    }
                }
                other => panic!("case {case}: eta {want:?} under 4 not refused: {other:?}"),
            }
        }
    }

    #[test]
    fn the_motion_test_runs_from_the_fewest_blocks_that_can_fail_it() {
        // By hand: z(1e-4) = 3.719016; the bound 1 - z sqrt((k-2)/((k+1)(k-1))) against the
        // least ratio of k blocks, 1 - cos(pi / k).
        let bound = |k: f64| 1.0 - 3.719_016 * ((k - 2.0) / ((k + 1.0) * (k - 1.0))).sqrt();
        let least = |k: f64| 1.0 - (core::f64::consts::PI / k).cos();
        assert!(bound(12.0) < least(12.0) && bound(13.0) > least(13.0));
        for k in 0..STEADY_BLOCKS_MIN {
            assert_eq!(steady_min_q16(k), 0, "{k} blocks");
        }
        let min = steady_min_q16(13);
        assert!(
            (f64::from(min) / 65_536.0 - bound(13.0)).abs() < 2e-5,
            "{min}"
        );
        // A half cosine over 13 blocks of 4 one-sample ticks: the smoothest window there is,
        // refused at 13 blocks.
        let mut c = Calibrator::new(52, u64::MAX, 12, (1, 1000), [min, 0, 0]);
        for i in 0..52 {
            let j = f64::from(i / 4);
            let v = 500.0 * (1.0 - (core::f64::consts::PI * (j + 0.5) / 13.0).cos());
            c.push(AdcCode(2000 + v.round() as u16));
        }
        assert!(matches!(c.finish(), Err(CalibrationError::Unsteady { .. })));
    }

    #[test]
    fn a_ratio_at_the_bound_is_rest_and_below_it_is_motion() {
        // 40 blocks of 4 one-sample ticks, half of them one code up, in 6 runs (5 changes):
        // D = 5 * 16, spread 40 * 4: eta = 80 / 320 = 1/4 exactly.
        let runs = [8usize, 8, 8, 8, 4, 4];
        let codes: Vec<u16> = runs
            .iter()
            .enumerate()
            .flat_map(|(r, &len)| core::iter::repeat_n(2000 + (r % 2) as u16, 4 * len))
            .collect();
        let verdict = |min: u32| {
            let mut c = Calibrator::new(160, u64::MAX, 12, (1, 1000), [min, 0, 0]);
            codes.iter().for_each(|&x| c.push(AdcCode(x)));
            c.finish()
        };
        assert!(verdict(16_384).is_ok(), "eta = the bound: rest");
        match verdict(steady_min_q16(40)) {
            Err(CalibrationError::Unsteady { eta_q16, .. }) => {
                assert_eq!(
                    eta_q16,
                    [16_384, u32::MAX, u32::MAX],
                    "the others not tested"
                )
            }
            other => panic!("eta 1/4 under 0.43: {other:?}"),
        }
    }

    #[test]
    fn a_window_is_motion_only_if_every_block_length_tested_says_so() {
        // One-sample ticks: a sine of 0.245 cycles a sample beats at 0.02 cycles a 4-tick
        // block (an alias: neighbouring sums agree, eta near 0) but turns 0.225 cycles a
        // 5-tick block (eta 0.84): a vibration near the first length's rate, not a motion.
        // Each length alone refuses or takes it; together they take it. A step is refused
        // by all three.
        let n = 2000;
        let sine = |i: usize| {
            let x = 2000.0 + 100.0 * (core::f64::consts::TAU * 0.245 * i as f64).sin();
            x.round() as u16
        };
        let step = |i: usize| 2000 + 5 * u16::from(i >= n / 2);
        let blocks = BLOCK_TICKS.map(|t| steady_min_q16(n as u32 / t));
        let verdict = |f: &dyn Fn(usize) -> u16, mins: [u32; 3]| {
            let mut c = Calibrator::new(n as u32, u64::MAX, 12, (1, 1000), mins);
            (0..n).for_each(|i| c.push(AdcCode(f(i))));
            c.finish()
        };
        assert!(
            verdict(&sine, [blocks[0], 0, 0]).is_err(),
            "4-tick blocks alone"
        );
        assert!(
            verdict(&sine, [0, blocks[1], 0]).is_ok(),
            "5-tick blocks alone"
        );
        assert!(
            verdict(&sine, [0, 0, blocks[2]]).is_ok(),
            "6-tick blocks alone"
        );
        assert!(
            verdict(&sine, [blocks[0], 0, blocks[2]]).is_ok(),
            "one veto is enough"
        );
        assert!(verdict(&sine, blocks).is_ok(), "all three: two veto");
        match verdict(&step, blocks) {
            Err(CalibrationError::Unsteady {
                eta_q16, min_q16, ..
            }) => {
                assert!(
                    (0..3).all(|l| eta_q16[l] < min_q16[l]),
                    "{eta_q16:?} {min_q16:?}"
                );
            }
            other => panic!("a step: {other:?}"),
        }
        // The message names each length tested, at the tick's length, with its ratio and
        // bound.
        let mut c = Calibrator::new(n as u32, u64::MAX, 12, (1, 5000), blocks);
        (0..n).for_each(|i| c.push(AdcCode(step(i))));
        let Err(e @ CalibrationError::Unsteady { eta_q16, .. }) = c.finish() else {
            panic!("a step")
        };
        let [b0, b1, b2] = blocks.map(|b| f64::from(b) / 65_536.0);
        let [e0, e1, e2] = eta_q16.map(|e| f64::from(e) / 65_536.0);
        let want = std::format!(
            "motion during calibration: neighbouring means agree more than noise lets them \
             (von Neumann ratio {e0:.2} over 20 ms blocks, below {b0:.2}; {e1:.2} over 25 ms \
             blocks, below {b1:.2}; {e2:.2} over 30 ms blocks, below {b2:.2}; at rest about 1)"
        );
        assert_eq!(e.to_string(), want);
        let mut c = Calibrator::new(n as u32, u64::MAX, 12, (1, 5000), [blocks[0], 0, 0]);
        (0..n).for_each(|i| c.push(AdcCode(step(i))));
        let text = c.finish().expect_err("a step").to_string();
        assert!(
            text.contains("20 ms") && !text.contains("25 ms"),
            "a length not tested: {text}"
        );
    }

    #[test]
    fn a_step_is_unsteady_and_noise_or_a_constant_is_not() {
        // 40 blocks of 4 ticks of 1 sample (the bound of 40 blocks is 0.43).
        let min = steady_min_q16(40);
        assert_eq!(min, 27_963); // round((1 - 3.719016 sqrt(38 / (41 * 39))) 2^16), by hand
        let window = |f: &dyn Fn(usize) -> u16| {
            let mut c = Calibrator::new(160, u64::MAX, 12, (1, 1000), [min, 0, 0]);
            (0..160).for_each(|i| c.push(AdcCode(f(i))));
            c.finish()
        };
        // Alternating blocks: eta near 2. A constant: no spread at all.
        assert!(window(&|i| 2000 + ((i / 4) % 2) as u16).is_ok());
        assert!(window(&|_| 2000).is_ok());
        // A step of one code half-way: one jump of 4 between block sums, 40 blocks at +-2
        // from their mean: eta = 16 / (2 * 160) = 1/20.
        match window(&|i| 2000 + u16::from(i >= 80)) {
            Err(CalibrationError::Unsteady {
                eta_q16, min_q16, ..
            }) => {
                assert_eq!(min_q16, [min, 0, 0]);
                assert_eq!(eta_q16, [65_536 / 20, u32::MAX, u32::MAX]);
            }
            other => panic!("a step: {other:?}"),
        }
        // The same step with the test off (bound 0), or in a window of 7 blocks: taken.
        let mut off = Calibrator::new(160, u64::MAX, 12, (1, 1000), [0, 0, 0]);
        (0..160).for_each(|i| off.push(AdcCode(2000 + u16::from(i >= 80))));
        assert!(off.finish().is_ok());
        let mut short = Calibrator::new(28, u64::MAX, 12, (1, 1000), [min, 0, 0]);
        (0..28).for_each(|i| short.push(AdcCode(2000 + u16::from(i >= 16))));
        assert!(short.finish().is_ok(), "7 blocks are not tested");
        let mut restarted = Calibrator::new(160, u64::MAX, 12, (1, 1000), [min, 0, 0]);
        (0..160).for_each(|i| restarted.push(AdcCode(2000 + u16::from(i >= 80))));
        restarted.restart();
        (0..160).for_each(|i| restarted.push(AdcCode(2000 + ((i / 4) % 2) as u16)));
        assert!(restarted.finish().is_ok(), "a restart forgets the blocks");
    }

    #[test]
    fn tick_variances_match_their_definition() {
        // Random windows: tick sizes 1 to 500, 4 to 3000 ticks, quiet and full-range noisy
        // codes, correlated (a walk) and not; the Q32 values are the f64 definition floored,
        // to 1e-9 relative (f64's own error on these sums).
        let mut next = xorshift(0x2545_F491_4F6C_DD1Du64);
        for case in 0..300 {
            let tick = 1 + (next() % 500) as usize;
            let ticks = 4 + (next() % 3000) as usize;
            let n = (tick * ticks).min(1 << 20);
            let spread = [2, 40, 65_000][case % 3];
            let walk = case % 2 == 1;
            let mut level = 30_000i64;
            let codes: Vec<u16> = (0..n)
                .map(|_| {
                    let d = (next() % spread) as i64 - spread as i64 / 2;
                    if walk {
                        level = (level + d / 8).clamp(1, 65_534);
                        level as u16
                    } else {
                        (30_000 + d).clamp(1, 65_534) as u16
                    }
                })
                .collect();
            let mut c = Calibrator::new(n as u32, u64::MAX, 16, (tick as u32, 1000), [0, 0, 0]);
            codes.iter().for_each(|&x| c.push(AdcCode(x)));
            let (tv, lv) = c.tick_variances();
            let (want_t, want_l) = tick_variances_f64(&codes, tick);
            for (got, want) in [(tv, want_t), (lv, want_l)] {
                let got = got as f64 / 2f64.powi(32);
                let want = want.min(u64::MAX as f64 / 2f64.powi(32));
                assert!(
                    (got - want).abs() <= 1e-9 * want + 2f64.powi(-32),
                    "case {case}: tick {tick}, {ticks} ticks: {got} against {want}"
                );
            }
            // The signed lags, rounded toward zero: lag l of the f64 definition.
            let lags = c.tick_lags();
            for (l, &got) in lags.iter().enumerate() {
                let got = got as f64 / 2f64.powi(32);
                let sat = i64::MAX as f64 / 2f64.powi(32);
                let want = tick_lag_f64(&codes, tick, l + 1).clamp(-sat, sat);
                assert!(
                    (got - want).abs() <= 1e-9 * want.abs() + 2f64.powi(-32),
                    "case {case}: lag {}: {got} against {want}",
                    l + 1
                );
            }
        }
    }

    #[test]
    fn the_long_run_variance_is_at_least_half_the_tick_variance() {
        // Ticks in a period of three, deviations +10, +10, -20: g0 = 200, g1 = g2 = -100, so
        // g0 + 2 g1 + 2 g2 = -200: the anticorrelation would claim less than no noise at all.
        // The long-run variance is held at g0 / 2.
        let mut c = Calibrator::new(3000, u64::MAX, 12, (1, 1000), [0, 0, 0]);
        for i in 0..3000 {
            c.push(AdcCode([2010, 2010, 1980][i % 3]));
        }
        let (tick, long) = c.tick_variances();
        assert_eq!(tick, 200 << 32);
        assert_eq!(long, 100 << 32);
    }

    #[test]
    fn four_ticks_are_enough_and_three_are_not() {
        // Ticks of one sample: with 4 the variances are measured (here far above the floor),
        // with 3 both are the floor of 1/4 LSB^2.
        let mut c = Calibrator::new(4, u64::MAX, 12, (1, 1000), [0, 0, 0]);
        for x in [1000, 3000, 1000, 3000] {
            c.push(AdcCode(x));
        }
        let (t, _) = c.tick_variances();
        assert_eq!(t, 1_000_000 << 32, "g0 = 4 ticks of 1000^2 / 4");
        // Deviations -1000, 1000, -1000, 1000: C_1 = -3e6, C_2 = 2e6, C_3 = -1e6, over k D = 4.
        assert_eq!(
            c.tick_lags(),
            [-750_000 << 32, 500_000 << 32, -250_000 << 32]
        );
        let mut c = Calibrator::new(3, u64::MAX, 12, (1, 1000), [0, 0, 0]);
        for x in [1000, 3000, 1000] {
            c.push(AdcCode(x));
        }
        assert_eq!(c.tick_variances(), (1 << 30, 1 << 30));
        assert_eq!(c.tick_lags(), [0; 3]);
    }

    #[test]
    fn noise_exactly_at_the_bound_is_rest() {
        // 16 samples, one of them 1 LSB up: scatter n sum d^2 - (sum d)^2 = 15, dof 240,
        // variance 1/16 LSB^2 = 4096 in Q16. At a bound of exactly that it is rest; one
        // below, motion.
        let codes = core::iter::once(2001).chain([2000; 15]);
        let mut at = Calibrator::new(16, 4096, 12, (4, 1000), [0, 0, 0]);
        let mut below = Calibrator::new(16, 4095, 12, (4, 1000), [0, 0, 0]);
        for x in codes {
            at.push(AdcCode(x));
            below.push(AdcCode(x));
        }
        assert!(at.finish().is_ok());
        assert!(matches!(
            below.finish(),
            Err(CalibrationError::Motion { .. })
        ));
        assert_eq!(at.samples(), 16);
    }

    #[test]
    fn errors_say_what_went_wrong() {
        let clipped = CalibrationError::Clipped { code: 4095 }.to_string();
        assert!(
            clipped.contains("4095") && clipped.contains("rail"),
            "{clipped}"
        );
        let motion = CalibrationError::Motion {
            noise_rms_q16: 3 << 16,
        }
        .to_string();
        assert!(
            motion.contains("too noisy")
                && motion.contains("3.000 LSB")
                && motion.contains("rest_noise_max_m_s2"),
            "{motion}"
        );
    }

    #[test]
    fn rails_are_clipping() {
        let mut c = cal(3, 100);
        for x in [2000, 4095, 2000] {
            c.push(AdcCode(x));
        }
        assert_eq!(c.finish(), Err(CalibrationError::Clipped { code: 4095 }));
        let mut c = cal(3, 100);
        c.push(AdcCode(0));
        assert_eq!(c.finish(), Err(CalibrationError::Clipped { code: 0 }));
    }

    #[test]
    fn full_window_ignores_further_samples() {
        let mut c = cal(2, 100);
        for x in [10, 10, 3000] {
            c.push(AdcCode(x));
        }
        assert_eq!(c.finish().map(|r| r.bias_q16), Ok(10 << 16));
    }
}
