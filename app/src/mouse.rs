//! The USB HID mouse: device and class set-up over any `usb_device` bus, and one service
//! routine that polls the stack and pushes the next report.
//!
//! # Design
//! The report descriptor and the report bytes come from `imu_core::hid`, shared with the
//! host's `cargo lab hid`. The class keeps `HidSubClass::NoSubClass` (a Boot subclass would
//! refuse reports in report protocol). A report is pushed when the core has one pending;
//! the motion it carries is subtracted only after the push succeeded, so a `WouldBlock`
//! (the host has not read the last one yet) loses nothing. While the device is not
//! configured (reset, suspended, unplugged) motion is discarded rather than delivered late
//! as a jump, and every change of the link makes the reporter send the buttons again.

use imu_core::hid::{Reporter, MOUSE_REPORT_DESCRIPTOR};
use imu_core::Link;
use usb_device::{
    bus::{UsbBus, UsbBusAllocator},
    device::{StringDescriptors, UsbDevice, UsbDeviceBuilder, UsbDeviceState, UsbVidPid},
    prelude::BuilderError,
    UsbError,
};
use usbd_hid::hid_class::{
    HIDClass, HidClassSettings, HidProtocol, HidSubClass, ProtocolModeConfig,
};

use crate::identity;

/// The HID report descriptor, in static memory as the class requires.
static DESCRIPTOR: [u8; MOUSE_REPORT_DESCRIPTOR.len()] = MOUSE_REPORT_DESCRIPTOR;

/// The HID class exactly as the device builds it (the class tests build it the same way).
pub fn hid_class<B: UsbBus>(bus: &UsbBusAllocator<B>) -> HIDClass<'_, B> {
    let settings = HidClassSettings {
        subclass: HidSubClass::NoSubClass,
        protocol: HidProtocol::Mouse,
        config: ProtocolModeConfig::ForceReport,
        ..HidClassSettings::default()
    };
    HIDClass::new_ep_in_with_settings(bus, &DESCRIPTOR, identity::POLL_MS, settings)
}

/// The USB device exactly as the device builds it: [`identity`]'s IDs, strings and power,
/// remote wake-up supported.
///
/// # Errors
/// The builder's error if the strings or the power do not fit (they are constants).
pub fn usb_device<B: UsbBus>(bus: &UsbBusAllocator<B>) -> Result<UsbDevice<'_, B>, BuilderError> {
    let (vid, pid) = identity::VID_PID;
    Ok(UsbDeviceBuilder::new(bus, UsbVidPid(vid, pid))
        .strings(&[StringDescriptors::default()
            .manufacturer(identity::MANUFACTURER)
            .product(identity::PRODUCT)
            .serial_number(identity::SERIAL)])?
        .device_release(identity::RELEASE_BCD)
        .max_power(identity::MAX_POWER_MA)?
        .supports_remote_wakeup(true)
        .build())
}

/// The mouse: USB device, HID class, and the report scheduler.
pub struct Mouse<'a, B: UsbBus> {
    dev: UsbDevice<'a, B>,
    hid: HIDClass<'a, B>,
    reporter: Reporter,
    link: Link,
    drops: u32,
}

impl<'a, B: UsbBus> Mouse<'a, B> {
    /// Builds the device on `bus`.
    ///
    /// # Errors
    /// The builder's error if the strings do not fit (they are constants in [`identity`]).
    pub fn new(bus: &'a UsbBusAllocator<B>) -> Result<Self, BuilderError> {
        let hid = hid_class(bus);
        let dev = usb_device(bus)?;
        Ok(Self {
            dev,
            hid,
            reporter: Reporter::default(),
            link: Link::NotConfigured,
            drops: 0,
        })
    }

    /// Polls the USB stack, adds the tracker's fresh `counts` `[x, y, z]` and pushes the next
    /// pending report, if any.
    pub fn service(&mut self, counts: [i32; 3]) {
        self.dev.poll(&mut [&mut self.hid]);
        let link = match self.dev.state() {
            UsbDeviceState::Configured => Link::Configured,
            UsbDeviceState::Suspend => Link::Suspended,
            UsbDeviceState::Default | UsbDeviceState::Addressed => Link::NotConfigured,
        };
        if link != self.link {
            // Enumerated, reset, suspended or resumed: what the host knows starts afresh.
            self.reporter.host_reset();
            self.link = link;
        }
        if link != Link::Configured {
            self.reporter.discard_motion();
            return;
        }
        let (dx, dy) = imu_core::hid::screen_motion(counts);
        self.reporter.add_motion(dx, dy);
        if let Some(report) = self.reporter.pending() {
            match self.hid.push_raw_input(&report.to_bytes()) {
                Ok(_) => self.reporter.sent(&report),
                Err(UsbError::WouldBlock) => {}
                Err(_) => self.drops = self.drops.wrapping_add(1),
            }
        }
    }

    /// Sets the held buttons (`imu_core::hid::buttons` bits); sent with the next report.
    pub fn set_buttons(&mut self, held: u8) {
        self.reporter.set_buttons(held);
    }

    /// The link as of the last [`Self::service`].
    pub fn link(&self) -> Link {
        self.link
    }

    /// Whether the host has allowed remote wake-up (SET_FEATURE DEVICE_REMOTE_WAKEUP).
    pub fn remote_wakeup_enabled(&self) -> bool {
        self.dev.remote_wakeup_enabled()
    }

    /// Whether a report is waiting to be pushed (motion or a button change).
    pub fn pending(&self) -> bool {
        self.reporter.pending().is_some()
    }

    /// Reports accepted by the USB stack.
    pub fn reports(&self) -> u32 {
        self.reporter.reports()
    }

    /// The motion accepted by the USB stack so far, `(x, y)` [counts], wrapping.
    pub fn sent_total(&self) -> (i64, i64) {
        self.reporter.sent_total()
    }

    /// The motion dropped while the host was not listening, `(x, y)` [counts], wrapping.
    pub fn discarded(&self) -> (i64, i64) {
        self.reporter.discarded()
    }

    /// The motion owed to the host now, `(x, y)` [counts].
    pub fn undelivered(&self) -> (i64, i64) {
        self.reporter.undelivered()
    }

    /// Reports refused by the USB stack for a reason other than "busy".
    pub fn drops(&self) -> u32 {
        self.drops
    }
}
