//! `cargo lab speed`: speed against error. Instructions per sample on an emulated
//! Cortex-M4 (QEMU, exact and deterministic), host nanoseconds per sample, and each
//! configuration's position error against the f64 ground truth at 1 s, 60 s and 1 h.
//!
//! # Design
//! - Target: `firmware/src/bin/speed.rs` runs `imu_core::bench::kernels` on
//!   `imu_core::bench::testsignal::Trace` under SysTick in QEMU (`-icount shift=10`: one
//!   instruction = 1024 ns of virtual time, so ticks / (ticks per instruction) counts
//!   instructions). The harness calibrates ticks per instruction on 1000 `nop`s. The host
//!   runs the same kernels on the same trace and must reproduce every checksum bit for bit.
//! - Host: best of five runs over 1 M samples per kernel, in this one process.
//! - Error: an ADXL335 at 3 kHz (300 ug/sqrt(Hz) into its 50 Hz RC pole, 2 mg bias, 12-bit
//!   ADC), calibrated on its first second, then integrated; each configuration's position
//!   against the f64 twin with the ideal filter coefficient and the f64 mean as bias, rms over
//!   three trials. "Sensor noise" is the ADXL335's own error at the same T,
//!   `ND T^1.5 / sqrt 6` (eq 27 with R_v = ND^2 / 2, REFERENCE (f), (g)).

use std::path::Path;
use std::process::Command;
use std::time::Instant;

use dsp_process::SplitProcess;
use imu_core::bench::kernels::{
    self, Baseline, DevicePath, F32Stage, IntegratorStage, Kernel, LowpassStage, NarrowStage,
    PipelineAxis, PipelineBlock, ReadoutStage,
};
use imu_core::bench::testsignal::{Checksum, Trace};
use imu_core::bench::variants::{F32Pipeline, NarrowPipeline};
use imu_core::{AdcCode, Axis, Scheme};
use serde::Serialize;

use crate::formats::plot::{Line, Plot, Points};
use crate::oracle::twin;
use crate::world::noise;
use crate::world::scene;

/// The harness's trace seed, block and length (must match `firmware/src/bin/speed.rs`).
pub const SEED: u64 = 0x1A2B_3C4D;
/// Samples per timed block of the harness.
pub const BLOCK: usize = 256;
const BLOCKS: usize = 12;

/// idsp's first-order low-pass at 50 Hz / 3 kHz (as in the harness).
pub struct IdspLowpass {
    lp: idsp::Lowpass<1>,
    st: idsp::LowpassState<1>,
}

impl Default for IdspLowpass {
    fn default() -> Self {
        Self {
            lp: idsp::Lowpass([224_883_962]),
            st: idsp::LowpassState([i64::from(2048 << 16) << 32]),
        }
    }
}

impl Kernel for IdspLowpass {
    #[inline(never)]
    fn run(&mut self, codes: &[u16], sum: &mut Checksum) {
        let mut acc: u64 = 0;
        for &c in codes {
            acc = acc.wrapping_add(self.lp.process(&mut self.st, i32::from(c) << 16) as u64);
        }
        sum.add(acc);
    }
}

/// Every kernel, by the harness's names, freshly constructed.
pub fn kernels() -> Vec<(&'static str, Box<dyn Kernel>)> {
    vec![
        ("baseline", Box::new(Baseline)),
        (
            "pipeline_axis",
            Box::new(PipelineAxis::new(kernels::settings(true, Scheme::Euler))),
        ),
        (
            "pipeline_block",
            Box::new(PipelineBlock::new(
                kernels::settings(true, Scheme::Euler),
                3,
            )),
        ),
        (
            "pipeline_block_20khz",
            Box::new(PipelineBlock::new(
                kernels::settings_at(20_000, true, Scheme::Euler),
                20,
            )),
        ),
        (
            "pipeline_axis_nofilter",
            Box::new(PipelineAxis::new(kernels::settings(false, Scheme::Euler))),
        ),
        (
            "pipeline_axis_trapezoid",
            Box::new(PipelineAxis::new(kernels::settings(
                true,
                Scheme::Trapezoid,
            ))),
        ),
        ("lowpass", Box::new(LowpassStage::default())),
        ("idsp_lowpass", Box::new(IdspLowpass::default())),
        (
            "integrator_euler",
            Box::new(IntegratorStage::new(Scheme::Euler)),
        ),
        (
            "integrator_trapezoid",
            Box::new(IntegratorStage::new(Scheme::Trapezoid)),
        ),
        ("readout", Box::new(ReadoutStage::default())),
        ("f32_pipeline", Box::new(F32Stage::default())),
        ("narrow_pipeline", Box::new(NarrowStage::default())),
        ("device_3khz", Box::new(DevicePath::new(3000))),
        ("device_20khz", Box::new(DevicePath::new(20_000))),
        (
            "device_3khz_nodrift",
            Box::new(DevicePath::without_drift(3000)),
        ),
    ]
}

