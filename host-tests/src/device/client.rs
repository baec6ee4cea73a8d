//! The host's side of the configuration protocol: requests over a [`Link`] (the twin over
//! USB/IP, or a board through `hidapi`), responses matched by tag, refusals as typed errors
//! that name the key, and raw recording with every gap accounted.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use imu_core::profile::Key;
use imu_core::protocol::{
    code, header, AxisCalibration, Counters, ErrorCode, Frame, FrameError, Info, Request, Response,
    StreamFrame, PAIRS_MAX,
};

use crate::device::usbip_host::{UsbIpError, UsbIpHost};

/// A way to the device's configuration interface: 64-byte frames out and in.
pub trait Link {
    /// Sends one frame.
    ///
    /// # Errors
    /// The transport's failure, as text.
    fn send(&mut self, frame: &Frame) -> Result<(), ClientError>;
    /// The next frame from the device, or `None` after `timeout`.
    ///
    /// # Errors
    /// The transport's failure, as text.
    fn recv(&mut self, timeout: Duration) -> Result<Option<Frame>, ClientError>;
}

/// Why a device command failed.
#[derive(Debug, thiserror::Error)]
pub enum ClientError {
    /// The transport (USB/IP, hidapi).
    #[error("{0}")]
    Link(String),
    /// The device did not answer in time.
    #[error("the device did not answer {0} within {1:?}")]
    Timeout(&'static str, Duration),
    /// The device refused the request.
    #[error("the device refused: {}", describe(*.0))]
    Refused(ErrorCode),
    /// The device's answer did not decode, or did not fit the request.
    #[error("the device's answer is not this protocol: {0}")]
    Answer(String),
}

impl From<UsbIpError> for ClientError {
    fn from(e: UsbIpError) -> Self {
        Self::Link(e.to_string())
    }
}

/// A refusal in words, naming the key.
pub fn describe(e: ErrorCode) -> String {
    match e {
        ErrorCode::Version(v) => format!("protocol version {v} is not the device's"),
        ErrorCode::Command(c) => format!("unknown request {c:#04x}"),
        ErrorCode::Length => "a frame of the wrong length".into(),
        ErrorCode::UnknownKey(k) => format!("key id {k} is unknown to this firmware"),
        ErrorCode::Value(k) => format!("{k}: the value does not fit the key"),
        ErrorCode::Invalid(k) => format!("{k}: the configuration does not validate"),
        ErrorCode::Unsupported(Key::FsHz) => format!(
            "fs_hz: the device cannot run this rate (it takes {}..={} Hz, dividing 96 MHz)",
            imu_app::device::FS_MIN_HZ,
            imu_app::device::FS_MAX_HZ
        ),
        ErrorCode::Unsupported(Key::AdcBits) => format!(
            "adc_bits: the device's ADC has {} bits",
            imu_app::device::ADC_BITS
        ),
        ErrorCode::Unsupported(k) => format!("{k}: the device cannot run this value"),
        ErrorCode::Storage => "the flash store failed; nothing was kept".into(),
        ErrorCode::Busy => "a save is in progress".into(),
    }
}

impl Link for UsbIpHost {
    fn send(&mut self, frame: &Frame) -> Result<(), ClientError> {
        Ok(UsbIpHost::send(self, frame)?)
    }
    fn recv(&mut self, timeout: Duration) -> Result<Option<Frame>, ClientError> {
        Ok(UsbIpHost::recv(self, timeout)?)
    }
}

/// A raw recording.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Recorded {
    /// `[x, y, z]` codes in order, as sampled.
    pub samples: Vec<[u16; 3]>,
    /// `(index of the first sample after a gap, samples missing)`.
    pub gaps: Vec<(usize, u64)>,
    /// Stream frames received.
    pub frames: u32,
    /// Frames missing in the sequence numbers (lost between device and host).
    pub missing_frames: u32,
    /// The device's own totals when the stream stopped: frames sent, samples lost.
    pub device_totals: (u32, u32),
    /// Ended early by [`Client::record_until`]'s stop: fewer samples than asked.
    pub interrupted: bool,
}

impl Recorded {
    /// Samples missing in all (the device's gaps).
    pub fn lost(&self) -> u64 {
        self.gaps.iter().map(|g| g.1).sum()
    }
}

/// A session with the device's configuration interface.
pub struct Client<L: Link> {
    link: L,
    tag: u8,
    timeout: Duration,
    /// Stream frames that arrived while waiting for a response.
    stream: Vec<StreamFrame>,
}

