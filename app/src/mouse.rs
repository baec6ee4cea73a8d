//! The USB device: the HID mouse and, beside it, the vendor HID configuration interface
//! (`imu_core::protocol`), set up over any `usb_device` bus, and one service routine that
//! polls the stack, pushes the next mouse report and moves configuration frames.
//!
//! # Design
//! The report descriptor and the report bytes come from `imu_core::hid`, shared with the
//! host's `cargo lab hid`. The class keeps `HidSubClass::NoSubClass` (a Boot subclass would
//! refuse reports in report protocol). A report is pushed when the core has one pending;
//! the motion it carries is subtracted only after the push succeeded, so a `WouldBlock`
//! (the host has not read the last one yet) loses nothing. While the device is not
//! configured (reset, suspended, unplugged) motion is discarded rather than delivered late
//! as a jump, and every change of the link makes the reporter send the buttons again.
//!
//! The configuration interface is a second interface with its own IN and OUT endpoints, so
//! the mouse interface stays a plain mouse. One received request waits in an inbox until the
//! caller takes it; responses wait in a two-frame outbox and go out before any stream frame.
//! A change of the link empties both (the host that asked is gone).

use heapless::Deque;
use imu_core::hid::{Reporter, MOUSE_REPORT_DESCRIPTOR};
use imu_core::protocol::{Frame, StreamFrame, CONFIG_REPORT_DESCRIPTOR, FRAME_LEN};
use imu_core::Link;
use usb_device::{
    bus::{UsbBus, UsbBusAllocator},
    class::{ControlIn, ControlOut, UsbClass},
    descriptor::DescriptorWriter,
    device::{StringDescriptors, UsbDevice, UsbDeviceBuilder, UsbDeviceState, UsbVidPid},
    endpoint::EndpointAddress,
    prelude::BuilderError,
    UsbError,
};
use usbd_hid::hid_class::{HIDClass, HidClassSettings, HidProtocol, ProtocolModeConfig};

use crate::identity;
use crate::opening::{Gate, Opening};

/// The HID report descriptor, in static memory as the class requires.
static DESCRIPTOR: [u8; MOUSE_REPORT_DESCRIPTOR.len()] = MOUSE_REPORT_DESCRIPTOR;
/// The configuration interface's report descriptor.
static CONFIG_DESCRIPTOR: [u8; CONFIG_REPORT_DESCRIPTOR.len()] = CONFIG_REPORT_DESCRIPTOR;

/// The configuration interface exactly as the device builds it: a vendor HID interface with
/// an interrupt IN and an interrupt OUT endpoint of 64 bytes, polled every 1 ms.
pub fn config_class<B: UsbBus>(bus: &UsbBusAllocator<B>) -> HIDClass<'_, B> {
    HIDClass::new(bus, &CONFIG_DESCRIPTOR, identity::POLL_MS)
}

/// The HID class exactly as the device builds it (the class tests build it the same way).
pub fn hid_class<B: UsbBus>(bus: &UsbBusAllocator<B>) -> HIDClass<'_, B> {
    // The subclass stays usbd-hid's default, NoSubClass (a Boot subclass would refuse
    // report-protocol pushes); the class tests check it in the interface descriptor.
    let settings = HidClassSettings {
        protocol: HidProtocol::Mouse,
        config: ProtocolModeConfig::ForceReport,
        ..HidClassSettings::default()
    };
    HIDClass::new_ep_in_with_settings(bus, &DESCRIPTOR, identity::POLL_MS, settings)
}

/// The USB device exactly as the device builds it: [`identity`]'s IDs, strings and power,
/// `serial` as its serial number, remote wake-up supported.
///
/// # Errors
/// The builder's error if the strings or the power do not fit.
pub fn usb_device<'a, B: UsbBus>(
    bus: &'a UsbBusAllocator<B>,
    serial: &'static str,
) -> Result<UsbDevice<'a, B>, BuilderError> {
    let (vid, pid) = identity::VID_PID;
    Ok(UsbDeviceBuilder::new(bus, UsbVidPid(vid, pid))
        .strings(&[StringDescriptors::default()
            .manufacturer(identity::MANUFACTURER)
            .product(identity::PRODUCT)
            .serial_number(serial)])?
        .device_release(identity::RELEASE_BCD)
        .max_power(identity::MAX_POWER_MA)?
        .supports_remote_wakeup(true)
        .build())
}

/// What the mouse owes the host and how it stands with it: the core's report scheduler, the
/// link as last seen, and the pushes the USB stack refused for a reason other than a busy
/// endpoint. Free of the bus, so its rules are tested without one.
#[derive(Clone, Copy, Debug, Default)]
pub struct Reports {
    reporter: Reporter,
    link: Link,
    drops: u32,
    opening: Opening,
}

