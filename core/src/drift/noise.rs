//! Noise learning: what the sensor's noise is (calibrated, then learnt at rest), and what
//! the desk adds as it happens (a knock's ring, a machine's vibration).
//!
//! # The noise model (REFERENCE (i))
//! Per axis, from the calibration ([`Calibration`]): `q`, the long-run variance per sample (a
//! sum of `n >> D` samples at rest has variance `q n`), and the tick sums' variance and lag
//! covariances `g0 .. g3` (per sample). The calibration's `q` comes from one second and is
//! uncertain by `sqrt(8 / k)` relative (`k` ticks, about `k / 4` independent at the ADXL335's
//! correlation: 20 % for 1 s): the detector starts from its upper 2-sd bound and learns `q`
//! at rest, the squared offset of each block of [`LEARN_TICKS`] rest ticks (80 ms at 5 ms
//! ticks: a 50 Hz pole's correlation is gone, so a block sum's variance is `q` times its
//! length within 4 %) averaged over [`LEARN_BLOCKS`] blocks (about 10 s of rest; relative sd
//! of the estimate `sqrt(2 / 256)`, 9 %). Each test's sd comes from `q`: the sd of one
//! tick's sum is `sqrt(q D)`, of `n` samples `sqrt(q n)` (long-run: conservative for a
//! single tick, whose variance `g0 D` is smaller). The start tests' sd is that one times the
//! quantizer's bound ([`quantizer_bound_q16`]), from the calibration's codes: more than 1
//! only when the noise is below about 0.8 LSB, where an excursion of the codes has a heavier
//! tail than the fluctuations `q` is learnt from.
//!
//! `q` is the sensor's: a block with a tick that closed while the axis's desk was disturbed
//! (the disturbance below measured, or a burst) is not learnt from on that axis. The tests
//! allow for the disturbance themselves; learnt into `q` as well, a machine running on the
//! desk was counted twice, and grew the learnt sd 2.2-fold within 3 s of its start (47.6 mg
//! at 30 Hz, 303 ug/sqrt(Hz)): strokes of 20 mm over 1.5 s never started. Which blocks are
//! left out depends on the residual above `knock_hz`, nearly independent of a block's sum
//! (its content below it) on noise alone: the sample left is not biased.
//!
//! A block's squared offset is learnt as at most [`LEARN_CLIP`] `= 16` times `q` (4 sd of its
//! sum). On noise it is `q` times a chi-square of one degree of freedom, past 16 in 6.3e-5 of
//! blocks: the clip lowers the average by 1.2e-4 of `q` (`E min(Z^2, 16) = 0.99988`), nothing a
//! test sees. What it bounds is a block of a lobe the start tests have not claimed yet: the
//! noise is learnt from ticks [`super::REPLAY`] old, and a slow stroke's first lobe reaches
//! them before its second lobe's end finds the stroke (the two-lobe sum, [`super::rest`]). Each
//! such block raised `q` by its whole squared offset over [`LEARN_BLOCKS`] (a block 10 LSB a
//! sample off the ADXL335's zero: 43-fold), and the second lobe, standardised by the inflated
//! sd, fell short: 7 mm over 0.6 s, 0.4 s after the calibration at 740 ug/sqrt(Hz), never moved
//! (the learnt sd rose 7.7 % in one block, 5.7 % clipped). Clipped, a block raises `q` by at
//! most 15/128 (12 %), and a real rise of the sensor's noise is still learnt, doubling `q`
//! within 6 blocks (0.5 s of rest at 5 ms ticks). The lab's families and sweeps (seeds 1-8,
//! against no clip) move with it: 25 gains 8 trials within and loses 1, 16 gains 22 and loses 2
//! (both on a 10-bit ADC), 9 gains 66 and loses 12, 5 of them strokes after a tilt (not
//! traced). 4 sd is kept: the clip costs noise nothing there (at 3 sd 0.5 % of `q`), and no
//! kept row loses.
//!
//! # The disturbance
//! What is not the sensor's noise and not a hand: a knock's ring, a machine's vibration,
//! above `knock_hz` (REFERENCE (j)). It is measured, per axis and as it happens, by the
//! hand-band filter's residual `rho = L1 L2 s[t - delay] - F2[t]` (the tick sum at the
//! filter's centre against the filter: the hand's band removed, [`super::ticks`]): an
//! exponential average `P` of `rho^2` over `2^k` ticks (160 ms), against its noise-only
//! expectation `E = sum_ij c_i c_j C_|i-j|` (the residual's taps `c` over the calibration's
//! tick covariances `C_l = D g_l`, zero beyond lag 3). `P` is itself noisy: with about `2^k /
//! 2` independent terms its relative sd is `sqrt(2 / 2^k)`, so only `P` above `E` by 3 of
//! those counts. A sinusoid of tick-sum amplitude `A` adds `A^2 / 2` to `P` (times `L1 L2`
//! squared, the residual passing it whole above `knock_hz`): the disturbance's amplitude is
//! `A = sqrt(2 (P - E)) / (L1 L2)`. Each test then allows what a sinusoid of amplitude `A` at
//! or above `knock_hz` can do through its own window (the gains computed at validation): a
//! machine's vibration raises the thresholds by what it can fake, and no more.
//!
//! A knock rings and decays within a few of its periods, while `P` remembers it for several
//! of its own time constants; a machine that starts up is felt by `P` only after a fraction
//! of them. So a short average (40 ms, a quarter of the long one) bounds `A` both ways: its
//! upper bound (`P_short` raised by its own margin, 3 relative sd of an average of
//! `2^(k-2) / 2` squares, less `E`) caps it, and its lower bound (`P_short` lowered by that
//! margin) raises it. A weak, steady vibration stays between the two (the long average
//! measures it, the short one can neither confirm nor rule it out); a decaying ring leaves
//! the upper bound within tens of milliseconds. And a tick whose residual alone stands out of
//! the noise by the same margin's number of sd (3; a **burst**: a knock's first ring, a machine starting up
//! faster than any average follows) sets `A` at least to that residual's size for that tick.
//!
//! # The hand's own residual
//! A hand's motion leaks into the residual too, most where its acceleration has a kink: a
//! minimum-jerk stroke starts and ends with a jerk step, and a zigzag's legs meet at rest
//! with two lobes of one sign either side of a zero. Counted as the desk's, that leak
//! widened the quiet and velocity tests by the hand's own acceleration: a new user's zigzag
//! stopped at a turn while its next leg was under way at 1 m/s^2, and that leg started late,
//! from zero velocity (six legs at 300 ug/sqrt(Hz): 49 to 128 mm off in 12 of 12 draws). Where
//! the acceleration is convex over the filter's span (a kink from rest, a turn) the
//! trapezoid's non-negative taps give an output at least the centre's value (Jensen's
//! inequality), so the residual is no larger than the band output `F` (equal just before a
//! kink); a 10 Hz sinusoid leaks 0.92 of it. So while a motion is under way, a tick whose
//! residual is within `F` (plus a burst's margin for the noise) is the hand's and is not
//! taken into the averages, nor as a burst, when the hand dominates: `F` stands out of its
//! own noise by the burst margin (`hand_r`), and `F^2` exceeds the residual's long average
//! `P`. Without the second, a slow stroke on a vibrating desk (its `F` a tenth of the
//! vibration's residual) left out the ticks where the vibration crossed zero and kept its
//! crests, and the measured amplitude rose until the stroke never stopped; and a tick
//! counted before the hand's output caught up (a stroke's first residual against a tilt's
//! stale offset) would be held for the whole motion. With it, an amplitude above the hand's
//! is measured again and forgotten. `F` is the most the band output differs from its value
//! at the motion's zero and from its values at the block ends over the filter's span (a
//! tilt's offset, which the zero does not hold, cancels in the second; with the first alone
//! a six-leg zigzag's draws 4, 6 and 9 of 16 still missed), on the horizontal axes.
//!
//! # Its frequency
//! What a sinusoid can fake depends on its frequency (a velocity amplitude of `A / (2 pi f)`
//! per sample rate, a boxcar's gain falling as `1 / f`): sizing every allowance at `knock_hz`
//! would make a machine at 85 Hz as blinding as a desk ringing at 20 Hz. The residual's first
//! difference `rho[t] - rho[t-1]` has, for a sinusoid at `f` (seen at the tick rate `f_t`),
//! `4 sin^2(pi f / f_t)` times its power: the ratio of the two excess powers (each above its
//! noise expectation, the difference's discounted by its margin, so that noise makes the
//! frequency look lower, never higher) places the disturbance in one of [`BINS`] bins,
//! log-spaced from `knock_hz` to `f_t / 2`. Each bin's gains ([`Gains`]) are the largest at
//! or above its lower edge (every alias above it included), computed at validation.

