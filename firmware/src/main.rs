//! imu-mouse firmware: an ADXL335-class accelerometer on an STM32F411 "Black Pill" as a USB
//! HID mouse, by exact double integration of acceleration (RTIC 2).
//!
//! This crate is the board layer: pins, clocks, ADC, DMA, timers and the RTIC binding. The
//! application (USB mouse, housekeeping, sample glue) is `imu_app`, the same code that
//! `cargo lab twin` runs on the host.
//!
//! Tasks and priorities (highest first):
//! - `dma` (3, DMA2_STREAM0): a block of samples is ready every 1 ms (at rates that are a
//!   multiple of 1 kHz); deadline: before the next block completes, or the block is counted
//!   late (`Delivery::Late`) or the DMA overruns (a restart). Feeds the tracker, then pends
//!   the USB task.
//! - `usb` (2, OTG_FS): polls the USB stack, pushes the next mouse report, serves the
//!   configuration interface (a new rate retimes the sampling here) and the raw stream.
//! - `housekeeping` (1, async, every 1 ms on a running deadline, woken by SysTick): stall
//!   check, KEY, power, LED, logs, remote wake-up, watchdog. Its milliseconds, and the DMA
//!   task's, come from TIM5 (`imu_app::uptime`), which counts on while a flash erase stalls
//!   the CPU; deadlines a save covered are skipped, not run in a burst.
//! - `save` (1, async, spawned by a `save` or `defaults` request): the profile to flash; the
//!   CPU stalls while the flash programs or erases (the watchdog allows for it).
//! - `key_wake`, `usb_wake`, `probe_wake` (4, EXTI0, OTG_FS_WKUP, RTC_WKUP): Stop mode's
//!   wake-up lines, above every resource ceiling so that they end a Stop entered under the
//!   idle loop's locks; each only clears its line (`stop.rs`).
//! - `idle`: in USB suspend, Stop mode (`imu_app::sleep` decides, `stop.rs` programs it);
//!   otherwise `wfi`.
//!
//! Wiring, clocks and the flash layout: see `board.rs`. The sampling rate and every other
//! setting come from the profile in flash (`imu_app::store`), or the defaults.
#![no_std]
#![no_main]

mod board;
mod clock;
mod sampling;
mod stop;
mod storage;
mod tasks;
mod wakeup;

use defmt_rtt as _;
use panic_probe as _;
use rtic_monotonics::systick::prelude::*;

systick_monotonic!(Mono, 1000);

#[rtic::app(device = stm32f4xx_hal::pac, dispatchers = [EXTI1])]
mod app {
    use imu_app::commands::Commands;
    use imu_app::control::{self, Resources};
    use imu_app::store::Store;
    use imu_app::stream::Stream;
    use imu_app::{device, sampling::on_block, Housekeeping, Mouse, Status};
    use imu_core::profile::AxisMap;
    use imu_core::{PowerAction, Tracker};
    use rtic_monotonics::Monotonic;
    use stm32f4xx_hal::{
        dma::StreamsTuple,
        gpio::{Input, Output, PA0, PC13},
        otg_fs::{UsbBus, UsbBusType, USB},
        pac::{self, Interrupt},
        prelude::*,
        rcc::{Clocks, Config},
        rtc::Rtc,
        watchdog::IndependentWatchdog,
    };
    use usb_device::bus::UsbBusAllocator;

    use super::Mono;
    use crate::board::{self, BUF_MAX};
    use crate::clock::Clock;
    use crate::sampling::{Hardware, Outcome, Pins, Sampler};
    use crate::stop::{self, Stop};
    use crate::storage::StoreFlash;
    use crate::tasks::{self, Snapshot};
    use crate::wakeup::RemoteWakeup;

    #[shared]
    struct Shared {
        tracker: Tracker,
        sampler: Sampler,
        status: Status,
        mouse: Mouse<'static, UsbBusType>,
        commands: Commands,
        stream: Stream,
        route: AxisMap,
        wakeup: RemoteWakeup,
        watchdog: IndependentWatchdog,
    }

    #[local]
    struct Local {
        housekeeping: Housekeeping<PA0<Input>, PC13<Output>>,
        store: Store<StoreFlash>,
        stop: Stop,
    }

    /// The HAL's computed clocks against `board`'s constants: a mismatch stops at boot with
    /// a message, before anything runs at a wrong rate.
    fn check_clocks(c: &Clocks) {
        let want = [
            (c.sysclk().raw(), board::SYSCLK_HZ),
            (c.pclk1().raw(), board::PCLK1_HZ),
            (c.pclk2().raw(), board::PCLK2_HZ),
            (c.timclk1().raw(), board::TIMER_HZ),
            (c.pll48clk().map_or(0, |f| f.raw()), board::USB_HZ),
        ];
        for (i, (got, want)) in want.into_iter().enumerate() {
            if got != want {
                defmt::panic!("clock {} is {} Hz, board.rs says {} Hz", i, got, want);
            }
        }
    }

