//! The imu-mouse lab: `cargo lab <command>`; `cargo lab` alone lists the commands with an
//! example each. This file only parses and dispatches: each command is a module of
//! `host_tests::commands`, with its arguments, its run and the conventions they share.

use std::io::Write;
use std::process::ExitCode;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use host_tests::commands::{self as cmd, Error};

#[derive(Parser)]
#[command(
    name = "lab",
    version,
    about = "imu-mouse lab: inertial position error, predicted and measured"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// RMS position error predicted by the paper's laws and the exact finite-N results.
    Predict(cmd::predict::Args),
    /// Fixed-point error of each core stage against its f64 twin, with derived bounds.
    Budget(cmd::budget::Args),
    /// The USB HID report descriptor and the reports the device sends for a motion.
    Hid(cmd::hid::Args),
    /// The paper's laws by Monte Carlo through the real core: table, plots, JSON.
    Reproduce(cmd::reproduce::Args),
    /// One simulated scene through the whole device: the cursor's track and what it sends.
    Simulate(cmd::simulate::Args),
    /// A recorded trace (CSV of ADC codes) through the whole device.
    Replay(cmd::replay::Args),
    /// Speed against error: QEMU instruction counts, host ns, error vs f64.
    Speed(cmd::speed::Args),
    /// The mouse on a desk: strokes, rests, clicks, with and without drift control.
    Mouse(cmd::mouse::Args),
    /// Overlapping Allan deviation of a recording, and the noise figures read from it.
    Allan(cmd::allan::Args),
    /// The paper's experiment on a recording: calibrate, integrate, RMS over segments.
    Drift(cmd::drift::Args),
    /// The firmware's app as a USB/IP mouse on this host, fed in real time by a scene or a
    /// recording (`usbip attach -r 127.0.0.1 -b 1-1` makes it a mouse of a Linux desktop).
    Twin(cmd::twin::Args),
    /// The device's settings and raw recording over its configuration interface, on a
    /// board (hidapi) or the twin (`--twin 127.0.0.1:3240`).
    Device(cmd::device::Args),
    /// The settings page on 127.0.0.1, bridged to a board (hidapi) or the twin (`--twin`).
    Ui(cmd::ui::Args),
}

/// Each command with one example, in the order of `Command`.
const EXAMPLES: [(&str, &str); 13] = [
    ("predict", cmd::predict::EXAMPLE),
    ("budget", cmd::budget::EXAMPLE),
    ("hid", cmd::hid::EXAMPLE),
    ("reproduce", cmd::reproduce::EXAMPLE),
    ("simulate", cmd::simulate::EXAMPLE),
    ("replay", cmd::replay::EXAMPLE),
    ("speed", cmd::speed::EXAMPLE),
    ("mouse", cmd::mouse::EXAMPLE),
    ("allan", cmd::allan::EXAMPLE),
    ("drift", cmd::drift::EXAMPLE),
    ("twin", cmd::twin::EXAMPLE),
    ("device", cmd::device::EXAMPLE),
    ("ui", cmd::ui::EXAMPLE),
];

fn examples() -> String {
    let mut s = String::from("Examples:\n");
    for (name, example) in EXAMPLES {
        s += &format!("  {name:<10} {example}\n");
    }
    s + "\n`cargo lab <command> --help` for a command's arguments."
}

fn run(command: &Command) -> cmd::Outcome {
    match command {
        Command::Predict(a) => cmd::predict::run(a),
        Command::Budget(a) => cmd::budget::run(a),
        Command::Hid(a) => cmd::hid::run(a),
        Command::Reproduce(a) => cmd::reproduce::run(a),
        Command::Simulate(a) => cmd::simulate::run(a),
        Command::Replay(a) => cmd::replay::run(a),
        Command::Speed(a) => cmd::speed::run(a),
        Command::Mouse(a) => cmd::mouse::run(a),
        Command::Device(a) => cmd::device::run(a),
        Command::Allan(a) => cmd::allan::run(a),
        Command::Drift(a) => cmd::drift::run(a),
        Command::Twin(a) => cmd::twin::run(a),
        Command::Ui(a) => cmd::ui::run(a),
    }
}

/// Writes `text` and a newline to stdout. A reader that has gone (`| head`) is not an error.
fn emit(text: &str) -> std::io::Result<()> {
    let mut out = std::io::stdout().lock();
    writeln!(out, "{text}").and_then(|()| out.flush())
}

fn main() -> ExitCode {
    let help = || Cli::command().after_help(examples());
    let cli = match Cli::from_arg_matches(&help().get_matches()) {
        Ok(cli) => cli,
        Err(e) => e.exit(),
    };
    let (text, failure) = match cli.command.as_ref().map(run) {
        None => (help().render_help().to_string(), None),
        Some(Ok(text)) => (text, None),
        Some(Err(Error::Check { report, why })) => (report, Some((why, 1))),
        Some(Err(e)) => (String::new(), Some((e.to_string(), e.exit_code()))),
    };
    if !text.is_empty() {
        if let Err(e) = emit(&text) {
            if e.kind() != std::io::ErrorKind::BrokenPipe {
                eprintln!("error: stdout: {e}");
                return ExitCode::FAILURE;
            }
        }
    }
    match failure {
        None => ExitCode::SUCCESS,
        Some((why, code)) => {
            eprintln!("error: {why}");
            ExitCode::from(code)
        }
    }
}
