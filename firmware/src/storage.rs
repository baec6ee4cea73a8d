//! The profile store's flash: sectors 1 and 2 of the F411 (`board::STORE_START..STORE_END`)
//! as an `embedded-storage-async` NOR flash of two 16 KiB pages, for `imu_app::store`.
//!
//! # Design
//! The HAL's own `NorFlash` erases in 128 KiB units (the F4 family's largest sector), which
//! does not fit 16 KiB sectors, so this adapter maps page `k` of the store to sector
//! `STORE_FIRST_SECTOR + k` and offsets to `STORE_START + offset`, refusing anything outside
//! the store or misaligned. Writes are in 4-byte words (as `app/tests/store.rs` models);
//! the HAL programs them byte by byte (x8 parallelism).
//!
//! After an erase the flash interface's caches are reset (the HAL enables them in
//! `freeze`; RM0383 3.5: cached lines of an erased sector would still read the old bytes),
//! as ST's own driver does after every erase.
//!
//! Erase and program run `imu_app::flash`'s sequences (tested on the host) over the
//! registers, not the HAL's `UnlockedFlash`: the HAL never clears the flash interface's
//! sticky error flags, so after one stray error every later save would fail until reset, and
//! its erase writes `STRT` in the same write as `SER`/`SNB` without waiting for `BSY`
//! (RM0383 3.5.3 sets `STRT` after them). The interface is unlocked for each operation and
//! locked again after it.
//!
//! Every operation blocks the CPU until the flash is done (a single-bank part stalls every
//! fetch meanwhile); the async functions never return `Pending`.

use embedded_storage_async::nor_flash::{
    ErrorType, NorFlash, NorFlashError, NorFlashErrorKind, ReadNorFlash,
};
use imu_app::flash::{self, FlashInterface};
use stm32f4xx_hal::{flash::FlashExt, pac::FLASH};

use crate::board::{STORE_END, STORE_FIRST_SECTOR, STORE_PAGE, STORE_START};

/// Bytes the store spans.
const CAPACITY: u32 = STORE_END - STORE_START;

/// Why a flash operation was refused or failed.
#[derive(Clone, Copy, Debug, defmt::Format)]
pub enum FlashError {
    /// Outside the store's sectors.
    OutOfBounds,
    /// Not aligned to the write or erase unit.
    NotAligned,
    /// The flash interface reported an error (programming, write protection).
    Hardware,
}

impl NorFlashError for FlashError {
    fn kind(&self) -> NorFlashErrorKind {
        match self {
            Self::OutOfBounds => NorFlashErrorKind::OutOfBounds,
            Self::NotAligned => NorFlashErrorKind::NotAligned,
            Self::Hardware => NorFlashErrorKind::Other,
        }
    }
}

/// The store's two sectors.
pub struct StoreFlash {
    flash: FLASH,
}

impl StoreFlash {
    /// The store on the flash interface.
    pub fn new(flash: FLASH) -> Self {
        Self { flash }
    }

    /// The absolute offset of `len` bytes at store offset `offset`, both multiples of `unit`.
    fn at(offset: u32, len: usize, unit: u32) -> Result<usize, FlashError> {
        let len = u32::try_from(len).map_err(|_| FlashError::OutOfBounds)?;
        let end = offset.checked_add(len).ok_or(FlashError::OutOfBounds)?;
        if end > CAPACITY {
            return Err(FlashError::OutOfBounds);
        }
        if !offset.is_multiple_of(unit) || !len.is_multiple_of(unit) {
            return Err(FlashError::NotAligned);
        }
        Ok((STORE_START + offset) as usize)
    }

    /// Unlocks the flash interface's control register (RM0383 3.5.1: the two keys in order).
    fn unlock(&mut self) {
        const KEY1: u32 = 0x4567_0123;
        const KEY2: u32 = 0xCDEF_89AB;
        if self.flash.cr().read().lock().bit_is_set() {
            self.flash.keyr().write(|w| w.key().set(KEY1));
            self.flash.keyr().write(|w| w.key().set(KEY2));
        }
    }

    /// Locks it again.
    fn lock(&mut self) {
        self.flash.cr().modify(|_, w| w.lock().set_bit());
    }

