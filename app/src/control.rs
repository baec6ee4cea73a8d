//! A configuration request from the bus to the device: taken from the mouse's inbox,
//! decoded, decided by [`Commands`], answered, and its effect carried out on the tracker, the
//! axis mapping and the stream. The board (or the twin) adds what only it can do: retime the
//! sampling and write the flash.
//!
//! # Design
//! Shared resources come in as `rtic_core::Mutex`es, as in [`crate::housekeeping`], so the
//! firmware's USB task and the twin run the same sequence; each lock is short and none is
//! nested. A frame that does not decode is answered with the error it earned
//! (`FrameError::response`), never dropped in silence.

use imu_core::profile::AxisMap;
use imu_core::protocol::{Frame, Request, Response, StreamFrame, TrackerState};
use imu_core::{Phase, Tracker};
use rtic_core::Mutex;
use usb_device::bus::UsbBus;

use crate::commands::{Commands, Effect, View};
use crate::device::wake_motion_lsb;
use crate::mouse::Mouse;
use crate::status::Status;
use crate::stream::Stream;

/// The configuration interface's frames in and out: what [`serve`] needs of the USB device
/// ([`Mouse`] on the board and the twin; a stand-in in the tests).
pub trait Port {
    /// The request received, if any, and its length [bytes].
    fn take_request(&mut self) -> Option<(Frame, usize)>;
    /// Queues a response (dropped if the port's queue is full, which a host that waits for
    /// each answer never causes).
    fn respond(&mut self, frame: Frame);
    /// Pushes a stream frame if the interface is free; whether it went.
    fn push_stream_frame(&mut self, frame: &StreamFrame) -> bool;
    /// Mouse reports sent so far.
    fn reports_sent(&self) -> u32;
    /// The cursor's motion so far [counts] (right, down; [`imu_core::Reporter::added`]).
    fn motion(&self) -> [i64; 2];
}

impl<B: UsbBus> Port for Mouse<'_, B> {
    fn take_request(&mut self) -> Option<(Frame, usize)> {
        Mouse::take_request(self)
    }
    fn respond(&mut self, frame: Frame) {
        Mouse::respond(self, frame);
    }
    fn push_stream_frame(&mut self, frame: &StreamFrame) -> bool {
        Mouse::push_stream_frame(self, frame)
    }
    fn reports_sent(&self) -> u32 {
        self.reports().reporter().reports()
    }
    fn motion(&self) -> [i64; 2] {
        let (x, y) = self.reports().reporter().added();
        [x, y]
    }
}

/// What the device knows for the read-only requests: the tracker, the calibration, the
/// stream, the board's `reports` sent and cursor `counts`, and sampling `restarts`.
pub fn view(
    tracker: &mut impl Mutex<T = Tracker>,
    status: &mut impl Mutex<T = Status>,
    stream: &mut impl Mutex<T = Stream>,
    (reports, counts): (u32, [i64; 2]),
    restarts: u32,
) -> View {
    let (tracking, counters, state) = tracker.lock(|t| {
        let tracking = t.phase() == Phase::Tracking;
        (tracking, t.counters(), TrackerState::of(t))
    });
    let (on, (frames, lost)) = stream.lock(|s| (s.on(), s.totals()));
    View {
        tracking,
        counters,
        calibration: status.lock(|s| s.calibration()),
        restarts,
        reports,
        stream: (on, frames, lost),
        counts,
        tracker: state,
    }
}

/// The resources a request may read or change.
pub struct Resources<'r, M, C, T, S, R, Q> {
    /// The USB device (a [`Port`]).
    pub mouse: &'r mut M,
    /// The configuration interface's state.
    pub commands: &'r mut C,
    /// The tracker.
    pub tracker: &'r mut T,
    /// The calibration outcome and suspend state.
    pub status: &'r mut S,
    /// The axis mapping of the sample path.
    pub route: &'r mut R,
    /// The raw stream.
    pub stream: &'r mut Q,
}

