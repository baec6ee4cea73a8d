//! Benchmark kernels: each runs one stage or pipeline over a block of codes and folds every
//! output into a [`Checksum`]. The QEMU speed harness times them per block; the host runs
//! the same kernels on the same [`crate::bench::testsignal::Trace`] and must get the same checksum,
//! bit for bit. Not used by the device.

use crate::bench::testsignal::Checksum;
use crate::bench::variants::{F32Pipeline, NarrowPipeline};
use crate::{
    AdcCode, Axis, Config, IntegratorState, Lowpass, LowpassState, Readout, ReadoutState, Scheme,
    Settings, Tracker,
};

/// The default device's settings at 3 kHz, with the 50 Hz digital low-pass on or off and the
/// given scheme.
///
/// # Panics
/// Never: the configuration is a valid constant.
pub fn settings(filter: bool, scheme: Scheme) -> Settings {
    settings_at(3000, filter, scheme)
}

/// [`settings`] at `fs_hz` (a rate the configuration accepts, e.g. 20 000).
///
/// # Panics
/// If `fs_hz` is outside the accepted rates.
pub fn settings_at(fs_hz: u32, filter: bool, scheme: Scheme) -> Settings {
    match (Config {
        fs_hz,
        lowpass_fc_hz: if filter { Some(50.0) } else { None },
        scheme,
        drift: None,
        ..Config::default()
    })
    .validate()
    {
        Ok(s) => s,
        Err(e) => panic!("benchmark settings at {fs_hz} Hz: {e}"),
    }
}

/// One benchmarked variant. Per-sample outputs go into a wrapping sum folded into the
/// checksum once per block, so the bookkeeping costs about two instructions per sample
/// ([`Baseline`] measures it).
pub trait Kernel {
    /// Work done before a block is timed: what the device gets for free, such as the
    /// ADC's codes of a scene, built from `codes`. Nothing by default.
    fn prepare(&mut self, _codes: &[u16]) {}

    /// Runs over `codes` (after [`Self::prepare`] on them), folding outputs into `sum`.
    fn run(&mut self, codes: &[u16], sum: &mut Checksum);

    /// The most samples a timed block may hold: the harness's SysTick counts 2^24 ticks,
    /// about 97 000 emulated instructions, so a costly kernel is timed in shorter blocks
    /// (the host folds its checksum over the same blocks).
    fn max_block(&self) -> usize {
        usize::MAX
    }
}

/// The loop and bookkeeping alone: sums the codes. Its cost is subtracted from the others'
/// to report what a stage itself costs.
#[derive(Default)]
pub struct Baseline;

impl Kernel for Baseline {
    #[inline(never)]
    fn run(&mut self, codes: &[u16], sum: &mut Checksum) {
        let mut acc: u64 = 0;
        for &c in codes {
            acc = acc.wrapping_add(u64::from(c));
        }
        sum.add(acc);
    }
}

/// The whole per-axis pipeline: filter (optional), bias, double integration, and a count
/// read-out every third sample (the 1 kHz USB poll at 3 kHz), one sample at a time
/// ([`Axis::update`]).
pub struct PipelineAxis {
    settings: Settings,
    axis: Axis,
    n: u32,
}

impl PipelineAxis {
    /// The pipeline with `settings`, bias at code 2048.
    pub fn new(settings: Settings) -> Self {
        Self {
            settings,
            axis: Axis::new(2048 << 16),
            n: 0,
        }
    }
}

impl Kernel for PipelineAxis {
    #[inline(never)]
    fn run(&mut self, codes: &[u16], sum: &mut Checksum) {
        let mut acc: u64 = 0;
        for &c in codes {
            self.axis.update(&self.settings, AdcCode(c));
            self.n += 1;
            if self.n == 3 {
                self.n = 0;
                acc = acc.wrapping_add(self.axis.take_counts(&self.settings) as u64);
            }
        }
        sum.add(acc);
        sum.add(self.axis.integrator().velocity() as u64);
    }
}

/// [`PipelineAxis`] a poll's samples at a time ([`Axis::update_block`]), `poll` samples
/// per read-out: 3 is the 1 kHz poll at 3 kHz (the same outputs as [`PipelineAxis`], so
/// the same checksum), 20 the poll at 20 kHz.
pub struct PipelineBlock {
    pipeline: PipelineAxis,
    poll: u32,
}

impl PipelineBlock {
    /// The pipeline with `settings`, bias at code 2048, read every `poll` samples (`>= 1`).
    pub fn new(settings: Settings, poll: u32) -> Self {
        Self {
            pipeline: PipelineAxis::new(settings),
            poll: poll.max(1),
        }
    }
}

