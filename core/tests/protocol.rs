//! The configuration protocol and the stored profile record: every request and response
//! through its bytes and back, every error, malformed, truncated and foreign frames.

use imu_core::bench::testsignal::Trace;
use imu_core::profile::{AxisMap, Key, Kind, Profile, ProfileError, RecordError, RECORD_LEN};
use imu_core::protocol::{
    code, header, AxisCalibration, Counters, ErrorCode, FrameError, Info, Request, Response,
    Source, StreamFrame, TrackerState, FRAME_LEN, PAIRS_MAX, VERSION,
};
use imu_core::{Config, ConfigError, DriftError, Tracker};

fn pairs(p: &[(Key, f64)]) -> heapless::Vec<(Key, f64), PAIRS_MAX> {
    heapless::Vec::from_slice(p).expect("at most six pairs")
}

fn requests() -> Vec<Request> {
    vec![
        Request::Info,
        Request::Counters,
        Request::Calibration,
        Request::GetConfig { start: 7 },
        Request::SetConfig {
            commit: true,
            pairs: pairs(&[
                (Key::CountsPerInch, 1600.0),
                (Key::LowpassFcHz, f64::NAN),
                (Key::XSign, -1.0),
                (Key::FsHz, 4000.0),
                (Key::Drift, 0.0),
                (Key::HoldS, 0.012),
            ]),
        },
        Request::SetConfig {
            commit: false,
            pairs: pairs(&[]),
        },
        Request::Save,
        Request::Defaults,
        Request::Recalibrate,
        Request::StreamStart,
        Request::StreamStop,
    ]
}

/// Equality that treats NaN values (an "off" option) as equal.
fn same_request(a: &Request, b: &Request) -> bool {
    format!("{a:?}") == format!("{b:?}")
}

#[test]
fn every_request_round_trips_with_its_tag() {
    for (tag, req) in requests().into_iter().enumerate() {
        let frame = req.encode(tag as u8);
        assert_eq!(frame[0], VERSION);
        assert_eq!(frame[1], req.code());
        let (t, back) = Request::decode(&frame).expect("decodes");
        assert_eq!(t, tag as u8);
        assert!(same_request(&req, &back), "{req:?} came back as {back:?}");
    }
}

fn responses() -> Vec<Response> {
    let cal = AxisCalibration {
        bias_q16: 2048 << 16,
        noise_rms_q16: 70_000,
    };
    let mut errors: Vec<Response> = [
        ErrorCode::Version(9),
        ErrorCode::Command(0x55),
        ErrorCode::Length,
        ErrorCode::UnknownKey(200),
        ErrorCode::Value(Key::XAxis),
        ErrorCode::Invalid(Key::CountsPerInch),
        ErrorCode::Unsupported(Key::FsHz),
        ErrorCode::Storage,
        ErrorCode::Busy,
    ]
    .into_iter()
    .map(Response::Error)
    .collect();
    let mut all = vec![
        Response::Info(Info {
            firmware: [0, 3, 1],
            protocol: VERSION,
            source: Source::Invalid,
            invalid_key: Key::CountsPerInch as u8,
            fs_hz: 20_000,
            tracking: true,
            streaming: false,
        }),
        Response::Counters(Counters {
            samples: u64::MAX - 1,
            lost: 12,
            restarts: 3,
            reports: 99,
            rejected_windows: 4,
            stream_frames: 5,
            stream_lost: 6,
            counts: [i64::MIN, -7],
            tracker: TrackerState::Held,
        }),
        Response::Calibration(None),
        Response::Calibration(Some([cal, cal, AxisCalibration::default()])),
        Response::Config {
            total: Key::ALL.len() as u8,
            start: 24,
            pairs: pairs(&[(Key::XAxis, 2.0), (Key::BiasTauS, f64::NAN)]),
        },
        Response::Staged {
            count: 13,
            applied: false,
        },
        Response::Done(code::SAVE),
        Response::Done(code::DEFAULTS),
        Response::Done(code::RECALIBRATE),
        Response::Done(code::STREAM_START),
        Response::Stopped {
            frames: 1 << 20,
            lost: 7,
        },
    ];
    all.append(&mut errors);
    all
}

