//! The tick stream: what drift control keeps of the samples.
//!
//! # Ticks
//! A tick is `D = ceil(fs * 5 ms)` samples ([`super::tick_samples`]). Per tick and axis the
//! stream keeps the sum of the raw codes `s` (a ring of [`super::RING`] ticks: the tick-level
//! tests' windows). A sample costs one add per axis and sum; everything else runs once a
//! tick.
//!
//! # The hand-band filter
//! A hand on a desk moves below about 10 Hz; a desk top rings at 20-60 Hz and a machine
//! vibrates at 30-100 Hz (REFERENCE (j)). The slow start test and the tilt tests look at the
//! tick sums through two boxcars in cascade, of `L1 = 1 / knock_hz` and `L2 = 2 / (3
//! knock_hz)` (whole ticks; 50 ms and 35 ms at 20 Hz): a trapezoid with nulls at `knock_hz`
//! and `1.5 knock_hz` and their multiples, unity gain at DC, a delay of `(L1 + L2 - 2) / 2`
//! ticks. Its largest gain above `knock_hz` (with the tick's own boxcar) is 0.03 at 20 Hz,
//! 5 ms ticks, 3 kHz: 50 mg of vibration leaves 1.5 mg a tick. What that can add to the slow
//! start test's runs is computed at validation ([`super::rest`]).
//!
//! ```text
//! F1[t] = sum_{j < L1} s[t-j]          (running: + s[t] - s[t-L1])
//! G[t]  = F1[t - L2]                   (running: + s[t-L2] - s[t-L2-L1])
//! F2[t] = sum_{j < L2} F1[t-j]         (running: + F1[t] - G[t])
//! ```
//!
//! Exact integer sums of raw codes (`F2 < L1 L2 D 2^16 <= 2^40`): the zero is subtracted
//! only when a sum is used, so a new zero needs no recomputation.
//!
//! # Blocks
//! Every `round(20 ms / tick)` ticks the [`BlockSums`] of the block's integrated samples
//! close into a ring of [`super::BLOCKS`] blocks (1.28 s at 5 ms ticks): a motion's onset is
//! integrated after the fact, exactly, from the start of the block it lies in (up to 1.28 s
//! back: a slow stroke found late loses nothing of its start), and the tilt tests' windows.
//! Two consecutive blocks' sums merge exactly: `n = n1 + n2`, `sum = sum1 + sum2`,
//! `prefixes = prefixes1 + prefixes2 + n2 sum1`.

use crate::calibration::Calibration;
use crate::integrator::BlockSums;

use super::{DriftSettings, BLOCKS, RING};

/// Block ends at which the band output is kept ([`TickStream::hand_band`]).
pub const BAND_PAST: usize = 8;

/// One axis's integrated-sample sums over one block, compact ([`BlockSums`] without the
/// block's length, first and last samples: the length is the stream's, the replay does not
/// need the first, and the last is kept apart, in 32 bits).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TickSums {
    sum: i64,
    sum_of_prefixes: i64,
}

/// The current block's integrated-sample sums, axes side by side (one count, one first-sample
/// test per sample for all three): [`BlockSums`] per axis when read.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct OpenBlock {
    n: u32,
    first: [i64; 3],
    sum: [i64; 3],
    sum_of_prefixes: [i64; 3],
    last: [i64; 3],
}

impl OpenBlock {
    /// Appends one sample `y` per axis (Q16 counts), as [`BlockSums::push`] on each.
    #[inline(always)]
    fn push(&mut self, y: [i64; 3]) {
        if self.n == 0 {
            self.first = y;
        }
        self.n += 1;
        for ((sum, prefixes), y) in self.sum.iter_mut().zip(&mut self.sum_of_prefixes).zip(y) {
            *sum += y;
            *prefixes += *sum;
        }
        self.last = y;
    }

