//! The board: STM32F411CEU6 "Black Pill" with a 25 MHz crystal. Wiring, clocks and the one
//! flash layout; no decisions (those are in `imu_app` and `imu_core`).
//!
//! # Design
//! Wiring (ADXL335-class analog accelerometer, ratiometric, powered from 3V3):
//!
//! | signal | pin | peripheral |
//! |---|---|---|
//! | accelerometer X | PA1 | ADC1 IN1 |
//! | accelerometer Y | PA2 | ADC1 IN2 |
//! | accelerometer Z | PA3 | ADC1 IN3 |
//! | left button | PA0 (on-board KEY, to GND) | GPIO, pull-up |
//! | status LED | PC13 (on-board, lit when low) | GPIO |
//! | USB D-, D+ | PA11, PA12 (on-board USB-C) | OTG_FS |
//!
//! Clocks: HSE 25 MHz -> PLL -> SYSCLK 96 MHz (regulator scale 1, which the HAL does not set
//! on the F411), APB1 48 MHz (its timers TIM2 and TIM5 at 96 MHz), APB2 96 MHz, ADC
//! PCLK2 / 4 = 24 MHz (the F411's limit is 36 MHz), and the 48 MHz USB clock from the PLL.
//! `init` checks the HAL's computed clocks against these constants.
//! The ADC trigger is TIM2's update event (TRGO) at exactly the configured rate: PSC 0 and
//! ARR = `TIMER_HZ / fs - 1`, exact for every accepted rate. TIM5 runs free at 96 MHz
//! as the sample ledger's time base (it keeps counting while the core sleeps in `wfi`; in
//! Stop mode it stops with its clock, and the time asleep is credited, `crate::stop`).
//!
//! The sampling rate is a setting (`fs_hz`, set over USB and kept in flash; 3 kHz by
//! default, the rate of the paper's experiments). The device accepts 100 to 20 000 Hz
//! dividing [`TIMER_HZ`] (`imu_app::device::rate_accepted`); TIM2 counts `TIMER_HZ / fs`
//! cycles per sample.
//!
//! Flash layout (RM0383 table 5: sectors 0-3 of 16 KiB, 4 of 64 KiB, 5-7 of 128 KiB), set
//! in `memory.x`: sector 0 holds the vector table alone, sectors 1 and 2 the profile store,
//! the code starts at sector 3 (`_stext`). The store takes the smallest sectors because a
//! sector erase stalls every flash fetch, so the CPU, for its whole duration, and the erase
//! time grows with the sector: hundreds of milliseconds for 16 KiB, seconds for 128 KiB
//! (DS10314's flash characteristics, at the x8 parallelism the HAL uses; not measured here,
//! no board). An erase happens only when the store moves to its other page, once in
//! 76 saves (a record is 200 bytes, 22 keys; `app/tests/store.rs`).

use stm32f4xx_hal::adc::config::{Clock as AdcClock, SampleTime};

/// Crystal [Hz].
pub const HSE_HZ: u32 = 25_000_000;
/// System clock [Hz].
pub const SYSCLK_HZ: u32 = 96_000_000;
/// APB1 clock [Hz] (at most 50 MHz); its timers (TIM2, TIM5) run at twice this.
pub const PCLK1_HZ: u32 = 48_000_000;
/// APB2 clock [Hz] (the ADC's bus).
pub const PCLK2_HZ: u32 = 96_000_000;
/// Clock of TIM2 and TIM5 [Hz]: the ADC trigger and the sample ledger's time base.
pub const TIMER_HZ: u32 = 2 * PCLK1_HZ;
/// The ADC prescaler: PCLK2 / 4.
pub const ADC_PRESCALER: AdcClock = AdcClock::Pclk2_div_4;
/// ADC clock [Hz]: PCLK2 / 4.
pub const ADC_HZ: u32 = PCLK2_HZ / 4;
/// USB clock from the PLL's Q output [Hz].
pub const USB_HZ: u32 = 48_000_000;

const _: () = assert!(ADC_HZ <= 36_000_000, "the F411's ADC clock limit is 36 MHz");

