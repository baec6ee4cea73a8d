//! The 1 ms housekeeping tick: KEY, power, LED and the log schedule, over the resources the
//! firmware shares between its tasks.
//!
//! # Design
//! Shared resources come in as `rtic_core::Mutex`es, so the firmware passes its RTIC
//! resource proxies and the host twin passes `rtic_core::Exclusive`: both run this sequence.
//! Each lock is short and none is nested. The tick is driven by a running deadline (the
//! caller's), so `now_ms` advances by exactly 1 per tick; the log schedule is a deadline too,
//! never a `now % interval == 0` test that a late tick could skip.

use embedded_hal::digital::{InputPin, OutputPin, PinState};
use imu_core::{hid::buttons, ButtonEvent, Debouncer, PowerAction, Tracker};
use rtic_core::Mutex;
use usb_device::bus::UsbBus;

use crate::mouse::Mouse;
use crate::status::Status;

/// Timing of the housekeeping tick, in ticks of 1 ms.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Timing {
    /// Debounce of KEY [ms] (`>= 1`).
    pub debounce_ms: u16,
    /// Holding KEY this long recalibrates [ms].
    pub long_press_ms: u32,
    /// Interval of the periodic counter log [ms] (`>= 1`).
    pub log_interval_ms: u32,
}

/// What a tick decided that the caller carries out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Tick {
    /// The debounced KEY event, if one happened (already applied to the tracker and mouse;
    /// the caller should get a report out soon).
    pub button: Option<ButtonEvent>,
    /// What the sampling hardware must do for USB suspend and resume.
    pub power: PowerAction,
    /// Whether the periodic counter log is due.
    pub log: bool,
}

/// The housekeeping task's own state: KEY and LED pins and their timing.
pub struct Housekeeping<K, L> {
    key: K,
    key_active_low: bool,
    led: L,
    led_active_low: bool,
    debouncer: Debouncer,
    log_interval_ms: u32,
    next_log_ms: u32,
}

impl<K: InputPin, L: OutputPin> Housekeeping<K, L> {
    /// KEY on `key` (pressed when low if `key_active_low`), the LED on `led` (lit when low
    /// if `led_active_low`), first log at `start_ms` + the log interval.
    pub fn new(
        key: K,
        key_active_low: bool,
        led: L,
        led_active_low: bool,
        timing: Timing,
        start_ms: u32,
    ) -> Self {
        let log_interval_ms = timing.log_interval_ms.max(1);
        Self {
            key,
            key_active_low,
            led,
            led_active_low,
            debouncer: Debouncer::new(timing.debounce_ms, timing.long_press_ms),
            log_interval_ms,
            next_log_ms: start_ms.wrapping_add(log_interval_ms),
        }
    }

    /// One tick at `now_ms` [ms]; `arrives` says whether ADC data arrives (the board's stall
    /// check). A pin that cannot be read counts as KEY released.
    pub fn tick<'a, B: UsbBus + 'a>(
        &mut self,
        now_ms: u32,
        arrives: bool,
        tracker: &mut impl Mutex<T = Tracker>,
        status: &mut impl Mutex<T = Status>,
        mouse: &mut impl Mutex<T = Mouse<'a, B>>,
    ) -> Tick {
        let raw = self.key.is_low().map(|low| low == self.key_active_low);
        let button = self.debouncer.tick(raw.unwrap_or(false));
        match button {
            Some(ButtonEvent::Pressed) => press(tracker, mouse, buttons::LEFT),
            Some(ButtonEvent::Released) => press(tracker, mouse, 0),
            Some(ButtonEvent::LongPress) => tracker.lock(Tracker::recalibrate),
            None => {}
        }
        let (link, wake_ok) =
            mouse.lock(|m| (m.reports().link(), m.device().remote_wakeup_enabled()));
        let pressed = self.debouncer.is_pressed();
        let power = status.lock(|s| s.power(now_ms, link, wake_ok, pressed));
        if power == PowerAction::Resume {
            // The rest the tracker knew is stale after a suspend of any length.
            tracker.lock(Tracker::recalibrate);
        }
        let shown = tracker.lock(|t| status.lock(|s| s.indicator(link, arrives, t, now_ms)));
        let lit = shown.lit(now_ms) != self.led_active_low;
        // An LED that cannot be driven changes nothing the device does.
        let _ = self.led.set_state(PinState::from(lit));
        // Due once now is at or past the deadline, on a clock that wraps every 49.7 days:
        // the signed distance decides, as long as ticks are less than 24.8 days apart.
        let log = now_ms.wrapping_sub(self.next_log_ms) as i32 >= 0;
        if log {
            self.next_log_ms = self.next_log_ms.wrapping_add(self.log_interval_ms);
        }
        Tick { button, power, log }
    }
}

/// A debounced press or release: the buttons for the next report, and a click edge for drift
/// control (the jolt of a click must not drag the cursor).
fn press<'a, B: UsbBus + 'a>(
    tracker: &mut impl Mutex<T = Tracker>,
    mouse: &mut impl Mutex<T = Mouse<'a, B>>,
    held: u8,
) {
    mouse.lock(|m| m.set_buttons(held));
    tracker.lock(Tracker::button_edge);
}
