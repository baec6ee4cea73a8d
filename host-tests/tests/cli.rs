//! The lab's command-line conventions (`host_tests::commands`), on the built `lab` binary:
//! a closed pipe ends quietly, errors go to stderr with the documented exit status, `--json`
//! prints JSON only, and `cargo lab` alone lists every command with an example.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn lab() -> Command {
    Command::new(env!("CARGO_BIN_EXE_lab"))
}

fn output(args: &[&str]) -> Output {
    lab().args(args).output().expect("the lab runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// A recording of the device at rest: 2 s at 3 kHz, mid-scale codes with Z at +1 g.
fn rest_recording(name: &str) -> PathBuf {
    let path = std::env::temp_dir().join(format!("imu-lab-cli-{}-{name}.csv", std::process::id()));
    let mut csv = String::from("fs,3000\nn,x,y,z\n");
    for i in 0..6000 {
        csv += &format!("{i},{},{},2457\n", 2048 + i % 2, 2047 + i % 3);
    }
    std::fs::write(&path, csv).expect("temp file");
    path
}

#[test]
fn a_closed_pipe_ends_the_run_quietly() {
    // `cargo lab replay FILE --json | head -c 0`: the reader has gone before the first
    // write. Rust ignores SIGPIPE, so every write fails with EPIPE; the lab must stop
    // quietly (status 0, nothing on stderr), not panic with a backtrace.
    let file = rest_recording("pipe");
    for args in [
        vec!["replay", file.to_str().expect("utf-8 path"), "--json"],
        vec!["hid", "--dx", "100000", "--dy", "-3", "--json"],
        vec![
            "predict",
            "--fs",
            "100",
            "--t",
            "1,2,3",
            "--sigma-d",
            "0.05",
        ],
    ] {
        let (reader, writer) = std::io::pipe().expect("pipe");
        drop(reader);
        let out = lab()
            .args(&args)
            .stdout(writer)
            .stderr(Stdio::piped())
            .output()
            .expect("the lab runs");
        assert!(out.status.success(), "{args:?}: {:?}", out.status);
        assert_eq!(text(&out.stderr), "", "{args:?}");
    }
    std::fs::remove_file(file).ok();
}

#[test]
fn the_lab_alone_lists_every_command_with_an_example() {
    let out = output(&[]);
    assert!(out.status.success());
    let listing = text(&out.stdout);
    for name in [
        "predict",
        "budget",
        "hid",
        "reproduce",
        "simulate",
        "replay",
        "speed",
        "mouse",
        "allan",
        "drift",
        "twin",
    ] {
        assert!(
            listing.contains(&format!("cargo lab {name} ")),
            "no example for {name}:\n{listing}"
        );
    }
}

#[test]
fn a_bad_argument_is_named_on_stderr_with_status_2() {
    for (args, named) in [
        (
            vec!["simulate", "--scene", "adxl335-stroke", "--seconds", "-1"],
            "--seconds -1",
        ),
        (vec!["simulate", "--scene", "nowhere"], "--scene nowhere"),
        (vec!["reproduce", "--trials", "10"], "--trials 10"),
        (
            vec!["hid", "--dx", "0", "--dy", "0", "--buttons", "9"],
            "--buttons 9",
        ),
        (vec!["predict", "--fs", "0", "--t", "1"], "--fs 0"),
        (vec!["mouse", "--strokes", "0"], "--strokes 0"),
        (
            vec!["simulate", "--scene", "adxl335-rest", "--seconds", "1e9"],
            "--seconds 1e9: at most 3600 s",
        ),
        // Quoted as given, not as 301 digits.
        (
            vec!["predict", "--fs", "1e300", "--t", "1", "--sigma-d", "1e-3"],
            "--t 1 at --fs 1e300: N = 1e300 samples",
        ),
        // Refused as an argument before the file is read (it does not exist).
        (
            vec!["replay", "/nonexistent/imu.csv", "--fs", "-1"],
            "--fs -1",
        ),
        // Before the scene runs, not after.
        (
            vec![
                "simulate",
                "--scene",
                "adxl335-rest",
                "--csv",
                "/nonexistent/x.csv",
            ],
            "--csv /nonexistent/x.csv: its folder /nonexistent does not exist",
        ),
        (
            vec!["twin", "--serial", "two words"],
            "--serial two words: must be 1 to 32 letters",
        ),
        (
            vec!["twin", "--flash", "/nonexistent/flash.bin"],
            "--flash /nonexistent/flash.bin: its folder /nonexistent does not exist",
        ),
        (
            vec!["replay", "/nonexistent/imu.csv", "--every", "1e300"],
            "--every 1e300: at most 3600 s",
        ),
        (
            vec![
                "allan",
                "/nonexistent/imu.csv",
                "--columns",
                "x",
                "--scale",
                "1e300",
            ],
            "--scale 1e300: at most 1000",
        ),
        (
            vec![
                "allan",
                "/nonexistent/imu.csv",
                "--columns",
                "x",
                "--scale",
                "1",
                "--fs",
                "1e300",
            ],
            "--fs 1e300: at most 1e6 Hz",
        ),
        // The bounds a new user's trial found missing (no panic, no 1 TB allocation).
        (
            vec!["mouse", "--trace", "drags:1", "--fs", "50"],
            "--fs 50: the device's rates",
        ),
        (
            vec!["mouse", "--trace", "drags:1", "--noise-ug", "1e9"],
            "--noise-ug 1e9: must be above 0 and at most 5000",
        ),
        (
            vec!["mouse", "--trace", "drags:1", "--bits", "17"],
            "--bits 17: the core's ADC resolutions",
        ),
        (
            vec!["mouse", "--trace", "drags:1", "--every-ms", "0"],
            "--every-ms 0: 1..=60000 ms between trace lines",
        ),
        // A trial the full run does not have, a negative value given as such, an option
        // the trace would ignore (a second new user's trial).
        (
            vec!["mouse", "--trace", "strokes:200"],
            "--trace strokes:200: K, the trial of strokes: 0..200",
        ),
        (
            vec!["mouse", "--trace", "vibration-rest:x"],
            "--trace vibration-rest:x: K, the trial of vibration-rest: 0..20",
        ),
        (
            vec!["mouse", "--trace", "drags:1", "--noise-ug", "-5"],
            "--noise-ug -5: must be above 0",
        ),
        (
            vec!["mouse", "--trace", "drags:1", "--fs", "-100"],
            "invalid value '-100' for '--fs <FS>'",
        ),
        (
            vec!["mouse", "--trace", "drags:1", "--json"],
            "the argument '--trace <FAMILY:K>' cannot be used with '--json'",
        ),
        (
            vec!["mouse", "--rest-minutes", "1e12"],
            "--rest-minutes 1e12: at most",
        ),
        (
            vec![
                "drift",
                "/nonexistent/imu.csv",
                "--calibrate-s",
                "1e9",
                "--t",
                "1",
            ],
            "--calibrate-s 1e9: at most 60 s",
        ),
        (
            vec![
                "drift",
                "/nonexistent/imu.csv",
                "--calibrate-s",
                "1",
                "--t",
                "1e300",
            ],
            "--t 1e300: at most",
        ),
        (
            vec![
                "device",
                "--twin",
                "127.0.0.1:1",
                "--timeout",
                "1e9",
                "info",
            ],
            "--timeout 1e9: at most 3600 s",
        ),
        (
            vec!["twin", "--strokes", "1000000"],
            "--strokes 1000000: 1..=10000",
        ),
    ] {
        let out = output(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert_eq!(text(&out.stdout), "", "{args:?}: nothing on stdout");
        let err = text(&out.stderr);
        assert!(
            err.starts_with(&format!("error: {named}")),
            "{args:?}: {err}"
        );
    }
}

#[test]
fn a_missing_file_is_named_on_stderr_with_status_1() {
    let out = output(&["replay", "/nonexistent/imu.csv"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).starts_with("error: /nonexistent/imu.csv: "));
}

#[test]
fn the_families_table_says_what_a_reported_row_is() {
    // A new user read "rep." beside a row at 59.5 % as a pass (its JSON says `"pass":
    // true`): the table now says what it means.
    let out = output(&["mouse", "--families", "--quick"]);
    assert!(out.status.success());
    let table = text(&out.stdout);
    assert!(table.lines().any(|l| l.contains(" rep. ")), "{table}");
    assert!(
        table.contains("rep.: reported beside the targets, not one of them"),
        "{table}"
    );
}

#[test]
fn json_output_is_json_alone() {
    let file = rest_recording("json");
    for args in [
        vec!["replay", file.to_str().expect("utf-8 path"), "--json"],
        vec!["hid", "--dx", "3", "--dy", "4", "--json"],
        vec!["budget", "--quick", "--json"],
    ] {
        let out = output(&args);
        assert!(out.status.success(), "{args:?}");
        serde_json::from_slice::<serde_json::Value>(&out.stdout)
            .unwrap_or_else(|e| panic!("{args:?}: not JSON: {e}"));
        assert_eq!(text(&out.stderr), "", "{args:?}");
    }
    std::fs::remove_file(file).ok();
}

#[test]
fn replay_json_says_which_settings_it_ran() {
    // A new user's recording without a profile ran the board's defaults (800 counts/inch,
    // 0.33 V/g), and the JSON did not say so: only the table's `settings:` line did.
    let file = rest_recording("settings");
    let out = output(&[
        "replay",
        file.to_str().expect("utf-8 path"),
        "--json",
        "--adc-bits",
        "14",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let s = &v["settings"];
    assert_eq!(s["from"], "the defaults (the file has no profile)", "{s}");
    assert_eq!(s["changed_by"], serde_json::json!(["--adc-bits"]), "{s}");
    assert_eq!(s["counts_per_inch"], 800, "{s}");
    assert_eq!(s["adc_bits"], 14, "{s}");
    assert_eq!(s["drift_control"], true, "{s}");
    assert!(s["m_s2_per_lsb"].as_f64().is_some_and(|m| m > 0.0), "{s}");
    // The track's own fields stay where they were.
    assert!(v["counts"].is_array() && v["fs"] == 3000.0, "{v}");
    std::fs::remove_file(file).ok();
}

#[test]
fn replay_json_says_what_drift_control_did() {
    // A new user asked why a stroke after a lift arrived late and had only the cursor's
    // position to go on. 3 s at rest (calibration), a 20 mm stroke to the right (2 m/s^2 for
    // 0.1 s, then -2 m/s^2), 1 s at rest, a 20 mm lift straight up, 0.5 s in the air and
    // down again the same way, 2.9 s at rest: 41.8 codes per m/s^2 at the defaults.
    let path = std::env::temp_dir().join(format!("imu-lab-cli-{}-state.csv", std::process::id()));
    let mut csv = String::from("fs,3000\nn,x,y,z\n");
    let pulse = |t: f64, from: f64| match t - from {
        d if (0.0..0.1).contains(&d) => 84,
        d if (0.1..0.2).contains(&d) => -84,
        _ => 0,
    };
    for i in 0..24_000 {
        let t = f64::from(i) / 3000.0;
        let x = 2048 + i % 2 + pulse(t, 3.0);
        let z = 2457 + i % 3 + pulse(t, 4.2) - pulse(t, 4.9);
        csv += &format!("{i},{x},2047,{z}\n");
    }
    std::fs::write(&path, csv).expect("temp file");
    let out = output(&[
        "replay",
        path.to_str().expect("utf-8 path"),
        "--json",
        "--every",
        "0.05",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let points = v["points"].as_array().expect("points");
    let state_at = |t: f64| {
        let p = points
            .iter()
            .find(|p| (p["t_s"].as_f64().expect("t_s") - t).abs() < 1e-6)
            .unwrap_or_else(|| panic!("no point at {t} s: {v}"));
        p["state"]
            .as_str()
            .unwrap_or_else(|| panic!("no state: {p}"))
            .to_string()
    };
    assert_eq!(state_at(2.9), "still");
    // Moving from its start (held first, or delivered), still again after it.
    assert!(
        ["moving", "held"].contains(&state_at(3.15).as_str()),
        "{}",
        state_at(3.15)
    );
    assert_eq!(state_at(4.0), "still");
    // Up at 4.2-4.4 s, in the air until 4.9 s.
    assert_eq!(state_at(4.6), "lifted");
    assert_eq!(state_at(7.95), "still");
    // 84 codes of 0.0239 m/s^2 for 0.1 s each way: 20.1 mm, 633 counts at 800 counts/inch;
    // within target 1's 5 %.
    let right = v["counts"][0].as_i64().expect("counts");
    assert!((601..=665).contains(&right), "{right}");
    std::fs::remove_file(path).ok();
}

#[test]
fn device_arguments_are_refused_before_any_device_is_asked() {
    // Nothing listens on port 9: a command that tried to connect would fail with status 1.
    let dir = std::env::temp_dir();
    let dir_arg = dir.to_string_lossy().into_owned();
    for (args, named) in [
        (
            vec!["config", "set", "drift=maybe"],
            "config set drift=maybe: must be on or off",
        ),
        (
            vec!["config", "set", "scheme=rk4"],
            "must be euler or trapezoid",
        ),
        (
            vec!["config", "set", "cpi=3"],
            "config set cpi=3: unknown key",
        ),
        (
            vec![
                "config",
                "set",
                "counts_per_inch=800",
                "counts_per_inch=1600",
            ],
            "counts_per_inch is given twice",
        ),
        (
            vec!["record", "--seconds", "1", "--out", &dir_arg],
            "is a folder",
        ),
        (
            vec!["check", "--rest-s", "0.5"],
            "--rest-s 0.5: must be 1 to 60 s",
        ),
        (
            vec!["check", "--move-s", "1e9"],
            "--move-s 1e9: must be 1 to 60 s",
        ),
        (
            vec![
                "record",
                "--seconds",
                "1",
                "--out",
                "/nonexistent/imu/x.csv",
            ],
            "its folder /nonexistent/imu does not exist",
        ),
        (vec!["record", "--seconds", "-1"], "--seconds -1"),
    ] {
        let mut all = vec!["device", "--twin", "127.0.0.1:9"];
        all.extend(&args);
        let out = output(&all);
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(text(&out.stdout), "", "{args:?}");
        assert!(err.contains(named), "{args:?}: {err}");
    }
    assert!(!Path::new("/nonexistent/imu").exists(), "nothing created");
    // A twin that is not running: what to do, not an OS error number.
    let out = output(&["device", "--twin", "127.0.0.1:9", "info"]);
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("no twin listens on 127.0.0.1:9: start one with `cargo lab twin"),
        "{err}"
    );
}

/// A twin on a free local port with `args` (after `twin --addr ADDR`), answering `info`.
fn start_twin(args: &[&str]) -> (std::process::Child, String) {
    let port = {
        let l = std::net::TcpListener::bind("127.0.0.1:0").expect("a free port");
        l.local_addr().expect("address").port()
    };
    let addr = format!("127.0.0.1:{port}");
    let twin = lab()
        .args(["twin", "--addr", &addr])
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("the twin starts");
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(20);
    while output(&["device", "--twin", &addr, "info"]).status.code() != Some(0) {
        assert!(
            std::time::Instant::now() < deadline,
            "the twin did not answer"
        );
        std::thread::sleep(std::time::Duration::from_millis(200));
    }
    (twin, addr)
}

#[test]
fn device_commands_against_a_twin_answer_json_and_name_a_refused_key() {
    let (mut twin, addr) =
        start_twin(&["--scene", "rest", "--seconds", "30", "--serial", "CLITWIN7"]);
    let device = |args: &[&str]| {
        let mut all = vec!["device", "--twin", addr.as_str()];
        all.extend(args);
        output(&all)
    };
    // The twin is listed with its serial, and chosen by it.
    let listed = device(&["list"]);
    assert_eq!(listed.status.code(), Some(0), "{}", text(&listed.stderr));
    // Its release read from its device descriptor (the app's bcdDevice, 0x0100).
    assert_eq!(imu_app::identity::RELEASE_BCD, 0x0100);
    assert!(
        text(&listed.stdout).starts_with("CLITWIN7  imu-mouse accelerometer mouse  1.00  usbip://"),
        "{}",
        text(&listed.stdout)
    );
    let v: serde_json::Value =
        serde_json::from_slice(&device(&["--json", "list"]).stdout).expect("JSON");
    assert_eq!(v[0]["serial"], "CLITWIN7");
    assert_eq!(v[0]["release"], "1.00");
    assert_eq!(
        device(&["--serial", "CLITWIN7", "info"]).status.code(),
        Some(0)
    );
    let other = device(&["--serial", "OTHER", "info"]);
    assert_eq!(other.status.code(), Some(1));
    assert!(
        text(&other.stderr).contains("has serial CLITWIN7, not OTHER"),
        "{}",
        text(&other.stderr)
    );
    for (cmd, what) in [("save", "saved"), ("recalibrate", "recalibrated")] {
        let out = device(&["--json", cmd]);
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON alone");
        assert_eq!(v["done"], what, "{cmd}");
    }
    // Recalibrate waits for the window and shows the new zero: the rest scene's codes sit
    // near mid-scale, 2048.
    let out = device(&["recalibrate"]);
    let said = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(said.starts_with("recalibrated in "), "{said}");
    let zero: f64 = said
        .split("cursor x: zero ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .and_then(|z| z.parse().ok())
        .expect("a zero for cursor x");
    assert!((zero - 2048.0).abs() < 5.0, "{said}");
    // Each refusal names the key typed, what it takes here and why, with status 2.
    for (pair, says) in [
        (
            "counts_per_inch=1e9",
            "counts_per_inch takes 1..=25400 counts/inch",
        ),
        (
            "m_s2_per_lsb=1e30",
            "m_s2_per_lsb takes 0.00478841..=2.3942 m/s^2 at adc_bits=12:",
        ),
        (
            "calibration_s=1000",
            "calibration_s takes 0.00533334..=60 s at fs_hz=3000:",
        ),
        ("adc_bits=16", "this board's ADC has 12 bits"),
        ("lowpass_fc_hz=2000", "0.003 to below 1500 Hz, or off"),
        (
            "fs_hz=7000",
            "100..=20000 Hz, at rates that divide its 96 MHz clock",
        ),
    ] {
        let out = device(&["config", "set", pair]);
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{pair}: {err}");
        assert!(
            err.starts_with(&format!(
                "error: config set: {pair} refused by the device: "
            )) && err.contains(says),
            "{pair}: {err}"
        );
    }
    // A range moved by a rate given in the same set says so; so does a value already on the
    // device that the new rate no longer fits.
    for (pairs, says) in [
        (
            &["fs_hz=100", "calibration_s=0.05"][..],
            "calibration_s=0.05 refused by the device: calibration_s takes 0.16..=60 s at \
             fs_hz=100 (given in this set)",
        ),
        (&["calibration_s=0.05"][..], ""),
        (
            &["fs_hz=100"][..],
            "refused by the device: the device's calibration_s=0.05 would no longer fit; \
             calibration_s takes 0.16..=60 s at fs_hz=100 (given in this set)",
        ),
        (&["calibration_s=1"][..], ""),
    ] {
        let out = device(&[&["config", "set"][..], pairs].concat());
        let err = text(&out.stderr);
        if says.is_empty() {
            assert_eq!(out.status.code(), Some(0), "{pairs:?}: {err}");
        } else {
            assert_eq!(out.status.code(), Some(2), "{pairs:?}: {err}");
            assert!(
                err.starts_with(&format!("error: config set: {says}")),
                "{err}"
            );
        }
    }
    // The table: every key with its value, unit, what it takes and what it does.
    let table = text(&device(&["config", "get"]).stdout);
    assert!(
        !table.contains(" -0.."),
        "a range from 0 reads 0..: {table}"
    );
    assert!(
        table.lines().any(|l| l.starts_with("counts_per_inch ")
            && l.contains("counts/inch")
            && l.contains("1..=25400")
            && l.contains("mouse resolution")),
        "{table}"
    );
    // A profile saved to a file and set from it, a key on the command line changing it.
    let profile = std::env::temp_dir().join(format!("imu-cli-{}-profile.json", std::process::id()));
    let got = device(&["--json", "config", "get"]);
    let saved: serde_json::Value = serde_json::from_slice(&got.stdout).expect("JSON");
    assert_eq!(saved["scheme"], "euler");
    assert_eq!(saved["drift"], true);
    assert_eq!(saved["lowpass_fc_hz"], serde_json::Value::Null);
    assert_eq!(saved["counts_per_inch"], 800);
    std::fs::write(&profile, &got.stdout).expect("written");
    assert_eq!(
        device(&["config", "set", "counts_per_inch=1600", "drift=off"])
            .status
            .code(),
        Some(0)
    );
    let p = profile.to_str().expect("a UTF-8 path");
    let out = device(&["--json", "config", "set", "--file", p, "x_sign=-1"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let now: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let mut want = saved.clone();
    want["x_sign"] = serde_json::json!(-1);
    assert_eq!(
        now, want,
        "the file's profile, x_sign from the command line"
    );
    assert_eq!(
        device(&["config", "set", "--file", p]).status.code(),
        Some(0)
    );
    std::fs::write(&profile, "{\"cpi\": 1}").expect("written");
    let out = device(&["config", "set", "--file", p]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).contains("cpi=1: unknown key"),
        "{}",
        text(&out.stderr)
    );
    // A key twice is refused, not taken as the last; a profile that is not an object
    // says so.
    for (body, says) in [
        (
            "{\"counts_per_inch\": 400, \"counts_per_inch\": 1600}",
            "counts_per_inch is given twice",
        ),
        ("[800]", "not a profile: invalid type: sequence"),
        ("{\"counts_per_inch\": ", "not JSON"),
    ] {
        std::fs::write(&profile, body).expect("written");
        let out = device(&["config", "set", "--file", p]);
        assert_eq!(out.status.code(), Some(1), "{body}");
        assert!(
            text(&out.stderr).starts_with(&format!("error: {p}: {says}")),
            "{body}: {}",
            text(&out.stderr)
        );
    }
    let _ = std::fs::remove_file(&profile);
    let out = device(&["config", "set", "--file", p]);
    assert_eq!(
        text(&out.stderr).trim_end(),
        format!("error: {p}: no such file"),
        "a missing file in words, not an OS error number"
    );
    // A rate the device cannot run is refused naming the rate (not the calibration window
    // it would make too short), with status 2, and changes nothing.
    let before = text(&device(&["config", "get"]).stdout);
    let out = device(&["config", "set", "fs_hz=7"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("fs_hz"), "{}", text(&out.stderr));
    assert_eq!(text(&device(&["config", "get"]).stdout), before);
    // The scheme reads as the word `config set` takes.
    assert!(
        before
            .lines()
            .any(|l| l.starts_with("scheme ") && l.contains(" euler ")),
        "{before}"
    );
    // Ctrl-C during a recording keeps what arrived, marked partial.
    let file = std::env::temp_dir().join(format!("imu-cli-{}-partial.csv", std::process::id()));
    let rec = lab()
        .args([
            "device",
            "--twin",
            addr.as_str(),
            "record",
            "--seconds",
            "30",
            "--out",
        ])
        .arg(&file)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("record starts");
    std::thread::sleep(std::time::Duration::from_millis(800));
    // Meanwhile a second client: the twin serves one host at a time, and says so.
    let busy = device(&["--timeout", "0.5", "info"]);
    let err = text(&busy.stderr);
    assert_eq!(busy.status.code(), Some(1), "{err}");
    assert!(err.contains("it serves one host at a time"), "{err}");
    std::thread::sleep(std::time::Duration::from_millis(200));
    let killed = Command::new("kill")
        .args(["-INT", &rec.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(killed.success());
    let out = rec.wait_with_output().expect("record ends");
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("interrupted: the") && err.contains("marked partial"),
        "{err}"
    );
    let kept = std::fs::read_to_string(&file).expect("the partial file");
    assert!(
        kept.starts_with("# partial: interrupted after "),
        "{}",
        &kept[..80.min(kept.len())]
    );
    assert!(
        kept.lines().count() > 1000,
        "{} lines kept",
        kept.lines().count()
    );
    // The recording carries the device's settings: allan needs neither columns nor scale,
    // and replay runs the profile it was recorded with (the file's, set last above).
    assert!(
        kept.lines().any(|l| l.starts_with("profile,fs_hz=3000,")
            && l.contains(",x_sign=1,")
            && l.contains(",counts_per_inch=800,")),
        "{}",
        &kept[..600.min(kept.len())]
    );
    let out = lab()
        .args(["allan", "--out", "target/lab/cli-allan"])
        .arg(&file)
        .output()
        .expect("allan runs");
    let said = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(
        ["x: ", "y: ", "z: "].iter().all(|a| said.contains(a)),
        "{said}"
    );
    let out = lab()
        .arg("replay")
        .arg(&file)
        .output()
        .expect("replay runs");
    let said = text(&out.stdout);
    assert!(
        said.contains("settings: the recording's profile: 800 counts/inch"),
        "{said}{}",
        text(&out.stderr)
    );
    let out = lab()
        .args(["replay", "--m-s2-per-lsb", "1e9"])
        .arg(&file)
        .output()
        .expect("replay runs");
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.starts_with("error: --m-s2-per-lsb 1e9: takes 0.00478841..=2.3942 here"),
        "{err}"
    );
    let _ = std::fs::remove_file(&file);
    twin.kill().expect("the twin stops");
    twin.wait().expect("reaped");
}

#[test]
fn a_twin_that_cannot_listen_says_so_and_never_that_it_waits() {
    let out = output(&["twin", "--addr", "192.0.2.1:3240", "--seconds", "1"]);
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("cannot listen on 192.0.2.1:3240: this computer has no such address"),
        "{err}"
    );
    assert!(!err.contains("waiting for a host"), "{err}");
    // A port in use (a twin running already) is named as such, with what to do.
    let taken = std::net::TcpListener::bind("127.0.0.1:0").expect("a free port");
    let addr = taken.local_addr().expect("address").to_string();
    let out = output(&["twin", "--addr", &addr, "--seconds", "1"]);
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains(&format!("cannot listen on {addr}: the port is in use")),
        "{err}"
    );
}

#[test]
fn drift_says_why_there_is_no_z_score_and_refuses_a_time_under_a_sample() {
    // The rest recording's z column never changes: no noise the ADC resolves.
    let file = rest_recording("drift");
    let f = file.to_str().expect("utf-8 path");
    // With no --t: the times the file (2 s) holds ten segments of, 0.1 s alone here.
    let out = output(&[
        "drift",
        f,
        "--columns",
        "x,y",
        "--scale",
        "0.01",
        "--calibrate-s",
        "0.05",
        "--out",
        "target/lab/cli-drift",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let rows: Vec<Vec<String>> = text(&out.stdout)
        .lines()
        .filter(|l| l.starts_with("x "))
        .map(|l| l.split_whitespace().map(String::from).collect())
        .collect();
    assert_eq!(rows.len(), 1, "{rows:?}");
    assert_eq!((rows[0][1].as_str(), rows[0][2].as_str()), ("0.1", "13"));
    // With no --calibrate-s either: the device's 1 s window, which the file holds once.
    let out = output(&["drift", f, "--columns", "x,y", "--scale", "0.01"]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    assert!(
        text(&out.stderr).contains("--calibrate-s 1 and --t up to 0.1: a segment is 1.1 s"),
        "{}",
        text(&out.stderr)
    );
    let common = [
        "drift",
        f,
        "--columns",
        "x,y,z",
        "--scale",
        "0.01",
        "--calibrate-s",
        "0.1",
    ];
    let out = output(
        &[
            &common[..],
            &["--t", "0.5", "--out", "target/lab/cli-drift"],
        ]
        .concat(),
    );
    let table = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(!table.contains("inf") && !table.contains("NaN"), "{table}");
    assert!(
        table.contains("n/a") && table.contains("the axis never moved"),
        "{table}"
    );
    assert!(table.contains("fewer than 10 segments"), "{table}");
    let out = output(
        &[
            &common[..],
            &["--t", "0.5", "--json", "--out", "target/lab/cli-drift"],
        ]
        .concat(),
    );
    let rows: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let z_axis = rows["rows"]
        .as_array()
        .and_then(|r| r.iter().find(|row| row["axis"] == "z"))
        .expect("a z row");
    assert!(z_axis["z"].is_null(), "{z_axis}");
    let out = output(&[&common[..], &["--t", "1e-9"]].concat());
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("shorter than one sample"));
    let _ = std::fs::remove_file(&file);
}

#[test]
fn the_lab_says_its_version() {
    let out = output(&["--version"]);
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(
        text(&out.stdout).trim(),
        format!("lab {}", env!("CARGO_PKG_VERSION"))
    );
}

#[test]
fn a_replay_that_never_calibrates_prints_its_table_and_fails_saying_why() {
    let dir = std::env::temp_dir();
    let short = dir.join(format!("imu-cli-{}-short.csv", std::process::id()));
    std::fs::write(
        &short,
        "fs,3000\nn,x,y,z\n0,2048,2048,2457\n1,2048,2048,2457\n",
    )
    .expect("file");
    let railed = dir.join(format!("imu-cli-{}-railed.csv", std::process::id()));
    let mut csv = String::from("fs,3000\nn,x,y,z\n");
    for i in 0..6000 {
        csv += &format!("{i},0,{},2457\n", 2047 + i % 3);
    }
    std::fs::write(&railed, csv).expect("file");
    for (file, why) in [
        (&short, "shorter than the calibration window (1 s)"),
        (&railed, "the last window failed on x: ADC code 0 is a rail"),
    ] {
        let out = lab().arg("replay").arg(file).output().expect("runs");
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{err}");
        assert!(
            text(&out.stdout).contains("sent 0 HID reports"),
            "the table first"
        );
        assert!(
            err.contains("calibration never succeeded") && err.contains(why),
            "{err}"
        );
        let _ = std::fs::remove_file(file);
    }
}

#[test]
fn an_endless_input_is_refused_at_its_first_line_not_read_whole() {
    // /dev/zero has no line end: a reader that reads a line (or the file) whole never
    // returns; the bounded reader refuses it after 64 KiB and quotes only its start.
    for args in [
        &["replay", "/dev/zero"][..],
        &["allan", "/dev/zero", "--columns", "x", "--scale", "1"],
        &[
            "drift",
            "/dev/zero",
            "--columns",
            "x",
            "--scale",
            "1",
            "--calibrate-s",
            "1",
            "--t",
            "1",
        ],
    ] {
        let out = output(args);
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert!(
            err.starts_with("error: /dev/zero: line 1: longer than 65536 bytes"),
            "{args:?}: {err}"
        );
        assert!(err.len() < 200, "{args:?}: quoted short: {err}");
    }
}

#[test]
fn the_twin_refuses_a_recording_its_12_bit_adc_could_not_make() {
    let file = std::env::temp_dir().join(format!("imu-cli-{}-16bit.csv", std::process::id()));
    std::fs::write(
        &file,
        "fs,1000\nn,x,y,z\n0,2048,2048,2048\n1,5000,2048,2048\n",
    )
    .expect("file");
    let out = lab()
        .args(["twin", "--addr", "127.0.0.1:0", "--replay"])
        .arg(&file)
        .output()
        .expect("runs");
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("sample 1: codes [5000, 2048, 2048]: the board's 12-bit ADC gives 0..=4095"),
        "{err}"
    );
    let _ = std::fs::remove_file(&file);
}

#[test]
fn a_list_without_a_board_says_none_was_found() {
    // No board is attached to the machines this runs on.
    let out = output(&["device", "list"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(
        text(&out.stdout).starts_with("no imu-mouse found"),
        "{}",
        text(&out.stdout)
    );
    let out = output(&["device", "--json", "list"]);
    assert_eq!(text(&out.stdout).trim(), "[]");
}

#[test]
fn a_simulated_recording_replays_as_it_was_simulated() {
    let file = std::env::temp_dir().join(format!("imu-cli-{}-sim.csv", std::process::id()));
    let sim = lab()
        .args([
            "simulate",
            "--scene",
            "adxl335-stroke",
            "--seconds",
            "3",
            "--csv",
        ])
        .arg(&file)
        .output()
        .expect("simulate runs");
    assert_eq!(sim.status.code(), Some(0), "{}", text(&sim.stderr));
    let charts = std::env::temp_dir().join(format!("imu-cli-{}-charts", std::process::id()));
    let replay = lab()
        .arg("replay")
        .arg(&file)
        .arg("--out")
        .arg(&charts)
        .output()
        .expect("replay runs");
    assert_eq!(replay.status.code(), Some(0), "{}", text(&replay.stderr));
    // Its charts: the path and the acceleration, each a trace of points.
    for name in ["path.svg", "acceleration.svg"] {
        let svg = std::fs::read_to_string(charts.join(name)).expect("a chart");
        let points = svg
            .lines()
            .find(|l| l.starts_with("<polyline"))
            .map_or(0, |l| l.matches(',').count());
        assert!(points > 100, "{name}: {points} points");
        assert!(text(&replay.stdout).contains(name), "the plots are named");
    }
    let _ = std::fs::remove_dir_all(&charts);
    // The same track, row for row: the scene's settings went with its codes.
    let rows = |t: &str| -> Vec<String> {
        t.lines()
            .skip_while(|l| !l.trim_start().starts_with("t [s]"))
            .filter(|l| !l.starts_with("plots: "))
            .map(String::from)
            .collect()
    };
    let (a, b) = (rows(&text(&sim.stdout)), rows(&text(&replay.stdout)));
    assert!(a.len() > 4, "{}", text(&sim.stdout));
    assert_eq!(a, b);
    // allan takes the columns and the scale from the file.
    let out = lab()
        .args(["allan", "--out", "target/lab/cli-allan-sim"])
        .arg(&file)
        .output()
        .expect("allan runs");
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let _ = std::fs::remove_file(&file);
}

#[test]
fn allan_says_when_an_axis_is_railed_and_when_its_bias_is_only_a_bound() {
    // x noisy, y railed at 4095 throughout, z at the rail 9 samples in 10.
    let file = std::env::temp_dir().join(format!("imu-cli-{}-rail.csv", std::process::id()));
    let mut csv =
        String::from("fs,3000\nprofile,fs_hz=3000,m_s2_per_lsb=0.0239,adc_bits=12\nn,x,y,z\n");
    for i in 0..30_000u32 {
        let noise = (i.wrapping_mul(2_654_435_761) >> 29) as i32 - 4;
        csv += &format!(
            "{i},{},4095,{}\n",
            2048 + noise,
            if i % 10 == 0 { 4094 } else { 4095 }
        );
    }
    std::fs::write(&file, csv).expect("file");
    let out = lab()
        .args(["allan", "--out", "target/lab/cli-allan-rail"])
        .arg(&file)
        .output()
        .expect("runs");
    let said = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(
        said.contains("y: constant at 4095 for all 30000 samples: a railed or dead axis"),
        "{said}"
    );
    assert!(
        !said.contains("y: N_v"),
        "no figures for a railed axis: {said}"
    );
    assert!(
        said.contains("z: 90.0 % of samples at the rail code 4095: clipped"),
        "{said}"
    );
    // Every axis constant: the report, no plot, and a failed run (status 1).
    let mut csv =
        String::from("fs,3000\nprofile,fs_hz=3000,m_s2_per_lsb=0.0239,adc_bits=12\nn,x,y,z\n");
    for i in 0..3000u32 {
        csv += &format!("{i},0,4095,2048\n");
    }
    std::fs::write(&file, csv).expect("file");
    let dir = "target/lab/cli-allan-dead";
    let out = lab()
        .args(["allan", "--out", dir])
        .arg(&file)
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains("z: constant at 2048 for all 3000 samples"));
    assert!(
        text(&out.stderr).starts_with("error: every axis is constant: no noise to measure"),
        "{}",
        text(&out.stderr)
    );
    let plot = Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(dir);
    assert!(!plot.join("allan.svg").exists(), "no empty chart");
    let _ = std::fs::remove_file(&file);
    // The real recording: x's minimum is at its longest tau, so its bias is a bound.
    let out = output(&[
        "allan",
        concat!(env!("CARGO_MANIFEST_DIR"), "/data/mpu6050-static-100hz.csv"),
        "--columns",
        "ax,az",
        "--scale",
        "0.000598550415039",
        "--out",
        "target/lab/cli-allan-real",
    ]);
    let said = text(&out.stdout);
    assert!(
        said.contains("ax: N_v") && said.contains("bias instability <= "),
        "{said}"
    );
    assert!(
        said.contains("ax: the deviation still falls at the longest tau"),
        "{said}"
    );
    assert!(!said.contains("az: the deviation still falls"), "{said}");
}

#[test]
fn plots_land_in_the_workspace_target_wherever_the_lab_runs_from() {
    // cargo runs this test in host-tests/; the workspace's target is one folder up.
    let out = output(&[
        "allan",
        "data/mpu6050-static-100hz.csv",
        "--columns",
        "ax",
        "--scale",
        "0.000598550415039",
        "--out",
        "target/lab/cli-allan-cwd",
    ]);
    let said = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("the workspace");
    let plot = root.join("target/lab/cli-allan-cwd/allan.svg");
    assert!(
        said.contains(&format!("plot: {}", plot.display())),
        "{said}"
    );
    assert!(plot.is_file());
}

#[test]
fn a_repeating_twin_serves_past_the_end_of_its_scene() {
    let (mut twin, addr) = start_twin(&["--scene", "rest", "--seconds", "1", "--repeat"]);
    let info = || output(&["device", "--twin", addr.as_str(), "info"]);
    // Three times its 1 s scene later, it still answers.
    std::thread::sleep(std::time::Duration::from_secs(3));
    let out = info();
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(twin.try_wait().expect("status").is_none(), "still serving");
    // It samples in real time at every rate, one block a millisecond or not: 100 Hz is a
    // block every 10 ms, 1500 Hz one or two a millisecond (it once played one block a
    // millisecond at any rate: 100 Hz ran ten times fast).
    for fs in ["100", "1500"] {
        let set = output(&[
            "device",
            "--twin",
            &addr,
            "config",
            "set",
            &format!("fs_hz={fs}"),
        ]);
        assert_eq!(set.status.code(), Some(0), "{}", text(&set.stderr));
        let started = std::time::Instant::now();
        let file = std::env::temp_dir().join(format!("imu-cli-{}-{fs}.csv", std::process::id()));
        let rec = record_on(&addr, true, "1", &file);
        let took = started.elapsed().as_secs_f64();
        let v: serde_json::Value = serde_json::from_slice(&rec.stdout).expect("JSON");
        assert_eq!(v["samples"].to_string(), fs, "{v}");
        assert_eq!(v["lost"], 0, "{v}");
        assert!(took > 0.9, "{fs} Hz: 1 s recorded in {took:.2} s");
        let _ = std::fs::remove_file(&file);
    }
    twin.kill().expect("the twin stops");
    twin.wait().expect("reaped");
}

/// `cargo lab device --twin ADDR [--json] record --seconds S --out FILE`.
fn record_on(addr: &str, json: bool, seconds: &str, file: &Path) -> Output {
    let mut args = vec!["device", "--twin", addr];
    if json {
        args.push("--json");
    }
    args.extend(["record", "--seconds", seconds, "--out"]);
    lab().args(args).arg(file).output().expect("records")
}

/// `cargo lab device --twin ADDR [--json] check --out DIR`.
fn check_on(addr: &str, json: bool, dir: &str) -> Output {
    let mut args = vec!["device", "--twin", addr];
    if json {
        args.push("--json");
    }
    args.extend(["check", "--out", dir]);
    output(&args)
}

#[test]
fn a_device_check_of_a_good_board_says_so_and_finds_its_mapping() {
    let (mut twin, addr) = start_twin(&["--scene", "check"]);
    let out = check_on(&addr, true, "target/lab/cli-check");
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON alone");
    assert_eq!(v["verdict"]["problems"], serde_json::json!([]));
    assert_eq!(v["verdict"]["mapping"], serde_json::json!([0, 1.0, 1, 1.0]));
    assert_eq!(v["rest"]["gravity"], serde_json::json!([2, 1.0]));
    // The steps are asked for on stderr, in order.
    let err = text(&out.stderr);
    let (a, b) = (
        err.find("RIGHT").expect("asked right"),
        err.find("AWAY").expect("asked away"),
    );
    assert!(a < b, "{err}");
    twin.kill().expect("the twin stops");
    twin.wait().expect("reaped");
}

#[test]
fn a_device_check_of_a_board_mapped_wrong_says_what_to_set() {
    let (mut twin, addr) = start_twin(&["--scene", "check"]);
    let set = output(&["device", "--twin", &addr, "config", "set", "x_sign=-1"]);
    assert_eq!(set.status.code(), Some(0), "{}", text(&set.stderr));
    let out = check_on(&addr, false, "target/lab/cli-check-wrong");
    let said = text(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{said}{}", text(&out.stderr));
    assert!(said.contains("moved right: sensor +X"), "{said}");
    assert!(
        said.contains("PROBLEM: the axes are mapped otherwise: set them with `cargo lab device config set x_axis=0 x_sign=1 y_axis=1 y_sign=1`"),
        "{said}"
    );
    assert!(said.contains("verdict: 1 problem(s) to fix"), "{said}");
    assert!(text(&out.stderr).contains("the check found 1 problem(s)"));
    twin.kill().expect("the twin stops");
    twin.wait().expect("reaped");
}

#[test]
fn a_device_check_whose_rest_holds_a_stroke_says_so_first() {
    // The check scene runs from the first host on, over and over: 4 s recorded first put the
    // check's rest step over 4.x-8.x s of it, across the move right at 6.5-7.0 s.
    let (mut twin, addr) = start_twin(&["--scene", "check", "--repeat"]);
    let file = std::env::temp_dir().join(format!("imu-cli-{}-early.csv", std::process::id()));
    let rec = record_on(&addr, false, "4", &file);
    assert_eq!(rec.status.code(), Some(0), "{}", text(&rec.stderr));
    let out = check_on(&addr, true, "target/lab/cli-check-moved");
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}{}", text(&out.stdout), text(&out.stderr)));
    let first = v["verdict"]["problems"][0].as_str().unwrap_or_default();
    assert!(
        first.starts_with("the mouse moved during the rest step (X went"),
        "{v}"
    );
    assert_eq!(v["rest"]["moved"][0], 0, "{v}");
    let _ = std::fs::remove_file(&file);
    twin.kill().expect("the twin stops");
    twin.wait().expect("reaped");
}

#[test]
fn a_replay_names_the_flag_the_user_gave() {
    let file = rest_recording("flags");
    let out = lab()
        .arg("replay")
        .arg(&file)
        .args(["--adc-bits", "8"])
        .output()
        .expect("runs");
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.starts_with("error: --adc-bits 8: m_s2_per_lsb: the full scale"),
        "{err}"
    );
    let out = lab()
        .args(["allan", "--fs", "0", "--columns", "x", "--scale", "1"])
        .arg(&file)
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    assert!(
        text(&out.stderr).starts_with("error: --fs 0: must be"),
        "{}",
        text(&out.stderr)
    );
    let _ = std::fs::remove_file(&file);
}

#[test]
fn a_trace_describes_its_trial_in_words_and_units() {
    let out = output(&["mouse", "--trace", "drags:1"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let t = text(&out.stdout);
    let lines: Vec<&str> = t.lines().collect();
    assert!(lines[0].starts_with("a trial of "), "{t}");
    assert!(
        lines[1].contains("a drag: up over") && lines[1].contains("mm/s"),
        "{t}"
    );
    assert!(lines.iter().any(|l| l.starts_with("judged: ")), "{t}");
    assert!(
        lines
            .iter()
            .rev()
            .find(|l| !l.is_empty())
            .is_some_and(|l| l.starts_with("end: cursor [")),
        "{t}"
    );
    // No Rust debug text: no struct braces, no Some(..).
    assert!(!t.contains('{') && !t.contains("Some("), "{t}");
}

/// One HTTP/1.1 request to `port` on 127.0.0.1, and the whole answer.
fn http(port: u16, request: &str) -> String {
    use std::io::{Read, Write};
    let mut s = std::net::TcpStream::connect(("127.0.0.1", port)).expect("the page's server");
    s.set_read_timeout(Some(std::time::Duration::from_secs(10)))
        .expect("a timeout");
    s.write_all(request.as_bytes()).expect("sent");
    let mut answer = vec![];
    let _ = s.read_to_end(&mut answer);
    text(&answer)
}

#[test]
fn the_settings_page_server_serves_its_files_and_refuses_what_is_not_its_own() {
    let port = {
        let l = std::net::TcpListener::bind("127.0.0.1:0").expect("a free port");
        l.local_addr().expect("address").port()
    };
    let mut ui = lab()
        .args(["ui", "--port", &port.to_string()])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("the page's server starts");
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(20);
    while std::net::TcpStream::connect(("127.0.0.1", port)).is_err() {
        assert!(std::time::Instant::now() < deadline, "no server");
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    let get = |path: &str| http(port, &format!("GET {path} HTTP/1.1\r\nHost: x\r\n\r\n"));
    let page = get("/");
    assert!(page.starts_with("HTTP/1.1 200 OK"), "{page}");
    assert!(page.contains("<title>imu-mouse settings</title>"), "{page}");
    assert!(get("/imu_protocol.wasm").contains("Content-Type: application/wasm"));
    assert!(get("/index.html").contains("<title>imu-mouse settings</title>"));
    assert!(get("/../Cargo.toml").starts_with("HTTP/1.1 404"));
    let head = http(port, "HEAD / HTTP/1.1\r\nHost: x\r\n\r\n");
    assert!(
        head.starts_with("HTTP/1.1 200 OK") && head.ends_with("\r\n\r\n"),
        "{head}"
    );
    // The bridge only for the page's own origin: another site's page is refused.
    let upgrade = |origin: &str| {
        http(
            port,
            &format!(
                "GET /ws HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nUpgrade: websocket\r\n\
                 Connection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n\
                 Sec-WebSocket-Version: 13\r\nOrigin: {origin}\r\n\r\n"
            ),
        )
    };
    let foreign = upgrade("https://example.com");
    assert!(foreign.starts_with("HTTP/1.1 403"), "{foreign}");
    let own = upgrade(&format!("http://127.0.0.1:{port}"));
    assert!(own.starts_with("HTTP/1.1 101"), "{own}");
    // A check needs its recordings; a malformed one is a bad request, not a crash.
    let post = |body: &str| {
        http(
            port,
            &format!(
                "POST /check HTTP/1.1\r\nHost: x\r\nContent-Length: {}\r\n\r\n{body}",
                body.len()
            ),
        )
    };
    assert!(post("{}").starts_with("HTTP/1.1 400"));
    assert!(post("").starts_with("HTTP/1.1 400"));
    let empty =
        r#"{"fs":3000,"m_s2_per_lsb":0.024,"adc_bits":12,"current":[0,1,1,1],"steps":[[],[],[]]}"#;
    assert!(post(empty).starts_with("HTTP/1.1 400"));
    let still = format!(
        r#"{{"fs":1000,"m_s2_per_lsb":0.0239,"adc_bits":12,"current":[0,1,1,1],"steps":[{s},{s},{s}]}}"#,
        s = format!("[{}]", vec!["[2048,2049,2458]"; 1000].join(","))
    );
    // An axis map no profile has, and codes a 12-bit ADC cannot give: refused, not judged.
    assert!(post(&still.replace("[0,1,1,1]", "[9,7,1,1]")).starts_with("HTTP/1.1 400"));
    assert!(
        post(&still.replace("[2048,2049,2458]", "[5000,2049,2458]")).starts_with("HTTP/1.1 400")
    );
    let judged = post(&still);
    assert!(judged.starts_with("HTTP/1.1 200 OK"), "{judged}");
    assert!(judged.contains("no clear move right was seen"), "{judged}");
    assert!(judged.contains("<svg"), "{judged}");
    ui.kill().expect("stops");
    ui.wait().expect("reaped");
}
