//! The disturbance's gains through the tests: their largest values above a frequency,
//! computed once per configuration (at validation), in `f64`.
//!
//! # What is computed
//! A sinusoid at `f` [Hz] reaches a test on tick sums through the tick's own boxcar of `D`
//! samples, `S(f) = |sin(pi f / f_t)| / (D |sin(pi f / fs)|)` (`f_t = fs / D` the tick rate),
//! then through the test's boxcars of `n` ticks, `B_n(f) = |sin(pi n f / f_t) / (n sin(pi f /
//! f_t))|` (noise.rs). Each disturbance bin needs, for each test, the largest of `S(f) T(f)`
//! (`T` the test's product of tick boxcars) over `lo <= f <= fs / 2`: a disturbance at or above
//! the bin's lower edge `lo` can do no more than that.
//!
//! # How, cheaply
//! Scanning `f` from `lo` to Nyquist on a fine grid costs `fs / 2 / step` evaluations per
//! bin and test (780 000 sines at 3 kHz: seconds of soft-float `f64` on the Cortex-M4, where
//! the settings are derived whenever they change). The structure makes one tick period
//! enough: `T` and the numerator of `S` depend on `f` only through its residue `r` modulo
//! `f_t` (and are even in it), while the denominator `D |sin(pi f / fs)|` increases with `f`
//! up to `fs / 2`. So over the aliases `f = m f_t +- r` of a residue, `S T` is largest at the
//! smallest alias at or above `lo`, and
//!
//! ```text
//! max_{lo <= f <= fs/2} S(f) T(f) = max_{0 <= r <= f_t / 2} T(r) |sin(pi r / f_t)| / (D |sin(pi f*(r) / fs)|)
//! f*(r) = the least m f_t + r (m >= 0) or m f_t - r (m >= 1) that is >= lo (none above fs / 2: skipped)
//! ```
//!
//! `r` runs over half a tick period in steps of `f_t / (RESIDUES_PER_LOBE n)`, `n` the
//! longest boxcar (ticks), whose lobes, `f_t / n` wide, are the narrowest: every bin and test
//! from one pass of `RESIDUES_PER_LOBE n / 2` residues (1280 for the 0.4 s window at 5 ms
//! ticks), about 20 000 sines in all at any rate. A step of `1 / 32` of a lobe misses a
//! lobe's peak by at most `(pi / 64)^2 / 2` of it, 0.12 % (the sidelobes' curvature, the
//! largest, taken for all). Each range's lower end is evaluated too: the largest value is
//! often there, on a slope the grid would cut.

/// The grid of frequencies of [`max_over`] [Hz].
pub const STEP_HZ: f64 = 0.25;

/// Residues per lobe of the longest boxcar in [`aliased_maxima`].
pub const RESIDUES_PER_LOBE: u32 = 32;

/// Gain of a boxcar of `n` samples at `x` cycles per sample: `|sin(pi n x) / (n sin(pi x))|`
/// (1 where `sin(pi x)` vanishes: the boxcar's own aliases of DC).
pub fn boxcar(n: u32, x: f64) -> f64 {
    let s = libm::sin(core::f64::consts::PI * x);
    if s.abs() < 1e-12 {
        return 1.0;
    }
    (libm::sin(core::f64::consts::PI * f64::from(n) * x) / (f64::from(n) * s)).abs()
}

/// The largest of `gain(f)` [dimensionless] for `f` from `lo` to `hi` [Hz], on a
/// [`STEP_HZ`] grid from `lo`, and at `hi` itself (where a rising gain is largest); 0 if `hi
/// < lo`.
pub fn max_over(lo: f64, hi: f64, gain: impl Fn(f64) -> f64) -> f64 {
    if hi < lo {
        return 0.0;
    }
    let mut best = gain(hi);
    let mut j = 0u32;
    loop {
        let f = lo + f64::from(j) * STEP_HZ;
        if f > hi {
            return best;
        }
        best = best.max(gain(f));
        j += 1;
    }
}