/// The harness's trace.
pub fn trace(n: usize) -> Vec<u16> {
    let mut t = Trace::new(SEED);
    (0..n).map(|_| t.next_code()).collect()
}

/// The host's checksum of each kernel over the harness's trace, in the harness's blocks.
pub fn host_checksums() -> Vec<(&'static str, u64)> {
    checksums_of(&trace(BLOCK * BLOCKS))
}

/// The checksum of each kernel over `codes`, in blocks of [`BLOCK`] samples (or the kernel's
/// own smaller block), as the harness folds them.
pub fn checksums_of(codes: &[u16]) -> Vec<(&'static str, u64)> {
    kernels()
        .into_iter()
        .map(|(name, mut k)| {
            let mut sum = Checksum::default();
            run_blocks(k.as_mut(), codes, &mut sum);
            (name, sum.0)
        })
        .collect()
}

/// Runs `k` over `codes` as the harness does: whole blocks of [`BLOCK`] samples (or the
/// kernel's own smaller block), each prepared, then run. Returns the samples run.
pub fn run_blocks(k: &mut dyn Kernel, codes: &[u16], sum: &mut Checksum) -> usize {
    let blocks = codes.chunks_exact(BLOCK.min(k.max_block()));
    let run = codes.len() - blocks.remainder().len();
    for b in blocks {
        k.prepare(b);
        k.run(b, sum);
    }
    run
}

/// One kernel as measured in QEMU.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TargetKernel {
    /// Kernel name.
    pub name: String,
    /// Instructions per sample (per call for `readout`), gross.
    pub instructions_per_sample: f64,
    /// The checksum QEMU printed.
    pub checksum: String,
    /// Whether the host computed the same checksum.
    pub bit_exact: bool,
    /// DWT cycles per sample: measured on a board, `None` in QEMU (its CYCCNT reads 0).
    pub cycles_per_sample: Option<f64>,
    /// Samples per timed block (a DMA block for the `device_*` kernels).
    pub block_samples: f64,
    /// Instructions of the costliest timed block, net of the empty timed region.
    pub worst_block_instructions: f64,
}

/// Why the target measurement could not run.
#[derive(Debug, thiserror::Error)]
pub enum SpeedError {
    /// No qemu-system-arm on the PATH.
    #[error("qemu-system-arm not found: install it (Debian/Ubuntu: `apt-get install qemu-system-arm`), or pass --host-only")]
    NoQemu,
    /// Building the harness failed.
    #[error("building the speed harness failed (is the target installed? `rustup target add thumbv7em-none-eabihf`): {0}")]
    Build(String),
    /// QEMU ran but the output was not as expected.
    #[error("the QEMU run failed: {0}")]
    Run(String),
}

