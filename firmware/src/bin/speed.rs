//! Speed harness for QEMU (`cargo lab speed`): runs the core's benchmark kernels on a
//! deterministic trace, times each block with SysTick, and prints ticks and output
//! checksums over semihosting; the host reproduces the checksums bit for bit.
//!
//! # Design
//! QEMU does not count cycles (DWT CYCCNT reads 0), but with `-icount shift=10` every guest
//! instruction advances virtual time by exactly 1024 ns, and SysTick counts that time. So
//! SysTick ticks are instructions times a fixed ratio, which the harness measures itself
//! on a block of 1000 `nop`s. Counts are exact and deterministic: instructions, not cycles.
//! The harness also reads the DWT cycle counter around each block: 0 in QEMU, real cycles
//! on a board (flash it with `cargo run -p firmware --bin speed --target
//! thumbv7em-none-eabihf --release`; probe-rs shows the semihosting output).
//! Output lines:
//! `calib <ticks of an empty block> <ticks of 1000 nops>`, then per kernel
//! `kernel <name> <samples> <blocks> <ticks> <checksum hex> <cycles> <most ticks in one
//! block>`, then `done`.
#![no_std]
#![no_main]

use cortex_m::peripheral::{syst::SystClkSource, DWT, SYST};
use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use dsp_process::SplitProcess;
use imu_core::bench::kernels::{
    self, Baseline, DevicePath, F32Stage, IntegratorStage, Kernel, LowpassStage, NarrowStage,
    PipelineAxis, PipelineBlock, ReadoutStage,
};
use imu_core::bench::testsignal::{Checksum, Trace};
use imu_core::Scheme;
// The device crate provides the interrupt vector table cortex-m-rt links.
use stm32f4xx_hal as _;

/// Samples per timed block: at most ~60 instructions per sample x 256 x ~172 ticks per
/// instruction stays below SysTick's 2^24.
const BLOCK: usize = 256;
/// Blocks per kernel.
const BLOCKS: usize = 12;
/// Seed of the trace (the host uses the same).
const SEED: u64 = 0x1A2B_3C4D;

