//! A request from the bus to the device (`imu_app::control`), over a stand-in port: answered
//! with its tag, malformed frames answered with their error, effects carried out on the
//! tracker, status, mapping and stream; saves answered when the flash is done; stream frames
//! leave the queue only when the port takes them.

use std::collections::VecDeque;

use imu_app::commands::Commands;
use imu_app::control::{self, Port, Resources};
use imu_app::stream::Stream;
use imu_app::Status;
use imu_core::profile::{AxisMap, Key, Profile};
use imu_core::protocol::{
    code, ErrorCode, Frame, Request, Response, Source, StreamFrame, TrackerState, FRAME_LEN,
};
use imu_core::{Phase, Tracker};
use rtic_core::Exclusive;

#[derive(Default)]
struct FakePort {
    inbox: VecDeque<(Frame, usize)>,
    sent: Vec<Frame>,
    busy: bool,
    streamed: Vec<StreamFrame>,
    reports: u32,
}

impl Port for FakePort {
    fn take_request(&mut self) -> Option<(Frame, usize)> {
        self.inbox.pop_front()
    }
    fn respond(&mut self, frame: Frame) {
        self.sent.push(frame);
    }
    fn push_stream_frame(&mut self, frame: &StreamFrame) -> bool {
        if self.busy {
            return false;
        }
        self.streamed.push(frame.clone());
        true
    }
    fn reports_sent(&self) -> u32 {
        self.reports
    }
    fn motion(&self) -> [i64; 2] {
        [-i64::from(self.reports), 2 * i64::from(self.reports)]
    }
}

struct Device {
    port: FakePort,
    commands: Commands,
    tracker: Tracker,
    status: Status,
    route: AxisMap,
    stream: Stream,
}

impl Device {
    fn new() -> Self {
        let p = Profile::default();
        Self {
            port: FakePort::default(),
            commands: Commands::new(p, Source::Defaults, None, 96_000_000),
            tracker: Tracker::new(&p.config).expect("valid"),
            status: Status::new(20),
            route: p.map,
            stream: Stream::default(),
        }
    }

    /// Queues `req` with `tag` and serves it; returns the effect and the answers sent.
    fn ask(&mut self, tag: u8, req: &Request) -> (imu_app::commands::Effect, Vec<(u8, Response)>) {
        let frame = req.encode(tag);
        self.port.inbox.push_back((frame, FRAME_LEN));
        self.serve()
    }

    fn serve(&mut self) -> (imu_app::commands::Effect, Vec<(u8, Response)>) {
        let mut r = Resources {
            mouse: &mut Exclusive(&mut self.port),
            commands: &mut Exclusive(&mut self.commands),
            tracker: &mut Exclusive(&mut self.tracker),
            status: &mut Exclusive(&mut self.status),
            route: &mut Exclusive(&mut self.route),
            stream: &mut Exclusive(&mut self.stream),
        };
        let effect = control::serve(&mut r, || 7);
        (effect, self.answers())
    }

    fn answers(&mut self) -> Vec<(u8, Response)> {
        self.port
            .sent
            .drain(..)
            .map(|f| Response::decode(&f).expect("decodes"))
            .collect()
    }

    /// Calibrates the tracker on a still block.
    fn calibrate(&mut self) {
        let still = [[2048u16, 2048, 2457]; 3];
        for _ in 0..1000 {
            if let Some(e) = self.tracker.feed(&still) {
                self.status.record(e, 0);
            }
        }
        assert_eq!(self.tracker.phase(), Phase::Tracking);
    }
}

fn set(pairs: &[(Key, f64)]) -> Request {
    Request::SetConfig {
        commit: true,
        pairs: heapless::Vec::from_slice(pairs).expect("six"),
    }
}

#[test]
fn nothing_waiting_does_nothing() {
    let mut d = Device::new();
    let (effect, answers) = d.serve();
    assert_eq!(effect, Default::default());
    assert!(answers.is_empty());
}

