//! A minimal USB/IP host: imports the twin's device over TCP, configures it, finds the
//! configuration interface (the HID interface whose report descriptor opens with the vendor
//! usage page 0xFF00) and moves 64-byte frames over its interrupt endpoints. The
//! `cargo lab device` commands use it against the twin; a board goes through `hidapi`.
//!
//! # Design
//! One TCP connection per session (closing it is a bus reset for the twin). Transfers are
//! `USBIP_CMD_SUBMIT` / `RET_SUBMIT` pairs matched by sequence number; a few interrupt IN
//! URBs stay outstanding so that a stream's frames are not held up by round trips, and a
//! timed-out wait leaves them pending (they complete later). Protocol: the Linux kernel's
//! `Documentation/usb/usbip_protocol.rst`, big-endian.

use std::collections::VecDeque;
use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::time::{Duration, Instant};

use imu_core::protocol::{Frame, FRAME_LEN};

use crate::device::usbip::{CMD_SUBMIT, OP_REQ_IMPORT, RET_SUBMIT, RET_UNLINK, VERSION};

/// Interrupt IN URBs kept outstanding.
const IN_FLIGHT: usize = 4;

/// Why a USB/IP session failed.
#[derive(Debug, thiserror::Error)]
pub enum UsbIpError {
    /// The socket.
    #[error("USB/IP connection: {0}")]
    Io(#[from] std::io::Error),
    /// The server refused the import or answered out of protocol.
    #[error("USB/IP: {0}")]
    Protocol(String),
    /// The device has no configuration interface.
    #[error("the device has no configuration interface (vendor HID, usage page 0xFF00)")]
    NoInterface,
}

fn proto<T>(what: impl Into<String>) -> Result<T, UsbIpError> {
    Err(UsbIpError::Protocol(what.into()))
}

/// An imported device and its configuration interface's endpoints.
pub struct UsbIpHost {
    tcp: TcpStream,
    seq: u32,
    ep_in: u32,
    ep_out: u32,
    /// Sequence numbers of the interrupt IN URBs outstanding.
    pending_in: VecDeque<u32>,
    /// IN frames received while waiting for something else.
    frames: VecDeque<Frame>,
    /// The control IN transfer outstanding, if any.
    control_in: Option<u32>,
    /// How long a reply may take.
    timeout: Duration,
}

impl UsbIpHost {
    /// Imports bus id `busid` from the server at `addr`, configures the device and finds its
    /// configuration interface.
    ///
    /// # Errors
    /// [`UsbIpError`]: the connection, a refused import, no configuration interface.
    pub fn connect(addr: SocketAddr, busid: &str, timeout: Duration) -> Result<Self, UsbIpError> {
        let tcp = TcpStream::connect_timeout(&addr, timeout)?;
        tcp.set_nodelay(true)?;
        tcp.set_read_timeout(Some(timeout))?;
        let mut host = Self {
            tcp,
            seq: 0,
            ep_in: 0,
            ep_out: 0,
            pending_in: VecDeque::new(),
            frames: VecDeque::new(),
            control_in: None,
            timeout,
        };
        host.import(busid)?;
        // SET_CONFIGURATION 1.
        host.control([0x00, 0x09, 1, 0, 0, 0, 0, 0], &[], 0)?;
        let (ep_in, ep_out) = host.find_interface()?;
        host.ep_in = ep_in;
        host.ep_out = ep_out;
        Ok(host)
    }

    fn import(&mut self, busid: &str) -> Result<(), UsbIpError> {
        let mut m = Vec::with_capacity(40);
        m.extend_from_slice(&VERSION.to_be_bytes());
        m.extend_from_slice(&OP_REQ_IMPORT.to_be_bytes());
        m.extend_from_slice(&0u32.to_be_bytes());
        let mut id = [0u8; 32];
        let n = busid.len().min(31);
        id[..n].copy_from_slice(&busid.as_bytes()[..n]);
        m.extend_from_slice(&id);
        self.tcp.write_all(&m)?;
        let mut head = [0u8; 8];
        self.tcp.read_exact(&mut head)?;
        if u32::from_be_bytes([head[4], head[5], head[6], head[7]]) != 0 {
            return proto(format!("the server has no device {busid}"));
        }
        let mut record = [0u8; 312];
        self.tcp.read_exact(&mut record)?;
        Ok(())
    }