#[test]
fn every_response_and_error_round_trips() {
    for (tag, resp) in responses().into_iter().enumerate() {
        let frame = resp.encode(tag as u8);
        let (t, back) = Response::decode(&frame).expect("decodes");
        assert_eq!(t, tag as u8);
        assert_eq!(format!("{resp:?}"), format!("{back:?}"));
    }
}

#[test]
fn foreign_versions_and_codes_are_named() {
    // The version before (protocol 1 had no cursor counts or tracker state in its
    // counters) and the one after are both named.
    for v in [VERSION - 1, VERSION + 1] {
        let mut f = Request::Info.encode(1);
        f[0] = v;
        assert_eq!(Request::decode(&f), Err(FrameError::Version(v)));
        assert_eq!(FrameError::Version(v).response(), ErrorCode::Version(v));
    }
    let mut f = Request::Info.encode(1);
    f[1] = 0x33;
    assert_eq!(Request::decode(&f), Err(FrameError::Code(0x33)));
    assert_eq!(FrameError::Code(0x33).response(), ErrorCode::Command(0x33));
    // A response code is not a request, and a request code is not a response.
    assert_eq!(
        Request::decode(&Response::Done(code::SAVE).encode(0)),
        Err(FrameError::Code(code::answer(code::SAVE)))
    );
    assert_eq!(
        Response::decode(&Request::Save.encode(0)),
        Err(FrameError::Code(code::SAVE))
    );
}

#[test]
fn truncated_frames_are_refused_at_every_length() {
    for req in requests() {
        let frame = req.encode(3);
        let len = 4 + usize::from(frame[3]);
        for cut in 0..len {
            let got = Request::decode(&frame[..cut]);
            assert_eq!(got, Err(FrameError::Truncated), "{req:?} cut at {cut}");
        }
        // The zero padding after the payload is not needed.
        assert!(Request::decode(&frame[..len]).is_ok());
    }
    for resp in responses() {
        let frame = resp.encode(3);
        let len = 4 + usize::from(frame[3]);
        for cut in 0..len {
            assert!(
                Response::decode(&frame[..cut]).is_err(),
                "{resp:?} cut at {cut}"
            );
        }
    }
}

#[test]
fn payloads_that_do_not_match_their_code_are_refused() {
    // A payload length beyond the frame's 60 bytes.
    let mut f = Request::Info.encode(0);
    f[3] = 61;
    assert_eq!(header(&f), Err(FrameError::Truncated));
    // Extra bytes after a request that takes none.
    let mut f = Request::Save.encode(0);
    f[3] = 1;
    assert_eq!(Request::decode(&f), Err(FrameError::Payload));
    // GET_CONFIG without its start.
    let mut f = Request::GetConfig { start: 0 }.encode(0);
    f[3] = 0;
    assert_eq!(Request::decode(&f), Err(FrameError::Payload));
    // A commit byte other than 0 or 1.
    let mut f = Request::SetConfig {
        commit: false,
        pairs: pairs(&[]),
    }
    .encode(0);
    f[4] = 2;
    assert_eq!(Request::decode(&f), Err(FrameError::Payload));
    // A pair cut short, and seven pairs.
    let mut f = Request::SetConfig {
        commit: true,
        pairs: pairs(&[(Key::FsHz, 100.0)]),
    }
    .encode(0);
    f[3] -= 1;
    assert_eq!(Request::decode(&f), Err(FrameError::Payload));
    let mut f = [0u8; FRAME_LEN];
    f[..4].copy_from_slice(&[VERSION, code::SET_CONFIG, 0, 1 + 63]);
    assert_eq!(header(&f), Err(FrameError::Truncated));
    // An unknown key id is named.
    let mut f = Request::SetConfig {
        commit: true,
        pairs: pairs(&[(Key::FsHz, 100.0)]),
    }
    .encode(0);
    f[5] = 99;
    assert_eq!(Request::decode(&f), Err(FrameError::UnknownKey(99)));
    assert_eq!(
        FrameError::UnknownKey(99).response(),
        ErrorCode::UnknownKey(99)
    );
    // An error response with an unknown error code, or a key error without a key.
    let mut f = Response::Error(ErrorCode::Storage).encode(0);
    f[4] = 77;
    assert_eq!(Response::decode(&f), Err(FrameError::Payload));
    let mut f = Response::Error(ErrorCode::Value(Key::FsHz)).encode(0);
    f[5] = 0;
    assert_eq!(Response::decode(&f), Err(FrameError::Payload));
    // An info with an unknown source.
    let mut f = responses()[0].encode(0);
    f[8] = 9;
    assert_eq!(Response::decode(&f), Err(FrameError::Payload));
}