/// Builds the harness and runs it in QEMU (`netduinoplus2`, an STM32F405 whose memory map
/// fits memory.x).
///
/// # Errors
/// [`SpeedError`] if QEMU is missing, the build fails, or the output is malformed.
pub fn run_target(workspace: &Path) -> Result<Vec<TargetKernel>, SpeedError> {
    if Command::new("qemu-system-arm")
        .arg("--version")
        .output()
        .is_err()
    {
        return Err(SpeedError::NoQemu);
    }
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let build = Command::new(cargo)
        .current_dir(workspace)
        .args([
            "build",
            "-q",
            "-p",
            "firmware",
            "--bin",
            "speed",
            "--target",
            "thumbv7em-none-eabihf",
            "--release",
        ])
        .output()
        .map_err(|e| SpeedError::Build(e.to_string()))?;
    if !build.status.success() {
        return Err(SpeedError::Build(
            String::from_utf8_lossy(&build.stderr).into_owned(),
        ));
    }
    let elf = workspace.join("target/thumbv7em-none-eabihf/release/speed");
    let out = Command::new("timeout")
        .args([
            "300",
            "qemu-system-arm",
            "-machine",
            "netduinoplus2",
            "-cpu",
            "cortex-m4",
            "-nographic",
            "-monitor",
            "none",
            "-serial",
            "none",
        ])
        .args([
            "-semihosting-config",
            "enable=on,target=native",
            "-icount",
            "shift=10,align=off,sleep=off",
            "-kernel",
        ])
        .arg(&elf)
        .output()
        .map_err(|e| SpeedError::Run(e.to_string()))?;
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    if !out.status.success() || !text.contains("\ndone") {
        return Err(SpeedError::Run(format!(
            "exit {:?}, output:\n{text}",
            out.status.code()
        )));
    }
    parse_target(&text, &host_checksums()).map_err(SpeedError::Run)
}

/// Parses the harness's output against the host's checksums.
///
/// # Errors
/// A message naming the malformed line.
pub fn parse_target(text: &str, host: &[(&str, u64)]) -> Result<Vec<TargetKernel>, String> {
    let mut per_instr = None;
    let mut empty = 0.0;
    let mut out = vec![];
    for line in text.lines() {
        let f: Vec<&str> = line.split_whitespace().collect();
        let num = |i: usize, what: &str| -> Result<f64, String> {
            f[i].parse().map_err(|_| format!("{what} `{line}`"))
        };
        match f.first() {
            Some(&"calib") if f.len() == 3 => {
                let e = num(1, "bad calib line")?;
                let n = num(2, "bad calib line")?;
                per_instr = Some((n - e) / 1000.0);
                empty = e;
            }
            Some(&"kernel") if f.len() == 8 => {
                let r = per_instr.ok_or("kernel line before the calib line")?;
                let samples = num(2, "bad kernel line")?;
                let ticks = num(4, "bad kernel line")?;
                let sum = u64::from_str_radix(f[5], 16)
                    .map_err(|_| format!("bad checksum in `{line}`"))?;
                let bit_exact = host.iter().any(|(n, s)| *n == f[1] && *s == sum);
                let cycles = num(6, "bad cycle count in")?;
                let blocks = num(3, "bad kernel line")?;
                let most = num(7, "bad kernel line")?;
                out.push(TargetKernel {
                    name: f[1].to_string(),
                    // Net of the empty timed region (the call and the SysTick reads) per
                    // block: it matters for the device kernels' blocks of 3 and 20.
                    instructions_per_sample: (ticks - blocks * empty) / r / samples,
                    checksum: f[5].to_string(),
                    bit_exact,
                    cycles_per_sample: (cycles > 0.0).then(|| cycles / samples),
                    block_samples: samples / blocks,
                    worst_block_instructions: (most - empty) / r,
                });
            }
            _ => {}
        }
    }
    if out.len() != host.len() {
        return Err(format!(
            "{} kernels reported, {} expected",
            out.len(),
            host.len()
        ));
    }
    Ok(out)
}

