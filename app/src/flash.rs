//! The flash interface's erase and program sequences (STM32F411, RM0383 3.5 and 3.6), apart
//! from its registers, so that their order is tested on the host.
//!
//! # Design
//! The flash interface's error flags (`FLASH_SR`: PGSERR, PGPERR, PGAERR, WRPERR, OPERR,
//! RDERR) stay set until written with 1. A sequence that only reads them after its operation
//! would blame every later operation for one stray error, so every operation here:
//!
//! 1. waits until the interface is idle (`BSY` clear: no operation may start while one runs);
//! 2. clears every error flag (and `EOP`);
//! 3. selects the operation (sector erase: `SER`, `SNB`, `PSIZE`; programming: `PG`, `PSIZE`)
//!    in one write, and only then starts it (`STRT` for an erase, the byte writes for
//!    programming), as RM0383 3.5.3 orders it;
//! 4. waits until idle again, reads the error flags, deselects the operation (`SER`, `PG`
//!    clear), and clears the flags it reports, so the next operation starts clean.
//!
//! Programming is byte by byte (`PSIZE` x8, the only parallelism valid at any supply voltage),
//! each byte waited for. The board implements [`FlashInterface`] over the registers
//! (`firmware/src/storage.rs`); the tests here implement it over a model that keeps its
//! error flags sticky, as the hardware does.

/// The flash interface's registers, as the sequences use them.
pub trait FlashInterface {
    /// Whether an operation is in progress (`FLASH_SR.BSY`).
    fn busy(&self) -> bool;
    /// The error flags set, as a mask (0: none): bit 0 OPERR, 1 WRPERR, 2 PGAERR, 3 PGPERR,
    /// 4 PGSERR, 5 RDERR (`FLASH_SR` bits 1, 4, 5, 6, 7, 8 on the F411).
    fn errors(&self) -> u8;
    /// Writes 1 to every error flag and to `EOP`, which clears them.
    fn clear_errors(&mut self);
    /// Selects a sector erase of sector `snb` at x8 parallelism, not started (`FLASH_CR`:
    /// `SER`, `SNB`, `PSIZE`; `PG` clear).
    fn select_erase(&mut self, snb: u8);
    /// Starts the selected erase (`FLASH_CR.STRT`).
    fn start(&mut self);
    /// Selects programming at x8 parallelism (`FLASH_CR`: `PG`, `PSIZE`; `SER` clear).
    fn select_program(&mut self);
    /// Writes `byte` to the flash at absolute address `addr` (a bus write that programs it).
    fn write(&mut self, addr: usize, byte: u8);
    /// Deselects both operations (`FLASH_CR`: `SER`, `PG` clear).
    fn deselect(&mut self);
}

/// An erase or program that the flash interface reported as failed: its error flags,
/// as [`FlashInterface::errors`] gives them (nonzero). They have been cleared.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FlashFault {
    /// The error flags the operation raised.
    pub errors: u8,
}

/// Erases sector `snb` (see the module docs for the sequence).
///
/// # Errors
/// [`FlashFault`] with the flags the erase raised (write protection, sequence).
pub fn erase(f: &mut impl FlashInterface, snb: u8) -> Result<(), FlashFault> {
    ready(f);
    f.select_erase(snb);
    f.start();
    finish(f)
}

/// Programs `bytes` from absolute address `addr` on, byte by byte, stopping at the first
/// byte the interface reports an error for.
///
/// # Errors
/// [`FlashFault`] with the flags the first failing byte raised.
pub fn program(f: &mut impl FlashInterface, addr: usize, bytes: &[u8]) -> Result<(), FlashFault> {
    ready(f);
    f.select_program();
    for (at, &byte) in (addr..).zip(bytes) {
        f.write(at, byte);
        wait(f);
        if f.errors() != 0 {
            break;
        }
    }
    finish(f)
}

/// Idle, and no error left from before.
fn ready(f: &mut impl FlashInterface) {
    wait(f);
    f.clear_errors();
}

fn wait(f: &impl FlashInterface) {
    while f.busy() {}
}

/// Idle, the operation deselected, its errors reported and cleared.
fn finish(f: &mut impl FlashInterface) -> Result<(), FlashFault> {
    wait(f);
    let errors = f.errors();
    f.deselect();
    if errors == 0 {
        return Ok(());
    }
    f.clear_errors();
    Err(FlashFault { errors })
}