impl Kernel for PipelineBlock {
    #[inline(never)]
    fn run(&mut self, codes: &[u16], sum: &mut Checksum) {
        let p = &mut self.pipeline;
        let mut acc: u64 = 0;
        let mut rest = codes;
        while !rest.is_empty() {
            let (now, later) = rest.split_at(((self.poll - p.n) as usize).min(rest.len()));
            p.axis
                .update_block(&p.settings, now.iter().map(|&c| AdcCode(c)));
            p.n += now.len() as u32;
            if p.n == self.poll {
                p.n = 0;
                acc = acc.wrapping_add(p.axis.take_counts(&p.settings) as u64);
            }
            rest = later;
        }
        sum.add(acc);
        sum.add(p.axis.integrator().velocity() as u64);
    }
}

/// Longest DMA block the device produces [triples] (1 ms at 20 kHz).
const DEVICE_BLOCK_MAX: usize = 20;

/// The device's sample path exactly as the firmware runs it: the default configuration at
/// `fs_hz` (drift control on, three axes), fed one DMA block of `fs / 1000` triples per
/// call ([`Tracker::feed`]), its counts taken after each block (the 1 kHz USB poll), a
/// button edge before a block that holds a click. The harness times each call, so the worst
/// block is measured against its 1 ms deadline. The block's codes are built by
/// [`Kernel::prepare`], before the timer starts: on the device the DMA writes them.
///
/// The desk, the same in samples at any rate so that both rates see the same phases,
/// repeating every [`DESK_PERIOD`] samples: rest, then at sample 768 a stroke (a push of 40
/// LSB on X and 20 on Y for 96 samples, then the same pull: about 1 m/s^2, back to rest),
/// rest, a click at sample 1300 (its freeze over before the next stroke), rest. Noise of -1,
/// 0 or +1 LSB from the trace's codes (as the calibration's) rides on every axis; Z carries
/// gravity's 1 g offset of 410 LSB.
pub struct DevicePath {
    tracker: Tracker,
    block: usize,
    k: u32,
    /// The block [`Kernel::prepare`] built, `len` triples of it.
    codes: [[u16; 3]; DEVICE_BLOCK_MAX],
    len: usize,
    /// Whether the prepared block holds a click.
    click: bool,
}

/// Samples per repetition of [`DevicePath`]'s desk.
pub const DESK_PERIOD: u32 = 1536;

impl DevicePath {
    /// The path at `fs_hz` (a rate the device accepts, `>= 1000` so that a block is 1 ms),
    /// calibrated on a quiet first second.
    pub fn new(fs_hz: u32) -> Self {
        Self::with(&Config {
            fs_hz,
            ..Config::default()
        })
    }

    /// The same path with drift control off (the profile key `drift` off): what drift
    /// control costs is the difference.
    pub fn without_drift(fs_hz: u32) -> Self {
        Self::with(&Config {
            fs_hz,
            drift: None,
            ..Config::default()
        })
    }

    fn with(config: &Config) -> Self {
        let fs_hz = config.fs_hz;
        let Ok(mut tracker) = Tracker::new(config) else {
            unreachable!("the default configuration is valid at every accepted rate")
        };
        let mut quiet = crate::bench::testsignal::Trace::new(0x0CA1);
        while tracker.phase() == crate::Phase::Calibrating {
            let d = i32::from(quiet.next_code() % 3) - 1;
            let c = (2048 + d) as u16;
            tracker.feed(&[[c, c, c + 410]]);
        }
        Self {
            tracker,
            block: (fs_hz / 1000).clamp(1, DEVICE_BLOCK_MAX as u32) as usize,
            k: 0,
            codes: [[0; 3]; DEVICE_BLOCK_MAX],
            len: 0,
            click: false,
        }
    }

    /// The desk's push at sample `k`: `(x, y)` in LSB, and whether the button changes.
    fn desk(k: u32) -> ((i32, i32), bool) {
        let t = k % DESK_PERIOD;
        let push = match t {
            768..=863 => (40, 20),
            864..=959 => (-40, -20),
            _ => (0, 0),
        };
        (push, t == 1300)
    }
}