/// Host nanoseconds per sample of each kernel and of the f64 twin: best of five runs over
/// `n` samples.
pub fn host_ns(n: usize) -> Vec<(&'static str, f64)> {
    let codes = trace(n);
    // Best of five runs of `f`, which returns the samples it ran.
    let best = |f: &mut dyn FnMut() -> usize| {
        (0..5)
            .map(|_| {
                let t = Instant::now();
                let samples = f();
                t.elapsed().as_secs_f64() / samples as f64
            })
            .fold(f64::MAX, f64::min)
            * 1e9
    };
    let mut out: Vec<(&'static str, f64)> = kernels()
        .into_iter()
        .map(|(name, mut k)| {
            let mut sum = Checksum::default();
            let ns = best(&mut || run_blocks(k.as_mut(), &codes, &mut sum));
            std::hint::black_box(sum);
            (name, ns)
        })
        .collect();
    let mut f = twin_axis(true, 2048.0);
    let ns = best(&mut || {
        for &c in &codes {
            f.update(c);
        }
        codes.len()
    });
    std::hint::black_box(f.position());
    out.push(("f64_twin", ns));
    out
}

fn twin_axis(filter: bool, bias: f64) -> twin::Axis {
    twin::Axis {
        lowpass: filter.then(|| twin::Lowpass::ideal(50.0 / 3000.0, bias)),
        bias,
        integrator: twin::Integrator::new(twin::Scheme::Euler),
    }
}

/// A configuration of the speed table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    /// The device's path: Q16, i64/i128, 50 Hz low-pass, Euler, one sample at a time.
    Default,
    /// The same arithmetic a block at a time ([`imu_core::Axis::update_block`]): one pass
    /// per USB poll, bit for bit the default's outputs.
    Block,
    /// The same without the low-pass.
    NoFilter,
    /// The same with the trapezoid.
    Trapezoid,
    /// Q8 bias, i32/i64, no filter.
    Narrow,
    /// f32 throughout, with the low-pass.
    F32,
    /// The f64 twin itself (the ground truth's implementation).
    F64,
    /// The device's whole path at 3 kHz (`device_3khz`: the tracker with drift control),
    /// per axis-sample. Its error is not the arithmetic's: drift control's stops and starts
    /// are decisions, measured on scenes (`cargo lab mouse`, docs/drift-control.md).
    Tracker,
}

impl Variant {
    /// All of them, in table order.
    pub const ALL: [Variant; 8] = [
        Self::Default,
        Self::Block,
        Self::NoFilter,
        Self::Trapezoid,
        Self::Narrow,
        Self::F32,
        Self::F64,
        Self::Tracker,
    ];

    /// The variants whose error is measured: all but the f64 twin, which is the reference.
    pub const MEASURED: [Variant; 6] = [
        Self::Default,
        Self::Block,
        Self::NoFilter,
        Self::Trapezoid,
        Self::Narrow,
        Self::F32,
    ];

    /// Name in the table and JSON.
    pub fn name(self) -> &'static str {
        match self {
            Self::Default => "default (Q16, i64/i128, low-pass, Euler)",
            Self::Block => "default, a block per USB poll",
            Self::NoFilter => "default without low-pass",
            Self::Trapezoid => "default with trapezoid",
            Self::Narrow => "narrow (Q8, i32/i64, no filter)",
            Self::F32 => "f32 (low-pass, Euler)",
            Self::F64 => "f64 twin (the reference)",
            Self::Tracker => "device path, drift control (per axis)",
        }
    }

    /// The target kernel that measures it.
    pub fn kernel(self) -> Option<&'static str> {
        match self {
            Self::Default => Some("pipeline_axis"),
            Self::Block => Some("pipeline_block"),
            Self::NoFilter => Some("pipeline_axis_nofilter"),
            Self::Trapezoid => Some("pipeline_axis_trapezoid"),
            Self::Narrow => Some("narrow_pipeline"),
            Self::F32 => Some("f32_pipeline"),
            Self::F64 => None,
            Self::Tracker => Some("device_3khz"),
        }
    }

    /// Axis-samples per sample of its kernel: 3 for the device path (a kernel sample is a
    /// triple), 1 otherwise.
    pub fn axes_per_kernel_sample(self) -> f64 {
        match self {
            Self::Tracker => 3.0,
            _ => 1.0,
        }
    }
}

/// Times at which errors are reported [s].
pub const ERROR_TIMES_S: [f64; 3] = [1.0, 60.0, 3600.0];

/// RMS position error of each variant against the f64 ground truth at [`ERROR_TIMES_S`]
/// up to `max_t_s` (the others are `None`) [m]. The f64 twin is that ground truth: its errors
/// are not measured, and are `None` at every time.
pub fn errors(trials: u64, max_t_s: f64) -> Vec<(Variant, Vec<Option<f64>>)> {
    let times: Vec<f64> = ERROR_TIMES_S
        .iter()
        .copied()
        .filter(|&t| t <= max_t_s)
        .collect();
    errors_at(trials, &times)
        .into_iter()
        .map(|(v, e)| {
            let mut e: Vec<Option<f64>> = e.into_iter().map(Some).collect();
            e.resize(ERROR_TIMES_S.len(), None);
            (v, e)
        })
        .chain([Variant::F64, Variant::Tracker].map(|v| (v, vec![None; ERROR_TIMES_S.len()])))
        .collect()
}