/// Takes the waiting request, if any, decides it and queues its response (a save answers
/// later, through [`answer_save`]), and carries out what needs no board ([`carry_out`]).
/// `restarts` gives the board's sampling restarts for the counters. Returns the effect, of
/// which the caller still owes the retime and the save.
pub fn serve<'r, P, M, C, T, S, R, Q>(
    r: &mut Resources<'r, M, C, T, S, R, Q>,
    restarts: impl FnOnce() -> u32,
) -> Effect
where
    P: Port,
    M: Mutex<T = P>,
    C: Mutex<T = Commands>,
    T: Mutex<T = Tracker>,
    S: Mutex<T = Status>,
    R: Mutex<T = AxisMap>,
    Q: Mutex<T = Stream>,
{
    let Some((frame, len)) = r.mouse.lock(P::take_request) else {
        return Effect::default();
    };
    let mouse = &mut *r.mouse;
    let bytes = &frame[..len.min(frame.len())];
    let (tag, reply) = match Request::decode(bytes) {
        Ok((tag, req)) => {
            let sent = mouse.lock(|m| (m.reports_sent(), m.motion()));
            let v = view(r.tracker, r.status, r.stream, sent, restarts());
            (tag, r.commands.lock(|c| c.handle(tag, req, &v)))
        }
        Err(e) => {
            let tag = bytes.get(2).copied().unwrap_or(0);
            let response = Response::Error(e.response());
            return answer(mouse, tag, &response);
        }
    };
    if let Some(response) = &reply.response {
        answer(mouse, tag, response);
    }
    carry_out(&reply.effect, r);
    reply.effect
}

fn answer<P: Port>(mouse: &mut impl Mutex<T = P>, tag: u8, response: &Response) -> Effect {
    let frame = response.encode(tag);
    mouse.lock(|m| m.respond(frame));
    Effect::default()
}

/// The effect's part that needs no board: the running profile to the tracker (a new
/// configuration recalibrates; the wake-up threshold follows the scale) and the axis
/// mapping, a recalibration, the stream started or stopped. A new configuration stops a
/// running stream: its rate or code width may have changed, and a recording must not change
/// meaning half-way (the host sees the stream stop and says so).
fn carry_out<'r, M, C, T, S, R, Q>(effect: &Effect, r: &mut Resources<'r, M, C, T, S, R, Q>)
where
    C: Mutex<T = Commands>,
    T: Mutex<T = Tracker>,
    S: Mutex<T = Status>,
    R: Mutex<T = AxisMap>,
    Q: Mutex<T = Stream>,
{
    let profile = r.commands.lock(|c| *c.running());
    if effect.apply {
        // Validated by `Commands` with the tracker's own rules: a refusal cannot happen, and
        // would leave the tracker as it was.
        let _ = r.tracker.lock(|t| t.reconfigure(&profile.config));
        let wake = wake_motion_lsb(profile.config.m_s2_per_lsb);
        r.status.lock(|s| *s = Status::new(wake));
        r.route.lock(|m| *m = profile.map);
        r.stream.lock(Stream::stop);
    }
    if effect.recalibrate {
        r.tracker.lock(Tracker::recalibrate);
    }
    match effect.stream {
        Some(true) => r.stream.lock(|s| s.start(profile.config.adc_bits)),
        Some(false) => {
            r.stream.lock(Stream::stop);
        }
        None => {}
    }
}

/// Pushes the raw stream's next frame if the configuration interface is free.
pub fn push_stream<P: Port>(mouse: &mut impl Mutex<T = P>, stream: &mut impl Mutex<T = Stream>) {
    let Some(frame) = stream.lock(|s| s.frame()) else {
        return;
    };
    if mouse.lock(|m| m.push_stream_frame(&frame)) {
        stream.lock(|s| s.sent(&frame));
    }
}

/// The save asked for is done (`ok`) or failed: its response goes out.
pub fn answer_save<P: Port>(
    ok: bool,
    commands: &mut impl Mutex<T = Commands>,
    mouse: &mut impl Mutex<T = P>,
) {
    if let Some((tag, response)) = commands.lock(|c| c.saved(ok)) {
        answer(mouse, tag, &response);
    }
}