impl<L: Link> Client<L> {
    /// A session over `link`; each answer may take up to `timeout`.
    pub fn new(link: L, timeout: Duration) -> Self {
        Self {
            link,
            tag: 0,
            timeout,
            stream: Vec::new(),
        }
    }

    /// Sends `req` and returns its response; stream frames that arrive meanwhile are kept.
    ///
    /// # Errors
    /// [`ClientError`]: the link, no answer, a refusal, an answer that does not decode.
    pub fn request(&mut self, req: &Request) -> Result<Response, ClientError> {
        self.tag = self.tag.wrapping_add(1);
        self.link.send(&req.encode(self.tag))?;
        loop {
            let frame = self
                .link
                .recv(self.timeout)?
                .ok_or(ClientError::Timeout("a request", self.timeout))?;
            let (c, tag, _) = header(&frame).map_err(|e| answer(&e))?;
            if c == code::STREAM || c == code::STREAM_WIDE {
                self.stream
                    .push(StreamFrame::decode(&frame).map_err(|e| answer(&e))?);
                continue;
            }
            if tag != self.tag {
                continue; // the answer to an earlier request that timed out
            }
            return match Response::decode(&frame).map_err(|e| answer(&e))?.1 {
                Response::Error(e) => Err(ClientError::Refused(e)),
                r => Ok(r),
            };
        }
    }

    /// Identity, firmware version, where the profile came from.
    ///
    /// # Errors
    /// As [`Self::request`].
    pub fn info(&mut self) -> Result<Info, ClientError> {
        match self.request(&Request::Info)? {
            Response::Info(i) => Ok(i),
            other => Err(unexpected(&other)),
        }
    }

    /// The device's counters.
    ///
    /// # Errors
    /// As [`Self::request`].
    pub fn counters(&mut self) -> Result<Counters, ClientError> {
        match self.request(&Request::Counters)? {
            Response::Counters(c) => Ok(c),
            other => Err(unexpected(&other)),
        }
    }

    /// The last calibration (the tracker's axes: cursor X, cursor Y, vertical).
    ///
    /// # Errors
    /// As [`Self::request`].
    pub fn calibration(&mut self) -> Result<Option<[AxisCalibration; 3]>, ClientError> {
        match self.request(&Request::Calibration)? {
            Response::Calibration(c) => Ok(c),
            other => Err(unexpected(&other)),
        }
    }

    /// Every key's value.
    ///
    /// # Errors
    /// As [`Self::request`].
    pub fn config(&mut self) -> Result<Vec<(Key, f64)>, ClientError> {
        let mut out = Vec::new();
        loop {
            let start = u8::try_from(out.len()).map_err(|_| answer(&"too many keys"))?;
            match self.request(&Request::GetConfig { start })? {
                Response::Config { pairs, total, .. } => {
                    if pairs.is_empty() || out.len() + pairs.len() > usize::from(total) {
                        return Ok(out);
                    }
                    out.extend(pairs);
                }
                other => return Err(unexpected(&other)),
            }
        }
    }

    /// Sets `pairs` as a whole: staged six per frame, applied by the last (every key or
    /// none). Nothing is sent for no pairs.
    ///
    /// # Errors
    /// As [`Self::request`]; a refusal names the key, and nothing changed on the device.
    pub fn set(&mut self, pairs: &[(Key, f64)]) -> Result<(), ClientError> {
        let chunks: Vec<&[(Key, f64)]> = pairs.chunks(PAIRS_MAX).collect();
        for (i, chunk) in chunks.iter().enumerate() {
            let req = Request::SetConfig {
                commit: i + 1 == chunks.len(),
                pairs: heapless::Vec::from_slice(chunk).map_err(|_| answer(&"six pairs"))?,
            };
            match self.request(&req)? {
                Response::Staged { .. } => {}
                other => return Err(unexpected(&other)),
            }
        }
        Ok(())
    }

    fn done(&mut self, req: Request) -> Result<(), ClientError> {
        let want = req.code();
        match self.request(&req)? {
            Response::Done(c) if c == want => Ok(()),
            other => Err(unexpected(&other)),
        }
    }

    /// Keeps the running profile in flash.
    ///
    /// # Errors
    /// As [`Self::request`].
    pub fn save(&mut self) -> Result<(), ClientError> {
        self.done(Request::Save)
    }

    /// Runs and keeps the defaults.
    ///
    /// # Errors
    /// As [`Self::request`].
    pub fn defaults(&mut self) -> Result<(), ClientError> {
        self.done(Request::Defaults)
    }

