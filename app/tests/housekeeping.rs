//! The housekeeping tick as the firmware and the twin run it: the log schedule is a running
//! deadline (every 5000 ticks exactly, from the start), KEY is debounced 5 ticks and reaches
//! the buttons, and the LED follows the documented precedence. The USB bus here never
//! enumerates (a bus with no host), which is also what a board without a USB cable sees.

use std::cell::Cell;
use std::rc::Rc;

use embedded_hal::digital::{ErrorType, InputPin, OutputPin};
use imu_app::{device, Housekeeping, Mouse, Status};
use imu_core::{ButtonEvent, Link, PowerAction, Tracker};
use rtic_core::Exclusive;
use usb_device::bus::{PollResult, UsbBus, UsbBusAllocator};
use usb_device::endpoint::{EndpointAddress, EndpointType};
use usb_device::{Result as UsbResult, UsbDirection};

/// A bus with no host attached: nothing ever arrives.
struct NoHost;

impl UsbBus for NoHost {
    fn alloc_ep(
        &mut self,
        dir: UsbDirection,
        addr: Option<EndpointAddress>,
        _: EndpointType,
        _: u16,
        _: u8,
    ) -> UsbResult<EndpointAddress> {
        Ok(addr.unwrap_or(EndpointAddress::from_parts(1, dir)))
    }
    fn enable(&mut self) {}
    fn reset(&self) {}
    fn set_device_address(&self, _: u8) {}
    fn write(&self, _: EndpointAddress, _: &[u8]) -> UsbResult<usize> {
        Err(usb_device::UsbError::WouldBlock)
    }
    fn read(&self, _: EndpointAddress, _: &mut [u8]) -> UsbResult<usize> {
        Err(usb_device::UsbError::WouldBlock)
    }
    fn set_stalled(&self, _: EndpointAddress, _: bool) {}
    fn is_stalled(&self, _: EndpointAddress) -> bool {
        false
    }
    fn suspend(&self) {}
    fn resume(&self) {}
    fn poll(&self) -> PollResult {
        PollResult::None
    }
}

#[derive(Clone)]
struct Key(Rc<Cell<bool>>);
impl ErrorType for Key {
    type Error = core::convert::Infallible;
}
impl InputPin for Key {
    fn is_high(&mut self) -> Result<bool, Self::Error> {
        Ok(!self.0.get())
    }
    fn is_low(&mut self) -> Result<bool, Self::Error> {
        Ok(self.0.get()) // active low: pressed pulls it to ground
    }
}

#[derive(Clone)]
struct Led(Rc<Cell<bool>>);
impl ErrorType for Led {
    type Error = core::convert::Infallible;
}
impl OutputPin for Led {
    fn set_low(&mut self) -> Result<(), Self::Error> {
        self.0.set(false);
        Ok(())
    }
    fn set_high(&mut self) -> Result<(), Self::Error> {
        self.0.set(true);
        Ok(())
    }
}

/// One housekeeping tick over exclusively held resources, as the twin runs it.
fn tick(
    hk: &mut Housekeeping<Key, Led>,
    now_ms: u32,
    arrives: bool,
    tracker: &mut Tracker,
    status: &mut Status,
    mouse: &mut Mouse<'_, NoHost>,
) -> imu_app::housekeeping::Tick {
    hk.tick(
        now_ms,
        arrives,
        &mut Exclusive(tracker),
        &mut Exclusive(status),
        &mut Exclusive(mouse),
    )
}

#[test]
fn logs_every_interval_key_debounced_and_led_shows_not_configured() {
    let alloc = UsbBusAllocator::new(NoHost);
    let mut mouse = Mouse::new(&alloc, imu_app::identity::SERIAL).expect("identity fits");
    let mut tracker = Tracker::new(&device::tracker_config(3000)).expect("valid");
    let mut status = Status::new(20);
    let pressed = Rc::new(Cell::new(false));
    let lit_low = Rc::new(Cell::new(true));
    let start = 123u32;
    let mut hk = Housekeeping::new(
        Key(pressed.clone()),
        true,
        Led(lit_low.clone()),
        true,
        device::TIMING,
        start,
    );
    let (mut logs, mut events, mut lit_ms) = (vec![], vec![], 0u32);
    for ms in start + 1..=start + 12_000 {
        pressed.set((start + 100..start + 110).contains(&ms) || ms == start + 200);
        mouse.service([0; 3], ms);
        let tick = tick(&mut hk, ms, true, &mut tracker, &mut status, &mut mouse);
        if tick.log {
            logs.push(ms - start);
        }
        if let Some(e) = tick.button {
            events.push((ms - start, e));
        }
        assert_eq!(tick.power, PowerAction::None);
        if (start + 2000..start + 3000).contains(&ms) && !lit_low.get() {
            lit_ms += 1; // lit when low
        }
    }
    assert_eq!(
        logs,
        [5000, 10_000],
        "a log every 5000 ticks, none skipped or doubled"
    );
    // A 10 ms press: seen 5 ticks after it starts and ends; the 1-tick glitch never.
    assert_eq!(
        events,
        [(104, ButtonEvent::Pressed), (114, ButtonEvent::Released)]
    );
    assert_eq!(mouse.reports().link(), Link::NotConfigured);
    assert_eq!(lit_ms, 100, "not configured: one 100 ms flash a second");
}