#[test]
fn random_and_mutated_frames_never_panic() {
    let mut s = Trace::new(7);
    let seeds: Vec<[u8; FRAME_LEN]> = requests()
        .iter()
        .map(|r| r.encode(1))
        .chain(responses().iter().map(|r| r.encode(1)))
        .collect();
    let mut decoded = 0;
    for i in 0..200_000 {
        let mut f = seeds[i % seeds.len()];
        // Flip one to four bytes; keep the version right half the time so decoding goes deep.
        for _ in 0..1 + s.next_u64() % 4 {
            let at = (s.next_u64() % 12) as usize;
            f[at] = s.next_u64() as u8;
        }
        if i % 2 == 0 {
            f[0] = VERSION;
        }
        let len = (s.next_u64() % (FRAME_LEN as u64 + 1)) as usize;
        decoded += usize::from(Request::decode(&f[..len]).is_ok());
        decoded += usize::from(Response::decode(&f[..len]).is_ok());
        let _ = StreamFrame::decode(&f[..len]);
    }
    // Mutations that keep a frame valid exist (a changed tag or value): decoding went deep.
    assert!(decoded > 1000, "{decoded}");
}

#[test]
fn stream_frames_carry_codes_exactly_both_packings() {
    for (wide, n, max) in [
        (false, 12, 4095u16),
        (false, 5, 4095),
        (true, 9, u16::MAX),
        (true, 1, u16::MAX),
    ] {
        let mut s = Trace::new(3);
        let triples: heapless::Vec<[u16; 3], 12> = (0..n)
            .map(|_| [0; 3].map(|_: u16| (s.next_u64() % (u64::from(max) + 1)) as u16))
            .collect();
        let f = StreamFrame {
            seq: 65_535,
            lost: 300,
            triples,
            wide,
        };
        let back = StreamFrame::decode(&f.encode()).expect("decodes");
        assert_eq!(back, f);
    }
    // The rails survive packing.
    let f = StreamFrame {
        seq: 1,
        lost: 0,
        triples: heapless::Vec::from_slice(&[[0, 4095, 0], [4095, 0, 4095]]).expect("2"),
        wide: false,
    };
    assert_eq!(StreamFrame::decode(&f.encode()).expect("decodes"), f);
    // A count beyond the frame's capacity, and a payload of the wrong length.
    let mut bytes = f.encode();
    bytes[8] = 13;
    assert_eq!(StreamFrame::decode(&bytes), Err(FrameError::Payload));
    let mut bytes = f.encode();
    bytes[3] += 1;
    assert_eq!(StreamFrame::decode(&bytes), Err(FrameError::Payload));
    assert_eq!(StreamFrame::capacity(12), 12);
    assert_eq!(StreamFrame::capacity(13), 9);
}