    /// Calibrates again.
    ///
    /// # Errors
    /// As [`Self::request`].
    pub fn recalibrate(&mut self) -> Result<(), ClientError> {
        self.done(Request::Recalibrate)
    }

    /// Records `samples` raw sample triples (or fewer if the stream stalls for the timeout).
    ///
    /// # Errors
    /// As [`Self::request`], or no stream frame within the timeout.
    pub fn record(
        &mut self,
        samples: usize,
        progress: impl FnMut(usize),
    ) -> Result<Recorded, ClientError> {
        self.record_until(samples, progress, &AtomicBool::new(false))
    }

    /// [`Self::record`], ending early (the stream stopped, [`Recorded::interrupted`] set,
    /// what arrived kept) once `stop` is set: a user's Ctrl-C.
    ///
    /// # Errors
    /// As [`Self::record`].
    pub fn record_until(
        &mut self,
        samples: usize,
        mut progress: impl FnMut(usize),
        stop: &AtomicBool,
    ) -> Result<Recorded, ClientError> {
        // A stream left running (a recording interrupted on this host, which never stopped
        // it) is stopped first; its frames still on the way are told apart by their numbers:
        // the device numbers a new stream's frames from 0, so a first frame numbered
        // FIRST_FRAMES or more is the old stream's (one that ran at least 0.2 s at 300 frames
        // a second), and one below it is the new stream's, the frames before it missing.
        self.request(&Request::StreamStop)?;
        self.stream.clear();
        self.done(Request::StreamStart)?;
        let mut rec = Recorded::default();
        let mut next_seq: Option<u16> = None;
        let mut take = |rec: &mut Recorded, f: StreamFrame| {
            match next_seq {
                None if f.seq >= FIRST_FRAMES => return, // the old stream's
                None => rec.missing_frames += u32::from(f.seq),
                Some(want) => rec.missing_frames += u32::from(f.seq.wrapping_sub(want)),
            }
            next_seq = Some(f.seq.wrapping_add(1));
            rec.frames += 1;
            if f.lost > 0 {
                rec.gaps.push((rec.samples.len(), u64::from(f.lost)));
            }
            rec.samples.extend(f.triples.iter().copied());
        };
        for f in std::mem::take(&mut self.stream) {
            take(&mut rec, f);
        }
        while rec.samples.len() < samples {
            if stop.load(Ordering::Relaxed) {
                rec.interrupted = true;
                break;
            }
            let frame = self
                .link
                .recv(self.timeout)?
                .ok_or(ClientError::Timeout("stream frames", self.timeout))?;
            match StreamFrame::decode(&frame) {
                Ok(f) => take(&mut rec, f),
                Err(FrameError::Code(_)) => {} // a late answer
                Err(e) => return Err(answer(&e)),
            }
            progress(rec.samples.len());
        }
        match self.request(&Request::StreamStop)? {
            Response::Stopped { frames, lost } => rec.device_totals = (frames, lost),
            other => return Err(unexpected(&other)),
        }
        self.stream.clear();
        rec.samples.truncate(samples);
        Ok(rec)
    }
}

/// A new stream's first frame is numbered below this (see [`Client::record`]).
const FIRST_FRAMES: u16 = 64;

fn answer(e: &dyn std::fmt::Debug) -> ClientError {
    ClientError::Answer(format!("{e:?}"))
}

fn unexpected(r: &Response) -> ClientError {
    ClientError::Answer(format!("unexpected answer {r:?}"))
}

/// An imu-mouse's configuration interface found on this host's USB.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Found {
    /// Its USB serial number (a board's MCU unique ID, 24 hex digits).
    pub serial: String,
    /// Its product string.
    pub product: String,
    /// Its release (`bcdDevice`, as `1.00`).
    pub release: String,
    /// The operating system's path to its HID interface.
    pub path: String,
}