use crate::calibration::Calibration;

use super::ticks::TickStream;
use super::DriftSettings;

/// Ticks per block of the noise learnt at rest.
pub const LEARN_TICKS: u32 = 16;
/// Blocks in the learnt noise's exponential average.
pub const LEARN_BLOCKS: u64 = 128;
/// A block's squared offset is learnt as at most this many times `q` (`4^2`: 4 sd of the
/// block's sum; see the module docs).
pub const LEARN_CLIP: u64 = 16;
/// The floor of a learnt variance [LSB^2 per sample, Q32]: a quarter LSB^2 (a noise-free
/// sensor still flickers between two codes).
const VAR_FLOOR: u64 = 1 << 30;

/// Frequency bins of the disturbance.
pub const BINS: usize = 6;

/// What a sinusoid of tick-sum amplitude `A` at or above a bin's lower edge can do through
/// each test, per unit of `A` (Q16 unless stated).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Gains {
    /// Through the hand-band filter, summed over any run of consecutive ticks: `G_band(f) /
    /// |sin(pi f / f_t)|` ([`super::rest`]).
    pub(crate) band_run_q16: u64,
    /// Through the quiet test's window, per tick.
    pub(crate) quiet_q16: u64,
    /// Through the tilt test's sub-windows, per tick.
    pub(crate) sub_q16: [u64; 2],
    /// Through a third of the landing window, per tick.
    pub(crate) land_q16: u64,
    /// Its velocity amplitude [Q16 LSB samples per Q16 LSB samples of `A`].
    pub(crate) velocity_q16: u64,
    /// Its displacement amplitude in the lift test's units (`2 d`, peak to peak), Q0.
    pub(crate) displacement: u64,
}

/// Per-axis noise in the detector's integer units.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Noise {
    /// Long-run variance per sample `q` [LSB^2, Q32].
    pub(crate) q_q32: u64,
    /// The start tests' sd of one tick's sum, `r sqrt(q D)` [Q16 LSB samples], `r` the
    /// quantizer's bound ([`quantizer_bound_q16`]).
    pub(crate) sd_q16: i64,
    /// The quantizer's bound `r` [Q16, `>= 65536`], fixed at calibration.
    pub(crate) quant_q16: u32,
}

impl Noise {
    /// The noise with long-run variance `q_q32` at tick length `D` and quantizer bound
    /// `quant_q16`.
    pub(crate) fn new(s: &DriftSettings, q_q32: u64, quant_q16: u32) -> Self {
        // sqrt(q D) in Q16: the square root of a Q32 value; times r in Q16.
        let sd = crate::math::isqrt_u128(u128::from(q_q32) * u128::from(s.tick));
        let sd = ((sd * u128::from(quant_q16)) >> 16).min(i64::MAX as u128) as i64;
        Self {
            q_q32,
            sd_q16: sd,
            quant_q16,
        }
    }

    /// From a calibration: its `q` at the upper 2-sd bound of its own uncertainty. `starts`:
    /// whether the axis feeds the start tests (X and Y); only those carry the quantizer's
    /// bound, which costs about 111 000 instructions on a quiet sensor (Z's would be unused).
    pub(crate) fn from_calibration(s: &DriftSettings, cal: &Calibration, starts: bool) -> Self {
        let ticks = u64::from(cal.samples / s.tick).max(1);
        let q = u128::from(cal.long_run_var_q32);
        // 1 + z sqrt(8 / k), Q8 (z = 2: the tuning's q_inflation_sd).
        let z = u128::from(s.inflation_q8);
        let inflate_q8 = 256 + ((z * crate::math::isqrt_u128(8 * 65_536 / u128::from(ticks))) >> 8);
        let q = ((q * inflate_q8) >> 8).min(u128::from(u64::MAX)) as u64;
        let r = if starts {
            quantizer_bound_q16(cal.noise_rms_q16, cal.bias_q16)
        } else {
            1 << 16
        };
        Self::new(s, q, r)
    }

