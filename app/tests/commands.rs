//! The configuration requests decided (`imu_app::commands`): each answer, each effect, and a
//! refused configuration that changes nothing.

use imu_app::commands::{Commands, Effect, View};
use imu_app::identity::FIRMWARE_VERSION;
use imu_core::profile::{Key, Profile};
use imu_core::protocol::{
    code, ErrorCode, Info, Request, Response, Source, TrackerState, PAIRS_MAX,
};
use imu_core::{Calibration, Counters};

const CLOCK: u32 = 96_000_000;

fn commands() -> Commands {
    Commands::new(Profile::default(), Source::Stored, None, CLOCK)
}

fn set(pairs: &[(Key, f64)], commit: bool) -> Request {
    Request::SetConfig {
        commit,
        pairs: heapless::Vec::from_slice(pairs).expect("at most six"),
    }
}

fn response(c: &mut Commands, req: Request) -> Response {
    c.handle(1, req, &View::default())
        .response
        .expect("answered now")
}

#[test]
fn info_counters_and_calibration_report_the_view() {
    let cal = Calibration {
        bias_q16: 2048 << 16,
        noise_rms_q16: u64::from(u32::MAX) + 5,
        samples: 3000,
        tick_var_q32: 0,
        long_run_var_q32: 0,
        tick_lags_q32: [0; 3],
    };
    let view = View {
        tracking: true,
        counters: Counters {
            samples: 10,
            lost: 2,
            rejected_windows: 3,
            ..Counters::default()
        },
        calibration: Some([cal; 3]),
        restarts: 4,
        reports: 5,
        stream: (true, 6, 7),
        counts: [-11, 12],
        tracker: TrackerState::Lifted,
    };
    let mut c = Commands::new(
        Profile::default(),
        Source::Invalid,
        Some(Key::AdcBits),
        CLOCK,
    );
    let r = |c: &mut Commands, req| c.handle(9, req, &view).response.expect("now");
    assert_eq!(
        r(&mut c, Request::Info),
        Response::Info(Info {
            firmware: FIRMWARE_VERSION,
            protocol: imu_core::protocol::VERSION,
            source: Source::Invalid,
            invalid_key: Key::AdcBits as u8,
            fs_hz: 3000,
            tracking: true,
            streaming: true,
        })
    );
    let Response::Counters(k) = r(&mut c, Request::Counters) else {
        panic!("counters")
    };
    assert_eq!(
        (k.samples, k.lost, k.restarts, k.reports, k.rejected_windows),
        (10, 2, 4, 5, 3)
    );
    assert_eq!((k.stream_frames, k.stream_lost), (6, 7));
    assert_eq!((k.counts, k.tracker), ([-11, 12], TrackerState::Lifted));
    let Response::Calibration(Some(axes)) = r(&mut c, Request::Calibration) else {
        panic!("calibration")
    };
    assert_eq!(axes[2].bias_q16, 2048 << 16);
    assert_eq!(axes[2].noise_rms_q16, u32::MAX, "saturates, never wraps");
    assert_eq!(
        response(&mut commands(), Request::Calibration),
        Response::Calibration(None)
    );
}

#[test]
fn get_config_pages_through_every_key() {
    let mut c = commands();
    let mut got = Vec::new();
    let mut start = 0u8;
    loop {
        let Response::Config {
            total,
            start: s,
            pairs,
        } = response(&mut c, Request::GetConfig { start })
        else {
            panic!("config")
        };
        assert_eq!((total as usize, s), (Key::ALL.len(), start));
        assert!(pairs.len() <= PAIRS_MAX);
        if pairs.is_empty() {
            break;
        }
        start += pairs.len() as u8;
        got.extend(pairs);
    }
    assert_eq!(got.len(), Key::ALL.len());
    for (k, v) in got {
        let want = Profile::default().get(k);
        assert!(v == want || (v.is_nan() && want.is_nan()), "{k}");
    }
    // Past the end: an empty page, not an error.
    let Response::Config { pairs, .. } = response(&mut c, Request::GetConfig { start: 255 }) else {
        panic!("config")
    };
    assert!(pairs.is_empty());
}

#[test]
fn a_set_is_staged_over_frames_and_applied_as_a_whole() {
    let mut c = commands();
    let reply = c.handle(
        1,
        set(&[(Key::CountsPerInch, 1600.0)], false),
        &View::default(),
    );
    assert_eq!(
        reply.response,
        Some(Response::Staged {
            count: 1,
            applied: false
        })
    );
    assert_eq!(reply.effect, Effect::default());
    assert_eq!(c.running().config.counts_per_inch, 800, "not yet");
    let reply = c.handle(2, set(&[(Key::FsHz, 4000.0)], true), &View::default());
    assert_eq!(
        reply.response,
        Some(Response::Staged {
            count: 2,
            applied: true
        })
    );
    assert_eq!(
        reply.effect,
        Effect {
            apply: true,
            retime: true,
            ..Effect::default()
        }
    );
    assert_eq!(c.running().config.counts_per_inch, 1600);
    assert_eq!(c.running().config.fs_hz, 4000);
    assert_eq!(c.source(), Source::Changed);
    // The same rate again: applied without a retime.
    let reply = c.handle(3, set(&[(Key::XSign, -1.0)], true), &View::default());
    assert!(reply.effect.apply && !reply.effect.retime);
    assert!(c.running().map.x_flip);
}

