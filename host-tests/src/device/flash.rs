//! The twin's flash: the board's two 16 KiB store sectors in memory, kept in a file across
//! runs of the twin, behind the same `embedded-storage-async` NOR flash traits as the board's
//! (`firmware/src/storage.rs`): 4-byte writes that may only clear bits, 16 KiB erases to
//! 0xFF, out-of-range and misaligned operations refused.
//!
//! # Design
//! The image is written back to its file after every write and erase, so killing the twin at
//! any moment keeps what the flash held (a flash keeps its bits without power). An image
//! file of the wrong size is not the twin's: it is refused rather than overwritten.

use std::path::{Path, PathBuf};

use embedded_storage_async::nor_flash::{
    ErrorType, NorFlash, NorFlashError, NorFlashErrorKind, ReadNorFlash,
};

/// Bytes of the store: two 16 KiB sectors, as the board's.
pub const CAPACITY: usize = 2 * PAGE;
/// Erase unit [bytes].
pub const PAGE: usize = 16 * 1024;

/// A flash operation refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FlashError {
    /// Outside the store.
    OutOfBounds,
    /// Not aligned to the write or erase unit.
    NotAligned,
    /// A write would set a bit that is 0 (NOR flash can only clear bits before an erase).
    NotErased,
    /// The image file could not be written.
    File,
}

impl NorFlashError for FlashError {
    fn kind(&self) -> NorFlashErrorKind {
        match self {
            Self::OutOfBounds => NorFlashErrorKind::OutOfBounds,
            Self::NotAligned => NorFlashErrorKind::NotAligned,
            Self::NotErased | Self::File => NorFlashErrorKind::Other,
        }
    }
}

/// The store's sectors, optionally backed by an image file.
#[derive(Debug)]
pub struct FileFlash {
    bytes: Vec<u8>,
    file: Option<PathBuf>,
}

impl FileFlash {
    /// An erased flash kept only in memory.
    pub fn blank() -> Self {
        Self {
            bytes: vec![0xFF; CAPACITY],
            file: None,
        }
    }

    /// The flash kept in `path`: its image if the file exists, else erased (the file is
    /// created at the first write).
    ///
    /// # Errors
    /// The file cannot be read, or is not a store image ([`CAPACITY`] bytes).
    pub fn open(path: &Path) -> std::io::Result<Self> {
        let bytes = match std::fs::read(path) {
            Ok(b) if b.len() == CAPACITY => b,
            Ok(b) => {
                return Err(std::io::Error::new(
                    std::io::ErrorKind::InvalidData,
                    format!(
                        "{}: {} bytes, a store image has {CAPACITY}",
                        path.display(),
                        b.len()
                    ),
                ))
            }
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => vec![0xFF; CAPACITY],
            Err(e) => return Err(e),
        };
        Ok(Self {
            bytes,
            file: Some(path.to_owned()),
        })
    }

    /// The image.
    pub fn bytes(&self) -> &[u8] {
        &self.bytes
    }

    fn range(offset: u32, len: usize, unit: usize) -> Result<std::ops::Range<usize>, FlashError> {
        let start = offset as usize;
        let end = start.checked_add(len).ok_or(FlashError::OutOfBounds)?;
        if end > CAPACITY {
            return Err(FlashError::OutOfBounds);
        }
        if !start.is_multiple_of(unit) || !len.is_multiple_of(unit) {
            return Err(FlashError::NotAligned);
        }
        Ok(start..end)
    }

    fn persist(&self) -> Result<(), FlashError> {
        match &self.file {
            Some(path) => std::fs::write(path, &self.bytes).map_err(|_| FlashError::File),
            None => Ok(()),
        }
    }
}

impl ErrorType for FileFlash {
    type Error = FlashError;
}

impl ReadNorFlash for FileFlash {
    const READ_SIZE: usize = 1;

    async fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), FlashError> {
        let r = Self::range(offset, bytes.len(), 1)?;
        bytes.copy_from_slice(&self.bytes[r]);
        Ok(())
    }

    fn capacity(&self) -> usize {
        CAPACITY
    }
}

impl NorFlash for FileFlash {
    const WRITE_SIZE: usize = 4;
    const ERASE_SIZE: usize = PAGE;

    async fn erase(&mut self, from: u32, to: u32) -> Result<(), FlashError> {
        let len = to.checked_sub(from).ok_or(FlashError::OutOfBounds)? as usize;
        let r = Self::range(from, len, PAGE)?;
        self.bytes[r].fill(0xFF);
        self.persist()
    }

    async fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), FlashError> {
        let r = Self::range(offset, bytes.len(), Self::WRITE_SIZE)?;
        if self.bytes[r.clone()]
            .iter()
            .zip(bytes)
            .any(|(old, new)| new & !old != 0)
        {
            return Err(FlashError::NotErased);
        }
        self.bytes[r].copy_from_slice(bytes);
        self.persist()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use imu_app::store::block_on;

    #[test]
    fn writes_only_clear_bits_and_erase_sets_them() {
        let mut f = FileFlash::blank();
        block_on(f.write(4, &[0x0F, 0xF0, 0x00, 0xFF])).expect("erased");
        assert_eq!(
            block_on(f.write(4, &[0xFF, 0xF0, 0x00, 0xFF])),
            Err(FlashError::NotErased)
        );
        block_on(f.write(4, &[0x0E, 0xF0, 0x00, 0xFF])).expect("clears a bit");
        assert_eq!(block_on(f.write(2, &[0; 4])), Err(FlashError::NotAligned));
        assert_eq!(
            block_on(f.write(CAPACITY as u32 - 4, &[0; 8])),
            Err(FlashError::OutOfBounds)
        );
        assert_eq!(block_on(f.erase(0, 100)), Err(FlashError::NotAligned));
        block_on(f.erase(0, PAGE as u32)).expect("a page");
        assert!(f.bytes()[..PAGE].iter().all(|&b| b == 0xFF));
    }

    #[test]
    fn the_image_survives_in_its_file_and_a_foreign_file_is_refused() {
        let dir = std::env::temp_dir().join(format!("imu-flash-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let path = dir.join("store.bin");
        let _ = std::fs::remove_file(&path);
        let mut f = FileFlash::open(&path).expect("absent: erased");
        block_on(f.write(8, &[1, 2, 3, 4])).expect("erased");
        let g = FileFlash::open(&path).expect("written");
        assert_eq!(&g.bytes()[8..12], &[1, 2, 3, 4]);
        std::fs::write(&path, [0u8; 10]).expect("write");
        assert!(FileFlash::open(&path).is_err());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
