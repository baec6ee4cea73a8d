//! A `usb_device` bus over USB/IP: the device side of the Linux USB/IP protocol on a TCP
//! port, so that the firmware's app runs on the host as a USB device that a USB/IP host
//! (Linux's `vhci-hcd` with `usbip attach`, or PyPI `usbip`) enumerates and reads.
//!
//! # Design
//! Written for the twin instead of patching `usbip-device` 0.2, whose URB path has two
//! defects (a control OUT's status-stage zero-length packet stays queued and answers the
//! next control IN; a STALL is never reported), panics on socket errors and short reads,
//! and reports a fixed VID:PID. Here:
//!
//! - Messages are parsed from a receive buffer, so a header split across TCP segments waits
//!   for the rest; any socket error closes the connection.
//! - A control transfer is one URB: its SETUP (and OUT data) go to EP0 OUT; an IN transfer
//!   completes when the device writes a short packet or the requested length, and the
//!   status-stage ZLP is then fed back to the device; an OUT transfer completes when the
//!   device writes its status-stage ZLP. A stall of EP0 completes the URB with `-EPIPE`.
//! - An interrupt IN endpoint holds one packet: the device gets `WouldBlock` until a host IN
//!   URB takes it, and an IN URB with nothing to send stays pending (a NAK).
//! - Closing the connection is a bus reset: pending URBs are dropped and the device returns
//!   to the Default state. USB/IP has no suspend, so the bus never reports one.
//! - USB/IP has no handshake: an IN packet counts as delivered when its RET_SUBMIT is sent,
//!   and the host confirms it only by submitting its next URB on the endpoint. The last
//!   packet before a disconnect stays unconfirmed ([`Monitor::unconfirmed`]): the kernel's
//!   `usbip detach` may drop a RET_SUBMIT still in the socket, a user-space host may have
//!   read it (`kernel_check.py` saw the first, `twin_check.py` the second).
//! - The device list shows the identity given to [`UsbIpBus::new`] (read from the app).
//!
//! Protocol: the Linux kernel's `Documentation/usb/usbip_protocol.rst` (OP_REQ_DEVLIST,
//! OP_REQ_IMPORT, USBIP_CMD_SUBMIT / RET_SUBMIT, USBIP_CMD_UNLINK / RET_UNLINK, big-endian).

use std::collections::VecDeque;
use std::io::{ErrorKind, Read, Write};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::sync::{Arc, Mutex, MutexGuard};

use usb_device::bus::{PollResult, UsbBus};
use usb_device::endpoint::{EndpointAddress, EndpointType};
use usb_device::{Result as UsbResult, UsbDirection, UsbError};

const ENDPOINTS: usize = 8;
pub(crate) const VERSION: u16 = 0x0111;
const OP_REQ_DEVLIST: u16 = 0x8005;
const OP_REP_DEVLIST: u16 = 0x0005;
pub(crate) const OP_REQ_IMPORT: u16 = 0x8003;
const OP_REP_IMPORT: u16 = 0x0003;
pub(crate) const CMD_SUBMIT: u32 = 1;
const CMD_UNLINK: u32 = 2;
pub(crate) const RET_SUBMIT: u32 = 3;
pub(crate) const RET_UNLINK: u32 = 4;
const EPIPE: i32 = -32;
const ECONNRESET: i32 = -104;
/// The one bus id this server exports.
pub const BUSID: &str = "1-1";

/// What the device list says about the device (the real descriptors are the device's).
#[derive(Clone, Copy, Debug)]
pub struct Listing {
    /// Vendor and product ID.
    pub vid_pid: (u16, u16),
    /// `bcdDevice`.
    pub release_bcd: u16,
    /// The interface's class, subclass and protocol (one interface).
    pub interface: (u8, u8, u8),
}

/// Traffic counters of the bus.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Traffic {
    /// Connections that imported the device.
    pub imports: u32,
    /// URBs completed.
    pub urbs: u64,
    /// Control URBs answered with a stall.
    pub stalls: u32,
    /// Interrupt IN packets delivered (mouse reports).
    pub in_packets: u64,
}

#[derive(Debug)]
struct Urb {
    seqnum: u32,
    len: u32,
}

