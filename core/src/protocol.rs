//! The configuration interface's command protocol: 64-byte frames on the device's vendor HID
//! interface, encoded and decoded here for both ends.
//!
//! # Design
//! Every frame is one 64-byte HID report (no report ID):
//!
//! | byte | meaning |
//! |---|---|
//! | 0 | protocol version, [`VERSION`] |
//! | 1 | code: a request, its response (`request | 0x80`), [`code::ERROR`] or [`code::STREAM`] |
//! | 2 | tag: chosen by the host, echoed by the response (stream frames: 0) |
//! | 3 | payload length, `0..=60` |
//! | 4.. | payload (little-endian integers and `f64`), then zeros |
//!
//! The host sends a request as an OUT report; the device answers each with one IN report,
//! a response or an [`ErrorCode`] naming what was wrong (a key where there is one). Raw
//! samples ([`crate::protocol::StreamFrame`]) share the IN endpoint while a stream runs.
//! Decoding never panics: a frame that is short, of another version, of an unknown code, or
//! whose payload does not match its code is a [`FrameError`], which the device answers with
//! an error response.
//!
//! Configuration travels as `(key id, f64)` pairs ([`crate::profile`]), six per frame. A
//! `config set` of more keys is staged over several [`Request::SetConfig`] frames and applied
//! as a whole by the one with `commit`: every key or none.

use heapless::Vec;

use crate::profile::Key;

/// Protocol version this firmware speaks (byte 0 of every frame).
pub const VERSION: u8 = 2;
/// Length of every frame [bytes]: one full-speed HID report.
pub const FRAME_LEN: usize = 64;
/// Largest payload [bytes].
pub const PAYLOAD_MAX: usize = FRAME_LEN - 4;
/// `(key, value)` pairs per frame.
pub const PAIRS_MAX: usize = 6;
/// Sample triples per stream frame with 12-bit packing (1.5 bytes per code).
pub const STREAM_TRIPLES_PACKED: usize = 12;
/// Sample triples per stream frame with 16-bit codes (ADCs of more than 12 bits).
pub const STREAM_TRIPLES_WIDE: usize = 9;

/// One frame's bytes.
pub type Frame = [u8; FRAME_LEN];

/// The configuration interface's HID report descriptor (27 bytes): vendor usage page
/// 0xFF00 (no driver claims it on any OS), one 64-byte input report and one 64-byte output
/// report, no report IDs.
pub const CONFIG_REPORT_DESCRIPTOR: [u8; 27] = [
    0x06, 0x00, 0xFF, // Usage Page (Vendor Defined 0xFF00)
    0x09, 0x01, // Usage (0x01)
    0xA1, 0x01, // Collection (Application)
    0x09, 0x02, //   Usage (0x02): device to host
    0x15, 0x00, //   Logical Minimum (0)
    0x26, 0xFF, 0x00, //   Logical Maximum (255)
    0x75, 0x08, //   Report Size (8)
    0x95, 0x40, //   Report Count (64)
    0x81, 0x02, //   Input (Data, Variable, Absolute)
    0x09, 0x03, //   Usage (0x03): host to device
    0x95, 0x40, //   Report Count (64)
    0x91, 0x02, //   Output (Data, Variable, Absolute)
    0xC0, // End Collection
];

/// Frame codes (byte 1).
pub mod code {
    /// Identity, firmware version, where the running configuration came from.
    pub const INFO: u8 = 0x01;
    /// Sample, loss, restart and report counters.
    pub const COUNTERS: u8 = 0x02;
    /// The last calibration.
    pub const CALIBRATION: u8 = 0x03;
    /// Up to six configuration values from a position in the key table.
    pub const GET_CONFIG: u8 = 0x10;
    /// Stage up to six values; `commit` applies everything staged.
    pub const SET_CONFIG: u8 = 0x11;
    /// Keep the running configuration in flash.
    pub const SAVE: u8 = 0x12;
    /// Run and keep the defaults.
    pub const DEFAULTS: u8 = 0x13;
    /// Calibrate again (the device must be still).
    pub const RECALIBRATE: u8 = 0x14;
    /// Start streaming raw ADC codes.
    pub const STREAM_START: u8 = 0x20;
    /// Stop streaming.
    pub const STREAM_STOP: u8 = 0x21;
    /// Added to a request's code (all below 0x80) to make its response's: [`answer`].
    pub const RESPONSE: u8 = 0x80;

