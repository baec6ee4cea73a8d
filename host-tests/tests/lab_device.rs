//! The configuration interface end to end: the twin (`imu_app` over USB/IP, its profile in a
//! flash image file) and the host's client (`host_tests::device::client` over the USB/IP
//! host). Every command; a refused value that changes nothing; a saved profile found by a
//! restarted twin; a raw recording equal to the scene's codes, sample for sample.

use std::net::SocketAddr;
use std::path::Path;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use host_tests::device::client::{Client, ClientError};
use host_tests::device::flash::FileFlash;
use host_tests::device::twin::{self, Input, Summary};
use host_tests::device::usbip::BUSID;
use host_tests::device::usbip_host::UsbIpHost;
use imu_core::profile::{Key, Profile};
use imu_core::protocol::{ErrorCode, Source};

/// A scene whose every sample is unique: `[i mod 4096, i / 4096, 2048]`.
fn scene(seconds: f64) -> Input {
    let n = (seconds * 3000.0) as usize;
    Input {
        fs_hz: 3000,
        codes: (0..n)
            .map(|i| [(i & 0xFFF) as u16, ((i >> 12) & 0xFFF) as u16, 2048])
            .collect(),
        held: Vec::new(),
    }
}

fn start_twin(port: u16, flash: &Path, seconds: f64) -> (SocketAddr, JoinHandle<Summary>) {
    let addr: SocketAddr = format!("127.0.0.1:{port}").parse().expect("address");
    let flash = FileFlash::open(flash).expect("flash image");
    let settings = twin::Settings {
        addr,
        wait_host_s: 20.0,
        drain_s: 0.5,
        serial: "LABDEVICE1",
        repeat: false,
    };
    let input = scene(seconds);
    let handle = std::thread::spawn(move || {
        twin::run(&input, settings, twin::Operator::default(), flash).expect("twin ran")
    });
    (addr, handle)
}

fn connect(addr: SocketAddr) -> Client<UsbIpHost> {
    let t0 = Instant::now();
    loop {
        match UsbIpHost::connect(addr, BUSID, Duration::from_secs(5)) {
            Ok(h) => return Client::new(h, Duration::from_secs(5)),
            Err(e) if t0.elapsed() < Duration::from_secs(10) => {
                let _ = e;
                std::thread::sleep(Duration::from_millis(50));
            }
            Err(e) => panic!("cannot reach the twin: {e}"),
        }
    }
}

/// The stretch of [`scene`] a recording holds, found from its first sample (the scene's
/// codes are unique and encode their own index).
fn scene_stretch(samples: &[[u16; 3]], seconds: f64) -> Vec<[u16; 3]> {
    let start = usize::from(samples[0][0]) + (usize::from(samples[0][1]) << 12);
    scene(seconds).codes[start..start + samples.len()].to_vec()
}

fn value(config: &[(Key, f64)], key: Key) -> f64 {
    config
        .iter()
        .find(|(k, _)| *k == key)
        .map(|p| p.1)
        .expect("listed")
}

