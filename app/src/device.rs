//! The device's settings that are not wiring: the rates it accepts, the block length, the
//! tracker's configuration for its sensor, and the housekeeping timing.
//!
//! # Design
//! A rate is accepted when it lies in [`FS_MIN_HZ`]`..=`[`FS_MAX_HZ`] and divides the
//! sample clock (so the trigger timer and the ledger count whole cycles). The firmware
//! checks its rate with [`rate_accepted`] at compile time, and a host test builds the
//! tracker at every accepted rate: a board configuration that would fail at boot fails the
//! build or the tests instead.

use core::fmt;

use imu_core::profile::{Key, Kind, Profile, Range, SCHEMES};
use imu_core::protocol::Source;
use imu_core::Config;

use crate::housekeeping::Timing;
use crate::store::Loaded;

/// Lowest accepted sampling rate [Hz]: one DMA block per sample at 100 Hz.
pub const FS_MIN_HZ: u32 = 100;
/// Highest accepted sampling rate [Hz]: a 3-channel scan at 112 + 12 ADC cycles of 24 MHz
/// takes 15.5 us, so 20 kHz keeps the ADC 31 % idle.
pub const FS_MAX_HZ: u32 = 20_000;

/// The board's ADC resolution [bits]: the F411's ADC, scanned at 12 bits. The only
/// `adc_bits` the device runs: its codes are 12-bit whatever the profile says, so 16 would
/// put the upper rail where no code reaches (a clipped window is never seen), and 8 puts
/// every code above the 255 rail (no window ever calibrates).
pub const ADC_BITS: u8 = 12;

/// The key of `config` this device cannot run with a sample clock of `clock_hz` [Hz], if any:
/// the sampling rate ([`rate_accepted`]) first, then the resolution ([`ADC_BITS`]). Checked
/// before the core's validation, whose refusals would otherwise name a key the user did not
/// set (a 1 s window at 7 Hz is too short; 8 bits make the 10 g scale span under 2 g).
pub fn unsupported(config: &Config, clock_hz: u32) -> Option<Key> {
    if !rate_accepted(config.fs_hz, clock_hz) {
        Some(Key::FsHz)
    } else if config.adc_bits != ADC_BITS {
        Some(Key::AdcBits)
    } else {
        None
    }
}

/// The values `key` takes on this device with the rest of `profile`, in the key's unit: the
/// core's [`Profile::range`], narrowed to the board's rates ([`FS_MIN_HZ`]`..=`[`FS_MAX_HZ`],
/// which must also divide the sample clock) and its ADC's resolution ([`ADC_BITS`]). The
/// host shows this table (`cargo lab device config get`) from the same code the firmware
/// runs, so the two never disagree.
pub fn range(profile: &Profile, key: Key) -> Option<Range> {
    match key {
        Key::FsHz => Some(Range::within(f64::from(FS_MIN_HZ), f64::from(FS_MAX_HZ))),
        Key::AdcBits => Some(Range::within(f64::from(ADC_BITS), f64::from(ADC_BITS))),
        _ => profile.range(key),
    }
}

/// What `key` takes on this device with the rest of `profile`, as a user writes it: its
/// [`range`] (with the key's unit after it when `unit` is asked for, and `, or off` for a key
/// that may be off), or its words (`on, off`; `euler, trapezoid`), or `1, -1` for a sign.
/// `cargo lab device` and the settings page both say it so.
///
/// # Errors
/// Only `out`'s own.
pub fn takes(out: &mut impl fmt::Write, profile: &Profile, key: Key, unit: bool) -> fmt::Result {
    match (key.kind(), range(profile, key)) {
        (Kind::Flag, _) => out.write_str("on, off"),
        (Kind::Sign, _) => out.write_str("1, -1"),
        _ if key == Key::Scheme => {
            for (i, w) in SCHEMES.iter().enumerate() {
                out.write_str(if i > 0 { ", " } else { "" })?;
                out.write_str(w)?;
            }
            Ok(())
        }
        (kind, Some(r)) => {
            write!(out, "{r}")?;
            if unit && !key.unit().is_empty() {
                write!(out, " {}", key.unit())?;
            }
            if kind == Kind::Optional {
                out.write_str(", or off")?;
            }
            Ok(())
        }
        (_, None) => Ok(()),
    }
}