    /// The code of the response to request `request` (a request code, below 0x80).
    pub const fn answer(request: u8) -> u8 {
        request.wrapping_add(RESPONSE)
    }
    /// A stream frame of raw codes, 12-bit packed.
    pub const STREAM: u8 = 0x40;
    /// A stream frame of raw codes, 16 bits each.
    pub const STREAM_WIDE: u8 = 0x41;
    /// An error response.
    pub const ERROR: u8 = 0xFF;
}

/// What the host asks.
#[derive(Clone, Debug, PartialEq)]
pub enum Request {
    /// [`code::INFO`].
    Info,
    /// [`code::COUNTERS`].
    Counters,
    /// [`code::CALIBRATION`].
    Calibration,
    /// [`code::GET_CONFIG`]: values of the keys from position `start` of [`Key::ALL`].
    GetConfig {
        /// Position in [`Key::ALL`].
        start: u8,
    },
    /// [`code::SET_CONFIG`].
    SetConfig {
        /// Apply everything staged (this frame's pairs included).
        commit: bool,
        /// The values to stage.
        pairs: Vec<(Key, f64), PAIRS_MAX>,
    },
    /// [`code::SAVE`].
    Save,
    /// [`code::DEFAULTS`].
    Defaults,
    /// [`code::RECALIBRATE`].
    Recalibrate,
    /// [`code::STREAM_START`].
    StreamStart,
    /// [`code::STREAM_STOP`].
    StreamStop,
}

/// Where the running configuration came from at start-up.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(u8)]
pub enum Source {
    /// Nothing stored: the defaults.
    Defaults = 0,
    /// The stored configuration.
    Stored = 1,
    /// The store could not be read (erased sectors of another use, corrupt): the defaults.
    Corrupt = 2,
    /// The stored configuration no longer validates (a firmware update): the defaults.
    Invalid = 3,
    /// Set over USB since start-up and not saved.
    Changed = 4,
}

impl Source {
    /// From its wire byte.
    pub const fn from_u8(b: u8) -> Option<Self> {
        Some(match b {
            0 => Self::Defaults,
            1 => Self::Stored,
            2 => Self::Corrupt,
            3 => Self::Invalid,
            4 => Self::Changed,
            _ => return None,
        })
    }
}

/// [`Response::Info`]'s content.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Info {
    /// Firmware version `[major, minor, patch]`.
    pub firmware: [u8; 3],
    /// Protocol version ([`VERSION`]).
    pub protocol: u8,
    /// Where the running configuration came from.
    pub source: Source,
    /// With [`Source::Invalid`]: the stored key that failed (0 otherwise).
    pub invalid_key: u8,
    /// Running sampling rate [Hz].
    pub fs_hz: u32,
    /// Whether the tracker is tracking (else calibrating).
    pub tracking: bool,
    /// Whether a raw stream is running.
    pub streaming: bool,
}

/// What the tracker is doing, as [`Response::Counters`] reports it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TrackerState {
    /// Calibrating: nothing is integrated yet.
    #[default]
    Calibrating = 0,
    /// Tracking without drift control: every sample is integrated (the paper's pipeline).
    Integrating = 1,
    /// At rest ([`crate::DriftState::Still`]).
    Still = 2,
    /// A motion, delivered as it is integrated.
    Moving = 3,
    /// A motion held back: younger than its hold, or held by the tilt tests.
    Held = 4,
    /// Lifted off the desk: tracking suspended until it rests.
    Lifted = 5,
    /// After a button edge: motion suppressed for the click freeze.
    Frozen = 6,
}

impl TrackerState {
    /// From its wire byte.
    pub const fn from_u8(b: u8) -> Option<Self> {
        Some(match b {
            0 => Self::Calibrating,
            1 => Self::Integrating,
            2 => Self::Still,
            3 => Self::Moving,
            4 => Self::Held,
            5 => Self::Lifted,
            6 => Self::Frozen,
            _ => return None,
        })
    }

