//! Every rate the firmware build accepts gives a valid tracker (the boot never fails on
//! configuration), and the block and wake-up rules hold.

use imu_app::device::{self, block_len, rate_accepted, tracker_config, FS_MAX_HZ, FS_MIN_HZ};
use imu_core::{SampleLedger, Tracker};

/// The firmware's sample clock (SYSCLK, the TIM2 and TIM5 clock) [Hz].
const CLOCK_HZ: u32 = 96_000_000;

#[test]
fn every_accepted_rate_builds_the_tracker_and_the_ledger() {
    let accepted: Vec<u32> = (0..=FS_MAX_HZ + 1)
        .filter(|&f| rate_accepted(f, CLOCK_HZ))
        .collect();
    // 96 MHz = 2^10 3 5^6: its divisors in 100..=20000.
    assert_eq!(accepted.first(), Some(&FS_MIN_HZ));
    assert!(accepted.contains(&120) && accepted.contains(&150) && accepted.contains(&20_000));
    assert!(!accepted.contains(&7000) && !accepted.contains(&99) && !accepted.contains(&20_001));
    for fs in accepted {
        let config = tracker_config(fs);
        if let Err(e) = Tracker::new(&config) {
            panic!("fs {fs} Hz: {e}");
        }
        let block = block_len(fs) as u32;
        if let Err(e) = SampleLedger::new(CLOCK_HZ, fs, block) {
            panic!("fs {fs} Hz: {e}");
        }
        assert!(block >= 1 && u64::from(block) * 1000 <= u64::from(fs).max(1000));
    }
}

#[test]
fn wake_threshold_is_far_above_the_noise_of_one_sample() {
    let lsb = tracker_config(3000).m_s2_per_lsb;
    let codes = device::wake_motion_lsb(lsb);
    // 0.5 m/s^2 at 0.0239 m/s^2 per code; the ADXL335's noise per sample is about 1 code.
    assert_eq!(codes, 20);
    assert_eq!(device::wake_motion_lsb(1.0), 4);
    assert_eq!(device::wake_motion_lsb(0.0), u16::MAX);
    assert_eq!(device::wake_motion_lsb(1e-9), u16::MAX);
}

#[test]
fn a_block_is_one_millisecond_of_samples_at_least_one() {
    for (fs, block) in [
        (100, 1),
        (999, 1),
        (1000, 1),
        (1500, 1),
        (3000, 3),
        (20_000, 20),
    ] {
        assert_eq!(block_len(fs), block, "{fs} Hz");
    }
}

#[test]
fn the_tracker_runs_at_the_device_rate_with_the_core_defaults() {
    let config = tracker_config(6000);
    assert_eq!(config.fs_hz, 6000);
    assert_eq!(
        config,
        imu_core::Config {
            fs_hz: 6000,
            ..imu_core::Config::default()
        }
    );
}

#[test]
fn the_firmware_version_is_the_crates() {
    let v = imu_app::identity::FIRMWARE_VERSION;
    assert_eq!(
        format!("{}.{}.{}", v[0], v[1], v[2]),
        env!("CARGO_PKG_VERSION")
    );
}

#[test]
fn the_watchdog_is_shortest_at_the_fastest_lsi() {
    // The IWDG's count is set for a 32 kHz LSI; at 47 kHz, the F411's fastest, it runs out
    // after 32/47 of the timeout: 5 s becomes 3.404 s.
    use imu_app::device::{WATCHDOG_MIN_MS, WATCHDOG_MS};
    let fastest = f64::from(WATCHDOG_MS) * 32e3 / 47e3;
    assert_eq!(WATCHDOG_MS, 5000);
    assert!(
        (f64::from(WATCHDOG_MIN_MS) - fastest).abs() < 1.0,
        "{WATCHDOG_MIN_MS} ms"
    );
    assert!(f64::from(WATCHDOG_MIN_MS) <= fastest);
}

#[test]
fn a_stored_profile_the_board_cannot_run_starts_the_defaults_naming_the_key() {
    use imu_app::store::Loaded;
    use imu_core::profile::{Key, Profile};
    use imu_core::protocol::Source;
    let stored = |key: Key, value: f64| {
        let mut profile = Profile::default();
        profile.set(key, value).expect("fits the key");
        assert_eq!(profile.validate(), Ok(()), "the core takes {key} = {value}");
        Loaded {
            profile,
            source: Source::Stored,
            invalid: None,
        }
    };
    // The core takes both; the board's timer cannot make 7 kHz and its ADC has 12 bits.
    for (key, value) in [(Key::FsHz, 7000.0), (Key::AdcBits, 16.0)] {
        let l = device::runnable(stored(key, value), CLOCK_HZ);
        assert_eq!((l.source, l.invalid), (Source::Invalid, Some(key)), "{key}");
        assert_eq!(l.profile, Profile::default());
    }
    let ok = device::runnable(stored(Key::CountsPerInch, 1600.0), CLOCK_HZ);
    assert_eq!((ok.source, ok.invalid), (Source::Stored, None));
    assert_eq!(ok.profile.config.counts_per_inch, 1600);
}

#[test]
fn the_device_s_key_table_is_the_core_s_narrowed_to_the_board() {
    use imu_core::profile::{Key, Profile, Range};
    let p = Profile::default();
    assert_eq!(
        device::range(&p, Key::FsHz),
        Some(Range::within(100.0, 20_000.0))
    );
    assert_eq!(
        device::range(&p, Key::AdcBits),
        Some(Range::within(12.0, 12.0))
    );
    // Every rate and resolution in the table's range that the clock divides is one the
    // device runs, and none outside it.
    for fs in [99, 100, 20_000, 20_001] {
        let mut q = p;
        q.config.fs_hz = fs;
        let inside = device::range(&p, Key::FsHz).is_some_and(|r| r.contains(f64::from(fs)));
        assert_eq!(
            device::unsupported(&q.config, CLOCK_HZ).is_none(),
            inside,
            "{fs} Hz"
        );
    }
    for k in Key::ALL {
        if !matches!(k, Key::FsHz | Key::AdcBits) {
            assert_eq!(device::range(&p, k), p.range(k), "{k}");
        }
    }
}

#[test]
fn what_a_key_takes_is_said_as_a_user_writes_it() {
    use imu_core::profile::{Key, Profile};
    let p = Profile::default();
    let takes = |k, unit| {
        let mut s = String::new();
        device::takes(&mut s, &p, k, unit).expect("a String takes any text");
        s
    };
    assert_eq!(takes(Key::FsHz, true), "100..=20000 Hz");
    assert_eq!(takes(Key::FsHz, false), "100..=20000");
    assert_eq!(takes(Key::XAxis, true), "0..=2");
    let off = takes(Key::LowpassFcHz, true);
    assert!(
        off.starts_with("0.003 to below 1500 Hz") && off.ends_with(", or off"),
        "{off}"
    );
    assert_eq!(takes(Key::Drift, true), "on, off");
    assert_eq!(takes(Key::Scheme, true), "euler, trapezoid");
    assert_eq!(takes(Key::XSign, true), "1, -1");
}