/// Whether the device runs at `fs_hz` [Hz] with a sample clock of `clock_hz` [Hz].
pub const fn rate_accepted(fs_hz: u32, clock_hz: u32) -> bool {
    fs_hz >= FS_MIN_HZ && fs_hz <= FS_MAX_HZ && clock_hz.is_multiple_of(fs_hz)
}

/// The independent watchdog's timeout as programmed [ms], for the LSI's nominal 32 kHz (the
/// HAL's assumption). It must outlast the longest stretch in which housekeeping cannot feed
/// it: a save, which runs synchronously at housekeeping's priority and stalls the CPU during
/// each erase. `app/tests/store.rs` budgets the worst saves against [`WATCHDOG_MIN_MS`]: the
/// page move about 2.4 s (one erase at 800 ms, 1.3 MB read through the CRC), the first save
/// over old code about 1.8 s (two erases). The price: a hung device resets after 5 s, up
/// to 9.4 s with the slowest LSI (17 kHz).
pub const WATCHDOG_MS: u32 = 5000;

/// The shortest the watchdog's timeout can be [ms]: the F411's LSI runs at 17 to 47 kHz
/// (DS10314, LSI characteristics), so the count programmed for 32 kHz may last only 32/47 of
/// [`WATCHDOG_MS`].
pub const WATCHDOG_MIN_MS: u32 = WATCHDOG_MS * 32 / 47;

/// Sample triples per DMA block at `fs_hz` [Hz]: 1 ms of samples, rounded down, at least
/// one. A block lasts exactly 1 ms only when `fs_hz` is a multiple of 1 kHz; otherwise
/// `block / fs_hz` (at 1500 Hz one sample is 0.67 ms, at 150 Hz 6.7 ms).
pub const fn block_len(fs_hz: u32) -> usize {
    if fs_hz >= 1000 {
        (fs_hz / 1000) as usize
    } else {
        1
    }
}

/// The tracker's configuration at `fs_hz` [Hz]: the core's default for this device (an
/// ADXL335, ratiometric: 300 mV/g at a 3 V supply, 330 mV/g at the board's 3.3 V, so 10 g
/// across a 12-bit ADC referenced to the same 3.3 V; 800 counts per inch, drift control on;
/// REFERENCE (g)) at that rate.
pub fn tracker_config(fs_hz: u32) -> Config {
    Config {
        fs_hz,
        ..Config::default()
    }
}

/// The housekeeping timing of the 1 ms tick: 5 ms debounce, 2 s long press (recalibrate),
/// a counter log every 5 s.
pub const TIMING: Timing = Timing {
    debounce_ms: 5,
    long_press_ms: 2000,
    log_interval_ms: 5000,
};

/// The suspend probe's motion threshold in ADC codes for [`crate::identity::WAKE_MOTION_M_S2`]
/// at `m_s2_per_lsb` [m/s^2 per code] (finite and > 0, as a validated `Config` has it): at
/// least 4 codes, at most `u16::MAX` (the float-to-integer cast saturates; a scale of 0 gives
/// the maximum, never a wake-up on noise).
pub fn wake_motion_lsb(m_s2_per_lsb: f64) -> u16 {
    ((crate::identity::WAKE_MOTION_M_S2 / m_s2_per_lsb) as u16).max(4)
}

/// The profile to start with: `loaded` if the device can run it with a sample clock of
/// `clock_hz` [Hz] ([`unsupported`]), else the defaults, reported as a stored profile that no
/// longer validates, naming the key (the core accepts rates the trigger timer cannot make
/// and resolutions the ADC does not have).
pub fn runnable(loaded: Loaded, clock_hz: u32) -> Loaded {
    match unsupported(&loaded.profile.config, clock_hz) {
        None => loaded,
        Some(key) => Loaded {
            profile: Profile::default(),
            source: Source::Invalid,
            invalid: Some(key),
        },
    }
}