#[derive(Debug)]
struct Control {
    seqnum: u32,
    dir_in: bool,
    len: u32,
    data: Vec<u8>,
}

#[derive(Debug, Default)]
struct InEp {
    max: u16,
    packet: Option<Vec<u8>>,
    urbs: VecDeque<Urb>,
    stalled: bool,
    /// The last packet sent to the host, until it submits its next URB here.
    unconfirmed: Option<Vec<u8>>,
}

#[derive(Debug, Default)]
struct OutEp {
    max: u16,
    /// Packets for the device: `(is_setup, bytes)`.
    packets: VecDeque<(bool, Vec<u8>)>,
    stalled: bool,
}

struct Inner {
    listener: TcpListener,
    listing: Listing,
    conn: Option<TcpStream>,
    rx: Vec<u8>,
    attached: bool,
    reset_pending: bool,
    /// A suspend (`true`) or resume (`false`) of the bus asked for by the twin's operator
    /// (USB/IP has neither), reported by the next poll.
    bus_request: Option<bool>,
    /// Suspended: the bus is idle, as a suspended bus is (the host's transfers wait).
    suspended: bool,
    ins: [Option<InEp>; ENDPOINTS],
    outs: [Option<OutEp>; ENDPOINTS],
    control: Option<Control>,
    in_complete: u16,
    traffic: Traffic,
    /// `(endpoint, packet)`: the last IN packet before each disconnect, never confirmed.
    unconfirmed: Vec<(u8, Vec<u8>)>,
}

/// The USB/IP bus. One device, exported as bus id [`BUSID`].
pub struct UsbIpBus(Arc<Mutex<Inner>>);

/// A view of the bus's state for its owner, once the bus itself is inside the allocator.
#[derive(Clone)]
pub struct Monitor(Arc<Mutex<Inner>>);

fn lock(m: &Mutex<Inner>) -> MutexGuard<'_, Inner> {
    // A panic while holding the lock would already have ended the twin.
    m.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

impl UsbIpBus {
    /// Listens on `addr` (the USB/IP port is 3240) for a host.
    ///
    /// # Errors
    /// The socket's error if the address cannot be bound (in use: one twin per port).
    pub fn new(addr: SocketAddr, listing: Listing) -> std::io::Result<Self> {
        let listener = TcpListener::bind(addr)?;
        listener.set_nonblocking(true)?;
        Ok(Self(Arc::new(Mutex::new(Inner {
            listener,
            listing,
            conn: None,
            rx: Vec::new(),
            attached: false,
            reset_pending: false,
            bus_request: None,
            suspended: false,
            ins: Default::default(),
            outs: Default::default(),
            control: None,
            in_complete: 0,
            traffic: Traffic::default(),
            unconfirmed: Vec::new(),
        }))))
    }

    fn lock(&self) -> MutexGuard<'_, Inner> {
        lock(&self.0)
    }

    /// A monitor of this bus.
    pub fn monitor(&self) -> Monitor {
        Monitor(self.0.clone())
    }
}

impl Monitor {
    /// Traffic so far.
    pub fn traffic(&self) -> Traffic {
        lock(&self.0).traffic
    }

    /// `(endpoint, packet)`: the last IN packet sent before each disconnect, which the host
    /// never confirmed by submitting its next URB (see the module docs).
    pub fn unconfirmed(&self) -> Vec<(u8, Vec<u8>)> {
        lock(&self.0).unconfirmed.clone()
    }

    /// Suspends (`true`) or resumes (`false`) the bus at the next poll, as a host's idle bus
    /// or its resume signalling would (USB/IP carries neither: the twin's operator asks).
    pub fn request_suspend(&self, suspend: bool) {
        lock(&self.0).bus_request = Some(suspend);
    }

    /// Whether a host has imported the device and is connected.
    pub fn attached(&self) -> bool {
        lock(&self.0).attached
    }

    /// Whether an interrupt IN packet waits for the host (accepted, not yet delivered).
    pub fn in_flight(&self) -> bool {
        lock(&self.0)
            .ins
            .iter()
            .skip(1)
            .flatten()
            .any(|e| e.packet.is_some())
    }
}