/// The device to talk to among `found`: the one with `serial` if given, else the only one.
///
/// # Errors
/// [`ClientError::Link`]: none found (with the Linux permission hint), none with that serial,
/// or several and no serial to choose by (each is named).
pub fn choose(found: &[Found], serial: Option<&str>) -> Result<Found, ClientError> {
    let (vid, pid) = imu_app::identity::VID_PID;
    let serials = || {
        found
            .iter()
            .map(|f| f.serial.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    };
    match (found, serial) {
        ([], _) => Err(ClientError::Link(format!(
            "no imu-mouse ({vid:04x}:{pid:04x}) with a configuration interface; on Linux a \
             user needs the udev rule of docs/device.md to open it"
        ))),
        (_, Some(want)) => found
            .iter()
            .find(|f| f.serial == want)
            .cloned()
            .ok_or_else(|| {
                ClientError::Link(format!(
                    "no imu-mouse with serial {want}; found: {}",
                    serials()
                ))
            }),
        ([one], None) => Ok(one.clone()),
        (_, None) => Err(ClientError::Link(format!(
            "{} imu-mice are plugged in: choose one with --serial ({})",
            found.len(),
            serials()
        ))),
    }
}

/// The configuration interface of a board on this host's USB, through `hidapi`.
pub struct HidLink(hidapi::HidDevice);

impl HidLink {
    /// Every imu-mouse (`imu_app::identity::VID_PID`) on this host whose HID interface has the
    /// vendor usage page 0xFF00, with the hidapi context that found them.
    ///
    /// # Errors
    /// hidapi's error.
    pub fn list() -> Result<(hidapi::HidApi, Vec<Found>), ClientError> {
        let (vid, pid) = imu_app::identity::VID_PID;
        let api = hidapi::HidApi::new().map_err(|e| ClientError::Link(e.to_string()))?;
        let found = api
            .device_list()
            .filter(|d| d.vendor_id() == vid && d.product_id() == pid && d.usage_page() == 0xFF00)
            .map(|d| Found {
                serial: d.serial_number().unwrap_or("").to_string(),
                product: d.product_string().unwrap_or("").to_string(),
                release: release_text(d.release_number()),
                path: d.path().to_string_lossy().into_owned(),
            })
            .collect();
        Ok((api, found))
    }

    /// Opens the imu-mouse with `serial`, or the only one ([`choose`]).
    ///
    /// # Errors
    /// hidapi's error, or [`choose`]'s.
    pub fn open(serial: Option<&str>) -> Result<Self, ClientError> {
        let (api, found) = Self::list()?;
        let f = choose(&found, serial)?;
        let path =
            std::ffi::CString::new(f.path.clone()).map_err(|e| ClientError::Link(e.to_string()))?;
        let dev = api
            .open_path(&path)
            .map_err(|e| ClientError::Link(format!("{}: {e}", f.path)))?;
        Ok(Self(dev))
    }
}

impl Link for HidLink {
    fn send(&mut self, frame: &Frame) -> Result<(), ClientError> {
        // hidapi's first byte is the report ID: 0 for a device without IDs.
        let mut out = [0u8; 1 + imu_core::protocol::FRAME_LEN];
        out[1..].copy_from_slice(frame);
        self.0
            .write(&out)
            .map(|_| ())
            .map_err(|e| ClientError::Link(e.to_string()))
    }

    fn recv(&mut self, timeout: Duration) -> Result<Option<Frame>, ClientError> {
        let mut f = [0u8; imu_core::protocol::FRAME_LEN];
        let ms = i32::try_from(timeout.as_millis()).unwrap_or(i32::MAX);
        match self.0.read_timeout(&mut f, ms) {
            Ok(0) => Ok(None),
            Ok(_) => Ok(Some(f)),
            Err(e) => Err(ClientError::Link(e.to_string())),
        }
    }
}

/// A release as `bcdDevice` gives it (binary-coded decimal, `0x0100`), as text (`1.00`).
pub fn release_text(bcd: u16) -> String {
    format!("{:x}.{:02x}", bcd >> 8, bcd & 0xFF)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn found(serial: &str) -> Found {
        Found {
            serial: serial.into(),
            product: imu_app::identity::PRODUCT.into(),
            release: "1.00".into(),
            path: format!("/dev/hidraw-{serial}"),
        }
    }

    #[test]
    fn a_device_is_chosen_by_serial_or_as_the_only_one() {
        let two = [found("AAA"), found("BBB")];
        assert_eq!(choose(&two, Some("BBB")).ok(), Some(found("BBB")));
        assert_eq!(choose(&two[..1], None).ok(), Some(found("AAA")));
        let e = choose(&two, None).expect_err("which one?").to_string();
        assert!(
            e.contains("2 imu-mice") && e.contains("--serial (AAA, BBB)"),
            "{e}"
        );
        let e = choose(&two, Some("CCC"))
            .expect_err("not there")
            .to_string();
        assert!(
            e.contains("no imu-mouse with serial CCC; found: AAA, BBB"),
            "{e}"
        );
        let e = choose(&[], None).expect_err("none").to_string();
        assert!(e.contains("udev rule"), "{e}");
    }
}
