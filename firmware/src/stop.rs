//! Stop mode's registers while USB is suspended: the wake-up lines, the regulator, the
//! probe's scan and the clock restore behind `imu_app::sleep::StopMode`. Every decision
//! (when to stop, what a wake means, the reset when the clocks do not return) is
//! `imu_app::sleep`'s, tested on the host.
//!
//! # Design
//! - Wake-up lines (RM0383 10.2.5): line 0 (PA0, KEY to ground: falling edge), line 18
//!   (OTG_FS_WKUP: resume or reset signalling, rising), line 22 (the RTC wake-up timer, every
//!   [`board::PROBE_MS`] from the LSI, rising). Masked while awake; unmasked for a whole
//!   episode, whose first Stop clears them and restarts the RTC's period, while later Stops
//!   clear only the timer's line, so that a KEY or USB edge between two Stops stays pending.
//!   Their interrupts are bound at a priority above every resource ceiling (`main.rs`) and
//!   `wfi` runs with BASEPRI lowered to 0 (PRIMASK set), so any pending interrupt ends a
//!   Stop; the episode clears what it read in EXTI and in the NVIC, and the handlers (which
//!   only clear their line) run once the clocks are back.
//! - Entry: the sampling parked (TIM2 stopped, DMA off, ADC off), the USB PHY clock stopped
//!   (PCGCCTL.STPPCLK, as ST's own suspend does), PWR_CR: Stop (PDDS 0) with the low-power
//!   regulator in low-voltage mode (LPDS, LPLVDS) and the flash powered down (FPDS),
//!   SLEEPDEEP, `wfi`. The Stop is skipped when a line is pending, KEY is held, or the OTG
//!   core no longer reads the bus suspended ([`bus_suspended`]: a resume `imu_core::Power`
//!   has not yet seen).
//! - The core wakes on the HSI (16 MHz) with the PLL and HSE off; the prescalers, the
//!   flash wait states and the PLL's configuration are kept. [`Stop::restore`] turns the
//!   HSE on, locks the PLL, waits for the regulator's scale 1, switches to the PLL (each step
//!   bounded by [`board::RESTORE_SPINS`]), checks RCC_CFGR and RCC_PLLCFGR against their
//!   values at boot (after `check_clocks` passed), and only then restarts the PHY clock.
//! - The debugger: with one attached at boot, DBGMCU.DBG_STOP keeps the debug port alive
//!   in Stop (at a Stop current far above the data sheet's; SysTick's interrupt is off
//!   through each episode, so it does not end the Stops); without one, a real Stop.
//!
//! Only a board can show the current and the wake timing: see docs/device.md, "Suspend in
//! Stop mode, and its current".

