//! The mouse as the host's USB stack sees it, built with the app's own device and class
//! builders on `usbd-class-tester`'s emulated bus (enumerated: address and configuration
//! set, EP0 of 8 bytes so that descriptors take several packets). What usbd-hid 0.10
//! really does is asserted, stalls included; a descriptor change that would break the mouse
//! on a host fails here.

use imu_app::{identity, mouse};
use imu_core::hid::{MouseReport, MOUSE_REPORT_DESCRIPTOR, REPORT_LEN};
use usb_device::bus::UsbBusAllocator;
use usb_device::device::UsbDevice;
use usbd_class_tester::prelude::*;

struct Ctx;

impl UsbDeviceCtx for Ctx {
    type C<'c> = mouse::MouseClass<'c, EmulatedUsbBus>;

    fn create_class<'a>(
        &mut self,
        alloc: &'a UsbBusAllocator<EmulatedUsbBus>,
    ) -> AnyResult<mouse::MouseClass<'a, EmulatedUsbBus>> {
        Ok(mouse::mouse_class(alloc))
    }

    fn build_usb_device<'a>(
        &mut self,
        alloc: &'a UsbBusAllocator<EmulatedUsbBus>,
    ) -> AnyResult<UsbDevice<'a, EmulatedUsbBus>> {
        mouse::usb_device(alloc, identity::SERIAL).map_err(AnyUsbError::UsbDeviceBuilder)
    }
}

const GET_DESCRIPTOR: u8 = 6;
const HID_GET_REPORT: u8 = 0x01;
const HID_GET_IDLE: u8 = 0x02;
const HID_GET_PROTOCOL: u8 = 0x03;
const HID_SET_IDLE: u8 = 0x0A;
const HID_SET_PROTOCOL: u8 = 0x0B;

fn le16(b: &[u8], i: usize) -> u16 {
    u16::from_le_bytes([b[i], b[i + 1]])
}

#[test]
fn device_descriptor_names_the_product() {
    Ctx.with_usb(|mut cls, mut dev| {
        let d = dev
            .device_get_descriptor(&mut cls, 1, 0, 0, 18)
            .expect("device descriptor");
        assert_eq!(d.len(), 18);
        assert_eq!((d[0], d[1]), (18, 1));
        assert_eq!(
            le16(&d, 2),
            0x0210,
            "bcdUSB 2.1: usb-device 0.3 serves a BOS descriptor"
        );
        assert_eq!((d[4], d[5], d[6]), (0, 0, 0), "class in the interface");
        assert_eq!(d[7], 8, "bMaxPacketSize0");
        assert_eq!((le16(&d, 8), le16(&d, 10)), identity::VID_PID);
        assert_eq!(le16(&d, 12), identity::RELEASE_BCD);
        assert_eq!((d[14], d[15], d[16]), (1, 2, 3), "string indices");
        assert_eq!(d[17], 1, "one configuration");
    })
    .expect("enumerates");
}

#[test]
fn configuration_is_one_hid_mouse_interface_with_remote_wakeup() {
    Ctx.with_usb(|mut cls, mut dev| {
        let head = dev
            .device_get_descriptor(&mut cls, 2, 0, 0, 9)
            .expect("config head");
        let total = le16(&head, 2);
        let c = dev
            .device_get_descriptor(&mut cls, 2, 0, 0, total)
            .expect("configuration");
        assert_eq!(c.len(), usize::from(total));
        assert_eq!(
            total,
            9 + 9 + 9 + 7,
            "configuration, interface, HID, endpoint"
        );
        assert_eq!(c[4], 1, "one interface");
        assert_eq!(c[7], 0x80 | 0x20, "bus powered, remote wake-up");
        assert_eq!(usize::from(c[8]) * 2, identity::MAX_POWER_MA);
        let iface = &c[9..18];
        assert_eq!((iface[1], iface[4]), (4, 1), "interface with one endpoint");
        assert_eq!(
            (iface[5], iface[6], iface[7]),
            (3, 0, 2),
            "HID, no subclass, mouse"
        );
        let hid = &c[18..27];
        assert_eq!((hid[0], hid[1]), (9, 0x21));
        assert_eq!(le16(hid, 2), 0x0110, "HID 1.10");
        assert_eq!((hid[5], hid[6]), (1, 0x22), "one report descriptor");
        assert_eq!(usize::from(le16(hid, 7)), MOUSE_REPORT_DESCRIPTOR.len());
        let ep = &c[27..34];
        assert_eq!((ep[1], ep[2], ep[3]), (5, 0x81, 3), "EP1 IN, interrupt");
        assert!(
            usize::from(le16(ep, 4)) >= REPORT_LEN,
            "a report fits one packet"
        );
        assert_eq!(ep[6], identity::POLL_MS);
    })
    .expect("enumerates");
}

#[test]
fn strings_read_back() {
    Ctx.with_usb(|mut cls, mut dev| {
        let en = 0x0409;
        assert_eq!(
            dev.device_get_string(&mut cls, 1, en).as_deref(),
            Ok(identity::MANUFACTURER)
        );
        assert_eq!(
            dev.device_get_string(&mut cls, 2, en).as_deref(),
            Ok(identity::PRODUCT)
        );
        assert_eq!(
            dev.device_get_string(&mut cls, 3, en).as_deref(),
            Ok(identity::SERIAL)
        );
        let langs = dev
            .device_get_descriptor(&mut cls, 3, 0, 0, 255)
            .expect("languages");
        assert_eq!(langs, [4, 3, 0x09, 0x04]);
    })
    .expect("enumerates");
}

