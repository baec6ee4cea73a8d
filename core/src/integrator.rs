//! Exact double integration of integer samples (REFERENCE (g), architecture A).
//!
//! # Design
//! Input: `c[n]`, bias-free acceleration in Q16 counts (`i64`, `|c| <= 65535 * 2^16`).
//! The integrator keeps twice the velocity and four times the position, so that both schemes
//! are exact integer recursions with no division:
//!
//! ```text
//! Euler      W[n] = W[n-1] + 2 c[n]               Z[n] = Z[n-1] + 2 W[n]
//! Trapezoid  W[n] = W[n-1] + c[n-1] + c[n]        Z[n] = Z[n-1] + W[n-1] + W[n]
//! ```
//!
//! `W = 2 V` and `Z = 4 S`, where `V = sum c` and `S = sum V` are REFERENCE (c)'s velocity and
//! position times `fs` and `fs^2`. In SI units:
//! `v = W * LSB / (2 * 2^16 * fs)` [m/s] and `s = Z * LSB / (4 * 2^16 * fs^2)` [m], with
//! `LSB` in m/s^2 ([`crate::Settings::metres_per_position_unit`]).
//!
//! Euler integrates samples `c[1..N]` (every sample is a step); the trapezoid integrates
//! `c[0..N]`, so its first sample only primes `c[-1]` and each later sample is a step.
//! Integer sums are exact: the integrator adds no error at all.
//!
//! # Ranges
//! `W` is `i64`, saturating (a wrap would be a cursor jump to the other side of the screen).
//! `Z` is `i128`: per sample it grows by at most `2 |W| <= 2^64` (Euler; `|W[n-1] + W[n]|`
//! for the trapezoid), so leaving `i128` needs more than `2^63` samples without a read-out
//! (which drains it): three million years at 100 kHz. The per-sample step therefore adds
//! without a saturation check (tests run with overflow checks on); the block step, whose
//! terms are larger, keeps its saturating adds.
//!
//! With a full-scale 12-bit input held constant (`|c| < 2^28`), `W`
//! stays below `2^29 N` and `Z` below `2^29 N^2`: at 100 kHz for 24 h (`N = 8.64e9`) that is
//! `2^62.0` and `2^95.1`, so nothing saturates in any documented run. 16-bit codes at full
//! scale (`|c| < 2^32`) reach the `i64` limit of `W` after `N = 2^30` samples.

/// Double-integration scheme.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Scheme {
    /// Rectangle rule on both stages, REFERENCE (c)(i): `v += a/fs`, `s += v/fs`.
    #[default]
    Euler,
    /// Trapezoid rule on both stages, REFERENCE (c)(ii): exact for a constant bias.
    Trapezoid,
}

/// State of the double integrator of one axis.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct IntegratorState {
    w: i64,
    z: i128,
    prev: i64,
    primed: bool,
}

impl IntegratorState {
    /// Twice the velocity, `W = 2 V`, in Q16 counts times samples.
    pub const fn velocity(&self) -> i64 {
        self.w
    }

    /// Four times the position, `Z = 4 S`, in Q16 counts times samples squared, since the last
    /// drain ([`Self::take_position`]).
    pub const fn position(&self) -> i128 {
        self.z
    }

    /// Returns the position accumulated since the last call and clears it. Velocity is kept,
    /// so the motion carries on; the caller moves the position into a read-out.
    #[inline]
    pub fn take_position(&mut self) -> i128 {
        core::mem::take(&mut self.z)
    }

    /// Zero-velocity update: velocity to zero (the trapezoid waits for a new first sample);
    /// the position not yet drained is kept, so nothing already moved is lost.
    pub fn zero_velocity(&mut self) {
        self.w = 0;
        self.primed = false;
    }

    /// Moves the position not yet drained by `dz` (`Z = 4 S` units): a motion's end
    /// correcting what it delivered (see `drift::estimator`'s bridge). Saturating.
    pub fn correct(&mut self, dz: i128) {
        self.z = self.z.saturating_add(dz);
    }

    /// Sets the velocity to `w` (`W = 2 V`) at the start of a motion that carries one on
    /// (the trapezoid waits for a new first sample); the position is kept.
    pub fn set_velocity(&mut self, w: i64) {
        self.w = w;
        self.primed = false;
    }

    /// Primes the trapezoid with the sample `c` (Q16 counts) before the next: the next
    /// sample's step uses it as `c[n-1]`. Velocity and position are kept.
    pub fn prime(&mut self, c: i64) {
        self.prev = c;
        self.primed = true;
    }

