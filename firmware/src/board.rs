//! The board: STM32F411CEU6 "Black Pill" with a 25 MHz crystal, and everything about this
//! build that a maker may want to change, in one place.
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
//! Clocks: HSE 25 MHz -> PLL -> SYSCLK 96 MHz (also the DWT cycle counter), APB1 48 MHz (its
//! timers, TIM2 among them, at 96 MHz), APB2 96 MHz, and the 48 MHz USB clock from the PLL.
//! The ADC trigger is TIM2's update event (TRGO) at exactly [`FS_HZ`].

use imu_core::{Config, Drift, Scheme};
use stm32f4xx_hal::adc::config::SampleTime;

/// Crystal [Hz].
pub const HSE_HZ: u32 = 25_000_000;
/// System clock, and rate of the DWT cycle counter [Hz].
pub const SYSCLK_HZ: u32 = 96_000_000;
/// APB1 clock [Hz] (at most 50 MHz); TIM2 runs at twice this.
pub const PCLK1_HZ: u32 = 48_000_000;

/// Sampling rate of each axis [Hz]. **The one place to change it.** Must lie in
/// [`FS_MIN_HZ`]`..=`[`FS_MAX_HZ`] and divide [`SYSCLK_HZ`] (checked when this crate builds).
/// 3000 Hz is the rate of the paper's experiments.
pub const FS_HZ: u32 = 3000;
/// Lowest supported sampling rate [Hz]: one DMA block per sample at 100 Hz.
pub const FS_MIN_HZ: u32 = 100;
/// Highest supported sampling rate [Hz]: a 3-channel scan at [`ADC_SAMPLE_TIME`] takes
/// 3 x (112 + 12) ADC cycles at 24 MHz = 15.5 us, so 20 kHz leaves the ADC 69 % busy.
pub const FS_MAX_HZ: u32 = 20_000;

const _: () = assert!(
    FS_HZ >= FS_MIN_HZ && FS_HZ <= FS_MAX_HZ,
    "FS_HZ out of range"
);
const _: () = assert!(
    SYSCLK_HZ.is_multiple_of(FS_HZ),
    "FS_HZ must divide SYSCLK_HZ"
);

/// Sample triples per DMA block: one block per millisecond (at least one sample), so the
/// core sees fresh motion once per USB poll.
pub const BLOCK: usize = if FS_HZ >= 1000 {
    (FS_HZ / 1000) as usize
} else {
    1
};
/// Length of one DMA buffer [u16]: [`BLOCK`] scans of X, Y, Z.
pub const BUF_LEN: usize = 3 * BLOCK;

/// ADC sample time per channel: 112 ADC cycles = 4.7 us at 24 MHz, enough to settle through
/// the ADXL335's 32 kOhm output resistance (its RC filter capacitor also feeds the sample
/// capacitor).
pub const ADC_SAMPLE_TIME: SampleTime = SampleTime::Cycles_112;

/// Sampling is restarted when no block has arrived for this many sample periods (5 blocks).
pub const STALL_SAMPLES: u32 = 5 * BLOCK as u32;

/// Debounce of KEY [ms] (ticks of the 1 ms housekeeping loop).
pub const DEBOUNCE_MS: u16 = 5;
/// Holding KEY this long recalibrates [ms].
pub const LONG_PRESS_MS: u32 = 2000;
/// Independent watchdog timeout [ms]; fed by the 1 ms housekeeping loop.
pub const WATCHDOG_MS: u32 = 250;
/// Interval of the periodic counter log [ms].
pub const LOG_INTERVAL_MS: u32 = 5000;

/// USB vendor and product ID: pid.codes' test PID 1209:0001, free to use for testing an
/// open project. A released product should get its own PID from pid.codes.
pub const USB_VID_PID: (u16, u16) = (0x1209, 0x0001);
/// USB manufacturer string.
pub const USB_MANUFACTURER: &str = "imu-mouse project";
/// USB product string.
pub const USB_PRODUCT: &str = "imu-mouse accelerometer mouse";
/// USB serial number string.
pub const USB_SERIAL: &str = "0001";
/// HID polling interval requested from the host [ms].
pub const USB_POLL_MS: u8 = 1;

/// The tracker's configuration for this board (ADXL335 on a 12-bit ratiometric ADC,
/// REFERENCE (g)).
pub fn tracker_config() -> Config {
    Config {
        fs_hz: FS_HZ,
        lowpass_fc_hz: None,
        m_s2_per_lsb: 9.806_65 * 10.0 / 4096.0,
        adc_bits: 12,
        counts_per_inch: 800,
        scheme: Scheme::Euler,
        calibration_s: 1.0,
        rest_noise_max_m_s2: 0.1,
        // Stillness detection, zero-velocity updates, bias tracking and a 150 ms click freeze.
        drift: Some(Drift::default()),
    }
}