/// RMS position error of each measured variant ([`Variant::MEASURED`]) against the f64 ground
/// truth at each of `times` (ascending, whole samples at 3 kHz) [m].
pub fn errors_at(trials: u64, times: &[f64]) -> Vec<(Variant, Vec<f64>)> {
    let sc = scene::catalogue()
        .into_iter()
        .find(|s| s.name == "adxl335-rest")
        .expect("scene exists");
    let fs = 3000.0;
    let lsb = scene::ADXL335_LSB;
    let n_max = (times.last().copied().unwrap_or(0.0) * fs).round() as usize;
    let mut sq = vec![vec![0.0; times.len()]; Variant::MEASURED.len()];
    for trial in 0..trials {
        let mut rng = noise::rng(0x5EED ^ trial);
        let mut run = sc.start(&mut rng);
        let window: Vec<u16> = (0..3000).map(|_| run.next_code(&mut rng)).collect();
        let (mean, _) = twin::calibrate(&window);
        let cfg = |filter: bool, scheme: Scheme| kernels::settings(filter, scheme);
        let mut cal = cfg(true, Scheme::Euler).calibrator();
        window.iter().for_each(|&c| cal.push(AdcCode(c)));
        let bias_q16 = cal.finish().map_or(2048 << 16, |c| c.bias_q16);
        let settings = [
            cfg(true, Scheme::Euler),
            cfg(false, Scheme::Euler),
            cfg(true, Scheme::Trapezoid),
        ];
        let mut axes = [Axis::new(bias_q16); 3];
        // The block-wise default: codes gathered for a USB poll (3 samples) and passed at once.
        let mut block_axis = Axis::new(bias_q16);
        let mut pending = Vec::with_capacity(3);
        let mut narrow = NarrowPipeline::new((mean * 256.0).round() as i32);
        let mean32 = window.iter().map(|&c| f32::from(c)).sum::<f32>() / 3000.0;
        let k32 = settings[0].lowpass_k_q32() as f32 / 4_294_967_296.0;
        let mut f32p = F32Pipeline::new(Some(k32), mean32);
        let mut truth = [twin_axis(true, mean), twin_axis(false, mean)];
        let mut trap_truth = twin::Axis {
            integrator: twin::Integrator::new(twin::Scheme::Trapezoid),
            ..twin_axis(true, mean)
        };
        let mut next_t = 0;
        for n in 1..=n_max {
            let c = run.next_code(&mut rng);
            for (a, s) in axes.iter_mut().zip(&settings) {
                a.update(s, AdcCode(c));
            }
            pending.push(AdcCode(c));
            if pending.len() == 3 {
                block_axis.update_block(&settings[0], pending.drain(..));
            }
            narrow.update(c);
            f32p.update(c);
            truth[0].update(c);
            truth[1].update(c);
            trap_truth.update(c);
            if next_t < times.len() && n == (times[next_t] * fs).round() as usize {
                let to_m = lsb / (fs * fs);
                let unit = settings[0].metres_per_position_unit();
                let t_on = truth[0].position() * to_m;
                let t_off = truth[1].position() * to_m;
                // The trapezoid integrates one step fewer here (its first sample primes it).
                let t_trap = trap_truth.position() * to_m;
                // The times are whole polls at 3 kHz: the block-wise axis is up to date.
                let got = [
                    axes[0].integrator().position() as f64 * unit - t_on,
                    block_axis.integrator().position() as f64 * unit - t_on,
                    axes[1].integrator().position() as f64 * unit - t_off,
                    axes[2].integrator().position() as f64 * unit - t_trap,
                    narrow.s as f64 / 256.0 * to_m - t_off,
                    f64::from(f32p.s) * to_m - t_on,
                ];
                for (v, e) in got.iter().enumerate() {
                    sq[v][next_t] += e * e;
                }
                next_t += 1;
            }
        }
    }
    Variant::MEASURED
        .iter()
        .zip(sq)
        .map(|(&v, s)| (v, s.iter().map(|x| (x / trials as f64).sqrt()).collect()))
        .collect()
}

