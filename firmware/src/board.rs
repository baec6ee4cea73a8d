//! The board: STM32F411CEU6 "Black Pill" with a 25 MHz crystal. Wiring, clocks and the one
//! rate to change; no decisions (those are in `imu_app` and `imu_core`).
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
//! The ADC trigger is TIM2's update event (TRGO) at exactly [`FS_HZ`]: PSC 0 and ARR
//! computed here in 32 bits, the product checked at compile time. TIM5 runs free at 96 MHz
//! as the sample ledger's time base (it keeps counting while the core sleeps in `wfi`).

use imu_app::device::{block_len, rate_accepted};
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

/// Sampling rate of each axis [Hz]. **The one place to change it.** It must be accepted by
/// `imu_app::device::rate_accepted` (100 to 20 000 Hz, dividing [`TIMER_HZ`]): checked
/// when this crate builds. 3000 Hz is the rate of the paper's experiments.
pub const FS_HZ: u32 = 3000;

const _: () = assert!(
    rate_accepted(FS_HZ, TIMER_HZ),
    "FS_HZ must lie in 100..=20000 Hz and divide the 96 MHz timer clock"
);

/// TIM2 auto-reload for [`FS_HZ`] (PSC 0): one update every `TIMER_HZ / FS_HZ` cycles.
pub const TRIGGER_ARR: u32 = TIMER_HZ / FS_HZ - 1;
const _: () = assert!((TRIGGER_ARR as u64 + 1) * FS_HZ as u64 == TIMER_HZ as u64);

/// Probe rate while USB is suspended [Hz]: enough to catch a hand moving the mouse (its
/// accelerations last a tenth of a second and more) for remote wake-up.
pub const PROBE_HZ: u32 = 50;
/// TIM2 auto-reload for [`PROBE_HZ`].
pub const PROBE_ARR: u32 = TIMER_HZ / PROBE_HZ - 1;
const _: () = assert!((PROBE_ARR as u64 + 1) * PROBE_HZ as u64 == TIMER_HZ as u64);

/// Sample triples per DMA block (`imu_app::device::block_len`): 1 ms of samples, at least 1.
pub const BLOCK: usize = block_len(FS_HZ);
/// Length of one DMA buffer [u16]: [`BLOCK`] scans of X, Y, Z.
pub const BUF_LEN: usize = 3 * BLOCK;

/// ADC sample time per channel: 112 ADC cycles = 4.7 us at 24 MHz, enough to settle through
/// the ADXL335's 32 kOhm output resistance (its RC filter capacitor also feeds the sample
/// capacitor). A 3-channel scan takes 3 x (112 + 12) cycles = 15.5 us.
pub const ADC_SAMPLE_TIME: SampleTime = SampleTime::Cycles_112;

/// Sampling is restarted when no block has arrived for this many sample periods (5 blocks).
pub const STALL_SAMPLES: u32 = 5 * BLOCK as u32;

/// Independent watchdog timeout [ms]; fed by the 1 ms housekeeping loop.
pub const WATCHDOG_MS: u32 = 250;

/// Remote wake-up signalling time [ms] (USB 2.0: 1 to 15 ms).
pub const REMOTE_WAKEUP_MS: u32 = 10;