impl Reports {
    /// One service after the USB stack's poll at `now_ms` [ms]: the device's `state` now,
    /// the tracker's fresh `counts` `[x, y, z]`, and `push`, which hands one report's bytes
    /// to the stack.
    ///
    /// A change of the link (enumerated, reset, suspended, resumed) starts what the host
    /// knows afresh; while not configured, motion is discarded rather than delivered late as
    /// a jump. A new configuration opens with the held buttons alone and a quiet time
    /// ([`crate::opening`]: Linux drops the reports of its first 50 ms). A push refused with
    /// `WouldBlock` loses nothing (the motion stays owed); any other refusal is counted in
    /// [`Self::drops`].
    ///
    /// `delivered`: the host's IN transfer of the report in flight completed in this poll
    /// (it is then counted as sent, before a link change could count it lost).
    pub fn update(
        &mut self,
        state: UsbDeviceState,
        counts: [i32; 3],
        delivered: bool,
        now_ms: u32,
        push: impl FnOnce(&[u8]) -> Result<usize, UsbError>,
    ) {
        if delivered {
            self.reporter.delivered();
        }
        let link = match state {
            UsbDeviceState::Configured => Link::Configured,
            UsbDeviceState::Suspend => Link::Suspended,
            UsbDeviceState::Default | UsbDeviceState::Addressed => Link::NotConfigured,
        };
        if link != self.link {
            // A bus reset (the host re-enumerates) empties the endpoint; a suspend or a
            // resume keeps what is in it, delivered when the host polls again.
            if link == Link::NotConfigured {
                self.reporter.endpoint_lost();
            }
            if link == Link::Configured && self.link == Link::NotConfigured {
                self.opening.configured();
            }
            self.reporter.host_reset();
            self.link = link;
        }
        // Counted first, then discarded if the host is not listening: every count the tracker
        // hands over is sent, discarded or owed, never lost from the accounts.
        let (dx, dy) = imu_core::hid::screen_motion(counts);
        self.reporter.add_motion(dx, dy);
        if link != Link::Configured {
            self.reporter.discard_motion();
            return;
        }
        let report = match self.opening.gate(delivered, now_ms) {
            Gate::Hold => return,
            Gate::Opening => Some(self.reporter.buttons_only()),
            Gate::Open { resend } => {
                if resend {
                    self.reporter.resend_buttons();
                }
                self.reporter.pending()
            }
        };
        if let Some(report) = report {
            match push(&report.to_bytes()) {
                Ok(_) => {
                    self.reporter.accepted(&report);
                    self.opening.sent();
                }
                Err(UsbError::WouldBlock) => {}
                Err(_) => self.drops = self.drops.wrapping_add(1),
            }
        }
    }

    /// Sets the held buttons (`imu_core::hid::buttons` bits); sent with the next report.
    pub fn set_buttons(&mut self, held: u8) {
        self.reporter.set_buttons(held);
    }

    /// The link as of the last [`Self::update`].
    pub fn link(&self) -> Link {
        self.link
    }

    /// Whether a report is waiting to be pushed (motion or a button change).
    pub fn pending(&self) -> bool {
        self.reporter.pending().is_some()
    }

    /// The report scheduler: reports accepted, motion sent, discarded and owed [counts].
    pub fn reporter(&self) -> &Reporter {
        &self.reporter
    }

    /// Reports refused by the USB stack for a reason other than "busy".
    pub fn drops(&self) -> u32 {
        self.drops
    }
}

/// The mouse's IN endpoint: EP1, the first the bus allocates ([`hid_class`] is built
/// before [`config_class`]; `app/tests/usb_class.rs` reads the reports there).
pub const MOUSE_EP_IN: u8 = 0x81;

/// The mouse's HID class ([`hid_class`]), watching its IN endpoint: a report the stack took
/// is delivered only when the host's IN transfer completes ([`Reports::update`]). usbd-hid's
/// class implements only the descriptors and the class requests; those are passed through,
/// and every other callback keeps the trait's default, as it does in the class itself.
pub struct MouseClass<'a, B: UsbBus> {
    class: HIDClass<'a, B>,
    delivered: bool,
}

/// The mouse's class as the device builds it (see [`MouseClass`]).
pub fn mouse_class<B: UsbBus>(bus: &UsbBusAllocator<B>) -> MouseClass<'_, B> {
    MouseClass {
        class: hid_class(bus),
        delivered: false,
    }
}

impl<B: UsbBus> MouseClass<'_, B> {
    /// Hands a report's bytes to the endpoint (usbd-hid's `push_raw_input`).
    ///
    /// # Errors
    /// `WouldBlock` while the last report is still in the endpoint; the stack's other errors.
    pub fn push_raw_input(&self, data: &[u8]) -> usb_device::Result<usize> {
        self.class.push_raw_input(data)
    }

    /// Whether the host took a report from the endpoint since the last call.
    pub fn take_delivered(&mut self) -> bool {
        core::mem::take(&mut self.delivered)
    }
}