#[test]
fn a_refused_set_names_the_key_and_changes_nothing() {
    let cases: [(&[(Key, f64)], ErrorCode); 11] = [
        (&[(Key::AdcBits, 12.5)], ErrorCode::Value(Key::AdcBits)),
        // The board's ADC has 12 bits: any other resolution is the board's refusal, never a
        // scale the core would then blame.
        (&[(Key::AdcBits, 1.0)], ErrorCode::Unsupported(Key::AdcBits)),
        (&[(Key::AdcBits, 8.0)], ErrorCode::Unsupported(Key::AdcBits)),
        (
            &[(Key::AdcBits, 16.0)],
            ErrorCode::Unsupported(Key::AdcBits),
        ),
        // The rate is named before the resolution.
        (
            &[(Key::AdcBits, 16.0), (Key::FsHz, 7.0)],
            ErrorCode::Unsupported(Key::FsHz),
        ),
        (
            &[(Key::XAxis, 1.0), (Key::YAxis, 1.0)],
            ErrorCode::Invalid(Key::YAxis),
        ),
        // Only x_axis changed, onto y_axis's sensor axis: x_axis is named.
        (&[(Key::XAxis, 1.0)], ErrorCode::Invalid(Key::XAxis)),
        (&[(Key::YAxis, 0.0)], ErrorCode::Invalid(Key::YAxis)),
        // Valid for the core (1..=100 kHz) but not a rate the 96 MHz trigger makes.
        (&[(Key::FsHz, 7000.0)], ErrorCode::Unsupported(Key::FsHz)),
        (&[(Key::FsHz, 50.0)], ErrorCode::Unsupported(Key::FsHz)),
        // Too low for the device and for a 1 s calibration window: the rate is named, not the
        // window it makes too short.
        (&[(Key::FsHz, 7.0)], ErrorCode::Unsupported(Key::FsHz)),
    ];
    for (pairs, want) in cases {
        let mut c = commands();
        // Something staged before: refused along with the rest.
        c.handle(
            1,
            set(&[(Key::CountsPerInch, 1600.0)], false),
            &View::default(),
        );
        let before = *c.running();
        let reply = c.handle(2, set(pairs, true), &View::default());
        assert_eq!(reply.response, Some(Response::Error(want)), "{pairs:?}");
        assert_eq!(reply.effect, Effect::default());
        assert_eq!(*c.running(), before);
        assert_eq!(c.source(), Source::Stored);
        // The staged value went with the refusal: a commit of nothing changes nothing.
        let reply = c.handle(3, set(&[], true), &View::default());
        assert_eq!(c.running().config.counts_per_inch, 800, "{reply:?}");
    }
}

#[test]
fn a_save_answers_when_the_flash_is_done_and_is_busy_meanwhile() {
    let mut c = commands();
    c.handle(
        1,
        set(&[(Key::CountsPerInch, 1600.0)], true),
        &View::default(),
    );
    let reply = c.handle(7, Request::Save, &View::default());
    assert_eq!(reply.response, None);
    assert_eq!(
        reply.effect,
        Effect {
            save: true,
            ..Effect::default()
        }
    );
    assert_eq!(
        response(&mut c, Request::Info),
        Response::Error(ErrorCode::Busy)
    );
    assert_eq!(c.saved(true), Some((7, Response::Done(code::SAVE))));
    assert_eq!(c.source(), Source::Stored);
    assert_eq!(c.saved(true), None, "nothing asked");
    assert!(
        matches!(response(&mut c, Request::Info), Response::Info(_)),
        "no longer busy"
    );
    // A failed save says so, and the profile still runs.
    c.handle(8, Request::Save, &View::default());
    assert_eq!(
        c.saved(false),
        Some((8, Response::Error(ErrorCode::Storage)))
    );
    assert_eq!(c.running().config.counts_per_inch, 1600);
}

#[test]
fn defaults_run_and_are_kept() {
    let mut c = Commands::new(Profile::default(), Source::Corrupt, None, CLOCK);
    c.handle(1, set(&[(Key::FsHz, 6000.0)], true), &View::default());
    let reply = c.handle(2, Request::Defaults, &View::default());
    assert_eq!(reply.response, None);
    assert_eq!(
        reply.effect,
        Effect {
            apply: true,
            retime: true,
            save: true,
            ..Effect::default()
        }
    );
    assert_eq!(*c.running(), Profile::default());
    assert_eq!(c.saved(true), Some((2, Response::Done(code::DEFAULTS))));
    assert_eq!(c.source(), Source::Stored);
}

#[test]
fn recalibrate_and_the_stream_are_effects() {
    let mut c = commands();
    let r = c.handle(1, Request::Recalibrate, &View::default());
    assert_eq!(r.response, Some(Response::Done(code::RECALIBRATE)));
    assert!(r.effect.recalibrate);
    let r = c.handle(1, Request::StreamStart, &View::default());
    assert_eq!(r.response, Some(Response::Done(code::STREAM_START)));
    assert_eq!(r.effect.stream, Some(true));
    let view = View {
        stream: (true, 40, 3),
        ..View::default()
    };
    let r = c.handle(1, Request::StreamStop, &view);
    assert_eq!(
        r.response,
        Some(Response::Stopped {
            frames: 40,
            lost: 3
        })
    );
    assert_eq!(r.effect.stream, Some(false));
}
