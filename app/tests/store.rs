//! The profile store: what start-up finds (nothing, the stored profile, a corrupt store, a
//! profile that no longer validates), and power lost at every byte of a save.

use embedded_storage_async::nor_flash::{ErrorType, NorFlash, ReadNorFlash};
use imu_app::store::{Loaded, Store};
use imu_core::profile::{Key, Profile};
use imu_core::protocol::Source;
use sequential_storage::mock_flash::{MockFlashBase, MockFlashError, WriteCountCheck};

/// The board's flash shape (`firmware/src/storage.rs`, `StoreFlash`): byte reads, 4-byte
/// writes, erases of a page, over sequential-storage's mock flash (which reads only in its
/// write unit, and cuts the power). The read size decides how sequential-storage reads a
/// page's state and a record's header, and so how a save cut short is found again.
#[derive(Clone)]
struct Board<const P: usize, const W: usize>(MockFlashBase<P, 4, W>);

impl<const P: usize, const W: usize> ErrorType for Board<P, W> {
    type Error = MockFlashError;
}

impl<const P: usize, const W: usize> ReadNorFlash for Board<P, W> {
    const READ_SIZE: usize = 1;

    async fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), MockFlashError> {
        let start = offset & !3;
        let end = (offset as usize + bytes.len()).next_multiple_of(4);
        let mut words = vec![0u8; end - start as usize];
        self.0.read(start, &mut words).await?;
        let skip = (offset - start) as usize;
        bytes.copy_from_slice(&words[skip..skip + bytes.len()]);
        Ok(())
    }

    fn capacity(&self) -> usize {
        self.0.capacity()
    }
}

impl<const P: usize, const W: usize> NorFlash for Board<P, W> {
    const WRITE_SIZE: usize = 4;
    const ERASE_SIZE: usize = 4 * W;

    async fn erase(&mut self, from: u32, to: u32) -> Result<(), MockFlashError> {
        self.0.erase(from, to).await
    }

    async fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), MockFlashError> {
        self.0.write(offset, bytes).await
    }
}

impl<const P: usize, const W: usize> Board<P, W> {
    const FULL_FLASH_RANGE: core::ops::Range<u32> = MockFlashBase::<P, 4, W>::FULL_FLASH_RANGE;

    fn new() -> Self {
        Self(MockFlashBase::new(WriteCountCheck::OnceOnly, None, true))
    }
}

/// Two pages of 16 KiB, as the F411's sectors 1 and 2 (firmware/memory.x).
type Flash = Board<2, 4096>;
const RANGE: core::ops::Range<u32> = Flash::FULL_FLASH_RANGE;

fn flash() -> Flash {
    Flash::new()
}

fn store(f: Flash) -> Store<Flash> {
    Store::new(f, RANGE).expect("two whole pages")
}

fn profile(cpi: u32) -> Profile {
    let mut p = Profile::default();
    p.set(Key::CountsPerInch, f64::from(cpi)).expect("fits");
    p
}

#[test]
fn an_empty_store_runs_the_defaults_and_says_so() {
    let loaded = store(flash()).load();
    assert_eq!(
        loaded,
        Loaded {
            profile: Profile::default(),
            source: Source::Defaults,
            invalid: None
        }
    );
}

#[test]
fn a_saved_profile_is_found_after_a_restart() {
    let mut s = store(flash());
    s.save(&profile(1600)).expect("saved");
    s.save(&profile(3200)).expect("saved");
    let loaded = store(s.into_flash()).load();
    assert_eq!(loaded.source, Source::Stored);
    assert_eq!(loaded.profile, profile(3200));
}

#[test]
fn a_store_of_garbage_runs_the_defaults_then_saves_again() {
    // With the board's byte reads, sequential-storage reads this pattern as an empty store
    // (with 4-byte reads, the same pattern read as corrupt): either way the defaults run,
    // and the next save erases and writes.
    let mut f = flash();
    for (i, b) in f.0.as_bytes_mut().iter_mut().enumerate() {
        *b = (i * 7 + 3) as u8;
    }
    let mut s = store(f);
    let loaded = s.load();
    assert_eq!(loaded.profile, Profile::default());
    assert_eq!(loaded.source, Source::Defaults);
    s.save(&profile(1600))
        .expect("a corrupt store is erased and written");
    assert_eq!(store(s.into_flash()).load().profile, profile(1600));
}