    /// The variance of a sum of `n` samples whose zero was averaged over `nb` samples:
    /// `q (n + n^2 / nb)` [Q32 LSB^2 samples^2 ... in the units of a squared Q16 sum].
    pub(crate) fn var(&self, n: u64, nb: u64) -> u128 {
        u128::from(self.q_q32)
            .saturating_mul(u128::from(n) + crate::math::square_over(n, nb.max(1)))
    }
}

/// Per-sample input noise [LSB] below which [`quantizer_bound_q16`] takes this value: the
/// codes then sit on one value for 95 % of samples at a code's centre, and two terms of
/// the gain's Fourier series no longer give the bound to 10^-4 (1 % at 0.2 LSB).
const QUANT_SIGMA_MIN: f32 = 0.25;
/// The codes' rms [Q16 LSB] from which the quantizer's bound is exactly 1 in Q16 (1 LSB): the
/// input's noise is then at least 0.95 LSB, where `e_1 < 2^-18`.
const QUANT_RMS_EXACT_Q16: u64 = 1 << 16;

/// The rounded codes' mean and variance [LSB, LSB^2] for input noise of sd `sigma` [LSB] at
/// `u` [LSB] from a code's centre: `p_j = Phi((j + 1/2 - u) / sigma) - Phi((j - 1/2 - u) /
/// sigma)`, `sum_j j p_j` and `sum_j j^2 p_j - (sum_j j p_j)^2`, over the codes within 6
/// sd.
fn rounded_moments(sigma: f32, u: f32) -> (f32, f32) {
    let cdf = |x: f32| 0.5 * libm::erfcf(-x / (sigma * core::f32::consts::SQRT_2));
    let reach = libm::ceilf(6.0 * sigma) as i16 + 1;
    let (mut m1, mut m2) = (0.0, 0.0);
    let mut below = cdf(-f32::from(reach) - 0.5 - u);
    for j in -reach..=reach {
        let j = f32::from(j);
        let above = cdf(j + 0.5 - u);
        let p = above - below;
        below = above;
        m1 += j * p;
        m2 += j * j * p;
    }
    (m1, m2 - m1 * m1)
}