#[test]
fn a_request_is_answered_with_its_tag_and_the_devices_counts() {
    let mut d = Device::new();
    d.port.reports = 42;
    d.stream.start(12);
    d.stream.push(&[[1, 2, 3]], 5);
    d.tracker.lost(4);
    let (_, answers) = d.ask(9, &Request::Counters);
    let [(9, Response::Counters(c))] = answers.as_slice() else {
        panic!("{answers:?}")
    };
    assert_eq!((c.reports, c.restarts, c.lost), (42, 7, 4));
    assert_eq!((c.stream_frames, c.stream_lost), (0, 5));
    // The port's cursor counts, and the tracker's state (calibrating: nothing fed yet).
    assert_eq!(
        (c.counts, c.tracker),
        ([-42, 84], TrackerState::Calibrating)
    );
    let info = |d: &mut Device| match d.ask(1, &Request::Info).1.pop() {
        Some((1, Response::Info(i))) => i,
        other => panic!("{other:?}"),
    };
    let i = info(&mut d);
    assert!(!i.tracking && i.streaming);
    d.calibrate();
    assert!(info(&mut d).tracking);
    match d.ask(3, &Request::Calibration).1.pop() {
        Some((3, Response::Calibration(Some(axes)))) => assert_eq!(axes[0].bias_q16, 2048 << 16),
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_frame_that_does_not_decode_is_answered_with_its_error() {
    let mut d = Device::new();
    let mut frame = Request::Info.encode(5);
    frame[0] = 9;
    d.port.inbox.push_back((frame, FRAME_LEN));
    let (effect, answers) = d.serve();
    assert_eq!(effect, Default::default());
    assert_eq!(answers, [(5, Response::Error(ErrorCode::Version(9)))]);
    // A frame cut to its first two bytes: no tag to echo, 0.
    d.port.inbox.push_back((Request::Info.encode(5), 2));
    assert_eq!(d.serve().1, [(0, Response::Error(ErrorCode::Length))]);
}

#[test]
fn an_applied_set_reaches_the_tracker_the_status_and_the_mapping() {
    let mut d = Device::new();
    d.calibrate();
    assert!(d.status.calibration().is_some());
    let (effect, answers) = d.ask(
        1,
        &set(&[
            (Key::CountsPerInch, 1600.0),
            (Key::XAxis, 2.0),
            (Key::YSign, -1.0),
        ]),
    );
    assert!(effect.apply);
    assert!(matches!(
        answers[0].1,
        Response::Staged { applied: true, .. }
    ));
    assert_eq!(
        d.tracker.phase(),
        Phase::Calibrating,
        "reconfigured: recalibrates"
    );
    assert_eq!(
        d.status.calibration(),
        None,
        "a fresh status for the new scale"
    );
    assert_eq!(
        d.route,
        AxisMap {
            x_axis: 2,
            x_flip: false,
            y_axis: 1,
            y_flip: true
        }
    );
    // A new configuration stops a running stream (its rate or width may have changed).
    d.ask(3, &Request::StreamStart);
    assert!(d.stream.on());
    d.ask(4, &set(&[(Key::CountsPerInch, 800.0)]));
    assert!(!d.stream.on());
    // A refused set changes none of them.
    d.ask(5, &Request::StreamStart);
    d.calibrate();
    let (effect, answers) = d.ask(2, &set(&[(Key::AdcBits, 1.0)]));
    assert_eq!(effect, Default::default());
    assert_eq!(
        answers[0].1,
        Response::Error(ErrorCode::Unsupported(Key::AdcBits))
    );
    assert_eq!(d.tracker.phase(), Phase::Tracking);
    assert!(d.status.calibration().is_some());
    assert!(d.stream.on());
}

#[test]
fn recalibrate_and_the_stream_are_carried_out() {
    let mut d = Device::new();
    d.calibrate();
    let (_, answers) = d.ask(3, &Request::Recalibrate);
    assert_eq!(answers, [(3, Response::Done(code::RECALIBRATE))]);
    assert_eq!(d.tracker.phase(), Phase::Calibrating);

    // The board's 12-bit codes stream in narrow frames (wide ones are `stream.rs`'s test).
    d.ask(5, &Request::StreamStart);
    assert!(d.stream.on());
    d.stream.push(&[[4095, 1, 2]; 3], 0);
    assert!(!d.stream.frame().expect("queued").wide, "12-bit ADC");
    let (_, answers) = d.ask(6, &Request::StreamStop);
    assert!(!d.stream.on());
    assert_eq!(answers, [(6, Response::Stopped { frames: 0, lost: 0 })]);
}

#[test]
fn a_save_is_answered_when_the_flash_is_done() {
    let mut d = Device::new();
    let (effect, answers) = d.ask(8, &Request::Save);
    assert!(effect.save && answers.is_empty());
    control::answer_save(
        true,
        &mut Exclusive(&mut d.commands),
        &mut Exclusive(&mut d.port),
    );
    assert_eq!(d.answers(), [(8, Response::Done(code::SAVE))]);
    d.ask(9, &Request::Save);
    control::answer_save(
        false,
        &mut Exclusive(&mut d.commands),
        &mut Exclusive(&mut d.port),
    );
    assert_eq!(d.answers(), [(9, Response::Error(ErrorCode::Storage))]);
    // Nothing asked: nothing answered.
    control::answer_save(
        true,
        &mut Exclusive(&mut d.commands),
        &mut Exclusive(&mut d.port),
    );
    assert!(d.answers().is_empty());
}

#[test]
fn stream_frames_leave_the_queue_only_when_the_port_takes_them() {
    let mut d = Device::new();
    d.stream.start(12);
    d.stream.push(&[[1, 2, 3]; 5], 0);
    d.port.busy = true;
    control::push_stream(&mut Exclusive(&mut d.port), &mut Exclusive(&mut d.stream));
    assert!(d.port.streamed.is_empty());
    assert_eq!(d.stream.frame().map(|f| f.triples.len()), Some(5));
    d.port.busy = false;
    control::push_stream(&mut Exclusive(&mut d.port), &mut Exclusive(&mut d.stream));
    assert_eq!(d.port.streamed.len(), 1);
    assert_eq!(d.stream.frame(), None);
    // Nothing queued: nothing pushed.
    control::push_stream(&mut Exclusive(&mut d.port), &mut Exclusive(&mut d.stream));
    assert_eq!(d.port.streamed.len(), 1);
}