fn temp_flash(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("imu-device-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("flash.bin");
    let _ = std::fs::remove_file(&path);
    path
}

#[test]
fn every_command_works_and_a_saved_profile_survives_a_restart() {
    let flash = temp_flash("restart");
    let (addr, twin) = start_twin(3261, &flash, 6.0);
    let mut c = connect(addr);

    let info = c.info().expect("info");
    assert_eq!(info.source, Source::Defaults);
    assert_eq!(info.fs_hz, 3000);
    assert_eq!(info.firmware, imu_app::identity::FIRMWARE_VERSION);
    let config = c.config().expect("config get");
    assert_eq!(config.len(), Key::ALL.len());
    for (k, v) in &config {
        let want = Profile::default().get(*k);
        assert!(*v == want || (v.is_nan() && want.is_nan()), "{k}");
    }

    // Seven keys: staged over two frames, applied as a whole.
    let pairs = [
        (Key::CountsPerInch, 1600.0),
        (Key::XSign, -1.0),
        (Key::LowpassFcHz, 80.0),
        (Key::HoldS, 0.02),
        (Key::StrokeMaxS, 1.5),
        (Key::CalibrationS, 0.5),
        (Key::FsHz, 4000.0),
    ];
    c.set(&pairs).expect("set");
    let after = c.config().expect("config get");
    for (k, v) in pairs {
        assert_eq!(value(&after, k), v, "{k}");
    }
    assert_eq!(c.info().expect("info").source, Source::Changed);
    assert_eq!(c.info().expect("info").fs_hz, 4000);

    // Refused: the key is named and nothing changed.
    for (pairs, want) in [
        (
            vec![(Key::AdcBits, 16.0)],
            ErrorCode::Unsupported(Key::AdcBits),
        ),
        (
            vec![(Key::CountsPerInch, 1e9)],
            ErrorCode::Invalid(Key::CountsPerInch),
        ),
        (
            vec![(Key::CountsPerInch, 3200.0), (Key::FsHz, 7000.0)],
            ErrorCode::Unsupported(Key::FsHz),
        ),
        (vec![(Key::XAxis, 0.5)], ErrorCode::Value(Key::XAxis)),
    ] {
        match c.set(&pairs) {
            Err(ClientError::Refused(e)) => assert_eq!(e, want),
            other => panic!("{pairs:?}: {other:?}"),
        }
        let now = c.config().expect("config get");
        assert_eq!(
            format!("{now:?}"),
            format!("{after:?}"),
            "{pairs:?} changed something"
        );
    }

    c.save().expect("save");
    assert_eq!(c.info().expect("info").source, Source::Stored);
    c.recalibrate().expect("recalibrate");
    let counters = c.counters().expect("counters");
    assert!(counters.samples > 0, "{counters:?}");
    drop(c);
    let first = twin.join().expect("twin thread");
    assert_eq!(first.final_fs_hz, 4000);

    // A restart with the flash kept: the saved profile runs.
    let (addr, twin) = start_twin(3261, &flash, 1.0);
    let mut c = connect(addr);
    let info = c.info().expect("info");
    assert_eq!((info.source, info.fs_hz), (Source::Stored, 4000));
    let kept = c.config().expect("config get");
    assert_eq!(format!("{kept:?}"), format!("{after:?}"));
    // Defaults: running and kept.
    c.defaults().expect("defaults");
    assert_eq!(c.info().expect("info").fs_hz, 3000);
    drop(c);
    twin.join().expect("twin thread");
    let (addr, twin) = start_twin(3261, &flash, 0.5);
    let mut c = connect(addr);
    let info = c.info().expect("info");
    assert_eq!((info.source, info.fs_hz), (Source::Stored, 3000));
    drop(c);
    twin.join().expect("twin thread");
    let _ = std::fs::remove_file(&flash);
}

#[test]
fn a_recording_is_the_scene_sample_for_sample() {
    let flash = temp_flash("record");
    let (addr, twin) = start_twin(3262, &flash, 5.0);
    let mut c = connect(addr);
    let rec = c.record(6000, |_| {}).expect("record");
    drop(c);
    let summary = twin.join().expect("twin thread");
    assert_eq!(rec.samples.len(), 6000);
    assert_eq!(rec.lost(), 0, "gaps: {:?}", rec.gaps);
    assert_eq!(rec.missing_frames, 0);
    assert_eq!(rec.device_totals.1, 0);
    assert!(summary.stream_frames >= rec.frames);
    assert_eq!(rec.samples, scene_stretch(&rec.samples, 5.0));
    let _ = std::fs::remove_file(&flash);
}

#[test]
fn a_recording_after_an_abandoned_stream_starts_afresh() {
    // A recording interrupted on the host (Ctrl-C) leaves the device streaming; the next
    // `record` must not count the old stream's frames as missing ones of its own.
    use imu_core::protocol::Request;
    let flash = temp_flash("abandoned");
    let (addr, twin) = start_twin(3263, &flash, 5.0);
    let mut c = connect(addr);
    c.request(&Request::StreamStart).expect("started");
    std::thread::sleep(Duration::from_millis(300));
    let rec = c
        .record(3000, |_| {})
        .expect("record after an abandoned stream");
    drop(c);
    twin.join().expect("twin thread");
    assert_eq!(
        (rec.missing_frames, rec.lost()),
        (0, 0),
        "gaps: {:?}",
        rec.gaps
    );
    assert_eq!(rec.samples, scene_stretch(&rec.samples, 5.0));
    let _ = std::fs::remove_file(&flash);
}

#[test]
fn a_scene_plays_in_its_own_time_on_a_device_at_another_rate() {
    // The stored profile runs 6 kHz; the scene was made at 3 kHz: it must last its 2 s,
    // not 1 s (each scene sample is played twice), and the recording shows each sample twice.
    let flash = temp_flash("rate");
    let (addr, twin) = start_twin(3264, &flash, 3.0);
    let mut c = connect(addr);
    c.set(&[(Key::FsHz, 6000.0)]).expect("6 kHz");
    c.save().expect("save");
    drop(c);
    twin.join().expect("twin thread");
    let (addr, twin) = start_twin(3265, &flash, 2.0);
    let mut c = connect(addr);
    let t0 = Instant::now();
    let rec = c.record(600, |_| {}).expect("record");
    drop(c);
    let summary = twin.join().expect("twin thread");
    let wall = t0.elapsed().as_secs_f64();
    assert_eq!((summary.fs_hz, summary.final_fs_hz), (3000, 6000));
    assert!((summary.scene_s - 2.0).abs() < 1e-3, "{}", summary.scene_s);
    assert!(wall > 1.9, "the scene played in {wall} s");
    // Runs of equal samples (the scene's are unique): two long each, but at the ends.
    let mut runs = vec![1usize];
    for w in rec.samples.windows(2) {
        if w[0] == w[1] {
            *runs.last_mut().expect("a run") += 1;
        } else {
            runs.push(1);
        }
    }
    let inner = &runs[1..runs.len() - 1];
    assert!(inner.iter().all(|&r| r == 2), "runs {inner:?}");
    let _ = std::fs::remove_file(&flash);
}

#[test]
fn a_written_recording_reads_back_unchanged() {
    use host_tests::formats::recording::{parse, write, Recording};
    let mut p = Profile::default();
    p.set(Key::FsHz, 4000.0).expect("fits");
    p.set(Key::LowpassFcHz, 200.0).expect("fits");
    for profile in [
        None,
        Some(host_tests::device::profile::to_text(
            &host_tests::device::profile::pairs_of(&p),
        )),
    ] {
        let rec = Recording {
            fs: 4000,
            samples: scene(0.1).codes,
            profile,
        };
        assert_eq!(parse(write(&rec).as_bytes(), None).expect("parses"), rec);
    }
}
