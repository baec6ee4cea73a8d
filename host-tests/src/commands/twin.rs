//! `cargo lab twin`: the firmware's application as a USB/IP mouse on this host
//! ([`crate::device::twin`]), fed in real time by the desk scene or a recording. KEY is
//! pressed and released by `press` and `release` lines on stdin, the bus suspended and resumed
//! by `suspend` and `resume` lines.

use std::sync::atomic::Ordering;

use crate::device::flash::FileFlash;
use crate::device::twin;
use crate::formats::recording;
use crate::world::desk;

use super::{positive, Error, Outcome};

/// One example, for `cargo lab` alone.
pub const EXAMPLE: &str = "cargo lab twin --seconds 30   (then: usbip attach -r 127.0.0.1 -b 1-1)";

/// `cargo lab twin`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The scene: `desk` (strokes, rests and clicks), `rest` (the hand still for
    /// `--seconds`, 10 s if not given) or `check` (flat, still, then a stroke right and one
    /// away: what `cargo lab device check` asks for).
    #[arg(long, default_value = "desk", conflicts_with = "replay")]
    pub scene: String,
    /// Play a recording (CSV of ADC codes, as `cargo lab replay`) instead of a scene.
    #[arg(long)]
    pub replay: Option<std::path::PathBuf>,
    /// Play at most this long [s] (default: the whole scene or recording).
    #[arg(long, allow_negative_numbers = true)]
    pub seconds: Option<f64>,
    /// Strokes in the desk scene.
    #[arg(long, default_value_t = 20)]
    pub strokes: usize,
    /// Seed of every random draw (the same seed, the same scene).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// USB/IP address to listen on.
    #[arg(long, default_value = "127.0.0.1:3240")]
    pub addr: std::net::SocketAddr,
    /// How long to wait for a host to configure the device [s].
    #[arg(long, allow_negative_numbers = true, default_value_t = 60.0)]
    pub wait_host: f64,
    /// Keep the device's flash (its saved profile) in this file across runs; without it
    /// the twin starts with an erased flash (the defaults).
    #[arg(long)]
    pub flash: Option<std::path::PathBuf>,
    /// Play the scene or recording again and again, serving until Ctrl-C (without it the
    /// twin goes away when the scene has played). The first host must still come within
    /// `--wait-host`.
    #[arg(long)]
    pub repeat: bool,
    /// The device's USB serial number (`cargo lab device list` shows it; a board's is its
    /// MCU's unique ID).
    #[arg(long, default_value = "TWIN0001")]
    pub serial: String,
    /// Print JSON instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// The device's inputs for the scene or recording asked for.
fn input(a: &Args) -> Result<twin::Input, Error> {
    let mut input = match &a.replay {
        Some(file) => {
            let rec =
                recording::parse(super::open(file)?, None).map_err(|e| Error::file(file, e))?;
            // The twin's ADC is the board's: a code it cannot make is not a recording of it.
            let top = (1u16 << imu_app::device::ADC_BITS) - 1;
            if let Some((i, s)) = rec
                .samples
                .iter()
                .enumerate()
                .find(|(_, s)| s.iter().any(|&c| c > top))
            {
                return Err(Error::file(
                    file,
                    format!(
                        "sample {i}: codes {s:?}: the board's {}-bit ADC gives 0..={top}",
                        imu_app::device::ADC_BITS
                    ),
                ));
            }
            twin::Input {
                fs_hz: rec.fs,
                codes: rec.samples,
                held: Vec::new(),
            }
        }
        None => {
            let (codes, held) = match a.scene.as_str() {
                "desk" => desk::stream(a.strokes, a.seed),
                "rest" => desk::rest(a.seconds.unwrap_or(10.0).clamp(0.0, 86_400.0), a.seed),
                "check" => desk::check(a.seed),
                other => return Err(Error::arg("scene", other, "`desk`, `rest` or `check`")),
            };
            twin::Input {
                fs_hz: desk::FS as u32,
                codes,
                held,
            }
        }
    };
    if let Some(s) = a.seconds {
        positive("seconds", s)?;
        let n = (s * f64::from(input.fs_hz)) as usize;
        input.codes.truncate(n);
        input.held.truncate(n);
    }
    Ok(input)
}

/// The operator on stdin: KEY, held while the last of `press` / `release` was `press`; and
/// the bus, suspended by `suspend` and resumed by `resume` (USB/IP has no suspend).
fn operator() -> twin::Operator {
    let op = twin::Operator::default();
    let (key, bus) = (op.key.clone(), op.bus.clone());
    std::thread::spawn(move || {
        for line in std::io::stdin().lines().map_while(Result::ok) {
            match line.trim() {
                "press" => key.store(true, Ordering::Relaxed),
                "release" => key.store(false, Ordering::Relaxed),
                "suspend" => bus.store(twin::SUSPEND, Ordering::Relaxed),
                "resume" => bus.store(twin::RESUME, Ordering::Relaxed),
                _ => {}
            }
        }
    });
    op
}

/// Runs `cargo lab twin` until the scene has played and the host has drained it.
///
/// # Errors
/// A bad argument or recording; the socket; no host within `--wait-host`.
pub fn run(a: &Args) -> Outcome {
    if a.strokes == 0 || a.strokes > 10_000 {
        return Err(Error::arg("strokes", a.strokes, "1..=10000"));
    }
    let input = input(a)?;
    positive("wait-host", a.wait_host)?;
    if a.serial.is_empty()
        || a.serial.len() > 32
        || !a
            .serial
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b == b'-')
    {
        return Err(Error::arg(
            "serial",
            &a.serial,
            "must be 1 to 32 letters, digits or dashes",
        ));
    }
    if let Some(path) = &a.flash {
        if !path.exists() {
            super::writable("flash", path)?;
        }
    }
    let flash = match &a.flash {
        Some(path) => FileFlash::open(path).map_err(|e| Error::file(path, e))?,
        None => FileFlash::blank(),
    };
    let operator = operator();
    let settings = twin::Settings {
        addr: a.addr,
        wait_host_s: a.wait_host,
        drain_s: 2.0,
        // One twin a process: its serial lives as long as the process.
        serial: Box::leak(a.serial.clone().into_boxed_str()),
        repeat: a.repeat,
    };
    let s = twin::run(&input, settings, operator, flash).map_err(|e| Error::Run(e.to_string()))?;
    if a.json {
        return Ok(serde_json::to_string(&s)?);
    }
    Ok(format!(
        "twin: {:.1} s at {} Hz ({} at the end; profile: {}), {} reports (peak {} per s), \
         {} URBs, {} stalls, {} stream frames\n\
         counts (x, y): produced {:?}, sent {:?}, discarded {:?}, owed {:?}; accounted: {}\n\
         housekeeping ticks that started over 1 ms late (this computer's scheduler, not the \
         device): {}",
        s.scene_s,
        s.fs_hz,
        s.final_fs_hz,
        s.profile_source,
        s.reports,
        s.peak_report_rate_hz,
        s.urbs,
        s.stalls,
        s.stream_frames,
        s.produced,
        s.sent,
        s.discarded,
        s.undelivered,
        s.accounted,
        s.late_ticks
    ))
}