/// The quantizer's bound `r` [Q16, `>= 65536`]: how much further than a Gaussian of the
/// learnt sd the mean code can run, for codes at rest whose sd about their mean is `rms_q16`
/// [Q16 LSB] and whose mean is the code `bias_q16` [Q16 LSB; only its place between two
/// codes is used] (a calibration's `noise_rms_q16` and `bias_q16`).
///
/// An ADC rounds the input `x + n` (per-sample noise `n` of sd `sigma` LSB) to a code; the
/// mean code moves with the input's slow part `x` by the gain
/// `g(u) = sum_j phi_sigma(j + 1/2 - u) = 1 + 2 sum_k (-1)^k e_k cos(2 pi k u)`, `e_k = exp(-2 pi^2 k^2 sigma^2)` (Poisson's
/// sum), `u` the zero's place from a code's centre: `g_min = 1 - 2 e_1 + 2 e_2 - ...` at a
/// centre, `g_max = 1 + 2 e_1 + 2 e_2 + ...` at a boundary (0.85 and 1.16 at `sigma = 0.36`;
/// 1 within 10^-10 at the ADXL335's 1.1 LSB). The noise the tests learn at rest is the small
/// fluctuations', `g(u)` times the input's; an excursion of the input moves the mean code by
/// the integral of `g` over it, at most `g_max` times the excursion. A start test's alarm is
/// an excursion of a few tenths of an LSB over hundreds of milliseconds, where that matters,
/// and its false-alarm rate is exponential in the alarm's sd multiple (a sd 1.12 times the
/// learnt one makes the slow CUSUM's alarms 150 times as frequent). So each start test's sd
/// is the learnt one times `r = g_max / g_min`, the zero at a code's centre (the zero walks:
/// any place may be the one it learnt at): 1.37 at an input noise `sigma = 0.36` LSB, 2.0
/// at 0.3, 2.8 at 0.27, 1.03 at 0.5, 1 in Q16 from 0.82 up (codes' sd from about 0.87 LSB).
/// (The tightest bound, the largest secant over the local gain, is 1.23 at 0.36; it has no
/// closed form.)
///
/// `sigma` and `u` come from the codes' rms and mean, solved from [`rounded_moments`]: the
/// variance increases with `sigma` (a bisection of 20 steps at each `u` tried) and the mean
/// with `u` (the secant method, to 10^-5 LSB or 8 steps: near a code boundary, where `sigma`'s
/// ill-conditioning leaves the error jagged at f32's resolution, it may stop at about
/// 10^-4 LSB, which moves `r` by up to 0.1 %). In `f32`, which the
/// Cortex-M4F computes in hardware (the error function is libm's, in software): 111 000
/// instructions an axis in QEMU (the speed harness's `once quantizer_bound` line; 154 000
/// in f64), about 1.2 ms at 96 MHz, once a calibration and only for codes below 1 LSB rms.
/// The sampling goes on meanwhile; a block it cannot take in time is lost and held
/// ([`crate::Tracker::lost`]): a few milliseconds of rest. Skipped from a codes' sd of
/// [`QUANT_RMS_EXACT_Q16`] up, where it is exactly 1; below [`QUANT_SIGMA_MIN`], `sigma` takes
/// that value (`r` = 3.70, also for codes that never leave one value).
///
/// Where the zero sits near a boundary between two codes the codes' sd hardly depends on
/// `sigma` (two codes half the time each: 0.5 LSB for any `sigma` below 0.3), so the
/// inversion is ill-conditioned there: a calibration's sd, uncertain by several percent
/// from one second, moves `r` from 1.21 to 2.56 for `sigma = 0.36` at 1 % to 2 % either
/// way (at a centre by under 3 %). Too high only costs sensitivity; too low lets the heavier
/// tail back in (not mended: the long rest's 40 quiet devices, at every place, had no false
/// start).
pub fn quantizer_bound_q16(rms_q16: u64, bias_q16: i64) -> u32 {
    const ONE: u32 = 1 << 16;
    if rms_q16 >= QUANT_RMS_EXACT_Q16 {
        return ONE;
    }
    let rms = rms_q16 as f32 / 65_536.0;
    // The mean's distance from the nearest code, in whole Q16 arithmetic, then in LSB: the
    // moments are symmetric about a code's centre (the mean's sign follows `u`'s, the
    // variance does not see it), so `u` is solved on `0 ..= 0.5`.
    let frac = ((bias_q16.wrapping_add(1 << 15)).rem_euclid(1 << 16) - (1 << 15)).unsigned_abs()
        as f32
        / 65_536.0;
    // The input's sd at zero place `u`: the codes' variance increases with it (bisection;
    // at the floor when even that gives more than the codes' variance).
    let sigma_at = |u: f32| {
        let (mut lo, mut hi) = (QUANT_SIGMA_MIN, rms + 0.5);
        for _ in 0..20 {
            let mid = 0.5 * (lo + hi);
            if rounded_moments(mid, u).1 < rms * rms {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    };
    // The zero's place: the mean code's error at `u` (with the sd that place implies) to
    // zero by the secant method, from the mean's own place (within 0.03 LSB of it).
    let error = |u: f32| rounded_moments(sigma_at(u), u).0 - frac;
    let (mut u0, mut e0) = (frac, error(frac));
    // The second point: the first corrected by its error at unit slope (the mean code moves
    // with the zero at a gain near 1).
    let guess = frac - e0;
    let mut u = guess.clamp(0.0, 0.5);
    let mut e = error(u);
    for _ in 0..8 {
        if libm::fabsf(e) < 1e-5 || e == e0 {
            break;
        }
        let next = (u - e * (u - u0) / (e - e0)).clamp(0.0, 0.5);
        (u0, e0) = (u, e);
        u = next;
        e = error(u);
    }
    let sigma = sigma_at(u);
    let w = 2.0 * core::f32::consts::PI * core::f32::consts::PI * sigma * sigma;
    // Two terms of the series: from the floor up, the rest (`2 e_3 + ...`, 3.0e-5 at sigma =
    // 0.25) moves `r` by under 10^-4 of itself.
    let e = [1.0, 4.0].map(|k2| 2.0 * libm::expf(-w * k2));
    let g_max = 1.0 + e[0] + e[1];
    let g_min = 1.0 - e[0] + e[1];
    let r = crate::math::round_to_u64(f64::from(g_max / g_min) * 65_536.0);
    r.clamp(u64::from(ONE), u64::from(u32::MAX)) as u32
}

/// Whether `|d| <= k sqrt(var) + allow`, with `k^2` in Q8 (`var` and `d^2` in the same
/// units: Q32 squares of Q16 sums).
pub(crate) fn within(d: i64, var: u128, k2_q8: u64, allow: u64) -> bool {
    let d = d.unsigned_abs();
    if d <= allow {
        return true;
    }
    let e = u128::from(d - allow);
    e * e <= var.saturating_mul(u128::from(k2_q8)) >> 8
}

/// The noise learnt at rest: per axis the sum of the current block's ticks, and whether the
/// desk was disturbed as one of them closed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Learn {
    sum: [u64; 3],
    ticks: u32,
    tainted: [bool; 3],
}

impl Learn {
    /// A new block from the next tick.
    pub(crate) fn restart(&mut self) {
        *self = Self::default();
    }

    /// Adds a rest tick's code sums, and whether each axis's desk was disturbed as it closed;
    /// every [`LEARN_TICKS`] ticks the block's squared offset per sample is averaged into each
    /// axis's `q`, unless a tick of it was disturbed on that axis (see the module docs).
    pub(crate) fn push(
        &mut self,
        s: &DriftSettings,
        noise: &mut [Noise; 3],
        codes: [u32; 3],
        bias: [i64; 3],
        shaken: [bool; 3],
    ) {
        for (a, &c) in codes.iter().enumerate() {
            self.sum[a] += u64::from(c);
            self.tainted[a] |= shaken[a];
        }
        self.ticks += 1;
        if self.ticks < LEARN_TICKS {
            return;
        }
        let n = i128::from(LEARN_TICKS) * i128::from(s.tick);
        for (a, &b) in bias.iter().enumerate() {
            if self.tainted[a] {
                continue;
            }
            // Offset in Q16 LSB samples; its square over n is a variance per sample in Q32.
            let e = (i128::from(self.sum[a]) << 16) - n * i128::from(b); // < 2^59
            let var = crate::math::square_over(e.unsigned_abs() as u64, n as u64)
                .min(u128::from(u64::MAX));
            let q = u128::from(noise[a].q_q32);
            let var = var.min(q * u128::from(LEARN_CLIP));
            let m = u128::from(LEARN_BLOCKS);
            let q = ((q * (m - 1) + var) / m).max(u128::from(VAR_FLOOR)) as u64;
            noise[a] = Noise::new(s, q, noise[a].quant_q16);
        }
        self.restart();
    }
}

/// The disturbance on one axis, measured as it happens; see the module docs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Disturbance {
    /// Exponential averages of the squared residual and of its squared first difference
    /// over `2^k` ticks, and of the squared residual over `2^(k-2)` [LSB^2 (L1 L2)^2]; each
    /// square of a residual (or difference) saturated at `2^32 - 1`, so below `2^64` (a
    /// residual reaches `2^32` only past full scale: `L1 L2 D 2^16` is `2^26` at 3 kHz).
    power: [u64; 3],
    /// Their noise-only expectations [LSB^2 (L1 L2)^2, Q32].
    expect_q32: [u128; 2],
    /// The expectations times the long average's margin, `E m` (the same units): fixed by the
    /// calibration, so computed once, not per tick.
    margin_q32: [u128; 2],
    /// The residual a burst exceeds, `floor(sqrt(floor(E k^2 / 2^32)))` [LSB (L1 L2)]: `r^2 >
    /// N` exactly when `|r| > floor(sqrt(N))`, so a tick compares, not squares, in 128 bits.
    burst_r: u64,
    /// The band output a hand's stands out of the noise by, `floor(sqrt(floor(E_F k^2 /
    /// 2^32)))` [LSB (L1 L2)], `E_F` the output's noise-only variance (Q32).
    hand_r: u64,
    /// The powers at or below which the excess is zero, so that a tick at rest decides it
    /// in 64 bits: `[long, upper, lower]` (see [`Quiet`]).
    quiet: Quiet,
    /// The last residual.
    last: i64,
    /// The amplitude `A` of a sinusoid that would explain the excess [Q16 LSB samples, per
    /// tick sum]; 0 while `P` is within its own noise of `E`.
    pub(crate) amp_q16: u64,
    /// Its frequency bin, `0..BINS`.
    pub(crate) bin: u8,
    /// Whether the last tick's residual alone stood out of the noise (the margin's number of
    /// its sd): a disturbance the averages have not caught up with yet.
    pub(crate) burst: bool,
    /// Which of the last 64 ticks closed with this axis disturbed (`A > 0` or a burst): bit
    /// `k` for the tick that closed `k` ticks before the last ([`Learn`]).
    pub(crate) shaken: u64,
}

