//! The profile store: what start-up finds (nothing, the stored profile, a corrupt store, a
//! profile that no longer validates), and power lost at every byte of a save.

use imu_app::store::{Loaded, Store};
use imu_core::profile::{Key, Profile};
use imu_core::protocol::Source;
use sequential_storage::mock_flash::{MockFlashBase, WriteCountCheck};

/// Two pages of 16 KiB with 4-byte words, as the F411's sectors 1 and 2 (firmware/memory.x).
type Flash = MockFlashBase<2, 4, 4096>;
const RANGE: core::ops::Range<u32> = Flash::FULL_FLASH_RANGE;

fn flash() -> Flash {
    Flash::new(WriteCountCheck::OnceOnly, None, true)
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
fn a_store_of_garbage_runs_the_defaults_and_says_corrupt_then_saves_again() {
    let mut f = flash();
    for (i, b) in f.as_bytes_mut().iter_mut().enumerate() {
        *b = (i * 7 + 3) as u8;
    }
    let mut s = store(f);
    let loaded = s.load();
    assert_eq!(loaded.profile, Profile::default());
    assert_eq!(loaded.source, Source::Corrupt);
    s.save(&profile(1600))
        .expect("a corrupt store is erased and written");
    assert_eq!(store(s.into_flash()).load().profile, profile(1600));
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
    base: &MockFlashBase<P, 4, W>,
    new: &Profile,
    cut: u32,
) -> (Loaded, bool) {
    let range = MockFlashBase::<P, 4, W>::FULL_FLASH_RANGE;
    let mut f = base.clone();
    f.bytes_until_shutoff = Some(cut);
    let mut s = Store::new(f, range.clone()).expect("whole pages");
    let ok = s.save(new).is_ok();
    let mut f = s.into_flash();
    f.bytes_until_shutoff = None;
    (Store::new(f, range).expect("whole pages").load(), ok)
}

/// Power lost at every byte of a save: the next start-up finds the old profile or the new
/// one, never the defaults, and the store takes the next save.
fn every_cut<const P: usize, const W: usize>(
    base: &MockFlashBase<P, 4, W>,
    old: &Profile,
    new: &Profile,
) -> (u32, u32) {
    let (mut olds, mut news) = (0, 0);
    let mut cut = 0;
    loop {
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
        if ok {
            return (olds, news);
        }
        cut += 1;
    }
}

#[test]
fn power_lost_at_every_byte_of_a_save_leaves_the_old_or_the_new_profile() {
    let (old, new) = (profile(1600), profile(3200));
    let mut s = store(flash());
    s.save(&old).expect("saved");
    let base = s.into_flash();
    let (olds, news) = every_cut(&base, &old, &new);
    // The cut sweep covered the whole save: some cuts keep the old, the last ones the new.
    assert!(
        olds > 200 && news >= 1,
        "{olds} cuts kept the old, {news} the new"
    );
}

#[test]
fn power_lost_at_every_byte_of_a_save_that_erases_a_page_leaves_the_old_or_the_new() {
    // Pages of 1 KiB (three records each), so that the sweep over the erase stays short;
    // the map's logic does not depend on the page size.
    type Small = MockFlashBase<2, 4, 256>;
    let small = |f: Small| Store::new(f, Small::FULL_FLASH_RANGE).expect("two whole pages");
    // Save until the next save must erase (the map moves on to a page that is not empty).
    let mut s = small(Small::new(WriteCountCheck::OnceOnly, None, true));
    let mut saves = 0u32;
    let base = loop {
        let old = profile(1000 + saves);
        s.save(&old).expect("saved");
        saves += 1;
        let before = s.into_flash();
        let mut trial = small(before.clone());
        let stats = before.stats_snapshot();
        trial.save(&profile(9999)).expect("saved");
        let erased = stats.compare_to(trial.into_flash().stats_snapshot()).erases > 0;
        if erased {
            break before;
        }
        assert!(saves < 1000, "no save erased a page");
        s = small(before);
    };
    let old = profile(1000 + saves - 1);
    let (olds, news) = every_cut(&base, &old, &profile(9999));
    // The erase alone is 1024 bytes of the sweep.
    assert!(
        olds > 1024,
        "{olds} cuts kept the old, {news} the new ({saves} saves)"
    );
}

#[test]
fn a_flash_that_fails_is_reported_as_a_flash_error() {
    let mut f = flash();
    f.bytes_until_shutoff = Some(0);
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
    let mut s = store(flash());
    let mut at = Vec::new();
    for i in 0..400u32 {
        let f = s.into_flash();
        let before = f.stats_snapshot();
        let mut t = store(f);
        t.save(&profile(1000 + i)).expect("saved");
        let f = t.into_flash();
        if before.compare_to(f.stats_snapshot()).erases > 0 {
            at.push(i);
        }
        s = store(f);
    }
    let gaps: Vec<u32> = at.windows(2).map(|w| w[1] - w[0]).collect();
    assert!(gaps.len() >= 3, "erases at {at:?}");
    assert_eq!(imu_core::profile::RECORD_LEN, 200);
    assert!(gaps.iter().all(|&g| g == 76), "erases at {at:?}");
}