    /// Axis `a`'s sums.
    fn sums(&self, a: usize) -> BlockSums {
        BlockSums {
            n: self.n,
            sum: self.sum[a],
            sum_of_prefixes: self.sum_of_prefixes[a],
            first: self.first[a],
            last: self.last[a],
        }
    }
}

/// The running sums of the hand-band filter for one axis (raw codes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Band {
    f1: u64,
    g: u64,
    f2: u64,
}

/// The samples as drift control keeps them; see the module docs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TickStream {
    codes: [[u32; 3]; RING],
    blocks: [[TickSums; 3]; BLOCKS],
    /// Each block's last integrated sample (Q16 counts): a filtered 16-bit code, so
    /// `0..=65535 * 2^16` (the low-pass never leaves its inputs' range), which `u32` holds;
    /// apart from the sums so that no padding follows it (0.75 KiB of RAM).
    lasts: [[u32; 3]; BLOCKS],
    cur_codes: [u32; 3],
    cur_n: u32,
    cur_block: OpenBlock,
    block_ticks: u32,
    band: [Band; 3],
    /// The horizontal axes' `F2` at the last [`BAND_PAST`] blocks' ends, by block index
    /// modulo it ([`Self::hand_band`]).
    band_past: [[u64; 2]; BAND_PAST],
    /// The least and the greatest of the horizontal axes' `F2` at the last `band_lag` block
    /// ends, and its value at the zero: `[axis][lo, hi, zero]` ([`Self::hand_band`]).
    band_span: [[u64; 3]; 2],
    ticks: u64,
    blocks_done: u64,
    block_closed: bool,
    /// Samples per block.
    block_samples: u32,
}

impl TickStream {
    /// A stream that has seen the calibration's window: every tick in the rings at the
    /// calibrated mean (the device was at rest), so that every window is defined at once.
    pub(crate) fn new(s: &DriftSettings, cal: &[Calibration; 3]) -> Self {
        // The mean tick sum: D times the Q16 zero, rounded.
        let tick_sum: [u32; 3] = core::array::from_fn(|a| {
            let b = cal[a].bias_q16.clamp(0, 65_535 << 16) as u64;
            ((b * u64::from(s.tick) + (1 << 15)) >> 16) as u32
        });
        let [l1, l2] = s.band.map(u64::from);
        let band = tick_sum.map(|t| Band {
            f1: l1 * u64::from(t),
            g: l1 * u64::from(t),
            f2: l1 * l2 * u64::from(t),
        });
        let n = i64::from(s.block) * i64::from(s.tick);
        let block = cal.map(|c| TickSums {
            sum: n * c.bias_q16,
            sum_of_prefixes: 0,
        });
        let last = cal.map(|c| last_u32(c.bias_q16));
        Self {
            codes: [tick_sum; RING],
            blocks: [block; BLOCKS],
            lasts: [last; BLOCKS],
            cur_codes: [0; 3],
            cur_n: 0,
            cur_block: OpenBlock::default(),
            block_ticks: 0,
            band_past: [[band[0].f2, band[1].f2]; BAND_PAST],
            band_span: [[band[0].f2; 3], [band[1].f2; 3]],
            band,
            ticks: 0,
            blocks_done: 0,
            block_closed: false,
            block_samples: s.block * s.tick,
        }
    }

    /// Adds one sample: raw `codes`, integrated values `y` (Q16 counts).
    #[inline(always)]
    pub(crate) fn push(&mut self, codes: [u16; 3], y: [i64; 3]) {
        for (sum, c) in self.cur_codes.iter_mut().zip(codes) {
            *sum += u32::from(c);
        }
        self.cur_block.push(y);
        self.cur_n += 1;
    }

    /// Whether the current tick is complete.
    #[inline(always)]
    pub(crate) fn tick_done(&self, s: &DriftSettings) -> bool {
        self.cur_n >= s.tick
    }