/// Start of the profile store [bytes from the flash's start]: sector 1.
pub const STORE_START: u32 = 0x4000;
/// End of the profile store [bytes from the flash's start]: sectors 1 and 2.
pub const STORE_END: u32 = 0xC000;
/// The store's erase unit [bytes]: one 16 KiB sector.
pub const STORE_PAGE: u32 = 0x4000;
/// Sector number of the store's first page.
pub const STORE_FIRST_SECTOR: u8 = 1;

/// Probe rate while USB is suspended [Hz]: enough to catch a hand moving the mouse (its
/// accelerations last a tenth of a second and more) for remote wake-up.
pub const PROBE_HZ: u32 = 50;
/// TIM2 auto-reload for [`PROBE_HZ`].
pub const PROBE_ARR: u32 = TIMER_HZ / PROBE_HZ - 1;
const _: () = assert!((PROBE_ARR as u64 + 1) * PROBE_HZ as u64 == TIMER_HZ as u64);

/// The probe's period in Stop mode [ms]: the RTC wake-up timer's, from the LSI (`crate::stop`),
/// at [`PROBE_HZ`].
pub const PROBE_MS: u32 = 1000 / PROBE_HZ;
const _: () = assert!(PROBE_MS * PROBE_HZ == 1000);

/// The clock the core wakes on from Stop [Hz]: the HSI (RM0383 5.3.4).
pub const HSI_HZ: u32 = 16_000_000;

/// ADC power-up time before the first conversion [core cycles]: tSTAB (3 us at most, DS10314)
/// at the wake clock, [`HSI_HZ`].
pub const ADC_STAB_CYCLES: u32 = 3 * (HSI_HZ / 1_000_000);

/// Register reads allowed for each step of the clock restore after Stop (HSE ready, PLL
/// locked, switched) before the wake counts as failed and the board resets. A read takes at
/// least 6 cycles of the 16 MHz HSI with its loop, so the bound is at least 37 ms a step,
/// many times a crystal's start-up (DS10314 quotes 2 ms typical) and the PLL's lock (well
/// under a millisecond): only a dead crystal or PLL reaches it.
pub const RESTORE_SPINS: u32 = 100_000;

/// Storage of one DMA buffer [u16]: the longest block (1 ms at 20 kHz) of X, Y, Z scans.
pub const BUF_MAX: usize = 3 * imu_app::sampling::BLOCK_MAX;

/// ADC sample time per channel: 112 ADC cycles = 4.7 us at 24 MHz, enough to settle through
/// the ADXL335's 32 kOhm output resistance (its RC filter capacitor also feeds the sample
/// capacitor). A 3-channel scan takes 3 x (112 + 12) cycles = 15.5 us.
pub const ADC_SAMPLE_TIME: SampleTime = SampleTime::Cycles_112;

/// Sampling is restarted when no block has arrived for this many block periods.
pub const STALL_BLOCKS: u32 = 5;

/// Independent watchdog timeout [ms], fed by the 1 ms housekeeping loop: see
/// `imu_app::device::WATCHDOG_MS` (the worst saves, each erase and every byte sequential-
/// storage reads through its bitwise CRC, budgeted against the fastest LSI in
/// `app/tests/store.rs`).
pub const WATCHDOG_MS: u32 = imu_app::device::WATCHDOG_MS;

/// Remote wake-up signalling time [ms] (USB 2.0: 1 to 15 ms).
pub const REMOTE_WAKEUP_MS: u32 = 10;

/// The MCU's 96-bit unique device ID, its 12 bytes in address order from 0x1FFF_7A10
/// (RM0383 section 24.1), through the HAL's reader: wafer X and Y (little-endian u16), the
/// wafer number, the lot number (7 ASCII bytes). The board's USB serial number is made from
/// it (`imu_app::identity::serial`).
pub fn unique_id() -> [u8; 12] {
    let uid = stm32f4xx_hal::signature::Uid::get();
    let mut id = [0u8; 12];
    id[..2].copy_from_slice(&uid.x().to_le_bytes());
    id[2..4].copy_from_slice(&uid.y().to_le_bytes());
    id[4] = uid.waf_num();
    for (d, s) in id[5..].iter_mut().zip(uid.lot_num().as_bytes()) {
        *d = *s;
    }
    id
}