impl Kernel for DevicePath {
    /// Builds the next DMA block from the first `fs / 1000` of `codes` (their noise).
    fn prepare(&mut self, codes: &[u16]) {
        self.len = codes.len().min(self.block);
        self.click = false;
        for (slot, &c) in self.codes.iter_mut().zip(&codes[..self.len]) {
            let ((px, py), click) = Self::desk(self.k);
            self.click |= click;
            let n = i32::from(c % 3) - 1;
            *slot = [2048 + n + px, 2048 - n + py, 2048 + 410 + n].map(|v| v as u16);
            self.k += 1;
        }
    }

    /// Feeds the prepared block (a click's edge first) and takes the counts.
    #[inline(never)]
    fn run(&mut self, _codes: &[u16], sum: &mut Checksum) {
        if self.click {
            self.tracker.button_edge();
        }
        self.tracker.feed(&self.codes[..self.len]);
        let [x, y, _] = self.tracker.take_counts();
        // The velocity is the exact sum of every integrated sample: it sees what the
        // rounded counts may not.
        let w = self.tracker.axes()[0].integrator().velocity();
        sum.add(
            (x as u64)
                .wrapping_add((y as u64) << 20)
                .wrapping_add(w as u64),
        );
        sum.add(self.tracker.counters().motions.into());
        for a in self.tracker.axes() {
            sum.add(a.bias_q16() as u64);
        }
    }

    fn max_block(&self) -> usize {
        self.block
    }
}

/// The low-pass alone (50 Hz at 3 kHz).
pub struct LowpassStage {
    lp: Lowpass,
    st: LowpassState,
}

impl Default for LowpassStage {
    fn default() -> Self {
        Self {
            lp: settings(true, Scheme::Euler)
                .lowpass()
                .copied()
                .unwrap_or(Lowpass::from_k_q32(0)),
            st: LowpassState::settled_q16(2048 << 16),
        }
    }
}

impl Kernel for LowpassStage {
    #[inline(never)]
    fn run(&mut self, codes: &[u16], sum: &mut Checksum) {
        let mut acc: u64 = 0;
        for &c in codes {
            acc = acc.wrapping_add(self.lp.process(&mut self.st, AdcCode(c)) as u64);
        }
        sum.add(acc);
    }
}

/// The double integrator alone, on `(code - 2048) << 16`.
pub struct IntegratorStage {
    scheme: Scheme,
    st: IntegratorState,
}

impl IntegratorStage {
    /// The integrator for `scheme`.
    pub fn new(scheme: Scheme) -> Self {
        Self {
            scheme,
            st: IntegratorState::default(),
        }
    }
}

impl Kernel for IntegratorStage {
    #[inline(never)]
    fn run(&mut self, codes: &[u16], sum: &mut Checksum) {
        for &c in codes {
            self.scheme.step(&mut self.st, (i64::from(c) - 2048) << 16);
        }
        sum.add(self.st.velocity() as u64);
        sum.add(self.st.position() as u64);
    }
}

/// The read-out alone: one `take` per code, of a position made from it.
pub struct ReadoutStage {
    r: Readout,
    st: ReadoutState,
}

impl Default for ReadoutStage {
    fn default() -> Self {
        Self {
            r: *settings(true, Scheme::Euler).readout(),
            st: ReadoutState::default(),
        }
    }
}

impl Kernel for ReadoutStage {
    #[inline(never)]
    fn run(&mut self, codes: &[u16], sum: &mut Checksum) {
        let mut acc: u64 = 0;
        for &c in codes {
            let z = i128::from(c) << 40;
            acc = acc.wrapping_add(self.r.take(&mut self.st, z) as u64);
        }
        sum.add(acc);
    }
}

/// The f32 pipeline (filter at the same coefficient, bias 2048).
pub struct F32Stage(pub F32Pipeline);

impl Default for F32Stage {
    fn default() -> Self {
        let k = settings(true, Scheme::Euler).lowpass_k_q32() as f32 / 4_294_967_296.0;
        Self(F32Pipeline::new(Some(k), 2048.0))
    }
}

impl Kernel for F32Stage {
    #[inline(never)]
    fn run(&mut self, codes: &[u16], sum: &mut Checksum) {
        for &c in codes {
            self.0.update(c);
        }
        sum.add(u64::from(self.0.s.to_bits()));
    }
}

/// The narrow integer pipeline (no filter, bias 2048).
pub struct NarrowStage(pub NarrowPipeline);

impl Default for NarrowStage {
    fn default() -> Self {
        Self(NarrowPipeline::new(2048 << 8))
    }
}

impl Kernel for NarrowStage {
    #[inline(never)]
    fn run(&mut self, codes: &[u16], sum: &mut Checksum) {
        for &c in codes {
            self.0.update(c);
        }
        sum.add(self.0.s as u64);
    }
}