    /// Closes the current tick into the rings, the filter and the blocks.
    pub(crate) fn close_tick(&mut self, s: &DriftSettings) {
        let [l1, l2] = s.band.map(|l| l as usize);
        let t = self.ticks as usize;
        let codes = core::mem::take(&mut self.cur_codes);
        for (a, band) in self.band.iter_mut().enumerate() {
            let at = |k: usize| u64::from(self.codes[(t + RING - k) % RING][a]);
            // The ring still holds the ticks before this one: `at(k)` is k ticks back from
            // this tick (at(1) the previous one).
            band.f1 = band.f1 + u64::from(codes[a]) - at(l1);
            band.g = band.g + at(l2) - at(l2 + l1); // L2 >= 1 (validation)
            band.f2 = band.f2 + band.f1 - band.g;
        }
        self.codes[t % RING] = codes;
        self.cur_n = 0;
        self.ticks += 1;
        self.block_ticks += 1;
        self.block_closed = self.block_ticks >= s.block;
        if self.block_closed {
            let i = (self.blocks_done % BLOCKS as u64) as usize;
            let b = &self.cur_block;
            for a in 0..3 {
                self.blocks[i][a] = TickSums {
                    sum: b.sum[a],
                    sum_of_prefixes: b.sum_of_prefixes[a],
                };
                self.lasts[i][a] = last_u32(b.last[a]);
            }
            self.band_past[(self.blocks_done % BAND_PAST as u64) as usize] =
                [self.band[0].f2, self.band[1].f2];
            self.cur_block = OpenBlock::default();
            self.blocks_done += 1;
            self.block_ticks = 0;
        }
    }

    /// Complete ticks so far.
    pub(crate) const fn ticks(&self) -> u64 {
        self.ticks
    }

    /// Whether the tick just closed also closed a block.
    pub(crate) const fn block_closed(&self) -> bool {
        self.block_closed
    }

    /// The raw code sum of `axis` `k` complete ticks back (`1` = the last one), `k <= RING`.
    pub(crate) fn code(&self, k: u64, axis: usize) -> u32 {
        self.codes[(self.ticks.wrapping_sub(k) % RING as u64) as usize][axis]
    }

    /// The raw code sums of the last `k` complete ticks (`k <= RING`), per axis.
    pub(crate) fn window(&self, k: u32) -> [u64; 3] {
        self.ticks_back(1, u64::from(k))
    }

    /// The raw code sums of the complete ticks `from..=to` back (`1` = the last one,
    /// `to <= RING`), per axis.
    #[inline(always)]
    pub(crate) fn ticks_back(&self, from: u64, to: u64) -> [u64; 3] {
        let mut sums = [0u64; 3];
        for i in from..=to {
            for (a, sum) in sums.iter_mut().enumerate() {
                *sum += u64::from(self.code(i, a));
            }
        }
        sums
    }

    /// The integrated-sample sum of `axis` over blocks `from..to` back (`1` = the last
    /// complete block), `to <= BLOCKS + 1` [Q16 LSB samples]: below `2^64` blocks of
    /// `2^47`.
    pub(crate) fn blocks_sum(&self, axis: usize, from: u32, to: u32) -> i64 {
        (from..to)
            .map(|k| {
                let i = self.blocks_done.wrapping_sub(u64::from(k)) % BLOCKS as u64;
                self.blocks[i as usize][axis].sum
            })
            .sum()
    }

    /// Complete blocks so far.
    pub(crate) const fn blocks(&self) -> u64 {
        self.blocks_done
    }

    /// Samples in the current tick so far.
    pub(crate) const fn partial(&self) -> u32 {
        self.cur_n
    }

    /// Samples since the last complete block (its closed ticks and the current tick so far).
    pub(crate) fn samples_in_block(&self) -> u32 {
        self.cur_block.n
    }

    /// The hand-band filter's output on `axis` as an offset from `bias` (Q16 counts), per
    /// tick [Q16 LSB samples]: `(F2 2^16 - L1 L2 D bias) / (L1 L2)`, rounded.
    pub(crate) fn band_offset(&self, s: &DriftSettings, axis: usize, bias: i64) -> i64 {
        let l = i64::from(s.band[0] * s.band[1]);
        // F2 < 2^40 (L1 L2 <= 31^2 ticks of 2^14 16-bit codes): shifted, 2^56.
        let f = ((self.band[axis].f2 as i64) << 16) - l * i64::from(s.tick) * bias;
        crate::math::div_round(f, l)
    }