    /// Euler steps over a block, given the block's sums: `a = sum c` and
    /// `b = sum_m sum_{k <= m} c[k]` (Q16 counts) over `n` samples. `W += 2 a` and
    /// `Z += 2 n W + 4 b`: exactly `n` calls of [`Scheme::step`] when none of them would
    /// saturate, which holds when `|W| < 2^62`, `n <= 2^14` and every `|c| < 2^32` (the
    /// velocity then moves by less than `2^47`); the caller checks that
    /// ([`crate::Axis::update_block`]). Otherwise the velocity saturates at the block's end
    /// instead of at the step that reaches the limit.
    ///
    /// # Ranges
    /// `|a| < 2^46` and `|b| < 2^59` under those bounds; `|2 n W| < 2^96` for any `n`: the
    /// position's `i128` takes it (see the module docs for its headroom).
    #[inline]
    pub fn euler_block(&mut self, n: u32, a: i64, b: i64) {
        self.z += 2 * i128::from(n) * i128::from(self.w) + 4 * i128::from(b);
        self.w = self.w.saturating_add(a.saturating_mul(2));
    }

    /// A state at rest but for the velocity `w` (`W = 2 V`), for tests near saturation.
    #[cfg(test)]
    pub(crate) fn with_velocity(w: i64) -> Self {
        Self {
            w,
            ..Self::default()
        }
    }

    /// Stops the motion: zero velocity and position, and the trapezoid waits for a new first
    /// sample.
    pub fn reset(&mut self) {
        *self = Self::default();
    }
}

/// Sums of a block of filtered samples `y[1..=n]` (Q16 counts), from which
/// [`Scheme::step_block`] integrates the whole block at once, exactly as `n` calls of
/// [`Scheme::step`] would. Drift control keeps one per axis for each 5 ms tick, so it can
/// integrate the onset of a motion after the fact without keeping every sample.
///
/// # Ranges
/// `|y| < 2^32` (16-bit codes in Q16) and `n <= 2^14`: `sum < 2^46` and
/// `sum_of_prefixes < n^2 2^31 <= 2^59`, both exact in `i64`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BlockSums {
    /// Samples in the block.
    pub n: u32,
    /// `sum y[k]` [Q16 counts].
    pub sum: i64,
    /// `sum_m sum_{k <= m} y[k]`, the sum of the prefix sums [Q16 counts].
    pub sum_of_prefixes: i64,
    /// `y[1]` [Q16 counts].
    pub first: i64,
    /// `y[n]` [Q16 counts].
    pub last: i64,
}

impl BlockSums {
    /// Appends one sample `y` (Q16 counts).
    #[inline]
    pub fn push(&mut self, y: i64) {
        if self.n == 0 {
            self.first = y;
        }
        self.n += 1;
        self.sum += y;
        self.sum_of_prefixes += self.sum;
        self.last = y;
    }
}

impl Scheme {
    /// Integrates a whole block, `c[k] = y[k] - bias_q16`, exactly as `b.n` calls of
    /// [`Self::step`] would (short of saturation, which the block form applies once per
    /// block). With `A = sum c`, `B = sum of prefix sums of c`, `n` steps from `(W0, Z0)`:
    ///
    /// ```text
    /// Euler      W = W0 + 2 A                      Z = Z0 + 2 n W0 + 4 B
    /// Trapezoid  W = W0 + c0 + 2 A - c[n]          (c0: the sample before the block)
    ///            Z = Z0 + W0 + W + 2 (n-1)(W0 + c0) + 4 (B - A) - 2 (A - c[n])
    /// ```
    ///
    /// An unprimed trapezoid primes on `c[1]` and integrates the other `n - 1`.
    pub fn step_block(self, state: &mut IntegratorState, b: &BlockSums, bias_q16: i64) {
        if b.n == 0 {
            return;
        }
        let n = i128::from(b.n);
        let bias = i128::from(bias_q16);
        let mut a = i128::from(b.sum) - n * bias;
        let mut bb = i128::from(b.sum_of_prefixes) - bias * n * (n + 1) / 2;
        let last = i128::from(b.last) - bias;
        let w0 = i128::from(state.w);
        let sat = |v: i128| v.clamp(i128::from(i64::MIN), i128::from(i64::MAX)) as i64;
        match self {
            Self::Euler => {
                state.w = sat(w0 + 2 * a);
                state.z = state.z.saturating_add(2 * n * w0).saturating_add(4 * bb);
            }
            Self::Trapezoid => {
                let mut n = n;
                if !state.primed {
                    let c1 = i128::from(b.first) - bias;
                    // Prime on c[1]; the remaining n - 1 samples have prefix sums P[m+1] - c1.
                    a -= c1;
                    bb -= n * c1;
                    n -= 1;
                    state.primed = true;
                    state.prev = c1 as i64;
                }
                if n > 0 {
                    let c0 = i128::from(state.prev);
                    let w = w0 + c0 + 2 * a - last;
                    let dz = w0 + w + 2 * (n - 1) * (w0 + c0) + 4 * (bb - a) - 2 * (a - last);
                    state.w = sat(w);
                    state.z = state.z.saturating_add(dz);
                    state.prev = last as i64;
                }
            }
        }
    }