/// For each lower edge `los[b]` and each tick-boxcar product `tests[k]` (a function of the
/// frequency in cycles per tick, periodic with period 1 and even, its boxcars at most
/// `longest` ticks long), the largest of `S(f) tests[k](f / f_t)` over `los[b] <= f <= fs /
/// 2` (see the module docs); `fs` [Hz], `tick` samples per tick (`>= 1`), every `los[b]` in
/// `(0, fs / 2]`.
pub fn aliased_maxima<const B: usize, const K: usize>(
    fs: f64,
    tick: u32,
    longest: u32,
    los: [f64; B],
    tests: [&dyn Fn(f64) -> f64; K],
) -> [[f64; K]; B] {
    let d = f64::from(tick);
    let f_t = fs / d;
    let nyq = fs / 2.0;
    let steps = RESIDUES_PER_LOBE * longest.max(1) / 2;
    let box_s = |f: f64| if tick == 1 { 1.0 } else { boxcar(tick, f / fs) };
    // Each range's lower end itself, where the largest value often is (the gains fall
    // above it), and which the residues' grid would miss by its slope.
    let mut best: [[f64; K]; B] =
        core::array::from_fn(|b| core::array::from_fn(|k| box_s(los[b]) * tests[k](los[b] / f_t)));
    for j in 0..=steps {
        let r = f_t / 2.0 * f64::from(j) / f64::from(steps);
        let x = r / f_t;
        let t: [f64; K] = core::array::from_fn(|k| tests[k](x));
        let numerator = libm::sin(core::f64::consts::PI * x).abs();
        for (lo, best) in los.iter().zip(&mut best) {
            let up = libm::ceil((lo - r) / f_t).max(0.0) * f_t + r;
            let down = libm::ceil((lo + r) / f_t).max(1.0) * f_t - r;
            let f = up.min(down);
            if f > nyq {
                continue;
            }
            // One sample per tick: no tick boxcar.
            let s = if tick == 1 {
                1.0
            } else {
                numerator / (d * libm::sin(core::f64::consts::PI * f / fs).abs())
            };
            for (b, t) in best.iter_mut().zip(t) {
                *b = b.max(s * t);
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The brute-force scan the alias argument replaces: every `step` Hz from `lo` to Nyquist.
    fn scanned(fs: f64, tick: u32, lo: f64, step: f64, test: &dyn Fn(f64) -> f64) -> f64 {
        let f_t = fs / f64::from(tick);
        let mut best = 0.0f64;
        let mut f = lo;
        while f <= fs / 2.0 {
            best = best.max(boxcar(tick, f / fs) * test(f / f_t));
            f += step;
        }
        best
    }

    #[test]
    fn one_period_of_residues_finds_the_scans_maxima() {
        // Rates with one sample per tick (100 Hz), a ragged tick (1001 Hz: 6 samples, 166.8 Hz
        // ticks), the default and the fastest; boxcars of the hand band (10 and 7 ticks), the
        // quiet window (4), the tilt windows (20, 80) and a long landing window.
        for (fs, tick) in [(100.0, 1), (1001.0, 6), (3000.0, 15), (20_000.0, 100)] {
            let tests: [&dyn Fn(f64) -> f64; 5] = [
                &|x| boxcar(10, x) * boxcar(7, x),
                &|x| boxcar(4, x),
                &|x| boxcar(20, x),
                &|x| boxcar(80, x),
                &|x| boxcar(1, x),
            ];
            let f_t = fs / f64::from(tick);
            let los = [20.0, 33.0, f_t / 2.0 - 1.0];
            let fast = aliased_maxima(fs, tick, 80, los, tests);
            for (b, &lo) in los.iter().enumerate() {
                for (k, test) in tests.iter().enumerate() {
                    // A finer scan than the residues' grid, 1/256 of the narrowest lobe
                    // (80 ticks: f_t / 80): the alias search may lose only the grid's 0.12 %
                    // at a lobe's peak (the scan its own 0.004 %), never gain.
                    let slow = scanned(fs, tick, lo, f_t / 80.0 / 256.0, test);
                    let f = fast[b][k];
                    assert!(f <= slow * 1.0003, "fs {fs} lo {lo} test {k}: {f} > {slow}");
                    assert!(
                        f >= slow * (1.0 - 0.0012),
                        "fs {fs} lo {lo} test {k}: {f} << {slow}"
                    );
                }
            }
        }
    }

    #[test]
    fn boxcar_gain_is_one_at_dc_and_null_at_its_zeros() {
        assert_eq!(boxcar(15, 0.0), 1.0);
        assert_eq!(boxcar(15, 1.0), 1.0);
        assert!(boxcar(15, 1.0 / 15.0) < 1e-12);
        assert!((boxcar(2, 0.25) - core::f64::consts::FRAC_1_SQRT_2).abs() < 1e-12);
    }

    #[test]
    fn max_over_includes_both_ends() {
        assert_eq!(max_over(1.0, 2.0, |f| f), 2.0);
        // An upper end off the grid.
        assert_eq!(max_over(1.0, 2.1, |f| f), 2.1);
        assert_eq!(max_over(1.0, 2.0, |f| 3.0 - f), 2.0);
        assert_eq!(max_over(1.0, 0.5, |f| f), 0.0);
    }
}