/// The averages' levels at or below which the excess is zero [LSB^2 (L1 L2)^2]; each is the
/// 128-bit test of [`Disturbance::update`] solved for the 64-bit power once, at calibration
/// (`x 2^j c <= N` exactly when `x <= floor(floor(N / 2^j) / c)` for whole `x`), and
/// saturated at `u64::MAX`, which every power is at or below.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Quiet {
    /// The long average is within its margin: `P 2^32 <= E m`.
    long: u64,
    /// The short average's upper bound is at or below `E`: `P_short (1 + m) <= E`.
    upper: u64,
    /// The short average's lower bound is at or below `E`: `P_short (1 - m) <= E`.
    lower: u64,
}

impl Quiet {
    /// The levels for expectation `e0` and long margin `margin0` (Q32) and the short
    /// average's margin `1 + m` in Q8 (`short_q8 >= 256`).
    fn new(e0: u128, margin0: u128, short_q8: u64) -> Self {
        let m = u128::from(short_q8 - 256);
        let sat = |x: u128| x.min(u128::from(u64::MAX)) as u64;
        // P_short c 2^24 <= e0, c the margin factor in Q8 (P_short 2^32 c / 2^8).
        let level = |c: u128| match c {
            0 => u64::MAX,
            c => sat((e0 >> 24) / c),
        };
        Self {
            long: sat(margin0 >> 32),
            upper: level(256 + m),
            lower: level(256u128.saturating_sub(m)),
        }
    }
}

/// `Var(sum_i c_i s[t-i])` for tick sums with covariances `cov(lag)` (zero beyond lag 3).
fn var_of_taps(c: &[i128], cov: impl Fn(usize) -> i128) -> i128 {
    let n = c.len();
    let mut e = 0i128;
    for i in 0..n {
        for j in i.saturating_sub(3)..(i + 4).min(n) {
            e += c[i] * c[j] * cov(i.abs_diff(j));
        }
    }
    e
}

impl Disturbance {
    /// The noise-only disturbance of a calibration: `P = E`.
    pub(crate) fn new(s: &DriftSettings, cal: &Calibration) -> Self {
        let [l1, l2] = s.band.map(|l| l as usize);
        let l = (l1 * l2) as i128;
        // The band output's taps (the trapezoid's); the residual's: minus those, plus L1 L2
        // at the centre; its first difference's, one longer.
        let taps = l1 + l2 - 1;
        let mut w = [0i128; super::RING];
        for i in 0..l1 {
            for j in 0..l2 {
                w[i + j] += 1;
            }
        }
        let mut c = w.map(|w| -w);
        c[s.band_delay as usize] += l;
        let mut dc = [0i128; super::RING];
        for k in 0..=taps {
            dc[k] = c[k] - if k > 0 { c[k - 1] } else { 0 };
        }
        let d = i128::from(s.tick);
        let cov = |lag: usize| -> i128 {
            match lag {
                0 => i128::from(cal.tick_var_q32) * d,
                1..=3 => i128::from(cal.tick_lags_q32[lag - 1]) * d,
                _ => 0,
            }
        };
        let expect_q32 = [
            var_of_taps(&c[..taps], cov).max(0) as u128,
            var_of_taps(&dc[..=taps], cov).max(0) as u128,
        ];
        let margin = |e: u128| e.saturating_mul(u128::from(s.dist_margin_q8)) >> 8;
        // The value a tick's output of noise-only variance `e` (Q32) exceeds by the burst's
        // margin, floored: `|x| > floor(sqrt(floor(e k^2 / 2^32)))` exactly when `x^2 2^32 >
        // e k^2`.
        let beyond = |e: u128| {
            crate::math::isqrt_u128((e.saturating_mul(u128::from(s.burst_k2_q8)) >> 8) >> 32) as u64
        };
        Self {
            power: [0, 1, 0].map(|i| (expect_q32[i] >> 32).min(u128::from(u64::MAX)) as u64),
            expect_q32,
            margin_q32: expect_q32.map(margin),
            burst_r: beyond(expect_q32[0]),
            hand_r: beyond(var_of_taps(&w[..taps], cov).max(0) as u128),
            quiet: Quiet::new(expect_q32[0], margin(expect_q32[0]), s.dist_margin_short_q8),
            last: 0,
            amp_q16: 0,
            bin: 0,
            burst: false,
            shaken: 0,
        }
    }

    /// The allowance of `gain` (Q16, per tick) over `ticks` ticks [Q16 LSB samples].
    pub(crate) fn allow(&self, gain_q16: u64, ticks: u64) -> u64 {
        // At rest on a quiet desk there is no disturbance: nothing to multiply (three
        // 128-bit products a call on the Cortex-M4, several calls a tick).
        if self.amp_q16 == 0 {
            return 0;
        }
        ((u128::from(gain_q16) * u128::from(self.amp_q16) * u128::from(ticks)) >> 16)
            .min(u128::from(u64::MAX)) as u64
    }

    /// Whether the desk is disturbed on this axis now: an amplitude measured, or a burst.
    pub(crate) const fn disturbed(&self) -> bool {
        self.amp_q16 > 0 || self.burst
    }

    /// This disturbance with another amplitude (at its frequency).
    pub(crate) fn with_amplitude(&self, amp_q16: u64) -> Self {
        Self { amp_q16, ..*self }
    }

