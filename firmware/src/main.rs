//! imu-mouse firmware: an ADXL335-class accelerometer on an STM32F411 "Black Pill" as a USB
//! HID mouse, by exact double integration of acceleration (RTIC 2).
//!
//! Tasks and priorities (highest first):
//! - `dma` (3, DMA2_STREAM0): a block of samples is ready every 1 ms; deadline: before the
//!   next block completes (1 ms at the default 3 kHz), or the DMA overruns and samples are
//!   lost (counted, not silent). Feeds the tracker, then pends the USB task.
//! - `usb` (2, OTG_FS): polls the USB stack and pushes the next mouse report.
//! - `housekeeping` (1, async, every 1 ms): KEY debounce, stall check, LED, logs, watchdog.
//! - `idle`: sleeps in `wfi`.
//!
//! Wiring, clocks and the sampling rate: see `board.rs`.
#![no_std]
#![no_main]

mod board;
mod sampling;
mod tasks;
mod usb;

use defmt_rtt as _;
use panic_probe as _;
use rtic_monotonics::systick::prelude::*;

systick_monotonic!(Mono, 1000);

#[rtic::app(device = stm32f4xx_hal::pac, dispatchers = [EXTI1])]
mod app {
    use cortex_m::peripheral::DWT;
    use imu_core::{Debouncer, Event, Reporter, SampleLedger, Tracker};
    use stm32f4xx_hal::{
        dma::StreamsTuple,
        gpio::{Input, Output, PA0, PC13},
        otg_fs::{UsbBus, UsbBusType, USB},
        pac::{self, Interrupt},
        prelude::*,
        rcc::Config,
        watchdog::IndependentWatchdog,
    };
    use usb_device::bus::UsbBusAllocator;

    use rtic_monotonics::Monotonic;

    use super::Mono;
    use crate::board::{self, BUF_LEN};
    use crate::sampling::{Hardware, Outcome, Pins, Sampler};
    use crate::tasks::{self, Status};
    use crate::usb::Mouse;

    #[shared]
    struct Shared {
        tracker: Tracker,
        sampler: Sampler,
        status: Status,
        buttons: u8,
        mouse: Mouse,
        reporter: Reporter,
    }

    #[local]
    struct Local {
        key: PA0<Input>,
        led: PC13<Output>,
        debouncer: Debouncer,
        watchdog: IndependentWatchdog,
        m_s2_per_lsb: f32,
    }