use cortex_m::peripheral::{NVIC, SCB};
use imu_app::sleep::{StopMode, Wakes};
use stm32f4xx_hal::{
    pac::{self, Interrupt, EXTI, PWR},
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
    armed: bool,
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
    // SAFETY: synopsys-usb-otg writes PCGCCTL only when the bus is enabled at boot (to 0);
    // this runs with interrupts masked, so nothing interleaves with the read-modify-write.
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
            armed: false,
        };
        stop.mask(true);
        dbgmcu.cr().modify(|_, w| w.dbg_stop().bit(debugger));
        stop
    }

    /// Masks (awake) or unmasks (through an episode) the three lines' interrupts.
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

    /// Clears `lines`' pending bits in EXTI and in the NVIC (an unmasked line latches its
    /// interrupt there too, and a latched interrupt would end the next `wfi` at once), and
    /// the RTC's wake-up flag with the RTC's line (the line is the flag's rising edge: a
    /// flag left set would never raise it again).
    fn clear(&mut self, lines: &[u8]) {
        if lines.contains(&RTC_LINE) {
            self.rtc.clear_interrupt(Event::Wakeup);
        }
        self.exti.pr().write(|w| {
            for &line in lines {
                w.pr(line).clear();
            }
            w
        });
        for &line in lines {
            NVIC::unpend(match line {
                KEY_LINE => Interrupt::EXTI0,
                USB_LINE => Interrupt::OTG_FS_WKUP,
                _ => Interrupt::RTC_WKUP,
            });
        }
    }

    /// One Stop of an episode, the sampling parked first (see the module docs). The first
    /// of an episode clears the three lines, restarts the RTC's period (so that the first
    /// timer wake is a whole period after it) and unmasks them for the whole episode; later
    /// ones clear only the timer's line, so that a KEY or USB edge between two Stops stays
    /// pending. The Stop is skipped (its reason returned) when a line is already pending,
    /// KEY is held, or the USB core no longer reads the bus suspended.
    fn enter(&mut self, sampler: &mut Sampler) -> Wakes {
        sampler.park();
        if self.armed {
            self.clear(&[RTC_LINE]);
        } else {
            self.clear(&LINES);
            self.rtc
                .enable_wakeup(fugit::MicrosDurationU64::millis(u64::from(board::PROBE_MS)));
            self.mask(false);
            systick_interrupt(false);
            self.armed = true;
        }
        phy_clock_stopped(true);
        let mut wakes = self.pending();
        wakes.key |= key_down();
        wakes.usb |= !bus_suspended();
        if wakes == Wakes::default() {
            self.pwr.cr().modify(|_, w| {
                w.pdds().clear_bit();
                w.lpds().set_bit();
                w.lplvds().set_bit();
                w.fpds().set_bit()
            });
            self.scb.set_sleepdeep();
            sleep_unmasked();
            self.scb.clear_sleepdeep();
            wakes = self.pending();
        }
        wakes
    }

    /// Ends an episode: the lines masked and cleared (their handlers find nothing).
    fn disarm(&mut self) {
        self.mask(true);
        self.clear(&LINES);
        systick_interrupt(true);
        self.armed = false;
    }

    /// HSE, PLL, the regulator's scale, switch, then the clock tree checked against boot's;
    /// the PHY clock back. The episode ends here either way.
    #[allow(unsafe_code)]
    fn restore(&mut self) -> bool {
        self.disarm();
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
            // With the PLL off the regulator runs at scale 3; the scale 1 that 96 MHz needs
            // is back only once the PLL is on (RM0383 5.1.3).
            && spin(|| self.pwr.csr().read().vosrdy().bit_is_set())
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

/// Whether the OTG core reads the bus suspended with no resume or reset pending
/// (OTG_FS_DSTS.SUSPSTS set, GINTSTS.WKUPINT and USBRST clear): the host has not come back
/// since `imu_core::Power` last saw the suspend.
#[allow(unsafe_code)]
pub fn bus_suspended() -> bool {
    // SAFETY: reads of two status registers; nothing is written.
    let (dev, global) = unsafe { (&*pac::OTG_FS_DEVICE::ptr(), &*pac::OTG_FS_GLOBAL::ptr()) };
    let ints = global.gintsts().read();
    dev.dsts().read().suspsts().bit_is_set()
        && ints.wkupint().bit_is_clear()
        && ints.usbrst().bit_is_clear()
}

/// Lets SysTick raise its interrupt, or not (SYST_CSR.TICKINT). Off through an episode:
/// SysTick counts in each awake probe (and in Stop with a debugger's DBG_STOP), and its
/// pending interrupt would end the next Stop at once and, since every episode restarts the
/// RTC's period, keep the probe from ever running. The monotonic then misses a tick or two
/// of a suspend, which no deadline of a suspended device depends on (housekeeping's time is
/// TIM5's, credited for the Stop).
#[allow(unsafe_code)]
fn systick_interrupt(on: bool) {
    const TICKINT: u32 = 1 << 1;
    // SAFETY: rtic-monotonics programs SYST once at boot and then only reads its counter;
    // this flips one bit of the control register with interrupts masked. The pending state
    // latched meanwhile is cleared, so the episode's first Stop does not end at once.
    unsafe {
        let syst = &*cortex_m::peripheral::SYST::PTR;
        let csr = syst.csr.read();
        syst.csr
            .write(if on { csr | TICKINT } else { csr & !TICKINT });
    }
    if !on {
        SCB::clear_pendst();
    }
}

/// `wfi` with BASEPRI lowered to 0 for it: the episode runs inside RTIC locks, and a pending
/// interrupt below their ceiling (the USB interrupt after a resume, a DMA block) must end the
/// Stop too. Sound because PRIMASK masks every handler meanwhile.
#[allow(unsafe_code)]
fn sleep_unmasked() {
    let basepri = cortex_m::register::basepri::read();
    // SAFETY: with PRIMASK set (the caller runs inside `interrupt::free`) no handler can run
    // while BASEPRI is lowered, so no RTIC lock is broken; it is restored before return.
    unsafe { cortex_m::register::basepri::write(0) };
    cortex_m::asm::dsb();
    cortex_m::asm::wfi();
    unsafe { cortex_m::register::basepri::write(basepri) };
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
