//! imu-mouse firmware (foundation stage): an RTIC 2 application for the STM32F411 Black Pill
//! that validates the default tracker configuration at start-up and then sleeps.
//!
//! The sampling path (timer-triggered ADC, DMA) and the USB HID mouse arrive with the firmware
//! issue; this stage proves that the core links into a `thumbv7em-none-eabihf` image.
#![no_std]
#![no_main]

use defmt_rtt as _;
use panic_probe as _;

#[rtic::app(device = stm32f4xx_hal::pac)]
mod app {
    use imu_core::Config;

    #[shared]
    struct Shared {}

    #[local]
    struct Local {}

    #[init]
    fn init(_cx: init::Context) -> (Shared, Local) {
        match Config::default().validate() {
            Ok(settings) => defmt::info!(
                "imu-mouse: fs = {} Hz, lowpass k = {}",
                settings.fs_hz(),
                settings.lowpass_k_q32()
            ),
            Err(e) => defmt::error!("imu-mouse: bad default configuration: {}", e),
        }
        (Shared {}, Local {})
    }

    #[idle]
    fn idle(_cx: idle::Context) -> ! {
        loop {
            cortex_m::asm::wfi();
        }
    }
}