fn be16(b: &[u8], i: usize) -> u16 {
    u16::from_be_bytes([b[i], b[i + 1]])
}
fn be32(b: &[u8], i: usize) -> u32 {
    u32::from_be_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]])
}

impl Inner {
    fn device_record(&self) -> Vec<u8> {
        let mut r = Vec::with_capacity(312);
        let mut path = [0u8; 256];
        let p = b"/sys/devices/imu-mouse/usbip/1-1";
        path[..p.len()].copy_from_slice(p);
        r.extend_from_slice(&path);
        let mut busid = [0u8; 32];
        busid[..BUSID.len()].copy_from_slice(BUSID.as_bytes());
        r.extend_from_slice(&busid);
        r.extend_from_slice(&1u32.to_be_bytes()); // busnum
        r.extend_from_slice(&2u32.to_be_bytes()); // devnum
        r.extend_from_slice(&2u32.to_be_bytes()); // speed: full
        let (vid, pid) = self.listing.vid_pid;
        r.extend_from_slice(&vid.to_be_bytes());
        r.extend_from_slice(&pid.to_be_bytes());
        r.extend_from_slice(&self.listing.release_bcd.to_be_bytes());
        r.extend_from_slice(&[0, 0, 0, 1, 1, 1]); // class, sub, proto, config, n configs, n ifaces
        r
    }

    fn send(&mut self, bytes: &[u8]) {
        let ok = self
            .conn
            .as_mut()
            .is_some_and(|c| c.write_all(bytes).is_ok());
        if !ok {
            self.disconnect();
        }
    }

    fn disconnect(&mut self) {
        if self.conn.take().is_some() && self.attached {
            self.reset_pending = true;
        }
        for (i, e) in self.ins.iter_mut().enumerate() {
            if let Some(p) = e.as_mut().and_then(|e| e.unconfirmed.take()) {
                self.unconfirmed.push((i as u8, p));
            }
        }
        self.attached = false;
        self.rx.clear();
        self.clear_transfers();
    }

    fn clear_transfers(&mut self) {
        self.control = None;
        self.in_complete = 0;
        for e in self.ins.iter_mut().flatten() {
            e.packet = None;
            e.urbs.clear();
            e.stalled = false;
        }
        for e in self.outs.iter_mut().flatten() {
            e.packets.clear();
            e.stalled = false;
        }
    }

    fn ret_submit(&mut self, seqnum: u32, status: i32, data: &[u8], out_len: u32) {
        let mut m = Vec::with_capacity(48 + data.len());
        for w in [RET_SUBMIT, seqnum, 0, 0, 0] {
            m.extend_from_slice(&w.to_be_bytes());
        }
        let actual = if data.is_empty() {
            out_len
        } else {
            data.len() as u32
        };
        for w in [status, actual as i32, 0, 0, 0] {
            m.extend_from_slice(&w.to_be_bytes());
        }
        m.extend_from_slice(&[0; 8]);
        m.extend_from_slice(data);
        self.traffic.urbs += 1;
        self.send(&m);
    }

    /// Accepts a host, reads what arrived and handles every whole message.
    fn service(&mut self) {
        if self.conn.is_none() {
            if let Ok((stream, _)) = self.listener.accept() {
                let ok = stream.set_nonblocking(true).is_ok() && stream.set_nodelay(true).is_ok();
                if ok {
                    self.conn = Some(stream);
                }
            }
            return;
        }
        let mut buf = [0u8; 4096];
        loop {
            let Some(c) = self.conn.as_mut() else { return };
            match c.read(&mut buf) {
                Ok(0) => return self.disconnect(),
                Ok(n) => self.rx.extend_from_slice(&buf[..n]),
                Err(e) if e.kind() == ErrorKind::WouldBlock => break,
                Err(e) if e.kind() == ErrorKind::Interrupted => {}
                Err(_) => return self.disconnect(),
            }
        }
        while self.conn.is_some() && self.handle_one() {}
    }

