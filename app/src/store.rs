//! The profile kept in flash across power cycles: a `sequential-storage` map over any NOR
//! flash, one key, the profile's record as its value.
//!
//! # Design
//! `sequential-storage` appends each save as a new item with a CRC, and a page is erased only
//! when the map moves on to the next one, so a save that loses power part-way leaves the
//! previous item as the last valid one: the store reads back the old profile or the new one,
//! never a mix (`app/tests/store.rs` cuts the power at every byte of a save).
//!
//! At start-up [`Store::load`] says where the running profile comes from
//! ([`Source`]): nothing stored, the stored one, or the defaults because the store could
//! not be read or the stored profile no longer validates (a firmware update that narrowed a
//! range); the last two are also reported over the configuration interface.
//!
//! The crate's API is async (`embedded-storage-async`); a blocking flash, as the HAL's and
//! the twin's are, completes every operation in its first poll, so [`block_on`] drives it
//! with a no-op waker. A flash that returns `Pending` is polled again at once (busy-wait).

use core::future::Future;
use core::ops::Range;
use core::pin::pin;
use core::task::{Context, Poll, Waker};

use embedded_storage_async::nor_flash::NorFlash;
use imu_core::profile::{Key, Profile, RECORD_LEN};
use imu_core::protocol::Source;
use sequential_storage::cache::{Cache, Uncached};
use sequential_storage::map::{MapConfig, MapStorage};

/// The map key under which the profile is kept.
const PROFILE_KEY: u8 = 1;
/// Work buffer [bytes]: the key (1 byte) and the record, rounded up to the flash's 4-byte
/// words, as `sequential-storage` asks.
const BUFFER_LEN: usize = 256;
/// The map key's serialised length [bytes] (a `u8`).
const KEY_LEN: usize = 1;
const _: () = assert!(BUFFER_LEN >= KEY_LEN + RECORD_LEN && BUFFER_LEN.is_multiple_of(4));

/// Runs `f` to completion, polling with a no-op waker (blocking flash: one poll).
pub fn block_on<F: Future>(f: F) -> F::Output {
    let mut f = pin!(f);
    let mut cx = Context::from_waker(Waker::noop());
    loop {
        if let Poll::Ready(out) = f.as_mut().poll(&mut cx) {
            return out;
        }
    }
}

/// Why a save failed (the store's own error kind; nothing was kept).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum StoreError {
    /// The flash reported an error.
    Flash,
    /// The store is corrupt (it is erased, and the save should be tried again).
    Corrupt,
    /// Any other failure of the map (full, buffer).
    Other,
}

fn error<E>(e: &sequential_storage::Error<E>) -> StoreError {
    match e {
        sequential_storage::Error::Storage { .. } => StoreError::Flash,
        sequential_storage::Error::Corrupted { .. } => StoreError::Corrupt,
        _ => StoreError::Other,
    }
}

/// What [`Store::load`] found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Loaded {
    /// The profile to run.
    pub profile: Profile,
    /// Where it came from.
    pub source: Source,
    /// With [`Source::Invalid`]: the stored key that failed.
    pub invalid: Option<Key>,
}

/// The profile store on the flash `S`, over `range` (whole pages; at least two).
pub struct Store<S: NorFlash> {
    map: MapStorage<u8, S, Cache<Uncached, Uncached, Uncached, u8>>,
    buffer: [u8; BUFFER_LEN],
}

impl<S: NorFlash> Store<S> {
    /// The store on `flash` in `range` [bytes from the flash's start].
    ///
    /// # Errors
    /// The map's configuration error if `range` is not whole pages or is shorter than two.
    pub fn new(
        flash: S,
        range: Range<u32>,
    ) -> Result<Self, sequential_storage::map::MapConfigError> {
        let config = MapConfig::try_new(range)?;
        Ok(Self {
            map: MapStorage::new(flash, config, Cache::new_uncached()),
            buffer: [0; BUFFER_LEN],
        })
    }

    /// The profile to start with and where it came from: the stored one if it reads and
    /// validates, else the defaults with the reason.
    pub fn load(&mut self) -> Loaded {
        let defaults = |source, invalid| Loaded {
            profile: Profile::default(),
            source,
            invalid,
        };
        let stored = block_on(self.map.fetch_item::<&[u8]>(&mut self.buffer, &PROFILE_KEY));
        match stored {
            Ok(None) => defaults(Source::Defaults, None),
            Err(_) => defaults(Source::Corrupt, None),
            Ok(Some(record)) => match Profile::decode(record) {
                Err(_) => defaults(Source::Corrupt, None),
                Ok(p) => match p.validate() {
                    Ok(()) => Loaded {
                        profile: p,
                        source: Source::Stored,
                        invalid: None,
                    },
                    Err(e) => defaults(Source::Invalid, Some(e.key())),
                },
            },
        }
    }

    /// Keeps `profile`. A corrupt store is erased and the save tried once more.
    ///
    /// # Errors
    /// [`StoreError`] if it could not be kept; the previous profile is still stored.
    pub fn save(&mut self, profile: &Profile) -> Result<(), StoreError> {
        let mut record = [0; RECORD_LEN];
        let n = profile.encode(&mut record);
        let value: &[u8] = &record[..n];
        match block_on(self.map.store_item(&mut self.buffer, &PROFILE_KEY, &value)) {
            Ok(()) => Ok(()),
            Err(e) if error(&e) == StoreError::Corrupt => {
                block_on(self.map.erase_all()).map_err(|e| error(&e))?;
                block_on(self.map.store_item(&mut self.buffer, &PROFILE_KEY, &value))
                    .map_err(|e| error(&e))
            }
            Err(e) => Err(error(&e)),
        }
    }

    /// The flash back (for the twin, which keeps its image in a file).
    pub fn into_flash(self) -> S {
        self.map.destroy().0
    }
}