/// The ADXL335's own noise error at `t` [m]: `ND t^1.5 / sqrt 6`, ND = 300 ug/sqrt(Hz).
pub fn sensor_noise_m(t: f64) -> f64 {
    300e-6 * 9.806_65 * t.powf(1.5) / 6f64.sqrt()
}

/// One row of the speed-against-error table.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Config {
    /// Configuration.
    pub name: &'static str,
    /// Host time per axis-sample [ns].
    pub host_ns_per_sample: f64,
    /// Target instructions per axis-sample (read-outs at the 1 kHz poll included), if
    /// measured.
    pub target_instructions_per_sample: Option<f64>,
    /// RMS error against f64 at 1 s, 60 s, 3600 s [m].
    pub err_m: std::collections::BTreeMap<String, Option<f64>>,
    /// The same as fractions of the sensor's own noise error.
    pub err_over_sensor_noise: std::collections::BTreeMap<String, Option<f64>>,
}

/// The device-path kernels, their sampling rates [Hz] and whether drift control is on.
pub const DEVICE_KERNELS: [(&str, u32, bool); 3] = [
    ("device_3khz", 3000, true),
    ("device_20khz", 20_000, true),
    ("device_3khz_nodrift", 3000, false),
];
/// The core clock [Hz] the shares are taken of (`firmware/src/board.rs`).
pub const CORE_HZ: f64 = 96e6;

/// The device's sample path at one rate, as measured in QEMU.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DeviceRow {
    /// Sampling rate [Hz].
    pub fs_hz: u32,
    /// Whether drift control is on (the default).
    pub drift: bool,
    /// Sample triples per DMA block.
    pub block: f64,
    /// Instructions per sample triple, mean over the trace (rest, strokes, clicks).
    pub instructions_per_triple: f64,
    /// Instructions of the costliest DMA block.
    pub worst_block_instructions: f64,
    /// A block's deadline in core clock cycles (its duration at 96 MHz).
    pub deadline_cycles: f64,
    /// Mean share of the core, `instructions_per_triple * fs / 96 MHz` (instructions count
    /// at least one cycle each: a lower bound).
    pub cpu_share: f64,
    /// The worst block's share of its deadline (a lower bound, as above).
    pub worst_block_share: f64,
}

/// The device rows of the target's kernels.
pub fn device_rows(t: &[TargetKernel]) -> Vec<DeviceRow> {
    DEVICE_KERNELS
        .iter()
        .filter_map(|&(name, fs, drift)| {
            let k = t.iter().find(|k| k.name == name)?;
            let deadline = k.block_samples / f64::from(fs) * CORE_HZ;
            Some(DeviceRow {
                fs_hz: fs,
                drift,
                block: k.block_samples,
                instructions_per_triple: k.instructions_per_sample,
                worst_block_instructions: k.worst_block_instructions,
                deadline_cycles: deadline,
                cpu_share: k.instructions_per_sample * f64::from(fs) / CORE_HZ,
                worst_block_share: k.worst_block_instructions / deadline,
            })
        })
        .collect()
}

/// The target part of the report.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Target {
    /// The emulated machine.
    pub machine: &'static str,
    /// Instructions per sample of every kernel (per sample triple for `device_*`).
    pub instructions_per_sample: std::collections::BTreeMap<String, f64>,
    /// The device's sample path at 3 kHz and at 20 kHz.
    pub device: Vec<DeviceRow>,
    /// Whether every checksum matched the host's.
    pub bit_exact: bool,
}

/// The whole report.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Report {
    /// QEMU results, if run.
    pub target: Option<Target>,
    /// Host ns per sample of every kernel and the f64 twin.
    pub host: std::collections::BTreeMap<String, f64>,
    /// The table.
    pub configs: Vec<Config>,
}