#[test]
fn a_store_read_as_corrupt_is_erased_by_the_next_save() {
    // sequential-storage's own mock flash reads in its 4-byte write unit, with which the
    // same pattern reads as corrupt: the defaults run, and the save that finds it corrupt
    // erases it and writes (StoreError::Corrupt is the one error a save retries).
    let mut f = MockFlashBase::<2, 4, 4096>::new(WriteCountCheck::OnceOnly, None, true);
    for (i, b) in f.as_bytes_mut().iter_mut().enumerate() {
        *b = (i * 7 + 3) as u8;
    }
    let range = MockFlashBase::<2, 4, 4096>::FULL_FLASH_RANGE;
    let mut s = Store::new(f, range.clone()).expect("two whole pages");
    let loaded = s.load();
    assert_eq!(loaded.profile, Profile::default());
    assert_eq!(loaded.source, Source::Corrupt);
    s.save(&profile(1600))
        .expect("a corrupt store is erased and written");
    let again = Store::new(s.into_flash(), range)
        .expect("two whole pages")
        .load();
    assert_eq!(
        (again.source, again.profile),
        (Source::Stored, profile(1600))
    );
}

#[test]
fn a_stored_profile_that_no_longer_validates_runs_the_defaults_and_names_the_key() {
    // Saved by a firmware that accepted it (adc_bits = 1 was accepted before issue 14).
    let mut bad = Profile::default();
    bad.set(Key::AdcBits, 1.0).expect("fits its kind");
    let mut s = store(flash());
    s.save(&bad).expect("the store does not validate");
    let loaded = store(s.into_flash()).load();
    assert_eq!(loaded.profile, Profile::default());
    assert_eq!(loaded.source, Source::Invalid);
    assert_eq!(loaded.invalid, Some(Key::AdcBits));
}

/// Saves `new` over a flash holding `base`, with the power cut after `cut` bytes of flash
/// operation (writes and erases); returns what the next start-up loads and whether the save
/// said it succeeded.
fn cut_save<const P: usize, const W: usize>(
    base: &Board<P, W>,
    new: &Profile,
    cut: u32,
) -> (Loaded, bool) {
    let range = Board::<P, W>::FULL_FLASH_RANGE;
    let mut f = base.clone();
    f.0.bytes_until_shutoff = Some(cut);
    let mut s = Store::new(f, range.clone()).expect("whole pages");
    let ok = s.save(new).is_ok();
    let mut f = s.into_flash();
    f.0.bytes_until_shutoff = None;
    (Store::new(f, range).expect("whole pages").load(), ok)
}

/// Power lost during a save: the next start-up finds the old profile or the new one, never
/// the defaults, and a save said done has written the new one. Cut at every byte of the
/// save's first and last [`EDGE`] bytes of flash operation (every write of a save not
/// erasing, and the markers and record around an erase) and at every [`STRIDE`]th byte in
/// between (inside a 16 KiB erase, whose bytes are cleared in order and differ only in how
/// much of the old page's data is left: a prime stride meets every phase of the words and
/// records). Returns the cuts that kept the old and the new, and the save's length in bytes.
fn every_cut<const P: usize, const W: usize>(
    base: &Board<P, W>,
    old: &Profile,
    new: &Profile,
) -> (u32, u32, u32) {
    const EDGE: u32 = 512;
    const STRIDE: u32 = 97;
    // The save's length: what a budget that never runs out has left of it afterwards.
    let mut f = base.clone();
    f.0.bytes_until_shutoff = Some(u32::MAX);
    let mut s = Store::new(f, Board::<P, W>::FULL_FLASH_RANGE).expect("whole pages");
    s.save(new).expect("an uncut save");
    let total = u32::MAX - s.into_flash().0.bytes_until_shutoff.expect("never ran out");
    let (mut olds, mut news) = (0, 0);
    let cuts = (0..=total).filter(|&k| k < EDGE || total - k <= EDGE || k % STRIDE == 0);
    for cut in cuts {
        let (loaded, ok) = cut_save(base, new, cut);
        assert_eq!(loaded.source, Source::Stored, "cut at byte {cut}");
        if loaded.profile == *old {
            assert!(
                !ok,
                "cut at byte {cut}: the save said done but the old profile loads"
            );
            olds += 1;
        } else {
            assert_eq!(
                loaded.profile, *new,
                "cut at byte {cut}: neither old nor new"
            );
            news += 1;
        }
        assert_eq!(ok, cut >= total, "cut at byte {cut} of {total}");
    }
    (olds, news, total)
}

#[test]
fn power_lost_at_every_byte_of_a_save_leaves_the_old_or_the_new_profile() {
    let (old, new) = (profile(1600), profile(3200));
    let mut s = store(flash());
    s.save(&old).expect("saved");
    let base = s.into_flash();
    let (olds, news, total) = every_cut(&base, &old, &new);
    // A save that erases nothing is cut at every byte: some cuts keep the old, the last
    // ones the new.
    assert!(total < 512, "{total} bytes");
    assert!(
        olds > 200 && news >= 1,
        "{olds} cuts kept the old, {news} the new"
    );
}