    /// `tracker`'s state now.
    pub fn of(tracker: &crate::Tracker) -> Self {
        use crate::DriftState;
        if tracker.phase() == crate::Phase::Calibrating {
            return Self::Calibrating;
        }
        match tracker.drift_state() {
            None => Self::Integrating,
            Some(DriftState::Still) => Self::Still,
            Some(DriftState::Moving) if tracker.is_holding() => Self::Held,
            Some(DriftState::Moving) => Self::Moving,
            Some(DriftState::Lifted) => Self::Lifted,
            Some(DriftState::Frozen) => Self::Frozen,
        }
    }

    /// Its name, as the host tool and the settings page show it.
    pub const fn name(self) -> &'static str {
        match self {
            Self::Calibrating => "calibrating",
            Self::Integrating => "integrating",
            Self::Still => "still",
            Self::Moving => "moving",
            Self::Held => "held",
            Self::Lifted => "lifted",
            Self::Frozen => "frozen",
        }
    }
}

/// [`Response::Counters`]'s content.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Sample triples received by the tracker.
    pub samples: u64,
    /// Sample triples lost by the hardware.
    pub lost: u64,
    /// Sampling restarts.
    pub restarts: u32,
    /// Mouse reports sent.
    pub reports: u32,
    /// Calibration windows rejected.
    pub rejected_windows: u32,
    /// Stream frames sent.
    pub stream_frames: u32,
    /// Sample triples the stream could not carry (queue full).
    pub stream_lost: u32,
    /// The cursor's motion since power-up [counts] (right, down; wrapping): every count
    /// the tracker produced, whether a host took it, it is still owed, or it was dropped
    /// while no host listened ([`crate::Reporter::added`]).
    pub counts: [i64; 2],
    /// What the tracker is doing.
    pub tracker: TrackerState,
}

/// One axis of [`Response::Calibration`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AxisCalibration {
    /// Bias (mean code at rest) [LSB, Q16].
    pub bias_q16: i64,
    /// Rms noise at rest [LSB, Q16].
    pub noise_rms_q16: u32,
}

/// What the device answers.
#[derive(Clone, Debug, PartialEq)]
pub enum Response {
    /// To [`Request::Info`].
    Info(Info),
    /// To [`Request::Counters`].
    Counters(Counters),
    /// To [`Request::Calibration`]: `None` before the first calibration.
    Calibration(Option<[AxisCalibration; 3]>),
    /// To [`Request::GetConfig`]: `total` keys; these `pairs` from `start`.
    Config {
        /// Number of keys in all.
        total: u8,
        /// Position of the first pair.
        start: u8,
        /// The values.
        pairs: Vec<(Key, f64), PAIRS_MAX>,
    },
    /// To [`Request::SetConfig`]: staged so far (`applied`: the commit ran).
    Staged {
        /// Keys staged (not yet applied) or applied.
        count: u8,
        /// Whether the staged values are now running.
        applied: bool,
    },
    /// To [`Request::Save`], [`Request::Defaults`], [`Request::Recalibrate`],
    /// [`Request::StreamStart`]: done. The code says which.
    Done(u8),
    /// To [`Request::StreamStop`]: frames sent and triples lost by this stream.
    Stopped {
        /// Stream frames sent.
        frames: u32,
        /// Sample triples lost (hardware and queue).
        lost: u32,
    },
    /// A request refused.
    Error(ErrorCode),
}

/// Why a request was refused (payload of [`code::ERROR`]: code byte, detail byte).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ErrorCode {
    /// The frame is not this protocol version (detail: the version received).
    Version(u8),
    /// Unknown request code (detail: the code).
    Command(u8),
    /// Frame or payload shorter or longer than its code needs.
    Length,
    /// A key id this firmware does not know (detail: the id).
    UnknownKey(u8),
    /// The value does not fit the key (detail: the key).
    Value(Key),
    /// The configuration does not validate; the key named is wrong (detail: the key).
    Invalid(Key),
    /// The device cannot run this value (a sampling rate the trigger timer cannot make).
    Unsupported(Key),
    /// The flash store failed; nothing was kept.
    Storage,
    /// A save is in progress.
    Busy,
}

