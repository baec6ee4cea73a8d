//! The lab's command-line conventions (`host_tests::commands`), on the built `lab` binary:
//! a closed pipe ends quietly, errors go to stderr with the documented exit status, `--json`
//! prints JSON only, and `cargo lab` alone lists every command with an example.

use std::path::PathBuf;
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
