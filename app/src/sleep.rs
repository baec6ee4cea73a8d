//! Stop mode while USB is suspended: when the board stops its clocks, what each wake-up
//! means, and why a wake that cannot restore the clocks resets.
//!
//! # Design
//! A suspended device may draw 2.5 mA from the bus (USB 2.0, 7.2.3); the F411 at 96 MHz in
//! `wfi` draws tens of mA. In Stop mode (regulator in low-power mode, flash powered down)
//! every clock but the LSI stops, RAM and registers are kept, and three EXTI lines wake the
//! core ([`StopMode`], `firmware/src/stop.rs`):
//! - **USB resume or reset** (OTG_FS_WKUP, EXTI 18): the clocks are restored and the USB
//!   stack sees the resume; `imu_core::Power` then resumes the sampling.
//! - **KEY** (EXTI 0): the clocks are restored, and the board stays awake while KEY is held
//!   ([`may_stop`]) so that the debounce and `Power` see the press and signal a remote
//!   wake-up.
//! - **The RTC wake-up timer**, every probe period (EXTI 22): one scan of X, Y, Z on the wake
//!   clock (HSI) for the motion probe, and the watchdog fed (the IWDG counts on in Stop).
//!   Back to Stop at once, unless the probe found motion that `Power` would signal now
//!   ([`imu_core::Power::motion_pending`]).
//!
//! Any other wake (an interrupt that was already pending, so the core never stopped)
//! restores the clocks and lets that interrupt run (the board keeps SysTick's interrupt off
//! through an episode, or its ticks would end the Stops). The board stops only when nothing needs its clocks ([`may_stop`]): suspended, the
//! USB core still reading the bus suspended, no remote wake-up being signalled (the OTG core
//! drives it from the 48 MHz clock), KEY released, no motion pending. Every rule here is a
//! state, none a time constant: the board is awake exactly as long as something needs it.
//!
//! A restore that fails (HSE or PLL not ready in time, or the clock tree read back unlike at
//! boot) ends the episode in [`End::Reset`]: a mouse that cannot get its USB clock back is
//! lost to its user until unplugged, and a reset re-runs boot's clock checks.
//!
//! Time: the cycle counter behind [`crate::uptime`] stops with the clocks, so each timer wake
//! credits one probe period ([`Episode::slept_ms`]); a wake by another source credits
//! nothing (at most one probe period lost, so `Power`'s 1 s retry may come up to one probe
//! period late). The probe period is the RTC's, timed by the LSI (17 to 47 kHz on the F411),
//! so a credited millisecond is 0.7 to 1.9 real ones; only the wake-up retry depends on it.

use crate::status::Status;

/// The board's Stop mode, as the decisions use it.
pub trait StopMode {
    /// Enters Stop with the wake-up sources armed and returns after the wake, on the wake
    /// clock, interrupts still masked; the sources that fired, each cleared. The board parks
    /// the sampling first (trigger stopped, DMA stream off, ADC off): nothing draws current
    /// that the probe does not need.
    fn stop(&mut self) -> Wakes;
    /// One scan of X, Y, Z on the wake clock `[x, y, z]` [ADC codes], the ADC powered only
    /// for it; `None` if the ADC did not answer.
    fn scan(&mut self) -> Option<[u16; 3]>;
    /// Feeds the independent watchdog.
    fn feed(&mut self);
    /// Restores the run clocks (HSE, PLL, the switch to it) and checks them against boot's;
    /// false if any step failed.
    fn restore(&mut self) -> bool;
}

/// The wake-up sources that fired during one Stop.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Wakes {
    /// USB resume or reset signalling (EXTI 18).
    pub usb: bool,
    /// KEY pressed (EXTI 0).
    pub key: bool,
    /// The RTC wake-up timer: one probe period passed (EXTI 22).
    pub timer: bool,
}

/// Why the board left Stop.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Why {
    /// The host resumed or reset the bus.
    Usb,
    /// KEY was pressed.
    Key,
    /// The probe found motion that `Power` signals next.
    Motion,
    /// The probe's scan failed (the acquisition could not be parked): awake; the next
    /// episode tries again a probe period later, and the log says why.
    Scan,
    /// No wake-up source fired: an interrupt was pending, which now runs.
    Other,
}

/// How a Stop episode ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum End {
    /// Running on the restored clocks, for this reason.
    Awake(Why),
    /// The clocks could not be restored: the board must reset.
    Reset(Why),
}

/// One Stop episode: from the first Stop to the restored clocks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Episode {
    /// Time asleep that the cycle counter did not see [ms]: probe periods, one a timer wake.
    pub slept_ms: u32,
    /// Probe scans taken.
    pub probes: u32,
    /// How it ended.
    pub end: End,
}

/// Whether the board may stop its clocks now, at `now_ms` [ms]: suspended as `Power` saw it
/// and `bus_suspended` still (the USB core's own reading, with no resume or reset pending:
/// `Power` sees the link only once a millisecond, and a resume in between must not be
/// slept through), no remote wake-up `signalling`, KEY not `key_down` (its raw level), and
/// no motion pending that `Power` would signal to a host that enabled `remote_wakeup`.
pub fn may_stop(
    status: &Status,
    now_ms: u32,
    remote_wakeup: bool,
    signalling: bool,
    key_down: bool,
    bus_suspended: bool,
) -> bool {
    status.suspended()
        && bus_suspended
        && !signalling
        && !key_down
        && !status.motion_pending(now_ms, remote_wakeup)
}

/// Runs one Stop episode from `now_ms` [ms]: Stop, and on each timer wake feed the watchdog,
/// credit `probe_ms` [ms] and probe, until a wake that needs the clocks; then restore them.
/// The probe samples go to `status`'s suspend state machine.
pub fn episode(
    hw: &mut impl StopMode,
    status: &mut Status,
    now_ms: u32,
    remote_wakeup: bool,
    probe_ms: u32,
) -> Episode {
    let mut slept_ms = 0u32;
    let mut probes = 0u32;
    let why = loop {
        let wakes = hw.stop();
        if wakes.timer {
            hw.feed();
            slept_ms = slept_ms.wrapping_add(probe_ms);
        }
        if wakes.usb {
            break Why::Usb;
        }
        if wakes.key {
            break Why::Key;
        }
        if !wakes.timer {
            break Why::Other;
        }
        let Some(codes) = hw.scan() else {
            break Why::Scan;
        };
        probes += 1;
        status.probe(codes);
        if status.motion_pending(now_ms.wrapping_add(slept_ms), remote_wakeup) {
            break Why::Motion;
        }
    };
    let end = if hw.restore() {
        End::Awake(why)
    } else {
        End::Reset(why)
    };
    Episode {
        slept_ms,
        probes,
        end,
    }
}