/// idsp's first-order low-pass at the same 50 Hz / 3 kHz corner, on Q16 codes.
struct IdspLowpass {
    lp: idsp::Lowpass<1>,
    st: idsp::LowpassState<1>,
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

fn elapsed(start: u32) -> u32 {
    start.wrapping_sub(SYST::get_current()) & 0x00FF_FFFF
}

macro_rules! rep10 {
    ($e:expr) => {
        $e;
        $e;
        $e;
        $e;
        $e;
        $e;
        $e;
        $e;
        $e;
        $e;
    };
}

fn time_kernel(name: &str, kernel: &mut dyn Kernel, codes: &[u16]) {
    let mut sum = Checksum::default();
    let (mut ticks, mut cycles, mut most): (u64, u64, u32) = (0, 0, 0);
    let block_len = BLOCK.min(kernel.max_block());
    for block in codes.chunks_exact(block_len) {
        kernel.prepare(block);
        let c0 = DWT::cycle_count();
        let start = SYST::get_current();
        kernel.run(block, &mut sum);
        let t = elapsed(start);
        ticks += u64::from(t);
        most = most.max(t);
        cycles += u64::from(DWT::cycle_count().wrapping_sub(c0));
    }
    // Only whole blocks run: the samples timed are the blocks' (3072 is not a multiple of 20).
    let blocks = codes.len() / block_len;
    hprintln!(
        "kernel {} {} {} {} {:016x} {} {}",
        name,
        blocks * block_len,
        blocks,
        ticks,
        sum.0,
        cycles,
        most
    );
}

#[inline(never)]
fn empty(_: &[u16], _: &mut Checksum) {}

#[entry]
fn main() -> ! {
    let Some(mut cp) = cortex_m::Peripherals::take() else {
        debug::exit(debug::EXIT_FAILURE);
        halt()
    };
    cp.DCB.enable_trace();
    cp.DWT.enable_cycle_counter();
    cp.SYST.set_clock_source(SystClkSource::Core);
    cp.SYST.set_reload(0x00FF_FFFF);
    cp.SYST.clear_current();
    cp.SYST.enable_counter();

    let mut codes = [0u16; BLOCK * BLOCKS];
    let mut trace = Trace::new(SEED);
    for c in codes.iter_mut() {
        *c = trace.next_code();
    }

    // Calibration: an empty timed region, and 1000 nops.
    let start = SYST::get_current();
    empty(&codes, &mut Checksum::default());
    let t_empty = elapsed(start);
    let start = SYST::get_current();
    rep10!(rep10!(rep10!(cortex_m::asm::nop())));
    let t_nop = elapsed(start);
    hprintln!("calib {} {}", t_empty, t_nop);

    let k = idsp_k();
    let mut idsp_lp = IdspLowpass {
        lp: idsp::Lowpass([k]),
        st: idsp::LowpassState([i64::from(2048 << 16) << 32]),
    };
    time_kernel("baseline", &mut Baseline, &codes);
    time_kernel(
        "pipeline_axis",
        &mut PipelineAxis::new(kernels::settings(true, Scheme::Euler)),
        &codes,
    );
    time_kernel(
        "pipeline_block",
        &mut PipelineBlock::new(kernels::settings(true, Scheme::Euler), 3),
        &codes,
    );
    time_kernel(
        "pipeline_block_20khz",
        &mut PipelineBlock::new(kernels::settings_at(20_000, true, Scheme::Euler), 20),
        &codes,
    );
    time_kernel(
        "pipeline_axis_nofilter",
        &mut PipelineAxis::new(kernels::settings(false, Scheme::Euler)),
        &codes,
    );
    time_kernel(
        "pipeline_axis_trapezoid",
        &mut PipelineAxis::new(kernels::settings(true, Scheme::Trapezoid)),
        &codes,
    );
    time_kernel("lowpass", &mut LowpassStage::default(), &codes);
    time_kernel("idsp_lowpass", &mut idsp_lp, &codes);
    time_kernel(
        "integrator_euler",
        &mut IntegratorStage::new(Scheme::Euler),
        &codes,
    );
    time_kernel(
        "integrator_trapezoid",
        &mut IntegratorStage::new(Scheme::Trapezoid),
        &codes,
    );
    time_kernel("readout", &mut ReadoutStage::default(), &codes);
    time_kernel("f32_pipeline", &mut F32Stage::default(), &codes);
    time_kernel("narrow_pipeline", &mut NarrowStage::default(), &codes);
    time_kernel("device_3khz", &mut DevicePath::new(3000), &codes);
    time_kernel("device_20khz", &mut DevicePath::new(20_000), &codes);
    time_kernel(
        "device_3khz_nodrift",
        &mut DevicePath::without_drift(3000),
        &codes,
    );
    // Once a calibration, for a sensor quieter than the ADC's step (0.406 LSB rms at a
    // code's centre): the quantizer's bound of one axis. Its ~10^5 instructions would wrap
    // the 24-bit SysTick at the core clock, so it and 1000 nops are timed on the external
    // reference (a core clock / 8 in QEMU): `once quantizer_bound TICKS NOP_TICKS R_Q16`,
    // instructions = 1000 TICKS / NOP_TICKS. Not parsed by `cargo lab speed` (run the ELF in
    // QEMU to read it: docs/speed.md).
    cp.SYST.set_clock_source(SystClkSource::External);
    cp.SYST.clear_current();
    let start = SYST::get_current();
    rep10!(rep10!(rep10!(cortex_m::asm::nop())));
    let t_nop_ext = elapsed(start);
    let start = SYST::get_current();
    let r = imu_core::drift::noise::quantizer_bound_q16(
        core::hint::black_box(26_608),
        core::hint::black_box(2048 << 16),
    );
    let t = elapsed(start);
    hprintln!("once quantizer_bound {} {} {}", t, t_nop_ext, r);
    hprintln!("done");
    debug::exit(debug::EXIT_SUCCESS);
    halt()
}

/// idsp's coefficient for a 50 Hz corner at 3 kHz: `k = pi 2^31 f0 / fn`, `fn = fs / 2`,
/// i.e. `pi 2^31 / 30` (its documentation), rounded.
const fn idsp_k() -> i32 {
    224_883_962 // round(3.141592653589793 * 2147483648 / 30)
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    debug::exit(debug::EXIT_FAILURE);
    halt()
}

/// Where execution ends if the semihosting exit returns (no debugger or emulator listening).
fn halt() -> ! {
    loop {
        cortex_m::asm::wfi();
    }
}