#[test]
fn no_adc_data_outranks_usb_on_the_led() {
    let alloc = UsbBusAllocator::new(NoHost);
    let mut mouse = Mouse::new(&alloc, imu_app::identity::SERIAL).expect("identity fits");
    let mut tracker = Tracker::new(&device::tracker_config(3000)).expect("valid");
    let mut status = Status::new(20);
    let lit_low = Rc::new(Cell::new(true));
    let key = Key(Rc::new(Cell::new(false)));
    let mut hk = Housekeeping::new(key, true, Led(lit_low.clone()), true, device::TIMING, 0);
    let mut lit_ms = 0;
    for ms in 1..=2000u32 {
        tick(&mut hk, ms, false, &mut tracker, &mut status, &mut mouse);
        lit_ms += u32::from(!lit_low.get());
    }
    assert_eq!(lit_ms, 1000, "no data: on 1 s, off 1 s");
}

#[test]
fn a_press_reaches_the_report_and_the_tracker_keeps_tracking() {
    // A tracking device: housekeeping must not recalibrate it on ordinary ticks (only on a
    // resume from suspend), and a debounced press must reach the mouse's next report and
    // drift control (a click edge freezes integration for its click-freeze time).
    let alloc = UsbBusAllocator::new(NoHost);
    let mut mouse = Mouse::new(&alloc, imu_app::identity::SERIAL).expect("identity fits");
    let mut tracker = Tracker::new(&device::tracker_config(3000)).expect("valid");
    tracker.feed(&[[2048, 2048, 2457]; 3000]);
    assert_eq!(tracker.phase(), imu_core::Phase::Tracking);
    let mut status = Status::new(20);
    let pressed = Rc::new(Cell::new(true));
    let mut hk = Housekeeping::new(
        Key(pressed),
        true,
        Led(Rc::new(Cell::new(true))),
        true,
        device::TIMING,
        0,
    );
    for ms in 1..=20u32 {
        tick(&mut hk, ms, true, &mut tracker, &mut status, &mut mouse);
    }
    assert_eq!(
        tracker.phase(),
        imu_core::Phase::Tracking,
        "no recalibration"
    );
    assert!(
        mouse.reports().pending(),
        "the press waits in the next report"
    );
    tracker.feed(&[[2048, 2048, 2457]; 30]);
    assert_eq!(
        tracker.counters().frozen_samples,
        30,
        "the click edge froze integration"
    );
}

#[test]
fn a_late_tick_still_logs_once() {
    // Ticks may come late (a busy executor): a tick past the deadline logs, and the next
    // deadline stays on the 5000 ms grid.
    let alloc = UsbBusAllocator::new(NoHost);
    let mut mouse = Mouse::new(&alloc, imu_app::identity::SERIAL).expect("identity fits");
    let mut tracker = Tracker::new(&device::tracker_config(3000)).expect("valid");
    let mut status = Status::new(20);
    let mut hk = Housekeeping::new(
        Key(Rc::new(Cell::new(false))),
        true,
        Led(Rc::new(Cell::new(true))),
        true,
        device::TIMING,
        u32::MAX - 1000, // the millisecond clock wraps during the run
    );
    let mut logged = vec![];
    for ms in [4000u32, 4003, 4004, 9003, 9004] {
        let now = (u32::MAX - 1000).wrapping_add(ms);
        let tick = tick(&mut hk, now, true, &mut tracker, &mut status, &mut mouse);
        if tick.log {
            logged.push(ms);
        }
    }
    assert_eq!(
        logged,
        [9003],
        "none before 5000, one late at 9003, none doubled"
    );
}

#[test]
fn the_mouse_services_its_reports_with_its_devices_state() {
    // With no host the device stays in its default state: fresh counts are accounted as
    // discarded, and a button change waits.
    let alloc = UsbBusAllocator::new(NoHost);
    let mut mouse = Mouse::new(&alloc, imu_app::identity::SERIAL).expect("identity fits");
    mouse.service([10, -4, 7], 0);
    assert_eq!(mouse.reports().reporter().discarded(), (10, 4));
    assert!(!mouse.reports().pending());
    mouse.set_buttons(imu_core::hid::buttons::RIGHT);
    assert!(mouse.reports().pending());
    assert!(!mouse.device().remote_wakeup_enabled());
}