    /// Takes what [`Self::hand_band`] compares with: the band output's least and greatest
    /// over the last `s.band_lag` block ends, and its value at the zeros `bias` (Q16 LSB per
    /// sample) of the horizontal axes. While a motion is under way: at its start and at each
    /// block's end (the zeros change only at a shadow's or a tilt's decision).
    pub(crate) fn band_span_refresh(&mut self, s: &DriftSettings, bias: [i64; 3]) {
        let l = u64::from(s.band[0] * s.band[1]) * u64::from(s.tick);
        for (a, span) in self.band_span.iter_mut().enumerate() {
            // L1 L2 D < 2^24 and a zero below 2^32 (a 16-bit code in Q16): below 2^56.
            let zero = (l * bias[a].clamp(0, u32::MAX.into()) as u64) >> 16;
            *span = [zero; 3];
            for k in 1..=u64::from(s.band_lag) {
                let i = (self.blocks_done.wrapping_sub(k) % BAND_PAST as u64) as usize;
                let f = self.band_past[i][a];
                span[0] = span[0].min(f);
                span[1] = span[1].max(f);
            }
        }
    }

    /// The hand's band output on horizontal `axis` [LSB, times `L1 L2`]: the most the
    /// filter's output differs from its value at the zero and from its values at the last
    /// `s.band_lag` block ends (at least the filter's span back, so that they share no
    /// tick). The first is a hand's acceleration; the second is its change, in which an
    /// offset the zero does not hold (a tilt's) cancels.
    pub(crate) fn hand_band(&self, axis: usize) -> u64 {
        let f = self.band[axis].f2;
        let [lo, hi, zero] = self.band_span[axis];
        f.abs_diff(lo).max(f.abs_diff(hi)).max(f.abs_diff(zero))
    }

    /// The hand-band residual of `axis`: `L1 L2 s[t - delay] - F2[t]`, the tick sum at the
    /// filter's centre against the filter [LSB, times `L1 L2`]; no zero in it.
    pub(crate) fn band_residual(&self, s: &DriftSettings, axis: usize) -> i64 {
        let l = i64::from(s.band[0] * s.band[1]);
        let centre = i64::from(self.code(u64::from(s.band_delay) + 1, axis));
        l * centre - self.band[axis].f2 as i64
    }

    /// The current tick's raw code sum on `axis` so far, as an offset from `bias` [Q16 LSB
    /// samples]: below `2^14` codes of 16 bits, `2^46`, and `n bias < 2^46`.
    #[inline(always)]
    pub(crate) fn partial_offset(&self, axis: usize, bias: i64) -> i64 {
        (i64::from(self.cur_codes[axis]) << 16) - i64::from(self.cur_n) * bias
    }

    /// The integrated-sample sums of the last `blocks` complete blocks (`< BLOCKS`), oldest
    /// first, then those of the current block so far (its closed ticks and the current tick's
    /// samples), if it has samples.
    pub(crate) fn replay(
        &self,
        s: &DriftSettings,
        blocks: usize,
    ) -> impl Iterator<Item = [BlockSums; 3]> + '_ {
        let first = self.blocks_done - blocks.min(BLOCKS - 1) as u64;
        let n = s.block * s.tick;
        (first..self.blocks_done)
            .map(move |i| {
                let i = (i % BLOCKS as u64) as usize;
                core::array::from_fn(|a| BlockSums {
                    n,
                    sum: self.blocks[i][a].sum,
                    sum_of_prefixes: self.blocks[i][a].sum_of_prefixes,
                    first: 0,
                    last: i64::from(self.lasts[i][a]),
                })
            })
            .chain((self.cur_block.n > 0).then(|| core::array::from_fn(|a| self.cur_block.sums(a))))
    }

    /// The last integrated sample of the block before the last `blocks` complete ones (Q16
    /// counts), to prime a trapezoid replay; `None` if there is no such block.
    pub(crate) fn replay_prev(&self, blocks: usize) -> Option<[i64; 3]> {
        let i = self.blocks_done.checked_sub(blocks as u64 + 1)?;
        // The ring holds the last BLOCKS blocks: a replay of at most BLOCKS - 1 (the cap in
        // `start`) leaves its predecessor in it.
        (blocks < BLOCKS).then(|| self.lasts[(i % BLOCKS as u64) as usize].map(i64::from))
    }
}