    /// Handles the first whole message in the receive buffer; `false` if there is none.
    fn handle_one(&mut self) -> bool {
        if !self.attached {
            if self.rx.len() < 8 {
                return false;
            }
            let code = be16(&self.rx, 2);
            match code {
                OP_REQ_DEVLIST => {
                    self.rx.drain(..8);
                    let mut m = Vec::new();
                    m.extend_from_slice(&VERSION.to_be_bytes());
                    m.extend_from_slice(&OP_REP_DEVLIST.to_be_bytes());
                    m.extend_from_slice(&0u32.to_be_bytes());
                    m.extend_from_slice(&1u32.to_be_bytes());
                    m.extend_from_slice(&self.device_record());
                    let (c, s, p) = self.listing.interface;
                    m.extend_from_slice(&[c, s, p, 0]);
                    self.send(&m);
                }
                OP_REQ_IMPORT => {
                    if self.rx.len() < 40 {
                        return false;
                    }
                    let busid: Vec<u8> = self.rx[8..40]
                        .iter()
                        .copied()
                        .take_while(|&b| b != 0)
                        .collect();
                    self.rx.drain(..40);
                    let found = busid == BUSID.as_bytes();
                    let mut m = Vec::new();
                    m.extend_from_slice(&VERSION.to_be_bytes());
                    m.extend_from_slice(&OP_REP_IMPORT.to_be_bytes());
                    m.extend_from_slice(&u32::from(!found).to_be_bytes());
                    if found {
                        m.extend_from_slice(&self.device_record());
                    }
                    self.send(&m);
                    if found {
                        self.attached = true;
                        self.reset_pending = true; // a fresh bus: the host enumerates
                        self.traffic.imports += 1;
                    }
                }
                _ => self.disconnect(),
            }
            return true;
        }
        if self.rx.len() < 48 {
            return false;
        }
        let h: Vec<u8> = self.rx[..48].to_vec();
        let (command, seqnum, dir, ep) = (be32(&h, 0), be32(&h, 4), be32(&h, 12), be32(&h, 16));
        match command {
            CMD_SUBMIT => {
                let len = be32(&h, 24);
                let out_data = dir == 0 && len > 0;
                let need = 48 + if out_data { len as usize } else { 0 };
                if self.rx.len() < need {
                    return false;
                }
                let data: Vec<u8> = self.rx[48..need].to_vec();
                self.rx.drain(..need);
                let setup: [u8; 8] = core::array::from_fn(|i| h[40 + i]);
                self.submit(seqnum, dir == 1, ep as usize, len, setup, data);
            }
            CMD_UNLINK => {
                let victim = be32(&h, 20);
                self.rx.drain(..48);
                let status = if self.unlink(victim) { ECONNRESET } else { 0 };
                let mut m = Vec::with_capacity(48);
                for w in [RET_UNLINK, seqnum, 0, 0, 0] {
                    m.extend_from_slice(&w.to_be_bytes());
                }
                m.extend_from_slice(&status.to_be_bytes());
                m.extend_from_slice(&[0; 24]);
                self.send(&m);
            }
            _ => self.disconnect(),
        }
        true
    }

    fn unlink(&mut self, seqnum: u32) -> bool {
        if self.control.as_ref().is_some_and(|c| c.seqnum == seqnum) {
            self.control = None;
            return true;
        }
        for e in self.ins.iter_mut().flatten() {
            if let Some(i) = e.urbs.iter().position(|u| u.seqnum == seqnum) {
                e.urbs.remove(i);
                return true;
            }
        }
        false
    }

    fn submit(
        &mut self,
        seqnum: u32,
        dir_in: bool,
        ep: usize,
        len: u32,
        setup: [u8; 8],
        data: Vec<u8>,
    ) {
        if ep == 0 {
            let Some(out0) = self.outs[0].as_mut() else {
                return self.ret_submit(seqnum, EPIPE, &[], 0);
            };
            out0.packets.clear();
            out0.stalled = false;
            out0.packets.push_back((true, setup.to_vec()));
            let max = usize::from(out0.max.max(8));
            for chunk in data.chunks(max) {
                out0.packets.push_back((false, chunk.to_vec()));
            }
            if let Some(in0) = self.ins[0].as_mut() {
                in0.stalled = false;
            }
            if let Some(old) = self.control.take() {
                self.ret_submit(old.seqnum, ECONNRESET, &[], 0);
            }
            self.control = Some(Control {
                seqnum,
                dir_in,
                len: if dir_in { len } else { data.len() as u32 },
                data: Vec::new(),
            });
            return;
        }
        if ep >= ENDPOINTS {
            return self.ret_submit(seqnum, EPIPE, &[], 0);
        }
        if dir_in {
            let Some(e) = self.ins[ep].as_mut() else {
                return self.ret_submit(seqnum, EPIPE, &[], 0);
            };
            if e.stalled {
                return self.ret_submit(seqnum, EPIPE, &[], 0);
            }
            e.unconfirmed = None;
            e.urbs.push_back(Urb { seqnum, len });
            self.complete_in(ep);
        } else {
            let Some(e) = self.outs[ep].as_mut() else {
                return self.ret_submit(seqnum, EPIPE, &[], 0);
            };
            let max = usize::from(e.max.max(1));
            for chunk in data.chunks(max) {
                e.packets.push_back((false, chunk.to_vec()));
            }
            self.ret_submit(seqnum, 0, &[], data.len() as u32);
        }
    }