impl ErrorCode {
    fn bytes(self) -> [u8; 2] {
        match self {
            Self::Version(v) => [1, v],
            Self::Command(c) => [2, c],
            Self::Length => [3, 0],
            Self::UnknownKey(k) => [4, k],
            Self::Value(k) => [5, k as u8],
            Self::Invalid(k) => [6, k as u8],
            Self::Unsupported(k) => [7, k as u8],
            Self::Storage => [8, 0],
            Self::Busy => [9, 0],
        }
    }

    fn from_bytes(c: u8, d: u8) -> Option<Self> {
        let key = Key::from_id(d);
        Some(match c {
            1 => Self::Version(d),
            2 => Self::Command(d),
            3 => Self::Length,
            4 => Self::UnknownKey(d),
            5 => Self::Value(key?),
            6 => Self::Invalid(key?),
            7 => Self::Unsupported(key?),
            8 => Self::Storage,
            9 => Self::Busy,
            _ => return None,
        })
    }
}

/// Why a frame could not be decoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FrameError {
    /// Shorter than its header, or its payload length beyond the frame.
    Truncated,
    /// Another protocol version.
    Version(u8),
    /// An unknown code.
    Code(u8),
    /// The payload does not match the code.
    Payload,
    /// A key id this firmware does not know.
    UnknownKey(u8),
}

impl FrameError {
    /// The error response the device sends for it.
    pub const fn response(self) -> ErrorCode {
        match self {
            Self::Truncated | Self::Payload => ErrorCode::Length,
            Self::Version(v) => ErrorCode::Version(v),
            Self::Code(c) => ErrorCode::Command(c),
            Self::UnknownKey(k) => ErrorCode::UnknownKey(k),
        }
    }
}

/// A frame being written: header, then payload bytes.
struct Writer {
    frame: Frame,
    len: usize,
}

impl Writer {
    fn new(code: u8, tag: u8) -> Self {
        let mut frame = [0; FRAME_LEN];
        frame[0] = VERSION;
        frame[1] = code;
        frame[2] = tag;
        Self { frame, len: 0 }
    }

    fn put(&mut self, bytes: &[u8]) -> &mut Self {
        let end = (self.len + bytes.len()).min(PAYLOAD_MAX);
        self.frame[4 + self.len..4 + end].copy_from_slice(&bytes[..end - self.len]);
        self.len = end;
        self
    }

    fn pairs(&mut self, pairs: &[(Key, f64)]) -> &mut Self {
        for (k, v) in pairs {
            self.put(&[*k as u8]).put(&v.to_le_bytes());
        }
        self
    }

    fn done(&mut self) -> Frame {
        self.frame[3] = self.len as u8;
        self.frame
    }
}

/// A payload being read; every read checks its length.
struct Reader<'a>(&'a [u8]);

impl<'a> Reader<'a> {
    fn take<const N: usize>(&mut self) -> Result<[u8; N], FrameError> {
        let (head, rest) = self.0.split_at_checked(N).ok_or(FrameError::Payload)?;
        self.0 = rest;
        let mut out = [0; N];
        out.copy_from_slice(head);
        Ok(out)
    }
    fn u8(&mut self) -> Result<u8, FrameError> {
        Ok(self.take::<1>()?[0])
    }
    fn u32(&mut self) -> Result<u32, FrameError> {
        self.take().map(u32::from_le_bytes)
    }
    fn u64(&mut self) -> Result<u64, FrameError> {
        self.take().map(u64::from_le_bytes)
    }
    fn i64(&mut self) -> Result<i64, FrameError> {
        self.take().map(i64::from_le_bytes)
    }
    fn end(&self) -> Result<(), FrameError> {
        if self.0.is_empty() {
            Ok(())
        } else {
            Err(FrameError::Payload)
        }
    }
    /// `(key, value)` pairs to the payload's end: a pair cut short, or more than
    /// [`PAIRS_MAX`], is [`FrameError::Payload`].
    fn pairs(&mut self) -> Result<Vec<(Key, f64), PAIRS_MAX>, FrameError> {
        let mut out = Vec::new();
        while !self.0.is_empty() {
            let id = self.u8()?;
            let key = Key::from_id(id).ok_or(FrameError::UnknownKey(id))?;
            let value = f64::from_le_bytes(self.take()?);
            out.push((key, value)).map_err(|_| FrameError::Payload)?;
        }
        Ok(out)
    }
}

