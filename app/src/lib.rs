//! imu-mouse's device application, free of registers: the USB HID mouse (device, class,
//! report scheduling), the 1 ms housekeeping (KEY, LED, suspend and wake-up, log schedule)
//! and the sample path's glue, generic over `usb_device::bus::UsbBus` and the embedded-hal
//! 1.0 digital pins.
//!
//! The firmware runs it on the STM32F411 (its board layer owns pins, clocks, ADC, DMA and
//! the RTIC binding, and makes no decision); `cargo lab twin` runs it unchanged on the host
//! as a USB/IP device. Every decision is in `imu_core` or here, and tested on the host.
//!
//! | module | stage |
//! |---|---|
//! | [`device`] | accepted rates, block length, tracker configuration, timing |
//! | [`identity`] | who the device is on USB |
//! | [`mouse`] | USB device: the HID mouse and the configuration interface |
//! | [`opening`] | the first reports after a new configuration (Linux drops 50 ms of them) |
//! | [`commands`] | configuration requests: responses and what the device must do |
//! | [`control`] | a request from the bus through [`commands`] to the tracker and stream |
//! | [`stream`] | raw ADC codes queued and cut into stream frames |
//! | [`store`] | the profile in flash (sequential-storage) |
//! | [`flash`] | the flash interface's erase and program sequences |
//! | [`sampler`] | the sampling's decisions: rates, suspend, stalls, restarts, retiming |
//! | [`sampling`] | a DMA block into the tracker (or the suspend probe) |
//! | [`sleep`] | Stop mode while suspended: when to stop, what a wake-up means |
//! | [`housekeeping`] | KEY, power, LED, log schedule every 1 ms |
//! | [`status`] | calibration outcome, suspend state, LED choice |
//! | [`uptime`] | milliseconds since boot from a hardware counter |
#![no_std]
#![forbid(unsafe_code)]

pub mod commands;
pub mod control;
pub mod device;
pub mod flash;
pub mod housekeeping;
pub mod identity;
pub mod mouse;
pub mod opening;
pub mod sampler;
pub mod sampling;
pub mod sleep;
pub mod status;
pub mod store;
pub mod stream;
pub mod uptime;

pub use housekeeping::{Housekeeping, Tick, Timing};
pub use mouse::Mouse;
pub use status::Status;