    fn submit(
        &mut self,
        dir_in: bool,
        ep: u32,
        len: u32,
        setup: [u8; 8],
        out: &[u8],
    ) -> Result<u32, UsbIpError> {
        self.seq += 1;
        let mut m = Vec::with_capacity(48 + out.len());
        for w in [
            CMD_SUBMIT,
            self.seq,
            0,
            u32::from(dir_in),
            ep,
            0,
            len,
            0,
            0,
            0,
        ] {
            m.extend_from_slice(&w.to_be_bytes());
        }
        m.extend_from_slice(&setup);
        m.extend_from_slice(out);
        self.tcp.write_all(&m)?;
        Ok(self.seq)
    }

    /// Reads one reply: `(seqnum, status, data)`.
    fn reply(&mut self) -> Result<(u32, i32, Vec<u8>), UsbIpError> {
        let mut h = [0u8; 48];
        self.tcp.read_exact(&mut h)?;
        let word = |i: usize| u32::from_be_bytes([h[i], h[i + 1], h[i + 2], h[i + 3]]);
        match word(0) {
            RET_SUBMIT => {
                let status = word(20) as i32;
                let len = word(24) as usize;
                let mut data = Vec::new();
                // Only IN transfers carry data back; ours are the only URBs with a length
                // that is not theirs (an OUT's actual length names bytes already sent).
                if self.pending_in.contains(&word(4)) || self.control_in == Some(word(4)) {
                    data.resize(len, 0);
                    self.tcp.read_exact(&mut data)?;
                }
                Ok((word(4), status, data))
            }
            RET_UNLINK => Ok((word(4), word(20) as i32, Vec::new())),
            other => proto(format!("unexpected reply {other}")),
        }
    }

    /// Waits for the reply to `seq`, keeping IN frames that arrive meanwhile.
    fn wait(&mut self, seq: u32) -> Result<(i32, Vec<u8>), UsbIpError> {
        self.tcp.set_read_timeout(Some(self.timeout))?;
        loop {
            let (s, status, data) = self.reply()?;
            if s == seq {
                return Ok((status, data));
            }
            self.take_in(s, status, data);
        }
    }

    /// Keeps the data of a completed interrupt IN URB as a frame (other replies are dropped).
    fn take_in(&mut self, seq: u32, status: i32, data: Vec<u8>) {
        if let Some(i) = self.pending_in.iter().position(|&p| p == seq) {
            self.pending_in.remove(i);
            if status == 0 && !data.is_empty() {
                let mut f = [0u8; FRAME_LEN];
                let n = data.len().min(FRAME_LEN);
                f[..n].copy_from_slice(&data[..n]);
                self.frames.push_back(f);
            }
        }
    }

    /// A control transfer: `setup`, OUT `data` or `in_len` bytes IN. Returns the IN data.
    fn control(&mut self, setup: [u8; 8], data: &[u8], in_len: u16) -> Result<Vec<u8>, UsbIpError> {
        let dir_in = setup[0] & 0x80 != 0;
        let len = if dir_in {
            u32::from(in_len)
        } else {
            data.len() as u32
        };
        let seq = self.submit(dir_in, 0, len, setup, data)?;
        self.control_in = dir_in.then_some(seq);
        let (status, back) = self.wait(seq)?;
        self.control_in = None;
        if status != 0 {
            return proto(format!(
                "control request {:02x} failed: status {status}",
                setup[1]
            ));
        }
        Ok(back)
    }

    /// The device's serial number string (the string its device descriptor's
    /// `iSerialNumber` names, in US English), or `None` if it has none.
    ///
    /// # Errors
    /// A failed control request, or a descriptor that is not one.
    pub fn serial(&mut self) -> Result<Option<String>, UsbIpError> {
        let device = self.device_descriptor()?;
        let Some(&index) = device.get(16).filter(|&&i| i != 0) else {
            return Ok(None);
        };
        let s = self.control([0x80, 0x06, index, 3, 0x09, 0x04, 255, 0], &[], 255)?;
        if s.len() < 2 || s[1] != 3 {
            return proto("the serial number is not a string descriptor");
        }
        let units: Vec<u16> = s[2..usize::from(s[0]).min(s.len())]
            .chunks_exact(2)
            .map(|c| u16::from_le_bytes([c[0], c[1]]))
            .collect();
        Ok(Some(String::from_utf16_lossy(&units)))
    }