impl<B: UsbBus> UsbClass<B> for MouseClass<'_, B> {
    fn get_configuration_descriptors(
        &self,
        writer: &mut DescriptorWriter,
    ) -> usb_device::Result<()> {
        self.class.get_configuration_descriptors(writer)
    }

    fn control_in(&mut self, xfer: ControlIn<B>) {
        self.class.control_in(xfer);
    }

    fn control_out(&mut self, xfer: ControlOut<B>) {
        self.class.control_out(xfer);
    }

    fn endpoint_in_complete(&mut self, addr: EndpointAddress) {
        if u8::from(addr) == MOUSE_EP_IN {
            self.delivered = true;
        }
    }
}

/// Responses waiting for the configuration interface's IN endpoint.
pub const OUTBOX: usize = 2;

/// The mouse: USB device, HID class, and what it owes the host ([`Reports`]); and the
/// configuration interface with its inbox and outbox.
pub struct Mouse<'a, B: UsbBus> {
    dev: UsbDevice<'a, B>,
    hid: MouseClass<'a, B>,
    port: HIDClass<'a, B>,
    reports: Reports,
    inbox: Option<(Frame, usize)>,
    outbox: Deque<Frame, OUTBOX>,
}

impl<'a, B: UsbBus> Mouse<'a, B> {
    /// Builds the device on `bus`, with the serial number `serial` ([`identity::serial`] on
    /// a board).
    ///
    /// # Errors
    /// The builder's error if the strings do not fit (the others are constants in
    /// [`identity`]).
    pub fn new(bus: &'a UsbBusAllocator<B>, serial: &'static str) -> Result<Self, BuilderError> {
        let hid = mouse_class(bus);
        let port = config_class(bus);
        let dev = usb_device(bus, serial)?;
        Ok(Self {
            dev,
            hid,
            port,
            reports: Reports::default(),
            inbox: None,
            outbox: Deque::new(),
        })
    }

    /// Polls the USB stack at `now_ms` [ms], adds the tracker's fresh `counts` `[x, y, z]`
    /// and pushes the next pending report, if any ([`Reports::update`]); takes a
    /// configuration request into the inbox if it is empty, and pushes the next response.
    pub fn service(&mut self, counts: [i32; 3], now_ms: u32) {
        self.dev.poll(&mut [&mut self.hid, &mut self.port]);
        let link = self.reports.link();
        let delivered = self.hid.take_delivered();
        let hid = &self.hid;
        self.reports
            .update(self.dev.state(), counts, delivered, now_ms, |bytes| {
                hid.push_raw_input(bytes)
            });
        if self.reports.link() != link {
            self.inbox = None;
            self.outbox.clear();
        }
        if self.inbox.is_none() {
            let mut frame = [0; FRAME_LEN];
            if let Ok(n) = self.port.pull_raw_output(&mut frame) {
                self.inbox = Some((frame, n));
            }
        }
        self.flush_outbox();
    }

    /// Pushes the oldest waiting response if the endpoint takes it.
    fn flush_outbox(&mut self) {
        if let Some(frame) = self.outbox.front() {
            if self.port.push_raw_input(frame).is_ok() {
                self.outbox.pop_front();
            }
        }
    }

    /// The configuration request received, if any, and its length [bytes]; the next one is
    /// read from the bus once this is taken.
    pub fn take_request(&mut self) -> Option<(Frame, usize)> {
        self.inbox.take()
    }

    /// Queues a response for the configuration interface, ahead of stream frames. Returns
    /// `false` (the response is dropped) if [`OUTBOX`] responses already wait, which a host
    /// that waits for each answer never causes.
    pub fn respond(&mut self, frame: Frame) -> bool {
        let queued = self.outbox.push_back(frame).is_ok();
        self.flush_outbox();
        queued
    }

    /// Pushes a raw stream frame if no response waits and the endpoint is free; returns
    /// whether it went (`Stream::sent` then takes its samples off the queue).
    pub fn push_stream_frame(&mut self, frame: &StreamFrame) -> bool {
        self.outbox.is_empty()
            && self.reports.link() == Link::Configured
            && self.port.push_raw_input(&frame.encode()).is_ok()
    }

    /// Sets the held buttons (`imu_core::hid::buttons` bits); sent with the next report.
    pub fn set_buttons(&mut self, held: u8) {
        self.reports.set_buttons(held);
    }

    /// The USB device, read-only: its state, and whether the host has allowed remote
    /// wake-up (`remote_wakeup_enabled`, set by SET_FEATURE DEVICE_REMOTE_WAKEUP).
    pub fn device(&self) -> &UsbDevice<'a, B> {
        &self.dev
    }

    /// What the mouse owes the host, and the link as of the last [`Self::service`].
    pub fn reports(&self) -> &Reports {
        &self.reports
    }
}