    #[init(local = [
        buf_a: [u16; BUF_MAX] = [0; BUF_MAX],
        buf_b: [u16; BUF_MAX] = [0; BUF_MAX],
        buf_c: [u16; BUF_MAX] = [0; BUF_MAX],
        ep_memory: [u32; 1024] = [0; 1024],
        usb_bus: Option<UsbBusAllocator<UsbBusType>> = None,
        serial: [u8; imu_app::identity::SERIAL_LEN] = [0; imu_app::identity::SERIAL_LEN],
    ])]
    fn init(cx: init::Context) -> (Shared, Local) {
        let mut dp: pac::Peripherals = cx.device;
        // 96 MHz needs regulator scale 1 before the PLL locks (RM0383 5.1.3).
        dp.RCC.apb1enr().modify(|_, w| w.pwren().set_bit());
        dp.PWR.cr().modify(|_, w| w.vos().scale1());
        let mut rcc = dp.RCC.freeze(
            Config::hse(board::HSE_HZ.Hz())
                .sysclk(board::SYSCLK_HZ.Hz())
                .pclk1(board::PCLK1_HZ.Hz())
                .pclk2(board::PCLK2_HZ.Hz())
                .require_pll48clk(),
        );
        check_clocks(&rcc.clocks);
        Mono::start(cx.core.SYST, board::SYSCLK_HZ);

        let Ok(mut store) = Store::new(
            StoreFlash::new(dp.FLASH),
            0..board::STORE_END - board::STORE_START,
        ) else {
            defmt::panic!("the store must be whole 16 KiB sectors (board.rs)")
        };
        let loaded = device::runnable(store.load(), board::TIMER_HZ);
        let config = loaded.profile.config;
        // The store validates, `runnable` checks the rate: this cannot fail.
        let Ok(tracker) = Tracker::new(&config) else {
            defmt::panic!("tracker configuration (see app/tests/device.rs)")
        };
        tasks::log_start(&loaded);

        let gpioa = dp.GPIOA.split(&mut rcc);
        let gpioc = dp.GPIOC.split(&mut rcc);
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
        let serial = imu_app::identity::serial(&board::unique_id(), cx.local.serial);
        let Ok(mouse) = Mouse::new(bus, serial) else {
            defmt::panic!("USB identity strings do not fit the descriptor")
        };

        // The debug port stays reachable while idle sleeps in `wfi` (DBG_SLEEP): attaching
        // to a sleeping F411 otherwise fails, and the Black Pill's SWD header has no NRST
        // for connect-under-reset. probe-rs clears the bit when it disconnects, so it is set
        // again at every boot (README, "Wiring and flashing": what to do if attach fails).
        dp.DBGMCU.cr().modify(|_, w| w.dbg_sleep().set_bit());
        let mut watchdog = IndependentWatchdog::new(dp.IWDG);
        watchdog.stop_on_debug(&dp.DBGMCU, true);
        watchdog.start(board::WATCHDOG_MS.millis());
        let rtc = Rtc::new_lsi(dp.RTC, &mut rcc, &mut dp.PWR);
        let debugger = cortex_m::peripheral::DCB::is_debugger_attached();
        let stop = Stop::new(
            dp.EXTI,
            dp.PWR,
            rtc,
            cx.core.SCB,
            &rcc,
            &dp.DBGMCU,
            debugger,
        );

        let clock = Clock::start(dp.TIM5, &mut rcc);
        let streams = StreamsTuple::new(dp.DMA2, &mut rcc);
        let buffers = [cx.local.buf_a, cx.local.buf_b, cx.local.buf_c];
        let hw = Hardware {
            tim2: dp.TIM2,
            adc1: dp.ADC1,
            stream: streams.0,
            pins,
        };
        let sampler = Sampler::start(hw, buffers, rcc, clock, config.fs_hz);
        let housekeeping = Housekeeping::new(
            gpioa.pa0.into_pull_up_input(),
            true,
            gpioc.pc13.into_push_pull_output(),
            true,
            device::TIMING,
            0,
        );
        if housekeeping::spawn().is_err() {
            defmt::panic!("housekeeping spawned twice");
        }
        let wake_lsb = device::wake_motion_lsb(config.m_s2_per_lsb);
        (
            Shared {
                tracker,
                sampler,
                status: Status::new(wake_lsb),
                mouse,
                commands: Commands::new(
                    loaded.profile,
                    loaded.source,
                    loaded.invalid,
                    board::TIMER_HZ,
                ),
                stream: Stream::default(),
                route: loaded.profile.map,
                wakeup: RemoteWakeup::default(),
                watchdog,
            },
            Local {
                housekeeping,
                store,
                stop,
            },
        )
    }

    /// A DMA block is full. Deadline: the next block (1 ms at rates of 1 kHz and more).
    #[task(binds = DMA2_STREAM0, priority = 3, shared = [sampler, tracker, status, stream, route])]
    fn dma(mut cx: dma::Context) {
        let now_ms = cx.shared.sampler.lock(Sampler::now_ms);
        let map = cx.shared.route.lock(|r| *r);
        let (mut tracker, mut status, mut stream) =
            (cx.shared.tracker, cx.shared.status, cx.shared.stream);
        let mut event = None;
        let outcome = cx.shared.sampler.lock(|s| {
            let outcome = s.on_dma(|block, delivery| {
                let (t, st, q) = (&mut tracker, &mut status, &mut stream);
                event = on_block(block, delivery, now_ms, map, t, st, q)
            });
            if let Outcome::Restarted(lost) = outcome {
                tracker.lock(|t| t.restarted(lost)); // under the sampler's lock: in order
                stream.lock(|q| q.lost(lost));
            }
            outcome
        });
        tasks::log_outcome(&outcome, event.as_ref());
        rtic::pend(Interrupt::OTG_FS);
    }

    /// The USB peripheral needs service, or the DMA task has fresh motion.
    #[task(binds = OTG_FS, priority = 2, shared = [tracker, mouse, commands, status, route, stream, sampler])]
    fn usb(cx: usb::Context) {
        let mut s = cx.shared;
        let (mut mouse, mut stream, mut sampler) = (s.mouse, s.stream, s.sampler);
        tasks::service_mouse(&mut mouse, &mut s.tracker, &mut s.route, &mut sampler);
        let mut r = Resources {
            mouse: &mut mouse,
            commands: &mut s.commands,
            tracker: &mut s.tracker,
            status: &mut s.status,
            route: &mut s.route,
            stream: &mut stream,
        };
        let effect = control::serve(&mut r, || sampler.lock(|s| s.ledger().counters().restarts));
        tasks::board_effect(&effect, &mut r, &mut sampler, || save::spawn().is_ok());
        control::push_stream(&mut mouse, &mut stream);
    }

    /// Keeps the running profile in flash, then answers the request that asked.
    #[task(priority = 1, shared = [commands, mouse], local = [store])]
    async fn save(mut cx: save::Context) {
        let profile = cx.shared.commands.lock(|c| *c.running());
        let result = cx.local.store.save(&profile);
        tasks::log_save(&result);
        control::answer_save(
            result.is_ok(),
            &mut cx.shared.commands,
            &mut cx.shared.mouse,
        );
        rtic::pend(Interrupt::OTG_FS);
    }

    /// Every millisecond, on a running deadline: stalled sampling, KEY, power, LED, logs,
    /// remote wake-up, watchdog.
    #[task(priority = 1, shared = [tracker, sampler, status, mouse, wakeup, watchdog], local = [housekeeping])]
    async fn housekeeping(mut cx: housekeeping::Context) {
        let mut next = Mono::now();
        loop {
            next += 1.millis();
            Mono::delay_until(next).await;
            // A save holds the CPU at this priority for up to seconds: the deadlines it
            // covered are skipped, not run in a burst that would compress the debounce; the
            // time itself comes from TIM5, which counts on through an erase's stall.
            let now = Mono::now();
            if now > next + 1.millis() {
                next = now;
            }
            let now_ms = cx.shared.sampler.lock(Sampler::now_ms);
            let arrives = tasks::check_stall(&mut cx.shared.sampler, &mut cx.shared.tracker);
            let sh = &mut cx.shared;
            let tick = cx.local.housekeeping.tick(
                now_ms,
                arrives,
                &mut sh.tracker,
                &mut sh.status,
                &mut sh.mouse,
            );
            match tick.power {
                PowerAction::Suspend => sh.sampler.lock(Sampler::suspend),
                PowerAction::Resume => sh.sampler.lock(Sampler::resume),
                PowerAction::Wake => sh.wakeup.lock(|w| w.start(now_ms, &mut sh.mouse)),
                PowerAction::None => {}
            }
            sh.wakeup.lock(|w| w.tick(now_ms, &mut sh.mouse));
            if tick.button.is_some() {
                rtic::pend(Interrupt::OTG_FS);
            }
            if tick.log {
                tasks::log_counters(&Snapshot::take(
                    &mut sh.tracker,
                    &mut sh.sampler,
                    &mut sh.mouse,
                ));
            }
            sh.watchdog.lock(IndependentWatchdog::feed);
        }
    }

    /// KEY pressed during a Stop (EXTI 0): the wake is the episode's to read.
    #[task(binds = EXTI0, priority = 4)]
    fn key_wake(_: key_wake::Context) {
        stop::clear_line(stop::KEY_LINE);
    }

    /// Resume or reset signalling during a Stop (EXTI 18).
    #[task(binds = OTG_FS_WKUP, priority = 4)]
    fn usb_wake(_: usb_wake::Context) {
        stop::clear_line(stop::USB_LINE);
    }

    /// The RTC wake-up timer during a Stop (EXTI 22).
    #[task(binds = RTC_WKUP, priority = 4)]
    fn probe_wake(_: probe_wake::Context) {
        stop::clear_line(stop::RTC_LINE);
    }

    /// Stop mode while suspended, else `wfi` (`tasks::rest`).
    #[idle(shared = [status, sampler, mouse, wakeup, watchdog], local = [stop])]
    fn idle(cx: idle::Context) -> ! {
        let mut s = cx.shared;
        loop {
            let (st, sa, m) = (&mut s.status, &mut s.sampler, &mut s.mouse);
            tasks::rest(cx.local.stop, st, sa, m, &mut s.wakeup, &mut s.watchdog);
        }
    }
}