    /// Resets the instruction and data caches (disabled while reset, then enabled again).
    fn reset_caches(&mut self) {
        let acr = self.flash.acr();
        acr.modify(|_, w| w.dcen().clear_bit().icen().clear_bit());
        acr.modify(|_, w| w.dcrst().set_bit().icrst().set_bit());
        acr.modify(|_, w| w.dcrst().clear_bit().icrst().clear_bit());
        acr.modify(|_, w| w.dcen().set_bit().icen().set_bit());
    }
}

impl FlashInterface for StoreFlash {
    fn busy(&self) -> bool {
        self.flash.sr().read().bsy().bit_is_set()
    }

    fn errors(&self) -> u8 {
        // Packed as `FlashInterface::errors` documents.
        let sr = self.flash.sr().read();
        [
            sr.operr().bit(),
            sr.wrperr().bit(),
            sr.pgaerr().bit(),
            sr.pgperr().bit(),
            sr.pgserr().bit(),
            sr.rderr().bit(),
        ]
        .iter()
        .enumerate()
        .map(|(i, &set)| u8::from(set) << i)
        .sum()
    }

    fn clear_errors(&mut self) {
        self.flash.sr().write(|w| {
            w.eop().clear();
            w.operr().clear();
            w.wrperr().clear();
            w.pgaerr().clear();
            w.pgperr().clear();
            w.pgserr().clear();
            w.rderr().clear()
        });
    }

    fn select_erase(&mut self, snb: u8) {
        self.flash.cr().modify(|_, w| {
            w.pg().clear_bit();
            w.ser().set_bit();
            #[allow(unsafe_code)]
            // SAFETY: SNB takes any 4-bit value; the store passes its own sectors, 1 and 2.
            unsafe {
                w.snb().bits(snb & 0xF);
            }
            w.psize().psize8()
        });
    }

    fn start(&mut self) {
        self.flash.cr().modify(|_, w| w.strt().set_bit());
    }

    fn select_program(&mut self) {
        self.flash.cr().modify(|_, w| {
            w.ser().clear_bit();
            w.pg().set_bit();
            w.psize().psize8()
        });
    }

    fn write(&mut self, addr: usize, byte: u8) {
        // A byte-wide bus write to the flash array programs that byte (PG set, x8).
        #[allow(unsafe_code)]
        // SAFETY: `addr` is inside the store's sectors (`at` checked it), which no code or
        // data is linked into (memory.x), and the interface is in programming mode.
        unsafe {
            core::ptr::write_volatile(addr as *mut u8, byte);
        }
    }

    fn deselect(&mut self) {
        self.flash
            .cr()
            .modify(|_, w| w.ser().clear_bit().pg().clear_bit());
    }
}

impl ErrorType for StoreFlash {
    type Error = FlashError;
}

impl ReadNorFlash for StoreFlash {
    const READ_SIZE: usize = 1;

    async fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), FlashError> {
        let at = Self::at(offset, bytes.len(), 1)?;
        let src = self
            .flash
            .read()
            .get(at..at + bytes.len())
            .ok_or(FlashError::OutOfBounds)?;
        bytes.copy_from_slice(src);
        Ok(())
    }

    fn capacity(&self) -> usize {
        CAPACITY as usize
    }
}

impl NorFlash for StoreFlash {
    const WRITE_SIZE: usize = 4;
    const ERASE_SIZE: usize = STORE_PAGE as usize;

    async fn erase(&mut self, from: u32, to: u32) -> Result<(), FlashError> {
        let len = to.checked_sub(from).ok_or(FlashError::OutOfBounds)? as usize;
        Self::at(from, len, STORE_PAGE)?;
        for page in (from..to).step_by(STORE_PAGE as usize) {
            let sector = STORE_FIRST_SECTOR + (page / STORE_PAGE) as u8;
            self.unlock();
            let result = flash::erase(self, sector);
            self.lock();
            self.reset_caches();
            result.map_err(|_| FlashError::Hardware)?;
        }
        Ok(())
    }

    async fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), FlashError> {
        let at = Self::at(offset, bytes.len(), Self::WRITE_SIZE as u32)?;
        self.unlock();
        let result = flash::program(self, at, bytes);
        self.lock();
        result.map_err(|_| FlashError::Hardware)
    }
}