/// Assembles the report (errors over `trials` trials up to `max_t_s`).
pub fn report(target: Option<Vec<TargetKernel>>, trials: u64, max_t_s: f64) -> Report {
    let host: std::collections::BTreeMap<String, f64> = host_ns(1 << 20)
        .into_iter()
        .map(|(k, v)| (k.to_string(), v))
        .collect();
    let errs = errors(trials, max_t_s);
    let key = |t: f64| format!("{}s", t as u64);
    let configs = errs
        .into_iter()
        .map(|(v, e)| {
            let kernel = v.kernel();
            let host_key = kernel.unwrap_or("f64_twin");
            let per = v.axes_per_kernel_sample();
            Config {
                name: v.name(),
                host_ns_per_sample: host.get(host_key).copied().unwrap_or(f64::NAN) / per,
                target_instructions_per_sample: target.as_ref().and_then(|t| {
                    kernel.and_then(|k| {
                        t.iter()
                            .find(|x| x.name == k)
                            .map(|x| x.instructions_per_sample / per)
                    })
                }),
                err_m: ERROR_TIMES_S
                    .iter()
                    .zip(&e)
                    .map(|(&t, x)| (key(t), *x))
                    .collect(),
                err_over_sensor_noise: ERROR_TIMES_S
                    .iter()
                    .zip(&e)
                    .map(|(&t, x)| (key(t), x.map(|x| x / sensor_noise_m(t))))
                    .collect(),
            }
        })
        .collect();
    Report {
        target: target.map(|t| Target {
            machine: "qemu-system-arm netduinoplus2 (Cortex-M4F), -icount shift=10",
            bit_exact: t.iter().all(|k| k.bit_exact),
            device: device_rows(&t),
            instructions_per_sample: t
                .into_iter()
                .map(|k| (k.name, k.instructions_per_sample))
                .collect(),
        }),
        host,
        configs,
    }
}

/// The Pareto plot: error at the longest time against target instructions per sample.
pub fn pareto(r: &Report) -> Option<Plot> {
    let pts: Vec<(f64, f64, &str)> = r
        .configs
        .iter()
        .filter_map(|c| {
            let x = c.target_instructions_per_sample?;
            // The longest time measured (keys are strings: order by ERROR_TIMES_S, not by key).
            let y = ERROR_TIMES_S
                .iter()
                .rev()
                .find_map(|&t| c.err_m.get(&format!("{}s", t as u64)).copied().flatten())?;
            Some((x, y.max(1e-12), c.name))
        })
        .collect();
    if pts.is_empty() {
        return None;
    }
    let colors = [
        "#1f77b4", "#2ca02c", "#9467bd", "#d62728", "#ff7f0e", "#8c564b",
    ];
    Some(Plot {
        title: "Speed against error: Cortex-M4 instructions vs error at the longest T".into(),
        x_label: "instructions per sample (QEMU)".into(),
        y_label: "RMS position error vs f64 [m]".into(),
        lines: vec![Line {
            label: "the sensor's own noise error at that T".into(),
            color: "#999999",
            dashed: true,
            pts: {
                let t = ERROR_TIMES_S
                    .iter()
                    .copied()
                    .rfind(|&t| {
                        r.configs.iter().any(|c| {
                            c.err_m
                                .get(&format!("{}s", t as u64))
                                .is_some_and(Option::is_some)
                        })
                    })
                    .unwrap_or(1.0);
                vec![(5.0, sensor_noise_m(t)), (500.0, sensor_noise_m(t))]
            },
        }],
        points: pts
            .iter()
            .zip(colors.iter().cycle())
            .map(|(&(x, y, name), &color)| Points {
                label: name.to_string(),
                color,
                pts: vec![(x, y, y, y)],
            })
            .collect(),
        marks: vec![],
    })
}