#[test]
fn power_lost_during_a_save_that_erases_a_page_leaves_the_old_or_the_new() {
    // The board's 16 KiB pages: the sweep covers the whole erase, byte by byte.
    type Small = Flash;
    let small = |f: Small| Store::new(f, Small::FULL_FLASH_RANGE).expect("two whole pages");
    // Save until the next save must erase (the map moves on to a page that is not empty).
    let mut s = small(Small::new());
    let mut saves = 0u32;
    let base = loop {
        let old = profile(1000 + saves);
        s.save(&old).expect("saved");
        saves += 1;
        let before = s.into_flash();
        let mut trial = small(before.clone());
        let stats = before.0.stats_snapshot();
        trial.save(&profile(9999)).expect("saved");
        let erased = stats
            .compare_to(trial.into_flash().0.stats_snapshot())
            .erases
            > 0;
        if erased {
            break before;
        }
        assert!(saves < 1000, "no save erased a page");
        s = small(before);
    };
    let old = profile(1000 + saves - 1);
    let (olds, news, total) = every_cut(&base, &old, &profile(9999));
    // The erase alone is 16 384 bytes of the save.
    assert!(total > 16_384, "{total} bytes");
    assert!(
        olds > 16_384 / 97,
        "{olds} cuts kept the old, {news} the new ({saves} saves)"
    );
}

#[test]
fn a_flash_that_fails_is_reported_as_a_flash_error() {
    let mut f = flash();
    f.0.bytes_until_shutoff = Some(0);
    assert_eq!(
        store(f).save(&profile(1600)),
        Err(imu_app::store::StoreError::Flash)
    );
}

#[test]
fn a_sector_is_erased_once_in_76_saves() {
    // 16 KiB pages hold records of 200 bytes (22 keys of 9 bytes and 2 of header) with the
    // key, the map's item header and word alignment, after the page's state words: a save
    // erases only when the map moves on to its other page (docs/device.md,
    // firmware/src/board.rs).
    let at: Vec<u32> = (0..)
        .zip(saves(400))
        .filter(|(_, cost)| cost.erases > 0)
        .map(|(i, _)| i)
        .collect();
    let gaps: Vec<u32> = at.windows(2).map(|w| w[1] - w[0]).collect();
    assert!(gaps.len() >= 3, "erases at {at:?}");
    assert_eq!(imu_core::profile::RECORD_LEN, 200);
    assert!(gaps.iter().all(|&g| g == 76), "erases at {at:?}");
}

/// The flash operations of each of `n` saves in a row from an empty store, each through a
/// store started afresh (as after a reset).
fn saves(n: u32) -> Vec<sequential_storage::mock_flash::FlashStatsResult> {
    let mut f = flash();
    (0..n)
        .map(|i| {
            let before = f.0.stats_snapshot();
            let mut t = store(f.clone());
            t.save(&profile(1000 + i)).expect("saved");
            f = t.into_flash();
            before.compare_to(f.0.stats_snapshot())
        })
        .collect()
}

/// What a save costs the board at worst [ms], from the mock's counts: sequential-storage's
/// CRC over every byte read (bitwise: 7 instructions a bit in the firmware's ELF, counted at
/// 2 cycles each for flash wait states, so 112 cycles a byte at 96 MHz), every byte written
/// at 100 us (DS10314's byte programming time, maximum) and every 16 KiB erase at 800 ms
/// (its maximum at x8).
fn worst_ms(stats: sequential_storage::mock_flash::FlashStatsResult) -> f64 {
    let read_ms = stats.bytes_read as f64 * 112.0 / 96e6 * 1e3;
    let write_ms = stats.bytes_written as f64 * 0.1;
    read_ms + write_ms + stats.erases as f64 * 800.0
}

#[test]
fn the_longest_saves_end_before_the_fastest_watchdog() {
    use imu_app::device::WATCHDOG_MIN_MS;
    // The save that moves the map to its other page (an erase), and the first save on a
    // board whose store sectors hold old code (both erased).
    let worst = saves(200).into_iter().map(worst_ms).fold(0.0, f64::max);
    let mut f = flash();
    for (i, b) in f.0.as_bytes_mut().iter_mut().enumerate() {
        *b = (i * 7 + 3) as u8;
    }
    let before = f.0.stats_snapshot();
    let mut t = store(f);
    t.load();
    t.save(&profile(1600)).expect("saved");
    let first = worst_ms(before.compare_to(t.into_flash().0.stats_snapshot()));
    println!("the page move: {worst:.0} ms, the first save over old code: {first:.0} ms");
    // Every term is a maximum already (the erase's and the programming's data-sheet maxima,
    // two cycles an instruction); a quarter more for what the budget leaves out (the
    // interrupts that run meanwhile).
    for ms in [worst, first] {
        assert!(
            1.25 * ms < f64::from(WATCHDOG_MIN_MS),
            "{ms} ms against {WATCHDOG_MIN_MS} ms"
        );
    }
}