#[test]
fn profile_keys_carry_every_value_and_refuse_what_does_not_fit() {
    let mut p = Profile::default();
    for k in Key::ALL {
        let v = p.get(k);
        let mut q = p;
        q.set(k, v).expect("its own value fits");
        assert_eq!(format!("{q:?}"), format!("{p:?}"), "{k}");
    }
    for k in Key::ALL {
        let bad: &[f64] = match k.kind() {
            Kind::Integer { max, .. } => &[0.5, -1.0, f64::from(max) + 1.0, f64::NAN],
            Kind::Flag => &[0.5, 2.0, -1.0, f64::NAN],
            Kind::Sign => &[0.0, 2.0, f64::NAN],
            Kind::Real => &[f64::NAN],
            Kind::Optional => &[],
        };
        for &v in bad {
            let before = p;
            assert_eq!(p.set(k, v), Err(ProfileError::Value(k)), "{k} = {v}");
            assert_eq!(format!("{p:?}"), format!("{before:?}"), "{k} changed");
        }
    }
    // Optional values: NaN is off.
    p.set(Key::LowpassFcHz, 50.0).expect("fits");
    assert_eq!(p.config.lowpass_fc_hz, Some(50.0));
    p.set(Key::LowpassFcHz, f64::NAN).expect("fits");
    assert_eq!(p.config.lowpass_fc_hz, None);
    // Drift parameters survive drift control going off and on.
    p.set(Key::HoldS, 0.02).expect("fits");
    p.set(Key::Drift, 0.0).expect("fits");
    assert_eq!(p.config.drift, None);
    p.set(Key::StrokeMaxS, 1.5).expect("fits");
    p.set(Key::Drift, 1.0).expect("fits");
    let d = p.config.drift.expect("on");
    assert_eq!((d.hold_s, d.stroke_max_s), (0.02, 1.5));
    // Signs and axes.
    p.set(Key::YSign, -1.0).expect("fits");
    p.set(Key::XAxis, 2.0).expect("fits");
    assert_eq!(
        p.map,
        AxisMap {
            x_axis: 2,
            x_flip: false,
            y_axis: 1,
            y_flip: true
        }
    );
}

#[test]
fn validation_names_the_key_that_is_wrong() {
    let cases: [(Key, f64, Key); 6] = [
        (Key::AdcBits, 1.0, Key::AdcBits),
        (Key::FsHz, 0.0, Key::FsHz),
        (Key::CountsPerInch, 0.0, Key::CountsPerInch),
        (Key::LowpassFcHz, 5000.0, Key::LowpassFcHz),
        (Key::StrokeMaxS, 0.1, Key::StrokeMaxS),
        (Key::YAxis, 0.0, Key::YAxis),
    ];
    for (key, value, named) in cases {
        let mut p = Profile::default();
        p.set(key, value).expect("fits its kind");
        let e = p.validate().expect_err("invalid");
        assert_eq!(e.key(), named, "{key} = {value}: {e}");
    }
    assert_eq!(Profile::default().validate(), Ok(()));
    // Every drift error maps to its own key.
    let drift_keys: Vec<Key> = [
        DriftError::FalseStart,
        DriftError::Hold,
        DriftError::Knock,
        DriftError::Stroke,
        DriftError::Glide,
        DriftError::Lift,
        DriftError::MountTilt,
        DriftError::BiasTau,
        DriftError::ClickFreeze,
    ]
    .map(|d| Key::of_error(ConfigError::Drift(d)))
    .to_vec();
    assert_eq!(drift_keys, Key::ALL[9..18].to_vec());
}

#[test]
fn the_record_round_trips_and_reads_what_it_can_of_another_version() {
    let mut p = Profile::new(Config {
        fs_hz: 4000,
        counts_per_inch: 1600,
        lowpass_fc_hz: Some(80.0),
        ..Config::default()
    });
    p.set(Key::XSign, -1.0).expect("fits");
    p.set(Key::Drift, 0.0).expect("fits");
    p.set(Key::HoldS, 0.02).expect("fits");
    let mut rec = [0; RECORD_LEN];
    assert_eq!(p.encode(&mut rec), RECORD_LEN);
    assert_eq!(Profile::decode(&rec), Ok(p));
    // Cut anywhere: refused, never a half profile.
    for cut in 0..2 {
        assert_eq!(Profile::decode(&rec[..cut]), Err(RecordError::Truncated));
    }
    for cut in 2..RECORD_LEN {
        assert_eq!(Profile::decode(&rec[..cut]), Err(RecordError::Truncated));
    }
    let mut other = rec;
    other[0] = 2;
    assert_eq!(Profile::decode(&other), Err(RecordError::Format(2)));
    // A record of a later firmware: an unknown id is skipped; a value that no longer fits
    // its key keeps the default; fewer keys keep the defaults.
    let mut later = rec;
    later[2] = 250;
    let got = Profile::decode(&later).expect("decodes");
    assert_eq!(got.config.fs_hz, Config::default().fs_hz);
    assert_eq!(got.config.counts_per_inch, 1600);
    let mut short = rec;
    short[1] = 4;
    let got = Profile::decode(&short[..2 + 4 * 9]).expect("decodes");
    assert_eq!(
        got.config.counts_per_inch,
        Config::default().counts_per_inch
    );
    assert_eq!(got.config.lowpass_fc_hz, Some(80.0));
}