    #[init(local = [
        buf_a: [u16; BUF_LEN] = [0; BUF_LEN],
        buf_b: [u16; BUF_LEN] = [0; BUF_LEN],
        buf_c: [u16; BUF_LEN] = [0; BUF_LEN],
        ep_memory: [u32; 1024] = [0; 1024],
        usb_bus: Option<UsbBusAllocator<UsbBusType>> = None,
    ])]
    fn init(cx: init::Context) -> (Shared, Local) {
        let mut core = cx.core;
        let dp: pac::Peripherals = cx.device;
        let mut rcc = dp.RCC.freeze(
            Config::hse(board::HSE_HZ.Hz())
                .sysclk(board::SYSCLK_HZ.Hz())
                .pclk1(board::PCLK1_HZ.Hz())
                .require_pll48clk(),
        );
        // Keep the debugger (RTT logs) alive while idle sleeps in wfi.
        dp.DBGMCU.cr().modify(|_, w| w.dbg_sleep().set_bit());
        core.DCB.enable_trace();
        core.DWT.enable_cycle_counter();
        Mono::start(core.SYST, board::SYSCLK_HZ);

        let config = board::tracker_config();
        let tracker = match Tracker::new(&config) {
            Ok(t) => t,
            Err(e) => defmt::panic!("board::tracker_config() is invalid: {}", e),
        };
        let ledger = match SampleLedger::new(board::SYSCLK_HZ, board::FS_HZ) {
            Ok(l) => l,
            Err(e) => defmt::panic!("board::FS_HZ: {}", e),
        };
        defmt::info!(
            "imu-mouse: fs {} Hz, {} samples per block, calibrating for {} s: keep still",
            board::FS_HZ,
            board::BLOCK,
            config.calibration_s
        );

        let gpioa = dp.GPIOA.split(&mut rcc);
        let gpioc = dp.GPIOC.split(&mut rcc);
        let key = gpioa.pa0.into_pull_up_input();
        let led = gpioc.pc13.into_push_pull_output();
        let pins = Pins {
            x: gpioa.pa1.into_analog(),
            y: gpioa.pa2.into_analog(),
            z: gpioa.pa3.into_analog(),
        };

        let usb = USB {
            usb_global: dp.OTG_FS_GLOBAL,
            usb_device: dp.OTG_FS_DEVICE,
            usb_pwrclk: dp.OTG_FS_PWRCLK,
            pin_dm: gpioa.pa11.into(),
            pin_dp: gpioa.pa12.into(),
            hclk: rcc.clocks.hclk(),
        };
        let bus = cx
            .local
            .usb_bus
            .insert(UsbBus::new(usb, cx.local.ep_memory));
        let mouse = match Mouse::new(bus) {
            Ok(m) => m,
            Err(_) => defmt::panic!("USB strings in board.rs do not fit the descriptor"),
        };

        let mut watchdog = IndependentWatchdog::new(dp.IWDG);
        watchdog.stop_on_debug(&dp.DBGMCU, true);
        watchdog.start(board::WATCHDOG_MS.millis());

        let streams = StreamsTuple::new(dp.DMA2, &mut rcc);
        let buffers = [cx.local.buf_a, cx.local.buf_b, cx.local.buf_c];
        let hw = Hardware {
            tim2: dp.TIM2,
            adc1: dp.ADC1,
            stream: streams.0,
            pins,
        };
        let sampler = match Sampler::start(hw, buffers, rcc, ledger, board::FS_HZ) {
            Ok(s) => s,
            Err(e) => defmt::panic!(
                "TIM2 cannot run at board::FS_HZ: {}",
                defmt::Debug2Format(&e)
            ),
        };

        if housekeeping::spawn().is_err() {
            defmt::panic!("housekeeping spawned twice");
        }
        (
            Shared {
                tracker,
                sampler,
                status: Status {
                    last: Event::Rejected {
                        axis: 0,
                        error: imu_core::CalibrationError::Motion { noise_rms_q16: 0 },
                    },
                    at_ms: None,
                },
                buttons: 0,
                mouse,
                reporter: Reporter::default(),
            },
            Local {
                key,
                led,
                debouncer: Debouncer::new(board::DEBOUNCE_MS, board::LONG_PRESS_MS),
                watchdog,
                m_s2_per_lsb: config.m_s2_per_lsb as f32,
            },
        )
    }

    /// A DMA block is full. Deadline: the next block (1 ms at 3 kHz).
    #[task(binds = DMA2_STREAM0, priority = 3, shared = [sampler, tracker, status], local = [m_s2_per_lsb])]
    fn dma(cx: dma::Context) {
        let now = DWT::cycle_count();
        let event = (cx.shared.sampler, cx.shared.tracker).lock(|s, t| tasks::on_dma(s, t, now));
        if let Some(event) = event {
            tasks::log_event(&event, *cx.local.m_s2_per_lsb);
            let mut status = cx.shared.status;
            status.lock(|st| {
                *st = Status {
                    last: event,
                    at_ms: Some(Mono::now().ticks()),
                }
            });
        }
        rtic::pend(Interrupt::OTG_FS);
    }

    /// The USB peripheral needs service, or the DMA task has fresh motion.
    #[task(binds = OTG_FS, priority = 2, shared = [tracker, mouse, reporter, buttons])]
    fn usb(mut cx: usb::Context) {
        let buttons = cx.shared.buttons.lock(|b| *b);
        let counts = cx.shared.tracker.lock(|t| t.take_counts());
        (cx.shared.mouse, cx.shared.reporter).lock(|m, r| tasks::on_usb(counts, m, r, buttons));
    }

    /// Every millisecond: KEY, stalled sampling, LED, logs, watchdog.
    #[task(priority = 1, shared = [tracker, sampler, status, buttons, mouse, reporter], local = [key, led, debouncer, watchdog])]
    async fn housekeeping(mut cx: housekeeping::Context) {
        loop {
            Mono::delay(1.millis()).await;
            let now_ms = Mono::now().ticks();
            if let Some(ev) = cx.local.debouncer.tick(cx.local.key.is_low()) {
                (&mut cx.shared.buttons, &mut cx.shared.tracker)
                    .lock(|b, t| tasks::on_button(ev, b, t));
            }
            let stall = cx
                .shared
                .sampler
                .lock(|s| s.check_stall(DWT::cycle_count(), board::STALL_SAMPLES));
            if let Outcome::Restarted(lost) = stall {
                cx.shared.tracker.lock(|t| tasks::on_restart(t, lost));
            }
            let configured = cx.shared.mouse.lock(|m| m.configured());
            let shown = (&mut cx.shared.tracker, &mut cx.shared.status)
                .lock(|t, st| tasks::indicator(t, st, configured, now_ms));
            cx.local.led.set_state((!shown.lit(now_ms)).into()); // PC13 LED lights when low
            if now_ms.is_multiple_of(board::LOG_INTERVAL_MS) {
                let snapshot = tasks::Snapshot {
                    tracker: cx.shared.tracker.lock(|t| t.counters()),
                    restarts: cx.shared.sampler.lock(|s| s.ledger().counters().restarts),
                    reports: cx.shared.reporter.lock(|r| r.reports()),
                    drops: cx.shared.mouse.lock(|m| m.drops()),
                    usb: configured,
                };
                tasks::log_counters(&snapshot);
            }
            cx.local.watchdog.feed();
        }
    }

    #[idle]
    fn idle(_: idle::Context) -> ! {
        loop {
            cortex_m::asm::wfi();
        }
    }
}