    /// The device's release, its device descriptor's `bcdDevice` (`0x0100` for 1.00).
    ///
    /// # Errors
    /// A failed control request, or a descriptor too short to hold it.
    pub fn release(&mut self) -> Result<u16, UsbIpError> {
        match self.device_descriptor()?.get(12..14) {
            Some(b) => Ok(u16::from_le_bytes([b[0], b[1]])),
            None => proto("the device descriptor is too short for bcdDevice"),
        }
    }

    /// The device descriptor (18 bytes).
    fn device_descriptor(&mut self) -> Result<Vec<u8>, UsbIpError> {
        self.control([0x80, 0x06, 0, 1, 0, 0, 18, 0], &[], 18)
    }

    /// The configuration interface's `(IN, OUT)` endpoint numbers.
    fn find_interface(&mut self) -> Result<(u32, u32), UsbIpError> {
        let head = self.control([0x80, 0x06, 0, 2, 0, 0, 9, 0], &[], 9)?;
        let total = head
            .get(2..4)
            .map_or(9, |b| u16::from_le_bytes([b[0], b[1]]));
        let config = self.control(
            [0x80, 0x06, 0, 2, 0, 0, total as u8, (total >> 8) as u8],
            &[],
            total,
        )?;
        let mut i = 0;
        let mut current: Option<(u8, u16, u32, u32)> = None; // (interface, report len, in, out)
        let mut candidates = Vec::new();
        while i + 1 < config.len() {
            let (len, kind) = (usize::from(config[i]), config[i + 1]);
            if len == 0 {
                break;
            }
            let d = &config[i..(i + len).min(config.len())];
            match kind {
                4 if d.len() >= 9 => {
                    candidates.extend(current.take());
                    current = (d[5] == 3).then_some((d[2], 0, 0, 0));
                }
                0x21 if d.len() >= 9 => {
                    if let Some(c) = current.as_mut() {
                        c.1 = u16::from_le_bytes([d[7], d[8]]);
                    }
                }
                5 if d.len() >= 7 => {
                    if let Some(c) = current.as_mut() {
                        let ep = u32::from(d[2] & 0x0F);
                        if d[2] & 0x80 != 0 {
                            c.2 = ep;
                        } else {
                            c.3 = ep;
                        }
                    }
                }
                _ => {}
            }
            i += len;
        }
        candidates.extend(current);
        for (iface, rlen, ep_in, ep_out) in candidates {
            let report = self.control(
                [0x81, 0x06, 0, 0x22, iface, 0, rlen as u8, (rlen >> 8) as u8],
                &[],
                rlen,
            )?;
            if report.starts_with(&[0x06, 0x00, 0xFF]) && ep_in != 0 && ep_out != 0 {
                return Ok((ep_in, ep_out));
            }
        }
        Err(UsbIpError::NoInterface)
    }

    /// Sends one frame on the interrupt OUT endpoint.
    ///
    /// # Errors
    /// The connection, or the transfer refused.
    pub fn send(&mut self, frame: &Frame) -> Result<(), UsbIpError> {
        let seq = self.submit(false, self.ep_out, FRAME_LEN as u32, [0; 8], frame)?;
        let (status, _) = self.wait(seq)?;
        if status != 0 {
            return proto(format!("interrupt OUT failed: status {status}"));
        }
        Ok(())
    }

    /// The next IN frame, waiting at most `timeout`; `None` if none came.
    ///
    /// # Errors
    /// The connection.
    pub fn recv(&mut self, timeout: Duration) -> Result<Option<Frame>, UsbIpError> {
        let deadline = Instant::now() + timeout;
        loop {
            if let Some(f) = self.frames.pop_front() {
                return Ok(Some(f));
            }
            while self.pending_in.len() < IN_FLIGHT {
                let seq = self.submit(true, self.ep_in, FRAME_LEN as u32, [0; 8], &[])?;
                self.pending_in.push_back(seq);
            }
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return Ok(None);
            }
            self.tcp.set_read_timeout(Some(left))?;
            // A timeout can only strike before a reply's first byte: replies arrive whole.
            let mut peek = [0u8; 1];
            match self.tcp.peek(&mut peek) {
                Ok(0) => return proto("the server closed the connection"),
                Ok(_) => {
                    self.tcp.set_read_timeout(Some(self.timeout))?;
                    let (s, status, data) = self.reply()?;
                    self.take_in(s, status, data);
                }
                Err(e)
                    if matches!(
                        e.kind(),
                        std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                    ) =>
                {
                    return Ok(None)
                }
                // A signal (the user's Ctrl-C, which the caller watches) woke the wait.
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => return Err(e.into()),
            }
        }
    }
}