#[test]
fn every_source_has_its_byte_and_no_other_byte_is_one() {
    for s in [
        Source::Defaults,
        Source::Stored,
        Source::Corrupt,
        Source::Invalid,
        Source::Changed,
    ] {
        assert_eq!(Source::from_u8(s as u8), Some(s));
    }
    assert_eq!(Source::from_u8(5), None);
}

#[test]
fn a_length_beyond_sixty_is_refused_even_in_a_longer_buffer() {
    let mut long = [0u8; 80];
    long[..FRAME_LEN].copy_from_slice(&Request::Info.encode(0));
    long[3] = 61;
    assert_eq!(header(&long), Err(FrameError::Truncated));
    long[3] = 60;
    assert!(header(&long).is_ok());
}

#[test]
fn keys_and_refusals_read_as_a_user_writes_them() {
    assert_eq!(Key::CountsPerInch.to_string(), "counts_per_inch");
    assert_eq!(Key::HoldS.to_string(), "drift.hold_s");
    let cases = [
        (
            ProfileError::Value(Key::XAxis),
            "x_axis: must be an integer in 0..=2",
        ),
        (
            ProfileError::Value(Key::Drift),
            "drift: must be 0 (off) or 1 (on)",
        ),
        (ProfileError::Value(Key::XSign), "x_sign: must be 1 or -1"),
        (
            ProfileError::Value(Key::HoldS),
            "drift.hold_s: not a valid number",
        ),
        (ProfileError::SameAxis, "y_axis: must differ from x_axis"),
    ];
    for (e, want) in cases {
        assert_eq!(e.to_string(), want);
    }
    let invalid = ProfileError::Invalid(ConfigError::AdcBits { adc_bits: 1 });
    assert!(invalid.to_string().starts_with("adc_bits = 1"), "{invalid}");
}

#[test]
fn an_axis_beyond_z_is_not_a_valid_map() {
    let ok = AxisMap::default();
    assert!(ok.is_valid());
    for bad in [
        AxisMap { x_axis: 3, ..ok },
        AxisMap { y_axis: 3, ..ok },
        AxisMap { y_axis: 0, ..ok },
    ] {
        assert!(!bad.is_valid(), "{bad:?}");
    }
}

#[test]
fn the_trackers_state_has_a_byte_each_and_follows_the_tracker() {
    let names = [
        "calibrating",
        "integrating",
        "still",
        "moving",
        "held",
        "lifted",
        "frozen",
    ];
    for (b, name) in (0..=6u8).zip(names) {
        let t = TrackerState::from_u8(b).expect("a state");
        assert_eq!((t as u8, t.name()), (b, name));
    }
    assert_eq!(TrackerState::from_u8(7), None);
    let rest = [[2048u16, 2048, 2048 + 418]; 3000]; // 1 s still, +1 g on Z
    let mut off = Tracker::new(&Config {
        drift: None,
        ..Config::default()
    })
    .expect("valid");
    assert_eq!(TrackerState::of(&off), TrackerState::Calibrating);
    off.feed(&rest);
    assert_eq!(TrackerState::of(&off), TrackerState::Integrating);
    let mut t = Tracker::new(&Config::default()).expect("valid");
    t.feed(&rest);
    assert_eq!(TrackerState::of(&t), TrackerState::Still);
    // A hard push on X: held while younger than the hold (16 ms), then moving.
    let mut seen = heapless::Vec::<TrackerState, 8>::new();
    for _ in 0..300 {
        t.feed(&[[2448, 2048, 2466]]);
        let now = TrackerState::of(&t);
        if seen.last() != Some(&now) {
            seen.push(now).expect("few states");
        }
    }
    assert_eq!(
        seen.as_slice(),
        [
            TrackerState::Still,
            TrackerState::Held,
            TrackerState::Moving
        ]
    );
    t.button_edge();
    assert_eq!(TrackerState::of(&t), TrackerState::Frozen);
}
