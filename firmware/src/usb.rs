//! The USB HID mouse: device and class set-up, and one service routine that polls the stack
//! and pushes the next report.
//!
//! # Design
//! The report descriptor and the report bytes come from `imu_core::hid`, shared with the
//! host's `cargo lab hid`. The class keeps `HidSubClass::NoSubClass` (a Boot subclass would
//! refuse reports in report protocol). A report is pushed when the core has one pending;
//! the motion it carries is subtracted only after the push succeeded, so a `WouldBlock`
//! (host has not read the last one yet) loses nothing. While the device is not configured
//! (reset, suspended, unplugged) motion is discarded rather than delivered late as a jump.

use imu_core::hid::{Reporter, MOUSE_REPORT_DESCRIPTOR};
use stm32f4xx_hal::otg_fs::UsbBusType;
use usb_device::{
    bus::UsbBusAllocator,
    device::{StringDescriptors, UsbDevice, UsbDeviceBuilder, UsbDeviceState, UsbVidPid},
    prelude::BuilderError,
    UsbError,
};
use usbd_hid::hid_class::{
    HIDClass, HidClassSettings, HidProtocol, HidSubClass, ProtocolModeConfig,
};

use crate::board;

/// The mouse's USB device and HID class.
pub struct Mouse {
    dev: UsbDevice<'static, UsbBusType>,
    hid: HIDClass<'static, UsbBusType>,
    configured: bool,
    drops: u32,
}

impl Mouse {
    /// Builds the device on `bus`.
    ///
    /// # Errors
    /// The builder's error if the strings do not fit (they are constants in `board`).
    pub fn new(bus: &'static UsbBusAllocator<UsbBusType>) -> Result<Self, BuilderError> {
        let settings = HidClassSettings {
            subclass: HidSubClass::NoSubClass,
            protocol: HidProtocol::Mouse,
            config: ProtocolModeConfig::ForceReport,
            ..HidClassSettings::default()
        };
        static DESCRIPTOR: [u8; MOUSE_REPORT_DESCRIPTOR.len()] = MOUSE_REPORT_DESCRIPTOR;
        let hid = HIDClass::new_ep_in_with_settings(bus, &DESCRIPTOR, board::USB_POLL_MS, settings);
        let (vid, pid) = board::USB_VID_PID;
        let dev = UsbDeviceBuilder::new(bus, UsbVidPid(vid, pid))
            .strings(&[StringDescriptors::default()
                .manufacturer(board::USB_MANUFACTURER)
                .product(board::USB_PRODUCT)
                .serial_number(board::USB_SERIAL)])?
            .max_power(100)?
            .build();
        Ok(Self {
            dev,
            hid,
            configured: false,
            drops: 0,
        })
    }

    /// Polls the USB stack and pushes the next pending report, if any.
    pub fn service(&mut self, reporter: &mut Reporter) {
        self.dev.poll(&mut [&mut self.hid]);
        let configured = self.dev.state() == UsbDeviceState::Configured;
        if configured != self.configured {
            // Enumerated, reset, suspended or resumed: what the host knows starts afresh.
            reporter.host_reset();
            self.configured = configured;
        }
        if !configured {
            reporter.discard_motion();
            return;
        }
        if let Some(report) = reporter.pending() {
            match self.hid.push_raw_input(&report.to_bytes()) {
                Ok(_) => reporter.sent(&report),
                Err(UsbError::WouldBlock) => {}
                Err(_) => self.drops = self.drops.wrapping_add(1),
            }
        }
    }

    /// Whether the host has configured the device (and not suspended it).
    pub fn configured(&self) -> bool {
        self.configured
    }

    /// Reports refused by the USB stack for a reason other than "busy".
    pub fn drops(&self) -> u32 {
        self.drops
    }
}