    /// Hands a waiting packet of `ep` to a waiting IN URB.
    fn complete_in(&mut self, ep: usize) {
        let Some(e) = self.ins[ep].as_mut() else {
            return;
        };
        if e.packet.is_none() || e.urbs.is_empty() {
            return;
        }
        let (Some(mut p), Some(u)) = (e.packet.take(), e.urbs.pop_front()) else {
            return;
        };
        p.truncate(u.len as usize);
        e.unconfirmed = Some(p.clone());
        self.in_complete |= 1 << ep;
        self.traffic.in_packets += 1;
        self.ret_submit(u.seqnum, 0, &p, 0);
    }

    fn write_ep0(&mut self, buf: &[u8]) {
        self.in_complete |= 1;
        let max = self.ins[0].as_ref().map_or(8, |e| usize::from(e.max));
        let Some(c) = self.control.as_mut() else {
            return;
        };
        if c.dir_in {
            c.data.extend_from_slice(buf);
            if buf.len() < max || c.data.len() >= c.len as usize {
                let Some(mut c) = self.control.take() else {
                    return;
                };
                c.data.truncate(c.len as usize);
                let n = c.data.len() as u32;
                self.ret_submit(c.seqnum, 0, &c.data, n);
                // The host's status stage: a zero-length OUT.
                if let Some(out0) = self.outs[0].as_mut() {
                    out0.packets.push_back((false, Vec::new()));
                }
            }
        } else if buf.is_empty() {
            let Some(c) = self.control.take() else { return };
            self.ret_submit(c.seqnum, 0, &[], c.len);
        }
    }
}

impl UsbBus for UsbIpBus {
    fn alloc_ep(
        &mut self,
        ep_dir: UsbDirection,
        ep_addr: Option<EndpointAddress>,
        _ep_type: EndpointType,
        max_packet_size: u16,
        _interval: u8,
    ) -> UsbResult<EndpointAddress> {
        let mut inner = self.lock();
        let taken = |i: usize, inner: &Inner| match ep_dir {
            UsbDirection::In => inner.ins[i].is_some(),
            UsbDirection::Out => inner.outs[i].is_some(),
        };
        let index = match ep_addr {
            Some(a) if a.index() < ENDPOINTS && !taken(a.index(), &inner) => a.index(),
            Some(_) => return Err(UsbError::InvalidEndpoint),
            None => (1..ENDPOINTS)
                .find(|&i| !taken(i, &inner))
                .ok_or(UsbError::EndpointOverflow)?,
        };
        match ep_dir {
            UsbDirection::In => {
                inner.ins[index] = Some(InEp {
                    max: max_packet_size,
                    ..InEp::default()
                })
            }
            UsbDirection::Out => {
                inner.outs[index] = Some(OutEp {
                    max: max_packet_size,
                    ..OutEp::default()
                })
            }
        }
        Ok(EndpointAddress::from_parts(index, ep_dir))
    }

    fn enable(&mut self) {}

    fn reset(&self) {
        self.lock().clear_transfers();
    }

    fn set_device_address(&self, _addr: u8) {}

