//! Instruction profile of the device's sample path (`firmware/tools/profile.sh`): the
//! speed harness's `device_3khz` kernel ([`DevicePath`] at 3 kHz, the same desk and trace),
//! with nothing else, for QEMU's per-instruction execution log.
//!
//! The harness (`speed.rs`) counts what the path costs; this binary shows where. Run under
//! `qemu-system-arm -singlestep -d exec,nochain`, every executed instruction is one log
//! line with its address; the script counts the lines from the first call of [`mark`] on
//! (after the calibration and the settings' derivation, which are not the sample path) and
//! attributes them to functions and source lines, inlining included. Each block's
//! [`Kernel::prepare`] (the desk's codes, which the DMA writes on a board) is in the count;
//! the script reports it apart.
#![no_std]
#![no_main]

use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use imu_core::bench::kernels::{DevicePath, Kernel};
use imu_core::bench::testsignal::{Checksum, Trace};
// The device crate provides the interrupt vector table cortex-m-rt links.
use stm32f4xx_hal as _;

/// Sample triples profiled: the speed harness's trace length (two periods of the desk).
const SAMPLES: usize = 3072;
/// Triples per block: one DMA block at 3 kHz.
const BLOCK: usize = 3;
/// The speed harness's trace seed.
const SEED: u64 = 0x1A2B_3C4D;

/// Where the profile starts: the script counts from this function's first instruction.
/// Out of line, so that its address is in the log.
#[inline(never)]
fn mark() {
    cortex_m::asm::nop();
}

#[entry]
fn main() -> ! {
    let mut codes = [0u16; SAMPLES];
    let mut trace = Trace::new(SEED);
    for c in codes.iter_mut() {
        *c = trace.next_code();
    }
    let mut kernel = DevicePath::new(3000);
    let mut sum = Checksum::default();
    mark();
    for block in codes.chunks_exact(BLOCK) {
        kernel.prepare(block);
        kernel.run(block, &mut sum);
    }
    hprintln!("checksum {:016x}", sum.0);
    debug::exit(debug::EXIT_SUCCESS);
    halt()
}

/// Where execution ends if the semihosting exit returns (no emulator listening).
fn halt() -> ! {
    loop {
        cortex_m::asm::wfi();
    }
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    debug::exit(debug::EXIT_FAILURE);
    halt()
}