/// The report as text.
pub fn table(r: &Report) -> String {
    let mut out = String::new();
    if let Some(t) = &r.target {
        out += &format!(
            "target: {} ({})\n",
            t.machine,
            if t.bit_exact {
                "all checksums bit-exact with the host"
            } else {
                "CHECKSUM MISMATCH"
            }
        );
        out += "  instructions, not cycles: QEMU does not model the pipeline (its DWT CYCCNT reads 0)\n";
        let base = t
            .instructions_per_sample
            .get("baseline")
            .copied()
            .unwrap_or(0.0);
        for (k, v) in &t.instructions_per_sample {
            out += &format!("  {k:<26} {v:>7.1} instructions/sample  ({:>6.1} net of the {base:.1}-instruction loop)\n", v - base);
        }
        out += "\nthe device's sample path (Tracker::feed as the firmware runs it: drift control, 3 axes,\n\
                one DMA block per call, counts taken per block; rest, strokes and a click):\n";
        for d in &t.device {
            out += &format!(
                "  {:>5} Hz{}, {:>2.0} triples/block: {:>7.1} instructions per triple ({:.1} per axis-sample); \
                 CPU >= {:.1} %; worst block {:.0} of {:.0} cycles (>= {:.1} % of its deadline)\n",
                d.fs_hz,
                if d.drift { "" } else { " without drift control" },
                d.block,
                d.instructions_per_triple,
                d.instructions_per_triple / 3.0,
                100.0 * d.cpu_share,
                d.worst_block_instructions,
                d.deadline_cycles,
                100.0 * d.worst_block_share
            );
        }
    }
    out += &format!(
        "\n{:<42} {:>10} {:>12} {:>11} {:>11} {:>11} {:>9}\n",
        "configuration", "host ns", "M4 instr", "err 1 s", "err 60 s", "err 1 h", "1 h/noise"
    );
    for c in &r.configs {
        let e = |k: &str| {
            c.err_m
                .get(k)
                .copied()
                .flatten()
                .map_or("-".to_string(), |v| format!("{v:.3e}"))
        };
        let f = c
            .err_over_sensor_noise
            .get("3600s")
            .copied()
            .flatten()
            .map_or("-".to_string(), |v| format!("{v:.2e}"));
        let instr = c
            .target_instructions_per_sample
            .map_or("-".to_string(), |v| format!("{v:.1}"));
        out += &format!(
            "{:<42} {:>10.2} {:>12} {:>11} {:>11} {:>11} {:>9}\n",
            c.name,
            c.host_ns_per_sample,
            instr,
            e("1s"),
            e("60s"),
            e("3600s"),
            f
        );
    }
    out += &format!(
        "errors: rms over trials against the f64 twin (ideal coefficient, f64 mean bias); sensor noise at 1 h: {:.1} m\n",
        sensor_noise_m(3600.0)
    );
    out
}

/// One example, for `cargo lab` alone.
pub const EXAMPLE: &str = "cargo lab speed --host-only --max-t 60";

/// `cargo lab speed`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Skip the QEMU run (no instruction counts).
    #[arg(long)]
    pub host_only: bool,
    /// Trials for the error columns.
    #[arg(long, default_value_t = 3)]
    pub trials: u64,
    /// Measure errors only up to this T [s] (3600 for the full table).
    #[arg(long, allow_negative_numbers = true, default_value_t = 3600.0)]
    pub max_t: f64,
    /// Directory for the Pareto plot.
    #[arg(long, default_value = "target/lab/speed")]
    pub out: std::path::PathBuf,
    /// Print JSON instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// Runs `cargo lab speed`.
///
/// # Errors
/// A bad argument; the QEMU harness failing to build or run; [`super::Error::Check`] when the
/// target's checksums differ from the host's.
pub fn run(a: &Args) -> super::Outcome {
    super::folder("out", &a.out)?;
    if a.trials == 0 {
        return Err(super::Error::arg("trials", 0, "at least one trial"));
    }
    super::positive("max-t", a.max_t)?;
    let workspace = Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .ok_or_else(|| super::Error::Run("no workspace directory".into()))?;
    let bar = super::progress(0, a.json, "");
    let target = if a.host_only {
        None
    } else {
        bar.set_message("building and running the QEMU harness");
        Some(run_target(workspace).map_err(|e| super::Error::Run(e.to_string()))?)
    };
    bar.set_message("host timing and errors against f64");
    let report = report(target, a.trials, a.max_t);
    bar.finish_and_clear();
    if let Some(plot) = pareto(&report) {
        super::write_out(&a.out, "pareto.svg", &plot.to_svg())?;
    }
    let mismatch = report.target.as_ref().is_some_and(|t| !t.bit_exact);
    let text = if a.json {
        serde_json::to_string_pretty(&report)?
    } else {
        table(&report)
    };
    if mismatch {
        return Err(super::Error::Check {
            report: text,
            why: "target and host checksums differ".into(),
        });
    }
    Ok(text)
}