    /// Integrates one sample `c` (Q16 counts).
    #[inline]
    pub fn step(self, state: &mut IntegratorState, c: i64) {
        match self {
            Self::Euler => {
                state.w = state.w.saturating_add(2 * c);
                state.z += 2 * i128::from(state.w); // headroom: see the module docs
            }
            Self::Trapezoid => {
                if state.primed {
                    let w = state.w.saturating_add(state.prev + c);
                    state.z += i128::from(state.w) + i128::from(w); // headroom: module docs
                    state.w = w;
                } else {
                    state.primed = true;
                }
                state.prev = c;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn euler_constant_is_n_n_plus_one_over_two() {
        let mut s = IntegratorState::default();
        for _ in 0..10 {
            Scheme::Euler.step(&mut s, 3);
        }
        assert_eq!(s.velocity(), 2 * 3 * 10);
        assert_eq!(s.position(), 4 * 3 * 10 * 11 / 2);
    }

    #[test]
    fn trapezoid_constant_is_exactly_n_squared_over_two() {
        let mut s = IntegratorState::default();
        for _ in 0..=10 {
            Scheme::Trapezoid.step(&mut s, 3); // 11 samples = 10 steps
        }
        assert_eq!(s.velocity(), 2 * 3 * 10);
        assert_eq!(s.position(), 4 * 3 * 100 / 2);
    }

    #[test]
    fn take_position_drains_and_keeps_velocity() {
        let mut s = IntegratorState::default();
        Scheme::Euler.step(&mut s, 1);
        Scheme::Euler.step(&mut s, 1);
        assert_eq!(s.take_position(), 2 * (2 + 4));
        assert_eq!(s.position(), 0);
        assert_eq!(s.velocity(), 4);
    }

    #[test]
    fn a_block_integrates_exactly_as_its_samples_do() {
        // A deterministic walk of samples, blocks of every length 1..=40, both schemes,
        // primed and unprimed starts, and a non-zero bias: the block form equals the steps.
        let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            ((x >> 20) as i64 % (1 << 30)) - (1 << 29)
        };
        for scheme in [Scheme::Euler, Scheme::Trapezoid] {
            for n in 1..=40u32 {
                let bias = next();
                let mut by_step = IntegratorState::default();
                for _ in 0..(n % 3) {
                    scheme.step(&mut by_step, next());
                }
                let mut by_block = by_step;
                let mut b = BlockSums::default();
                for _ in 0..n {
                    let y = next();
                    b.push(y);
                    scheme.step(&mut by_step, y - bias);
                }
                scheme.step_block(&mut by_block, &b, bias);
                assert_eq!(by_block, by_step, "{scheme:?} n {n}");
            }
        }
    }

    #[test]
    fn an_euler_block_is_its_steps() {
        // Blocks of 1 to 40 samples from a walk of velocities: the block form equals the
        // steps when no step saturates.
        let mut trace = crate::bench::testsignal::Trace::new(0xE0B);
        for n in 1..=40u32 {
            let w0 = (trace.next_u64() as i64) >> 3;
            let mut by_step = IntegratorState::with_velocity(w0);
            let mut by_block = by_step;
            let (mut a, mut b) = (0i64, 0i64);
            for _ in 0..n {
                let c = (trace.next_u64() as i64) >> 32;
                Scheme::Euler.step(&mut by_step, c);
                a += c;
                b += a;
            }
            by_block.euler_block(n, a, b);
            assert_eq!(by_block, by_step, "n {n}");
        }
    }

    #[test]
    fn velocity_saturates_instead_of_wrapping_and_position_takes_it_whole() {
        // The velocity saturates; the position, whose headroom is 2^63 samples at the
        // saturated velocity (module docs), adds it exactly.
        let mut s = IntegratorState {
            w: i64::MAX - 1,
            ..Default::default()
        };
        Scheme::Euler.step(&mut s, 1 << 32);
        assert_eq!(
            (s.velocity(), s.position()),
            (i64::MAX, 2 * i128::from(i64::MAX))
        );
        let mut s = IntegratorState {
            w: i64::MIN + 1,
            ..Default::default()
        };
        Scheme::Euler.step(&mut s, -(1 << 32));
        assert_eq!(
            (s.velocity(), s.position()),
            (i64::MIN, 2 * i128::from(i64::MIN))
        );
        let mut s = IntegratorState {
            w: i64::MAX - 1,
            prev: 1 << 32,
            primed: true,
            ..Default::default()
        };
        Scheme::Trapezoid.step(&mut s, 1 << 32);
        let want = i128::from(i64::MAX - 1) + i128::from(i64::MAX);
        assert_eq!((s.velocity(), s.position()), (i64::MAX, want));
    }
}