/// A frame's header checked: `(code, tag, payload)`.
///
/// # Errors
/// [`FrameError::Truncated`] if shorter than the header or its payload length says;
/// [`FrameError::Version`] for another version.
pub fn header(frame: &[u8]) -> Result<(u8, u8, &[u8]), FrameError> {
    let [version, code, tag, len, rest @ ..] = frame else {
        return Err(FrameError::Truncated);
    };
    if *version != VERSION {
        return Err(FrameError::Version(*version));
    }
    let payload = rest
        .get(..usize::from(*len))
        .filter(|_| usize::from(*len) <= PAYLOAD_MAX)
        .ok_or(FrameError::Truncated)?;
    Ok((*code, *tag, payload))
}

impl Request {
    /// The request's code.
    pub const fn code(&self) -> u8 {
        match self {
            Self::Info => code::INFO,
            Self::Counters => code::COUNTERS,
            Self::Calibration => code::CALIBRATION,
            Self::GetConfig { .. } => code::GET_CONFIG,
            Self::SetConfig { .. } => code::SET_CONFIG,
            Self::Save => code::SAVE,
            Self::Defaults => code::DEFAULTS,
            Self::Recalibrate => code::RECALIBRATE,
            Self::StreamStart => code::STREAM_START,
            Self::StreamStop => code::STREAM_STOP,
        }
    }

    /// The request as a frame with `tag`.
    pub fn encode(&self, tag: u8) -> Frame {
        let mut w = Writer::new(self.code(), tag);
        match self {
            Self::GetConfig { start } => w.put(&[*start]),
            Self::SetConfig { commit, pairs } => w.put(&[u8::from(*commit)]).pairs(pairs),
            _ => &mut w,
        }
        .done()
    }

    /// A request from a received frame: `(tag, request)`.
    ///
    /// # Errors
    /// [`FrameError`]: the header, an unknown code, a payload that does not match, an
    /// unknown key.
    pub fn decode(frame: &[u8]) -> Result<(u8, Self), FrameError> {
        let (c, tag, payload) = header(frame)?;
        let mut r = Reader(payload);
        let req = match c {
            code::INFO => Self::Info,
            code::COUNTERS => Self::Counters,
            code::CALIBRATION => Self::Calibration,
            code::GET_CONFIG => Self::GetConfig { start: r.u8()? },
            code::SET_CONFIG => {
                let commit = match r.u8()? {
                    0 => false,
                    1 => true,
                    _ => return Err(FrameError::Payload),
                };
                Self::SetConfig {
                    commit,
                    pairs: r.pairs()?,
                }
            }
            code::SAVE => Self::Save,
            code::DEFAULTS => Self::Defaults,
            code::RECALIBRATE => Self::Recalibrate,
            code::STREAM_START => Self::StreamStart,
            code::STREAM_STOP => Self::StreamStop,
            other => return Err(FrameError::Code(other)),
        };
        r.end()?;
        Ok((tag, req))
    }
}