    fn write(&self, ep_addr: EndpointAddress, buf: &[u8]) -> UsbResult<usize> {
        let mut inner = self.lock();
        let i = ep_addr.index();
        if i == 0 {
            inner.write_ep0(buf);
            return Ok(buf.len());
        }
        let attached = inner.attached;
        let Some(e) = inner.ins.get_mut(i).and_then(Option::as_mut) else {
            return Err(UsbError::InvalidEndpoint);
        };
        if !attached || e.packet.is_some() {
            return Err(UsbError::WouldBlock);
        }
        if buf.len() > usize::from(e.max) {
            return Err(UsbError::BufferOverflow);
        }
        e.packet = Some(buf.to_vec());
        inner.complete_in(i);
        Ok(buf.len())
    }

    fn read(&self, ep_addr: EndpointAddress, buf: &mut [u8]) -> UsbResult<usize> {
        let mut inner = self.lock();
        let Some(e) = inner.outs.get_mut(ep_addr.index()).and_then(Option::as_mut) else {
            return Err(UsbError::InvalidEndpoint);
        };
        let Some((_, p)) = e.packets.front() else {
            return Err(UsbError::WouldBlock);
        };
        if p.len() > buf.len() {
            return Err(UsbError::BufferOverflow);
        }
        let n = p.len();
        buf[..n].copy_from_slice(p);
        e.packets.pop_front();
        Ok(n)
    }

    fn set_stalled(&self, ep_addr: EndpointAddress, stalled: bool) {
        let mut inner = self.lock();
        let i = ep_addr.index();
        if i >= ENDPOINTS {
            return;
        }
        if i == 0 && stalled {
            if let Some(c) = inner.control.take() {
                inner.traffic.stalls += 1;
                inner.ret_submit(c.seqnum, EPIPE, &[], 0);
            }
            if let Some(out0) = inner.outs[0].as_mut() {
                out0.packets.retain(|(setup, _)| *setup);
            }
        }
        match ep_addr.direction() {
            UsbDirection::In => {
                if let Some(e) = inner.ins[i].as_mut() {
                    e.stalled = stalled;
                    if stalled && i != 0 {
                        let urbs: Vec<u32> = e.urbs.drain(..).map(|u| u.seqnum).collect();
                        for s in urbs {
                            inner.ret_submit(s, EPIPE, &[], 0);
                        }
                    }
                }
            }
            UsbDirection::Out => {
                if let Some(e) = inner.outs[i].as_mut() {
                    e.stalled = stalled;
                }
            }
        }
    }

    fn is_stalled(&self, ep_addr: EndpointAddress) -> bool {
        let inner = self.lock();
        let i = ep_addr.index();
        match ep_addr.direction() {
            UsbDirection::In => inner
                .ins
                .get(i)
                .and_then(Option::as_ref)
                .is_some_and(|e| e.stalled),
            UsbDirection::Out => inner
                .outs
                .get(i)
                .and_then(Option::as_ref)
                .is_some_and(|e| e.stalled),
        }
    }

    fn suspend(&self) {}

    fn resume(&self) {}

    fn poll(&self) -> PollResult {
        let mut inner = self.lock();
        if inner.suspended {
            // No traffic on a suspended bus: the host's transfers wait for the resume.
            if inner.bus_request.take() == Some(false) {
                inner.suspended = false;
                return PollResult::Resume;
            }
            return PollResult::None;
        }
        inner.service();
        if inner.reset_pending {
            inner.reset_pending = false;
            inner.clear_transfers();
            return PollResult::Reset;
        }
        let (mut ep_out, mut ep_setup) = (0u16, 0u16);
        for (i, e) in inner.outs.iter().enumerate() {
            match e.as_ref().and_then(|e| e.packets.front()) {
                Some((true, _)) => ep_setup |= 1 << i,
                Some((false, _)) => ep_out |= 1 << i,
                None => {}
            }
        }
        let ep_in_complete = std::mem::take(&mut inner.in_complete);
        if ep_out | ep_setup | ep_in_complete == 0 {
            // A suspend follows the bus's last traffic (3 ms of idle on a real bus), so it
            // is reported only once no transfer is left to report.
            return match inner.bus_request.take() {
                Some(true) => {
                    inner.suspended = true;
                    PollResult::Suspend
                }
                Some(false) | None => PollResult::None,
            };
        }
        PollResult::Data {
            ep_out,
            ep_in_complete,
            ep_setup,
        }
    }
}