impl TickStream {
    /// The velocity at the start of the last `back` complete blocks (`W = 2 V`, per axis,
    /// relative to `bias`) of a device at rest over the `pre` blocks before them: the velocity
    /// whose running integral over those blocks averages to zero. With `U(m)` the integral of
    /// the offsets from the pre-window's start to its sample `m` (`n` samples),
    /// `V = U(n) - mean U = A - B / n` from the merged block's sums `A = sum - n z` and
    /// `B = prefixes - z n (n + 1) / 2`. `None` if those blocks are not in the ring.
    pub(crate) fn rest_velocity(&self, back: u64, pre: u32, bias: [i64; 3]) -> Option<[i64; 3]> {
        let oldest = back + u64::from(pre);
        if oldest >= BLOCKS as u64 || oldest > self.blocks_done {
            return None;
        }
        Some(core::array::from_fn(|a| {
            let mut m = BlockSums::default();
            for k in (back + 1..=oldest).rev() {
                let t = self.blocks[((self.blocks_done - k) % BLOCKS as u64) as usize][a];
                // The merged sums need no last sample.
                let b = BlockSums {
                    n: self.block_samples,
                    sum: t.sum,
                    sum_of_prefixes: t.sum_of_prefixes,
                    first: 0,
                    last: 0,
                };
                m = merge(&m, &b);
            }
            let n = i128::from(m.n);
            let z = i128::from(bias[a]);
            let a_sum = i128::from(m.sum) - n * z;
            let b_sum = i128::from(m.sum_of_prefixes) - z * n * (n + 1) / 2;
            let v = a_sum - b_sum / n.max(1);
            (2 * v).clamp(i128::from(i64::MIN), i128::from(i64::MAX)) as i64
        }))
    }
}

/// A block's last integrated sample in the ring's 32 bits: in range for any filtered 16-bit
/// code (see [`TickStream`]'s `lasts`); saturated, never wrapped, were it not.
fn last_u32(y: i64) -> u32 {
    u32::try_from(y.max(0)).unwrap_or(u32::MAX)
}

/// Two consecutive blocks' sums as one (see the module docs); the first may be empty. The
/// result's `first` is not kept (the replay does not need it).
fn merge(a: &BlockSums, b: &BlockSums) -> BlockSums {
    if a.n == 0 {
        return *b;
    }
    BlockSums {
        n: a.n + b.n,
        sum: a.sum + b.sum,
        sum_of_prefixes: a.sum_of_prefixes + b.sum_of_prefixes + i64::from(b.n) * a.sum,
        first: a.first,
        last: b.last,
    }
}

/// An offset of a sum of `n` raw codes from `n` times `bias` (Q16 counts) [Q16 LSB samples]:
/// `sum 2^16 - n bias`. Sums of up to `2^26` samples of 16-bit codes: below `2^58`.
pub(crate) fn offset(sum: u64, n: u64, bias: i64) -> i64 {
    ((sum as i64) << 16) - n as i64 * bias
}

/// An offset of a sum of `n` integrated samples (Q16 counts) from `n` times `bias` [Q16 LSB
/// samples].
pub(crate) fn offset_q16(sum: i64, n: u64, bias: i64) -> i64 {
    sum - n as i64 * bias
}