    /// The amplitude a new disturbance may already have [Q16 LSB per tick sum]: until the
    /// desk has been disturbed for the long average's whole span (`2^k` ticks, the last 64
    /// at most), the long average has not caught up with it and the measured amplitude is
    /// only a lower bound (a machine starting up), so this is the short average's upper
    /// bound, `sqrt(2 (P_short (1 + m) - E)) / (L1 L2)` (see the module docs); after that,
    /// the measured amplitude.
    pub(crate) fn new_amplitude(&self, s: &DriftSettings) -> u64 {
        let span = 1u32.checked_shl(s.dist_shift).unwrap_or(64).min(64);
        let mask = u64::MAX >> (64 - span);
        if self.shaken & mask == mask {
            return self.amp_q16;
        }
        let m = u128::from(s.dist_margin_short_q8 - 256);
        let upper = self.short_q32(256 + m).saturating_sub(self.expect_q32[0]);
        Self::amplitude_q16(s, upper).max(self.amp_q16)
    }

    /// The short average times `c_q8` (Q8) [Q32]: `(P 2^32 c) >> 8` as `P c 2^24`, exact,
    /// and below 2^104 (`P < 2^64`, `c < 2^16`).
    fn short_q32(&self, c_q8: u128) -> u128 {
        (u128::from(self.power[2]) * c_q8) << 24
    }

    /// The amplitude of a sinusoid whose excess power is `excess` (Q32, below 2^104 as the
    /// short average's bound is): `sqrt(2 excess) / (L1 L2)` [Q16 LSB per tick sum]. The
    /// root of `2 excess < 2^105` is below 2^64: a 64-bit division.
    fn amplitude_q16(s: &DriftSettings, excess: u128) -> u64 {
        crate::math::isqrt_u128(2 * excess) as u64 / u64::from(s.band[0] * s.band[1])
    }

