//! Stop mode's registers while USB is suspended: the wake-up lines, the regulator, the
//! probe's scan and the clock restore behind `imu_app::sleep::StopMode`. Every decision
//! (when to stop, what a wake means, the reset when the clocks do not return) is
//! `imu_app::sleep`'s, tested on the host.
//!
//! # Design
//! - Wake-up lines (RM0383 10.2.5), armed in EXTI's interrupt mask only around each Stop,
//!   so that awake they raise nothing: line 0 (PA0, KEY to ground: falling edge), line 18
//!   (OTG_FS_WKUP: resume or reset signalling, rising), line 22 (the RTC wake-up timer, every
//!   [`board::PROBE_MS`] from the LSI, rising). Their interrupts are bound at a priority
//!   above every resource ceiling (`main.rs`), so `wfi` wakes inside the locks the episode
//!   holds; the episode runs with interrupts masked, so the handlers (which only clear
//!   their line) run once the clocks are back.
//! - Entry: the sampling parked (TIM2 stopped, DMA off, ADC off), the USB PHY clock
//!   stopped (PCGCCTL.STPPCLK, as RM0383 22.17.4 asks of a suspended core), PWR_CR: Stop
//!   (PDDS 0) with the low-power regulator in low-voltage mode (LPDS, LPLVDS) and the
//!   flash powered down (FPDS), SLEEPDEEP, `wfi`. A line already pending skips the Stop.
//! - The core wakes on the HSI (16 MHz) with the PLL and HSE off; the prescalers, the
//!   flash wait states and the PLL's configuration are kept. [`Stop::restore`] turns the
//!   HSE on, locks the PLL, switches to it (each step bounded by
//!   [`board::RESTORE_SPINS`]), checks RCC_CFGR and RCC_PLLCFGR against their values at boot
//!   (after `check_clocks` passed), and only then restarts the PHY clock.
//! - The debugger: with one attached at boot, DBGMCU.DBG_STOP keeps the debug port alive
//!   in Stop (at a Stop current far above the data sheet's); without one, a real Stop.
//!
//! Only a board can show the current and the wake timing: see README, "Suspend current".

use cortex_m::peripheral::SCB;
use imu_app::sleep::{StopMode, Wakes};
use stm32f4xx_hal::{
    pac::{self, EXTI, PWR},
    rtc::{Event, Rtc},
    watchdog::IndependentWatchdog,
};

use crate::board;
use crate::sampling::Sampler;

/// EXTI line of KEY (PA0).
pub const KEY_LINE: u8 = 0;
/// EXTI line of OTG_FS_WKUP.
pub const USB_LINE: u8 = 18;
/// EXTI line of the RTC wake-up timer.
pub const RTC_LINE: u8 = 22;
/// The three lines.
const LINES: [u8; 3] = [KEY_LINE, USB_LINE, RTC_LINE];

/// The clock tree as boot left it, after `check_clocks` passed.
#[derive(Clone, Copy)]
struct ClockTree {
    cfgr: u32,
    pllcfgr: u32,
}

impl ClockTree {
    fn now(rcc: &pac::rcc::RegisterBlock) -> Self {
        Self {
            cfgr: rcc.cfgr().read().bits(),
            pllcfgr: rcc.pllcfgr().read().bits(),
        }
    }
}

/// The Stop mode's registers: EXTI, PWR, the RTC's wake-up timer, SLEEPDEEP, and the clock
/// tree to restore.
pub struct Stop {
    exti: EXTI,
    pwr: PWR,
    rtc: Rtc,
    scb: SCB,
    boot: ClockTree,
}

/// Clears the pending bit of EXTI `line` (the wake-up handlers' one job).
#[allow(unsafe_code)]
pub fn clear_line(line: u8) {
    // SAFETY: PR is write-one-to-clear: this one store clears this line's bit and no other,
    // so it cannot race the episode's own clearing (which runs with interrupts masked).
    let exti = unsafe { &*EXTI::ptr() };
    exti.pr().write(|w| w.pr(line).clear());
}

/// Whether KEY is held now (PA0 low), its raw level.
#[allow(unsafe_code)]
pub fn key_down() -> bool {
    // SAFETY: reading the input data register has no side effect on the port.
    let gpioa = unsafe { &*pac::GPIOA::ptr() };
    gpioa.idr().read().idr0().bit_is_clear()
}

/// Sets or clears the OTG core's PHY clock stop (PCGCCTL.STPPCLK).
#[allow(unsafe_code)]
fn phy_clock_stopped(stopped: bool) {
    // SAFETY: PCGCCTL is written by the USB stack only at a bus reset (to 0), in the USB
    // interrupt, which cannot run here: the episode runs with interrupts masked.
    let pwrclk = unsafe { &*pac::OTG_FS_PWRCLK::ptr() };
    pwrclk.pcgcctl().modify(|_, w| w.stppclk().bit(stopped));
}

/// Waits up to [`board::RESTORE_SPINS`] reads for `ready`.
fn spin(ready: impl Fn() -> bool) -> bool {
    (0..board::RESTORE_SPINS).any(|_| ready())
}