#[test]
fn report_descriptor_is_the_cores_mouse() {
    Ctx.with_usb(|mut cls, mut dev| {
        let len = MOUSE_REPORT_DESCRIPTOR.len() as u16;
        let rt = CtrRequestType::to_host().standard().interface();
        let r = dev
            .control_read(&mut cls, rt, GET_DESCRIPTOR, 0x2200, 0, len)
            .expect("report descriptor");
        assert_eq!(r, MOUSE_REPORT_DESCRIPTOR);
        // What a host needs to bind it as a mouse: Generic Desktop / Mouse application
        // collection, a pointer with relative X and Y.
        assert_eq!(&r[..6], [0x05, 0x01, 0x09, 0x02, 0xA1, 0x01]);
        let hid = dev
            .control_read(&mut cls, rt, GET_DESCRIPTOR, 0x2100, 0, 9)
            .expect("HID descriptor");
        assert_eq!(usize::from(le16(&hid, 7)), MOUSE_REPORT_DESCRIPTOR.len());
    })
    .expect("enumerates");
}

#[test]
fn class_requests_behave_as_usbd_hid_implements_them() {
    Ctx.with_usb(|mut cls, mut dev| {
        let out = CtrRequestType::to_device().class().interface();
        let inn = CtrRequestType::to_host().class().interface();
        // SET_IDLE is accepted (and ignored); SET_PROTOCOL(report) is accepted because the
        // class says Mouse; GET_PROTOCOL answers report protocol (1).
        dev.control_write(&mut cls, out, HID_SET_IDLE, 0, 0, 0, &[])
            .expect("SET_IDLE");
        dev.control_write(&mut cls, out, HID_SET_PROTOCOL, 1, 0, 0, &[])
            .expect("SET_PROTOCOL");
        let p = dev
            .control_read(&mut cls, inn, HID_GET_PROTOCOL, 0, 0, 1)
            .expect("GET_PROTOCOL");
        assert_eq!(p, [1]);
        // A host that asks for the boot protocol (0) gets report protocol anyway: the class
        // forces it, so the 4-byte report with its wheel byte stays what the host parses.
        dev.control_write(&mut cls, out, HID_SET_PROTOCOL, 0, 0, 0, &[])
            .expect("SET_PROTOCOL(boot) is accepted");
        let p = dev
            .control_read(&mut cls, inn, HID_GET_PROTOCOL, 0, 0, 1)
            .expect("GET_PROTOCOL");
        assert_eq!(p, [1], "still report protocol");
        // GET_REPORT and GET_IDLE always stall in usbd-hid 0.10.
        let r = dev.control_read(&mut cls, inn, HID_GET_REPORT, 0x0100, 0, 4);
        assert_eq!(r, Err(AnyUsbError::EP0Stalled));
        let r = dev.control_read(&mut cls, inn, HID_GET_IDLE, 0, 0, 1);
        assert_eq!(r, Err(AnyUsbError::EP0Stalled));
        // The stall ends with the next SETUP: the device still answers.
        assert!(dev.device_get_descriptor(&mut cls, 1, 0, 0, 18).is_ok());
    })
    .expect("enumerates");
}

#[test]
fn pushed_reports_arrive_on_ep1_as_the_core_packs_them() {
    Ctx.with_usb(|mut cls, mut dev| {
        let r = MouseReport {
            buttons: 1,
            x: -5,
            y: 127,
            wheel: 0,
        };
        assert_eq!(cls.push_raw_input(&r.to_bytes()), Ok(REPORT_LEN));
        assert!(
            !cls.take_delivered(),
            "taken by the stack, not yet by the host"
        );
        let got = dev.ep_read(&mut cls, 1, 64).expect("report");
        assert_eq!(got, r.to_bytes());
        assert!(cls.take_delivered(), "the host's IN transfer completed");
        assert!(!cls.take_delivered(), "once");
    })
    .expect("enumerates");
}

#[test]
fn the_host_may_enable_remote_wakeup() {
    Ctx.with_usb(|mut cls, mut dev| {
        assert_eq!(
            dev.device_get_status(&mut cls),
            Ok(0),
            "bus powered, wake-up off"
        );
        assert!(!dev.usb_dev().remote_wakeup_enabled());
        dev.device_set_feature(&mut cls, 1)
            .expect("DEVICE_REMOTE_WAKEUP");
        assert!(dev.usb_dev().remote_wakeup_enabled());
        assert_eq!(dev.device_get_status(&mut cls), Ok(2));
        dev.device_clear_feature(&mut cls, 1).expect("clear");
        assert!(!dev.usb_dev().remote_wakeup_enabled());
    })
    .expect("enumerates");
}

#[test]
fn a_board_s_serial_is_its_unique_id_in_hex() {
    let mut out = [0u8; identity::SERIAL_LEN];
    let uid = [
        0x34, 0x12, 0x78, 0x56, 0x09, b'L', b'O', b'T', b'1', b'2', b'3', b'4',
    ];
    assert_eq!(identity::serial(&uid, &mut out), "34127856094C4F5431323334");
    // One bit apart, another serial.
    let mut other = uid;
    other[11] ^= 1;
    let mut out2 = [0u8; identity::SERIAL_LEN];
    assert_ne!(
        identity::serial(&other, &mut out2),
        "34127856094C4F5431323334"
    );
    assert_eq!(identity::serial(&[0xFF; 12], &mut out2), "F".repeat(24));
}