    /// This disturbance's gains.
    pub(crate) fn gains<'a>(&self, s: &'a DriftSettings) -> &'a Gains {
        &s.gains[usize::from(self.bin)]
    }

    /// Takes the tick just closed on `axis`; `hand`, while a motion is under way, the band
    /// output at the residual's centre ([`TickStream::hand_band`]): a residual the hand's
    /// own can explain is not the desk's (see the module docs).
    pub(crate) fn update(
        &mut self,
        s: &DriftSettings,
        stream: &TickStream,
        axis: usize,
        hand: u64,
    ) {
        let r = stream.band_residual(s, axis);
        let diff = r - core::mem::replace(&mut self.last, r);
        let hand = hand > self.hand_r
            && (hand >= 1 << 32 || hand * hand > self.power[0])
            && r.unsigned_abs() <= hand + self.burst_r;

        // r^2 2^32 > E k^2 as r^2 > floor(E k^2 / 2^32), as |r| > its floored root: the same
        // test, its bound fixed.
        self.burst = !hand && r.unsigned_abs() > self.burst_r;
        let l = u64::from(s.band[0] * s.band[1]);
        // A burst's own amplitude, until the averages catch up (Q16 LSB per tick sum).
        let burst_q16 = if self.burst {
            // |r| < 2^33 (L1 L2 D 2^16), shifted below 2^49: a 64-bit division.
            (r.unsigned_abs().min(1 << 47) << 16) / l
        } else {
            0
        };
        let k = s.dist_shift;
        if !hand {
            for ((p, x), k) in self.power.iter_mut().zip([r, diff, r]).zip([k, k, k - 2]) {
                let x2 = x.unsigned_abs().min(u64::from(u32::MAX)).pow(2);
                *p = if x2 >= *p {
                    *p + ((x2 - *p) >> k)
                } else {
                    *p - ((*p - x2) >> k)
                };
            }
        }
        // At rest the excess is zero: the upper bound at or below E, or neither the long
        // average nor the short one's lower bound above theirs. Decided in 64 bits.
        let q = &self.quiet;
        if self.power[2] <= q.upper || (self.power[0] <= q.long && self.power[2] <= q.lower) {
            self.amp_q16 = burst_q16;
            self.bin = 0;
            return;
        }
        let p = self.power.map(|p| u128::from(p) << 32);
        let e0 = self.expect_q32[0];
        // The short average's bounds on the excess: P_short (1 -+ m) - E, m = margin - 1.
        let m = u128::from(s.dist_margin_short_q8 - 256);
        let upper = self.short_q32(256 + m).saturating_sub(e0);
        let lower = self.short_q32(256u128.saturating_sub(m)).saturating_sub(e0);
        let long = if p[0] > self.margin_q32[0] {
            p[0] - e0
        } else {
            0
        };
        let excess = long.max(lower).min(upper);
        if excess == 0 {
            self.amp_q16 = burst_q16;
            self.bin = 0;
            return;
        }
        self.amp_q16 = Self::amplitude_q16(s, excess).max(burst_q16);
        // The frequency: the difference's excess (discounted by its margin) over the
        // residual's, against each bin's edge.
        // `floor(num / den) >= edge` as `num >= edge den`: no 128-bit division per tick.
        let num = p[1].saturating_sub(self.margin_q32[1]) >> 16;
        let den = excess >> 32;
        self.bin = match u64::try_from(den) {
            Ok(0) => 0,
            // Two 64-bit factors: their product fits 128 bits, no overflow check (a
            // 64 x 64 multiply, not a 128 x 128 one, on the Cortex-M4).
            Ok(den) => s
                .bin_ratio_q16
                .iter()
                .take_while(|&&edge| num >= u128::from(edge) * u128::from(den))
                .count() as u8,
            Err(_) => s
                .bin_ratio_q16
                .iter()
                .take_while(|&&edge| u128::from(edge).checked_mul(den).is_some_and(|m| num >= m))
                .count() as u8,
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The default drift control's settings at 3 kHz, the ADXL335's LSB.
    fn settings() -> DriftSettings {
        let Ok(s) = crate::drift::Drift::default().validate(3000, 0.0235) else {
            panic!("the default drift control is valid at 3 kHz");
        };
        s
    }

    /// The excess by its 128-bit definition ([`Disturbance::update`]): zero or not.
    fn excess_is_zero(p0: u64, p2: u64, e0: u128, margin0: u128, short_q8: u64) -> bool {
        let m = u128::from(short_q8 - 256);
        let short = |c: u128| (u128::from(p2) * c) << 24;
        let upper = short(256 + m).saturating_sub(e0);
        let lower = short(256u128.saturating_sub(m)).saturating_sub(e0);
        let p = u128::from(p0) << 32;
        let long = if p > margin0 { p - e0 } else { 0 };
        long.max(lower).min(upper) == 0
    }

    #[test]
    fn the_quiet_levels_decide_as_the_128_bit_excess_does() {
        // Expectations from tiny to past 2^64 after the shifts, margins either side of 2 (the
        // short one's lower factor then saturates at 0), powers at, below and above each level.
        for e0 in [
            0u128,
            1,
            1 << 24,
            (1 << 40) + 12_345,
            3 << 70,
            u128::MAX >> 20,
        ] {
            for short_q8 in [256u64, 300, 511, 512, 700] {
                for m_q8 in [256u128, 333, 768] {
                    let margin0 = e0.saturating_mul(m_q8) >> 8;
                    let q = Quiet::new(e0, margin0, short_q8);
                    let levels = [q.long, q.upper, q.lower, 0, 1, u64::MAX];
                    for &a in &levels {
                        for &b in &levels {
                            for p0 in [a.saturating_sub(1), a, a.saturating_add(1)] {
                                for p2 in [b.saturating_sub(1), b, b.saturating_add(1)] {
                                    let fast = p2 <= q.upper || (p0 <= q.long && p2 <= q.lower);
                                    assert_eq!(
                                        fast,
                                        excess_is_zero(p0, p2, e0, margin0, short_q8),
                                        "e0 {e0} short {short_q8} margin {m_q8} p0 {p0} p2 {p2}"
                                    );
                                }
                            }
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn a_burst_is_a_residual_whose_square_passes_the_bound() {
        for r2 in [0u128, 1, 2, 99, 100, 101, (1 << 62) + 7, (1 << 90) - 1] {
            let root = crate::math::isqrt_u128(r2) as u64;
            for r in [root.saturating_sub(1), root, root + 1, root + 2] {
                assert_eq!(r > root, u128::from(r).pow(2) > r2, "r {r} bound {r2}");
            }
        }
    }

    /// A calibration at rest with per-sample rms `rms` [LSB] and mean `mean` [LSB].
    fn cal(rms: f64, mean: f64) -> Calibration {
        Calibration {
            bias_q16: (mean * 65_536.0) as i64,
            noise_rms_q16: (rms * 65_536.0) as u64,
            samples: 3000,
            tick_var_q32: 3 << 32,
            long_run_var_q32: 3 << 32,
            tick_lags_q32: [0; 3],
        }
    }

    #[test]
    fn the_start_tests_sd_is_the_learnt_one_times_the_quantizers_bound_before_and_after_learning() {
        let s = settings();
        // Codes at a centre with 0.36 LSB of input noise (0.406 LSB rms): r = 1.37.
        let c = cal(0.406, 2048.0);
        let r = quantizer_bound_q16(c.noise_rms_q16, c.bias_q16);
        assert!((f64::from(r) / 65_536.0 - 1.367).abs() < 0.01, "{r}");
        let mut noise = [Noise::from_calibration(&s, &c, true); 3];
        let bare = |n: &Noise| crate::math::isqrt_u128(u128::from(n.q_q32) * u128::from(s.tick));
        for n in &noise {
            assert_eq!(n.sd_q16 as u128, (bare(n) * u128::from(r)) >> 16);
        }
        learn_block(&s, &mut noise, 2048, c.bias_q16, |_| [false; 3]);
        for n in &noise {
            assert_eq!(n.quant_q16, r);
            assert_eq!(n.sd_q16 as u128, (bare(n) * u128::from(r)) >> 16);
        }
        // The ADXL335's codes (1.1 LSB rms) leave the sd as it was.
        let n = Noise::from_calibration(&s, &cal(1.1, 2048.3), true);
        assert_eq!(n.quant_q16, 1 << 16);
        assert_eq!(n.sd_q16 as u128, bare(&n));
    }

    #[test]
    fn a_block_is_learnt_at_most_as_four_sd_of_its_sum() {
        let s = settings();
        let c = cal(1.1, 2048.3);
        let start = Noise::from_calibration(&s, &c, true);
        let q = start.q_q32 as f64;
        let n = f64::from(LEARN_TICKS * s.tick);
        let m = LEARN_BLOCKS as f64;
        // Codes 0.3 LSB a sample below the zero: a block's squared offset per sample,
        // 0.09 n LSB^2, is within 16 q and learnt whole.
        let mut noise = [start; 3];
        learn_block(&s, &mut noise, 2048, c.bias_q16, |_| [false; 3]);
        let off = (c.bias_q16 - (2048 << 16)) as f64 / 65_536.0;
        let var = off * off * n * 4_294_967_296.0;
        assert!(var < 16.0 * q);
        let want = (q * (m - 1.0) + var) / m;
        let got = noise[0].q_q32 as f64;
        assert!((got / want - 1.0).abs() < 1e-6, "{got} against {want}");
        // A lobe the start tests have not claimed yet, 10 LSB a sample off: 100 n LSB^2,
        // thousands of times q, is taken as 16 q (a rise of 15 / 128; unclipped, 43-fold).
        let mut noise = [start; 3];
        learn_block(&s, &mut noise, 2058, c.bias_q16, |_| [false; 3]);
        let want = (q * (m - 1.0) + 16.0 * q) / m;
        let got = noise[0].q_q32 as f64;
        assert!((got / want - 1.0).abs() < 1e-6, "{got} against {want}");
    }

    #[test]
    fn a_block_with_a_disturbed_tick_is_not_learnt_on_that_axis() {
        let s = settings();
        let c = cal(1.1, 2048.3);
        let start = [Noise::from_calibration(&s, &c, true); 3];
        let mut noise = start;
        // Ticks 10 LSB a sample off the zero, the sixth disturbed on Y: q moves on X and Z.
        learn_block(&s, &mut noise, 2058, c.bias_q16, |t| [false, t == 5, false]);
        assert!(noise[0].q_q32 > start[0].q_q32 && noise[2].q_q32 > start[2].q_q32);
        assert_eq!(noise[1], start[1]);
        // The next block, undisturbed, is learnt on Y too.
        let before = noise;
        learn_block(&s, &mut noise, 2058, c.bias_q16, |_| [false; 3]);
        assert!((0..3).all(|a| noise[a].q_q32 > before[a].q_q32));
    }

    /// One block of rest ticks at `code` a sample on every axis, the `t`-th disturbed where
    /// `shaken(t)` says, learnt into `noise` against the zero `bias` (Q16 counts).
    fn learn_block(
        s: &DriftSettings,
        noise: &mut [Noise; 3],
        code: u32,
        bias: i64,
        shaken: impl Fn(u32) -> [bool; 3],
    ) {
        let mut learn = Learn::default();
        for t in 0..LEARN_TICKS {
            learn.push(s, noise, [code * s.tick; 3], [bias; 3], shaken(t));
        }
    }

    #[test]
    fn the_calibrated_variance_is_raised_to_its_upper_two_sd_bound() {
        let s = settings();
        // 1 s at 3 kHz: k = 3000 / D ticks, q raised by 1 + 2 sqrt(8 / k).
        let c = cal(1.1, 2048.3);
        let k = f64::from(c.samples / s.tick);
        let want = 3.0 * (1.0 + 2.0 * (8.0 / k).sqrt());
        let n = Noise::from_calibration(&s, &c, true);
        let got = n.q_q32 as f64 / 4_294_967_296.0;
        // Q8 factor, the square root taken of a Q16 integer: within 0.5 %.
        assert!((got / want - 1.0).abs() < 0.005, "{got} against {want}");
        // A shorter calibration is less certain: a quarter of the ticks, twice the margin.
        let short = Calibration {
            samples: c.samples / 4,
            ..c
        };
        let got = Noise::from_calibration(&s, &short, true).q_q32 as f64 / 4_294_967_296.0;
        let want = 3.0 * (1.0 + 4.0 * (8.0 / k).sqrt());
        assert!((got / want - 1.0).abs() < 0.005, "{got} against {want}");
    }

    #[test]
    fn the_rounded_codes_moments_are_the_direct_sums_over_the_codes() {
        // The same moments in f64, over codes to 12 sd, from the error function's own
        // series-free definition: Phi by Simpson's rule over the density.
        let phi = |x: f64| {
            let steps = 4000;
            let (a, b) = (-12.0, x.max(-12.0));
            let h = (b - a) / f64::from(steps);
            let f = |t: f64| (-0.5 * t * t).exp() / (2.0 * core::f64::consts::PI).sqrt();
            let mut sum = f(a) + f(b);
            for i in 1..steps {
                sum += f(a + f64::from(i) * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
            }
            sum * h / 3.0
        };
        for (sigma, u) in [(0.3f64, 0.2f64), (0.36, -0.4), (0.5, 0.1), (0.9, 0.45)] {
            let (mut m1, mut m2) = (0.0, 0.0);
            for j in -12..=12 {
                let j = f64::from(j);
                let p = phi((j + 0.5 - u) / sigma) - phi((j - 0.5 - u) / sigma);
                m1 += j * p;
                m2 += j * j * p;
            }
            let (mean, var) = rounded_moments(sigma as f32, u as f32);
            assert!(
                (f64::from(mean) - m1).abs() < 1e-4,
                "mean {mean} against {m1}"
            );
            assert!((f64::from(var) - (m2 - m1 * m1)).abs() < 1e-4, "var {var}");
            // The mean follows the zero's place: toward it, never away.
            assert_eq!(mean.signum(), u.signum() as f32);
        }
    }

    #[test]
    fn a_disturbance_with_another_amplitude_keeps_its_frequency_and_state() {
        let s = settings();
        let d = Disturbance {
            amp_q16: 5 << 16,
            bin: 1,
            ..Disturbance::new(&s, &cal(1.1, 2048.3))
        };
        let desk = d.with_amplitude(2 << 16);
        assert_eq!(desk.amp_q16, 2 << 16);
        assert_eq!(
            Disturbance {
                amp_q16: d.amp_q16,
                ..desk
            },
            d
        );
        // What it allows scales with the amplitude it was given (the landing allows the
        // desk's as it was when the device was lifted).
        assert_eq!(desk.allow(1 << 16, 10) * 5, d.allow(1 << 16, 10) * 2);
    }

    #[test]
    fn a_new_disturbance_is_bounded_by_its_short_averages_upper_bound() {
        let s = settings();
        let d = Disturbance {
            amp_q16: 3 << 16,
            ..Disturbance::new(&s, &cal(1.1, 2048.3))
        };
        // The short average at 40 times its noise-only expectation.
        let p2 = ((d.expect_q32[0] >> 32) as u64) * 40;
        let d = Disturbance {
            power: [d.power[0], d.power[1], p2],
            ..d
        };
        // sqrt(2 (P_short (1 + m) - E)) / (L1 L2) in floating point.
        let m = (s.dist_margin_short_q8 - 256) as f64 / 256.0;
        let excess = p2 as f64 * (1.0 + m) * 2f64.powi(32) - d.expect_q32[0] as f64;
        let l = f64::from(s.band[0] * s.band[1]);
        let want = (2.0 * excess).sqrt() / l;
        let span = 1u32 << s.dist_shift;
        assert!(span < 64, "span {span}");
        let full = u64::MAX >> (64 - span);
        // Disturbed for the whole span (and before): the measured amplitude.
        for shaken in [full, u64::MAX, full | 1 << span] {
            assert_eq!(Disturbance { shaken, ..d }.new_amplitude(&s), 3 << 16);
        }
        // Not yet, at the span's oldest tick or its newest: the upper bound.
        for shaken in [full >> 1, full - 1, full & !(1 << (span - 1)) | 1 << span] {
            let got = Disturbance { shaken, ..d }.new_amplitude(&s) as f64;
            assert!(
                (got - want).abs() <= 1.0,
                "{shaken:#x}: {got} against {want}"
            );
            assert!(got > f64::from(3 << 16));
        }
        // A measured amplitude above the bound stands.
        let big = Disturbance {
            amp_q16: want as u64 * 2,
            shaken: 0,
            ..d
        };
        assert_eq!(big.new_amplitude(&s), want as u64 * 2);
    }

    #[test]
    fn only_the_axes_that_feed_the_start_tests_carry_the_quantizers_bound() {
        let s = settings();
        let c = cal(0.406, 2048.0);
        let r = quantizer_bound_q16(c.noise_rms_q16, c.bias_q16);
        assert!(r > 1 << 16);
        let d = crate::drift::Detector::new(&s, &[c; 3]);
        assert_eq!(d.noise.map(|n| n.quant_q16), [r, r, 1 << 16]);
    }
}
