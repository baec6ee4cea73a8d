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
use imu_core::protocol::{Request, Response};
use imu_core::{ConfigError, Tracker};
use rtic_core::Mutex;
use usb_device::bus::UsbBus;

use crate::commands::{Commands, Effect, View};
use crate::mouse::Mouse;
use crate::status::Status;
use crate::stream::Stream;

/// What the device knows for the read-only requests: the tracker, the calibration, the
/// stream, and the board's `reports` sent and sampling `restarts`.
pub fn view(
    tracker: &mut impl Mutex<T = Tracker>,
    status: &mut impl Mutex<T = Status>,
    stream: &mut impl Mutex<T = Stream>,
    reports: u32,
    restarts: u32,
) -> View {
    let (tracking, counters) = tracker.lock(|t| (View::tracking(t.phase()), t.counters()));
    let (on, (frames, lost)) = stream.lock(|s| (s.on(), s.totals()));
    View {
        tracking,
        counters,
        calibration: status.lock(|s| s.calibration()),
        restarts,
        reports,
        stream: (on, frames, lost),
    }
}

/// Takes the waiting request, if any, decides it and queues its response (a save answers
/// later, through [`answer_save`]). Returns what the caller must carry out
/// ([`carry_out`], then the retime and the save).
pub fn serve<'a, B: UsbBus + 'a>(
    mouse: &mut impl Mutex<T = Mouse<'a, B>>,
    commands: &mut impl Mutex<T = Commands>,
    view: impl FnOnce() -> View,
) -> Effect {
    let Some((frame, len)) = mouse.lock(Mouse::take_request) else {
        return Effect::default();
    };
    let (tag, reply) = match Request::decode(&frame[..len]) {
        Ok((tag, req)) => {
            let v = view();
            (tag, commands.lock(|c| c.handle(tag, req, &v)))
        }
        Err(e) => {
            let tag = frame.get(2).copied().unwrap_or(0);
            let response = Response::Error(e.response());
            return answer(mouse, tag, &response);
        }
    };
    if let Some(r) = &reply.response {
        answer(mouse, tag, r);
    }
    reply.effect
}

fn answer<'a, B: UsbBus + 'a>(
    mouse: &mut impl Mutex<T = Mouse<'a, B>>,
    tag: u8,
    response: &Response,
) -> Effect {
    let frame = response.encode(tag);
    mouse.lock(|m| m.respond(frame));
    Effect::default()
}

/// The effect's part that needs no board: the running profile to the tracker and the axis
/// mapping, a recalibration, the stream started or stopped.
///
/// # Errors
/// The tracker's refusal of the running configuration (it was validated by
/// [`Commands`] with the same rules, so this is not expected; nothing changed then).
pub fn carry_out(
    effect: &Effect,
    commands: &mut impl Mutex<T = Commands>,
    tracker: &mut impl Mutex<T = Tracker>,
    route: &mut impl Mutex<T = AxisMap>,
    stream: &mut impl Mutex<T = Stream>,
) -> Result<(), ConfigError> {
    let profile = commands.lock(|c| *c.running());
    if effect.apply {
        tracker.lock(|t| t.reconfigure(&profile.config))?;
        route.lock(|r| *r = profile.map);
    }
    if effect.recalibrate {
        tracker.lock(Tracker::recalibrate);
    }
    match effect.stream {
        Some(true) => stream.lock(|s| s.start(profile.config.adc_bits)),
        Some(false) => {
            stream.lock(Stream::stop);
        }
        None => {}
    }
    Ok(())
}

/// The save asked for is done (`ok`) or failed: its response goes out.
pub fn answer_save<'a, B: UsbBus + 'a>(
    ok: bool,
    commands: &mut impl Mutex<T = Commands>,
    mouse: &mut impl Mutex<T = Mouse<'a, B>>,
) {
    if let Some((tag, response)) = commands.lock(|c| c.saved(ok)) {
        answer(mouse, tag, &response);
    }
}