impl Response {
    /// The response as a frame answering the request with `tag`.
    pub fn encode(&self, tag: u8) -> Frame {
        match self {
            Self::Info(i) => Writer::new(code::answer(code::INFO), tag)
                .put(&i.firmware)
                .put(&[
                    i.protocol,
                    i.source as u8,
                    i.invalid_key,
                    u8::from(i.tracking),
                    u8::from(i.streaming),
                ])
                .put(&i.fs_hz.to_le_bytes())
                .done(),
            Self::Counters(c) => Writer::new(code::answer(code::COUNTERS), tag)
                .put(&c.samples.to_le_bytes())
                .put(&c.lost.to_le_bytes())
                .put(&c.restarts.to_le_bytes())
                .put(&c.reports.to_le_bytes())
                .put(&c.rejected_windows.to_le_bytes())
                .put(&c.stream_frames.to_le_bytes())
                .put(&c.stream_lost.to_le_bytes())
                .put(&c.counts[0].to_le_bytes())
                .put(&c.counts[1].to_le_bytes())
                .put(&[c.tracker as u8])
                .done(),
            Self::Calibration(cal) => {
                let mut w = Writer::new(code::answer(code::CALIBRATION), tag);
                w.put(&[u8::from(cal.is_some())]);
                for a in cal.iter().flatten() {
                    w.put(&a.bias_q16.to_le_bytes())
                        .put(&a.noise_rms_q16.to_le_bytes());
                }
                w.done()
            }
            Self::Config {
                total,
                start,
                pairs,
            } => Writer::new(code::answer(code::GET_CONFIG), tag)
                .put(&[*total, *start])
                .pairs(pairs)
                .done(),
            Self::Staged { count, applied } => Writer::new(code::answer(code::SET_CONFIG), tag)
                .put(&[*count, u8::from(*applied)])
                .done(),
            Self::Done(c) => Writer::new(code::answer(*c), tag).done(),
            Self::Stopped { frames, lost } => Writer::new(code::answer(code::STREAM_STOP), tag)
                .put(&frames.to_le_bytes())
                .put(&lost.to_le_bytes())
                .done(),
            Self::Error(e) => Writer::new(code::ERROR, tag).put(&e.bytes()).done(),
        }
    }

    /// A response from a received frame: `(tag, response)`.
    ///
    /// # Errors
    /// [`FrameError`]: the header, an unknown code (stream frames included: decode those
    /// with [`StreamFrame::decode`]), a payload that does not match.
    pub fn decode(frame: &[u8]) -> Result<(u8, Self), FrameError> {
        let (c, tag, payload) = header(frame)?;
        let mut p = Reader(payload);
        let resp = match c {
            code::ERROR => {
                let [c, d] = p.take()?;
                Self::Error(ErrorCode::from_bytes(c, d).ok_or(FrameError::Payload)?)
            }
            x if x == code::answer(code::INFO) => {
                let firmware = p.take()?;
                let [protocol, source, invalid_key, tracking, streaming] = p.take()?;
                Self::Info(Info {
                    firmware,
                    protocol,
                    source: Source::from_u8(source).ok_or(FrameError::Payload)?,
                    invalid_key,
                    tracking: tracking != 0,
                    streaming: streaming != 0,
                    fs_hz: p.u32()?,
                })
            }
            x if x == code::answer(code::COUNTERS) => Self::Counters(Counters {
                samples: p.u64()?,
                lost: p.u64()?,
                restarts: p.u32()?,
                reports: p.u32()?,
                rejected_windows: p.u32()?,
                stream_frames: p.u32()?,
                stream_lost: p.u32()?,
                counts: [p.i64()?, p.i64()?],
                tracker: TrackerState::from_u8(p.u8()?).ok_or(FrameError::Payload)?,
            }),
            x if x == code::answer(code::CALIBRATION) => {
                if p.u8()? == 0 {
                    Self::Calibration(None)
                } else {
                    let mut axes = [AxisCalibration::default(); 3];
                    for a in &mut axes {
                        a.bias_q16 = p.i64()?;
                        a.noise_rms_q16 = p.u32()?;
                    }
                    Self::Calibration(Some(axes))
                }
            }
            x if x == code::answer(code::GET_CONFIG) => {
                let [total, start] = p.take()?;
                Self::Config {
                    total,
                    start,
                    pairs: p.pairs()?,
                }
            }
            x if x == code::answer(code::SET_CONFIG) => {
                let [count, applied] = p.take()?;
                Self::Staged {
                    count,
                    applied: applied != 0,
                }
            }
            x if x == code::answer(code::STREAM_STOP) => Self::Stopped {
                frames: p.u32()?,
                lost: p.u32()?,
            },
            x if [
                code::SAVE,
                code::DEFAULTS,
                code::RECALIBRATE,
                code::STREAM_START,
            ]
            .map(code::answer)
            .contains(&x) =>
            {
                Self::Done(x - code::RESPONSE)
            }
            other => return Err(FrameError::Code(other)),
        };
        p.end()?;
        Ok((tag, resp))
    }
}