impl Stop {
    /// Arms the wake-up sources' edges (the mask is set around each Stop): KEY's line is
    /// PA0's (port A is SYSCFG_EXTICR1's reset value, and nothing changes it), the RTC
    /// wake-up timer runs at [`board::PROBE_MS`] on the LSI. `debugger`: one is attached at
    /// boot (DBG_STOP set, see the module docs).
    pub fn new(
        mut exti: EXTI,
        pwr: PWR,
        mut rtc: Rtc,
        scb: SCB,
        rcc: &pac::rcc::RegisterBlock,
        dbgmcu: &pac::DBGMCU,
        debugger: bool,
    ) -> Self {
        exti.ftsr().modify(|_, w| w.tr(KEY_LINE).set_bit());
        exti.rtsr().modify(|_, w| w.tr(USB_LINE).set_bit());
        rtc.enable_wakeup(fugit::MicrosDurationU64::millis(u64::from(board::PROBE_MS)));
        rtc.listen(&mut exti, Event::Wakeup);
        let mut stop = Self {
            exti,
            pwr,
            rtc,
            scb,
            boot: ClockTree::now(rcc),
        };
        stop.mask(true);
        dbgmcu.cr().modify(|_, w| w.dbg_stop().bit(debugger));
        stop
    }

    /// Masks (awake) or unmasks (around a Stop) the three lines' interrupts.
    fn mask(&mut self, masked: bool) {
        self.exti.imr().modify(|_, w| {
            for line in LINES {
                w.mr(line).bit(!masked);
            }
            w
        });
    }

    /// The lines pending now.
    fn pending(&self) -> Wakes {
        let pr = self.exti.pr().read();
        Wakes {
            usb: pr.pr(USB_LINE).bit_is_set(),
            key: pr.pr(KEY_LINE).bit_is_set(),
            timer: pr.pr(RTC_LINE).bit_is_set(),
        }
    }

    /// Clears the three lines' pending bits and the RTC's wake-up flag (the line is its
    /// rising edge: a flag left set would never raise it again).
    fn clear(&mut self) {
        self.rtc.clear_interrupt(Event::Wakeup);
        self.exti.pr().write(|w| {
            for line in LINES {
                w.pr(line).clear();
            }
            w
        });
    }

    /// One Stop, the sampling parked first (see the module docs).
    fn enter(&mut self, sampler: &mut Sampler) -> Wakes {
        sampler.park();
        phy_clock_stopped(true);
        self.clear();
        self.mask(false);
        if self.pending() == Wakes::default() {
            self.pwr.cr().modify(|_, w| {
                w.pdds().clear_bit();
                w.lpds().set_bit();
                w.lplvds().set_bit();
                w.fpds().set_bit()
            });
            self.scb.set_sleepdeep();
            cortex_m::asm::dsb();
            cortex_m::asm::wfi();
            self.scb.clear_sleepdeep();
        }
        let fired = self.pending();
        self.mask(true);
        self.clear();
        fired
    }

    /// HSE, PLL, switch, then the clock tree checked against boot's; the PHY clock back.
    #[allow(unsafe_code)]
    fn restore(&mut self) -> bool {
        // SAFETY: RCC_CR and RCC_CFGR are written only at boot (the HAL's `freeze`) and
        // here, with interrupts masked; the sampler's `Rcc` touches only the enable and reset
        // registers of its peripherals.
        let rcc = unsafe { &*pac::RCC::ptr() };
        rcc.cr().modify(|_, w| w.hseon().set_bit());
        let ok = spin(|| rcc.cr().read().hserdy().bit_is_set())
            && {
                rcc.cr().modify(|_, w| w.pllon().set_bit());
                spin(|| rcc.cr().read().pllrdy().bit_is_set())
            }
            && {
                rcc.cfgr().modify(|_, w| w.sw().pll());
                spin(|| rcc.cfgr().read().sws().is_pll())
            };
        let same = ok && {
            let now = ClockTree::now(rcc);
            now.cfgr == self.boot.cfgr && now.pllcfgr == self.boot.pllcfgr
        };
        if same {
            phy_clock_stopped(false);
        }
        same
    }
}

/// The board's Stop mode for one episode: the registers, the sampler (parked, and its
/// probe scans) and the watchdog.
pub struct Board<'a> {
    /// The Stop mode's registers.
    pub stop: &'a mut Stop,
    /// The sampling, parked during the episode.
    pub sampler: &'a mut Sampler,
    /// The independent watchdog (counting on in Stop, on the LSI).
    pub watchdog: &'a mut IndependentWatchdog,
}

impl StopMode for Board<'_> {
    fn stop(&mut self) -> Wakes {
        self.stop.enter(self.sampler)
    }

    fn scan(&mut self) -> Option<[u16; 3]> {
        self.sampler.probe_scan()
    }

    fn feed(&mut self) {
        self.watchdog.feed();
    }

    fn restore(&mut self) -> bool {
        self.stop.restore()
    }
}