/// A frame of raw ADC codes: `[x, y, z]` triples in the ADC's scan order, as sampled (before
/// the axis mapping), with a frame sequence number and the triples lost just before it.
///
/// Payload: `seq` (u16, wraps), `lost` (u16, triples missing between the previous frame and
/// this one, saturating), `n` (u8), then the codes: with [`code::STREAM`] two codes in three
/// bytes (`a` low 8 bits, `a` high 4 bits | `b` low 4 bits << 4, `b` high 8 bits; codes must be
/// below 4096), with [`code::STREAM_WIDE`] 16 bits each.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StreamFrame {
    /// Frame number, wrapping at 2^16.
    pub seq: u16,
    /// Sample triples lost between the previous frame and this one (saturating).
    pub lost: u16,
    /// The triples.
    pub triples: Vec<[u16; 3], STREAM_TRIPLES_PACKED>,
    /// Whether the codes are 16-bit (wide) rather than 12-bit packed.
    pub wide: bool,
}

impl StreamFrame {
    /// Triples per frame for an ADC of `adc_bits` bits.
    pub const fn capacity(adc_bits: u8) -> usize {
        if adc_bits <= 12 {
            STREAM_TRIPLES_PACKED
        } else {
            STREAM_TRIPLES_WIDE
        }
    }

    /// The frame's bytes. Packed codes are masked to 12 bits.
    pub fn encode(&self) -> Frame {
        let c = if self.wide {
            code::STREAM_WIDE
        } else {
            code::STREAM
        };
        let n = self
            .triples
            .len()
            .min(Self::capacity(if self.wide { 16 } else { 12 }));
        let mut w = Writer::new(c, 0);
        w.put(&self.seq.to_le_bytes())
            .put(&self.lost.to_le_bytes())
            .put(&[n as u8]);
        let codes = self.triples[..n].iter().flatten();
        if self.wide {
            for c in codes {
                w.put(&c.to_le_bytes());
            }
        } else {
            let mut pending: Option<u16> = None;
            for &c in codes {
                let c = c & 0x0FFF;
                match pending.take() {
                    None => pending = Some(c),
                    Some(a) => {
                        // `a`'s high nibble and `c`'s low nibble share a byte; their bits
                        // are disjoint, so the sum is their union.
                        w.put(&[a as u8, ((a >> 8) as u8) + ((c as u8) << 4), (c >> 4) as u8]);
                    }
                }
            }
            if let Some(a) = pending {
                w.put(&[a as u8, (a >> 8) as u8]);
            }
        }
        w.done()
    }

    /// A stream frame from received bytes.
    ///
    /// # Errors
    /// [`FrameError`]: the header, not a stream code, or a payload of the wrong length.
    pub fn decode(frame: &[u8]) -> Result<Self, FrameError> {
        let (c, _, payload) = header(frame)?;
        let wide = match c {
            code::STREAM => false,
            code::STREAM_WIDE => true,
            other => return Err(FrameError::Code(other)),
        };
        let mut p = Reader(payload);
        let seq = u16::from_le_bytes(p.take()?);
        let lost = u16::from_le_bytes(p.take()?);
        let n = usize::from(p.u8()?);
        if n > Self::capacity(if wide { 16 } else { 12 }) {
            return Err(FrameError::Payload);
        }
        let mut codes = [0u16; 3 * STREAM_TRIPLES_PACKED];
        if wide {
            for c in &mut codes[..3 * n] {
                *c = u16::from_le_bytes(p.take()?);
            }
        } else {
            for pair in codes[..3 * n].chunks_mut(2) {
                if let [a, b] = pair {
                    let [x, y, z] = p.take()?;
                    // Disjoint bits: the sums are unions.
                    *a = u16::from(x) + (u16::from(y & 0x0F) << 8);
                    *b = u16::from(y >> 4) + (u16::from(z) << 4);
                } else {
                    let [x, y] = p.take()?;
                    pair[0] = u16::from(x) + (u16::from(y & 0x0F) << 8);
                }
            }
        }
        p.end()?;
        let mut triples = Vec::new();
        for t in codes[..3 * n].chunks_exact(3) {
            triples
                .push([t[0], t[1], t[2]])
                .map_err(|_| FrameError::Payload)?;
        }
        Ok(Self {
            seq,
            lost,
            triples,
            wide,
        })
    }
}
