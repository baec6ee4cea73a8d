//! `cargo lab device`: the device's configuration interface from the command line, on a
//! board (through `hidapi`) or on the twin (`--twin ADDR`, over USB/IP): identity and
//! counters, the configuration by key, save, defaults, recalibrate, and raw recording in the
//! lab's recording format (`allan`, `drift` and `replay` read it).

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use imu_core::profile::{Key, Kind};
use imu_core::protocol::{Info, Source};
use serde::Serialize;

use crate::device::client::{Client, ClientError, HidLink, Link, Recorded};
use crate::device::usbip::BUSID;
use crate::device::usbip_host::{UsbIpError, UsbIpHost};
use crate::formats::recording;

use super::{positive, progress, Error, Outcome};

/// One example, for `cargo lab` alone.
pub const EXAMPLE: &str =
    "cargo lab device config set counts_per_inch=1600 && cargo lab device save   (a board; the twin: cargo lab device --twin 127.0.0.1:3240 info)";

/// `cargo lab device`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Talk to the twin (`cargo lab twin`) at this USB/IP address instead of a board.
    #[arg(long, global = true)]
    pub twin: Option<std::net::SocketAddr>,
    /// How long an answer may take [s].
    #[arg(
        long,
        global = true,
        allow_negative_numbers = true,
        default_value_t = 5.0
    )]
    pub timeout: f64,
    /// Print JSON instead of text.
    #[arg(long, global = true)]
    pub json: bool,
    /// What to do.
    #[command(subcommand)]
    pub what: What,
}

/// The device commands.
#[derive(clap::Subcommand, Debug)]
pub enum What {
    /// Firmware, protocol, where the settings came from, counters, last calibration.
    Info,
    /// Read or change the settings (applied at once, kept only by `save`).
    Config {
        /// `get`, or `set`.
        #[command(subcommand)]
        op: ConfigOp,
    },
    /// Keep the running settings in the device's flash.
    Save,
    /// Run and keep the default settings.
    Defaults,
    /// Calibrate again (keep the device still for the calibration window).
    Recalibrate,
    /// Record raw ADC codes to a CSV file in the lab's recording format.
    Record {
        /// Length [s] at the device's sampling rate.
        #[arg(long, allow_negative_numbers = true)]
        seconds: f64,
        /// The file to write.
        #[arg(long, default_value = "target/lab/device/recording.csv")]
        out: PathBuf,
    },
}

/// `cargo lab device config ...`.
#[derive(clap::Subcommand, Debug)]
pub enum ConfigOp {
    /// Every key and its value.
    Get,
    /// `KEY=VALUE ...`, applied as a whole or not at all (`off` for an optional value).
    Set {
        /// `KEY=VALUE` pairs, e.g. `counts_per_inch=1600 lowpass_fc_hz=off`.
        #[arg(required = true)]
        pairs: Vec<String>,
    },
}

/// The words `scheme` takes, by value.
const SCHEMES: [&str; 2] = ["euler", "trapezoid"];

/// A key's value as a user reads it (and writes it: `config set` takes it back).
fn show(key: Key, v: f64) -> String {
    match key.kind() {
        Kind::Optional if v.is_nan() => "off".into(),
        Kind::Flag => (if v == 1.0 { "on" } else { "off" }).into(),
        _ if key == Key::Scheme => SCHEMES
            .get(v as usize)
            .map_or_else(|| format!("{v}"), |w| (*w).into()),
        _ => format!("{v}"),
    }
}

/// What a key's value must be, in words, for an error message.
fn wanted(key: Key) -> &'static str {
    match key.kind() {
        Kind::Flag => "must be on or off",
        Kind::Optional => "must be a finite number or off",
        _ if key == Key::Scheme => "must be euler or trapezoid",
        _ => "must be a finite number",
    }
}

/// `KEY=VALUE` parsed.
///
/// # Errors
/// [`Error::Input`] (exit 2) naming the pair: no `=`, an unknown key, a value the key does
/// not take (a number; `off`/`on` where the key takes them; `euler`/`trapezoid`).
pub fn parse_pair(pair: &str) -> Result<(Key, f64), Error> {
    let bad = |why: &str| Error::Input(format!("config set {pair}: {why}"));
    let (k, v) = pair
        .split_once('=')
        .ok_or_else(|| bad("must be KEY=VALUE"))?;
    let key = Key::from_name(k.trim()).ok_or_else(|| {
        let names: Vec<&str> = Key::ALL.iter().map(|k| k.name()).collect();
        bad(&format!("unknown key; the keys: {}", names.join(", ")))
    })?;
    let v = v.trim();
    let word = match key.kind() {
        Kind::Optional if v == "off" => Some(f64::NAN),
        Kind::Flag => ["off", "on"].iter().position(|w| *w == v).map(|i| i as f64),
        _ if key == Key::Scheme => SCHEMES.iter().position(|w| *w == v).map(|i| i as f64),
        _ => None,
    };
    let number = || v.parse::<f64>().ok().filter(|x| x.is_finite());
    let value = word.or_else(number).ok_or_else(|| bad(wanted(key)))?;
    Ok((key, value))
}

/// Every pair of one `config set` parsed; a key given twice is refused (which one was
/// meant?).
///
/// # Errors
/// [`parse_pair`]'s, or [`Error::Input`] naming the repeated key.
pub fn parse_pairs(pairs: &[String]) -> Result<Vec<(Key, f64)>, Error> {
    let parsed = pairs
        .iter()
        .map(|p| parse_pair(p))
        .collect::<Result<Vec<_>, _>>()?;
    for (i, (k, _)) in parsed.iter().enumerate() {
        if parsed[..i].iter().any(|(j, _)| j == k) {
            return Err(Error::Input(format!(
                "config set: {k} is given twice; give each key once"
            )));
        }
    }
    Ok(parsed)
}

/// A recording's file checked before the device is asked for anything: not a folder, and
/// its folder exists (a typo in a path is not created silently).
///
/// # Errors
/// [`Error::Arg`] naming `--out`.
fn writable(out: &std::path::Path) -> Result<(), Error> {
    if out.is_dir() {
        return Err(Error::arg(
            "out",
            out.display(),
            "is a folder; give a file name",
        ));
    }
    match out.parent().filter(|d| !d.as_os_str().is_empty()) {
        Some(dir) if !dir.is_dir() => Err(Error::arg(
            "out",
            out.display(),
            format!("its folder {} does not exist", dir.display()),
        )),
        _ => Ok(()),
    }
}

#[derive(Serialize)]
struct InfoOut {
    firmware: String,
    protocol: u8,
    profile: String,
    fs_hz: u32,
    tracking: bool,
    streaming: bool,
    samples: u64,
    lost: u64,
    restarts: u32,
    reports: u32,
    rejected_windows: u32,
    /// Per tracker axis (cursor x, cursor y, vertical): bias and rms noise [LSB].
    calibration: Option<Vec<(f64, f64)>>,
}

fn source(info: &Info) -> String {
    let key = Key::from_id(info.invalid_key).map_or(String::new(), |k| format!(" ({k})"));
    match info.source {
        Source::Defaults => "defaults (none stored)".into(),
        Source::Stored => "stored".into(),
        Source::Corrupt => "defaults: the store was unreadable".into(),
        Source::Invalid => format!("defaults: the stored profile no longer validates{key}"),
        Source::Changed => "changed since start-up, not saved".into(),
    }
}

fn info<L: Link>(c: &mut Client<L>, json: bool) -> Outcome {
    let i = c.info()?;
    let k = c.counters()?;
    let cal = c.calibration()?;
    let out = InfoOut {
        firmware: format!("{}.{}.{}", i.firmware[0], i.firmware[1], i.firmware[2]),
        protocol: i.protocol,
        profile: source(&i),
        fs_hz: i.fs_hz,
        tracking: i.tracking,
        streaming: i.streaming,
        samples: k.samples,
        lost: k.lost,
        restarts: k.restarts,
        reports: k.reports,
        rejected_windows: k.rejected_windows,
        calibration: cal.map(|axes| {
            axes.iter()
                .map(|a| {
                    (
                        a.bias_q16 as f64 / 65_536.0,
                        f64::from(a.noise_rms_q16) / 65_536.0,
                    )
                })
                .collect()
        }),
    };
    if json {
        return super::json(&out);
    }
    let mut s = format!(
        "firmware {} (protocol {}), profile: {}\nfs {} Hz, {}\nsamples {} lost {} restarts {} \
         reports {} rejected calibration windows {}",
        out.firmware,
        out.protocol,
        out.profile,
        out.fs_hz,
        if out.tracking {
            "tracking"
        } else {
            "calibrating"
        },
        out.samples,
        out.lost,
        out.restarts,
        out.reports,
        out.rejected_windows
    );
    match &out.calibration {
        None => s.push_str("\nnot calibrated yet"),
        Some(axes) => {
            for (name, (bias, rms)) in ["cursor x", "cursor y", "vertical"].iter().zip(axes) {
                s.push_str(&format!(
                    "\n{name}: bias {bias:.3} LSB, noise {rms:.3} LSB rms"
                ));
            }
        }
    }
    Ok(s)
}

fn config_get<L: Link>(c: &mut Client<L>, json: bool) -> Outcome {
    let pairs = c.config()?;
    if json {
        let map: serde_json::Map<String, serde_json::Value> = pairs
            .iter()
            .map(|(k, v)| {
                let value = if v.is_nan() {
                    serde_json::Value::Null
                } else {
                    serde_json::json!(v)
                };
                (k.name().to_string(), value)
            })
            .collect();
        return super::json(&map);
    }
    Ok(pairs
        .iter()
        .map(|(k, v)| format!("{k}={}", show(*k, *v)))
        .collect::<Vec<_>>()
        .join("\n"))
}

/// Set by Ctrl-C during a recording.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Records `seconds` (checked by [`check_args`], like `out`) into `out`.
fn record<L: Link>(c: &mut Client<L>, seconds: f64, out: &PathBuf, json: bool) -> Outcome {
    let fs = c.info()?.fs_hz;
    let n = (seconds * f64::from(fs)).round().max(1.0) as usize;
    // Ctrl-C ends the recording and keeps what arrived (a second one would need the
    // handler again: a process installs it once).
    let _ = ctrlc::set_handler(|| INTERRUPTED.store(true, Ordering::Relaxed));
    let bar = progress(n as u64, json, "samples");
    let rec = c.record_until(n, |k| bar.set_position(k as u64), &INTERRUPTED)?;
    bar.finish_and_clear();
    let mut text = recording::write(&recording::Recording {
        fs,
        samples: rec.samples.clone(),
    });
    if rec.interrupted {
        text.insert_str(
            0,
            &format!(
                "# partial: interrupted after {} of {n} samples\n",
                rec.samples.len()
            ),
        );
    }
    std::fs::write(out, text).map_err(|e| Error::file(out, e))?;
    if rec.interrupted {
        return Err(Error::Run(format!(
            "interrupted: the {} samples that arrived are in {} (marked partial)",
            rec.samples.len(),
            out.display()
        )));
    }
    summary(&rec, fs, out, json)
}

#[derive(Serialize)]
struct RecordOut<'a> {
    file: &'a std::path::Path,
    fs_hz: u32,
    samples: usize,
    frames: u32,
    lost: u64,
    gaps: &'a [(usize, u64)],
    missing_frames: u32,
}

fn summary(rec: &Recorded, fs: u32, out: &std::path::Path, json: bool) -> Outcome {
    let r = RecordOut {
        file: out,
        fs_hz: fs,
        samples: rec.samples.len(),
        frames: rec.frames,
        lost: rec.lost(),
        gaps: &rec.gaps,
        missing_frames: rec.missing_frames,
    };
    let text = if json {
        serde_json::to_string_pretty(&r)?
    } else {
        format!(
            "{}: {} samples at {} Hz in {} frames",
            out.display(),
            r.samples,
            fs,
            r.frames
        )
    };
    if r.lost > 0 || r.missing_frames > 0 {
        // Written, and said: a gap is lost time, which the lab's readers refuse to hide.
        return Err(Error::Check {
            report: text,
            why: format!(
                "{} samples lost in {} gaps (first at sample {}), {} frames missing: the file \
                 holds the samples that arrived; lower fs_hz to record without loss",
                r.lost,
                rec.gaps.len(),
                rec.gaps.first().map_or(0, |g| g.0),
                r.missing_frames
            ),
        });
    }
    Ok(text)
}

fn dispatch<L: Link>(mut c: Client<L>, a: &Args) -> Outcome {
    match &a.what {
        What::Info => info(&mut c, a.json),
        What::Config { op: ConfigOp::Get } => config_get(&mut c, a.json),
        What::Config {
            op: ConfigOp::Set { pairs },
        } => {
            c.set(&parse_pairs(pairs)?)?;
            config_get(&mut c, a.json)
        }
        What::Save => {
            c.save()?;
            done(a.json, "saved", "saved")
        }
        What::Defaults => {
            c.defaults()?;
            done(a.json, "defaults", "defaults running and saved")
        }
        What::Recalibrate => {
            c.recalibrate()?;
            done(
                a.json,
                "recalibrating",
                "recalibrating: keep the device still",
            )
        }
        What::Record { seconds, out } => record(&mut c, *seconds, out, a.json),
    }
}

/// A command that only acknowledges: `{"done": WHAT}` with `--json`, else `text`.
fn done(json: bool, what: &str, text: &str) -> Outcome {
    if json {
        return super::json(&serde_json::json!({ "done": what }));
    }
    Ok(text.into())
}

/// The arguments checked before the device is asked for anything.
fn check_args(a: &Args) -> Result<(), Error> {
    positive("timeout", a.timeout)?;
    match &a.what {
        What::Config {
            op: ConfigOp::Set { pairs },
        } => parse_pairs(pairs).map(|_| ()),
        What::Record { seconds, out } => {
            positive("seconds", *seconds)?;
            writable(out)
        }
        _ => Ok(()),
    }
}

impl From<ClientError> for Error {
    fn from(e: ClientError) -> Self {
        use imu_core::protocol::ErrorCode;
        match e {
            // A value the device refuses is a bad argument (exit 2), named by its key.
            ClientError::Refused(
                ErrorCode::Value(_) | ErrorCode::Invalid(_) | ErrorCode::Unsupported(_),
            ) => Error::Input(e.to_string()),
            _ => Error::Run(e.to_string()),
        }
    }
}

/// A twin that could not be reached, with what to do about it.
fn unreachable(addr: std::net::SocketAddr, timeout: Duration, e: UsbIpError) -> Error {
    use std::io::ErrorKind;
    match &e {
        UsbIpError::Io(io) if io.kind() == ErrorKind::ConnectionRefused => Error::Run(format!(
            "no twin listens on {addr}: start one with `cargo lab twin --addr {addr}` (it \
             serves until its scene has played)"
        )),
        UsbIpError::Io(io) if matches!(io.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {
            Error::Run(format!(
                "the twin at {addr} did not answer within {timeout:?}: it serves one host at a \
                 time; is another `cargo lab device` or a USB/IP host attached to it?"
            ))
        }
        _ => Error::Run(e.to_string()),
    }
}

/// Runs `cargo lab device`.
///
/// # Errors
/// A bad argument, no device, a refusal (naming the key), a recording with gaps.
pub fn run(a: &Args) -> Outcome {
    check_args(a)?;
    let timeout = Duration::from_secs_f64(a.timeout);
    match a.twin {
        Some(addr) => {
            let host = UsbIpHost::connect(addr, BUSID, timeout)
                .map_err(|e| unreachable(addr, timeout, e))?;
            dispatch(Client::new(host, timeout), a)
        }
        None => dispatch(Client::new(HidLink::open()?, timeout), a),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pairs_parse_with_words_for_off_on_and_schemes() {
        assert_eq!(
            parse_pair("counts_per_inch=1600").ok(),
            Some((Key::CountsPerInch, 1600.0))
        );
        let (k, v) = parse_pair("lowpass_fc_hz=off").expect("off");
        assert!(k == Key::LowpassFcHz && v.is_nan());
        assert_eq!(parse_pair("drift=off").ok(), Some((Key::Drift, 0.0)));
        assert_eq!(parse_pair("drift=on").ok(), Some((Key::Drift, 1.0)));
        assert_eq!(
            parse_pair("scheme=trapezoid").ok(),
            Some((Key::Scheme, 1.0))
        );
        assert_eq!(parse_pair(" x_sign = -1 ").ok(), Some((Key::XSign, -1.0)));
        for bad in [
            "counts_per_inch",
            "cpi=3",
            "fs_hz=fast",
            "fs_hz=inf",
            "fs_hz=off",
        ] {
            let e = parse_pair(bad).expect_err(bad);
            assert!(e.to_string().contains(bad.trim()), "{e}");
        }
    }

    #[test]
    fn values_show_as_a_user_writes_them() {
        assert_eq!(show(Key::LowpassFcHz, f64::NAN), "off");
        assert_eq!(show(Key::Drift, 1.0), "on");
        assert_eq!(show(Key::FsHz, 3000.0), "3000");
        assert_eq!(show(Key::Scheme, 0.0), "euler");
        assert_eq!(show(Key::Scheme, 1.0), "trapezoid");
        // Every key's shown value reads back as itself.
        for (k, v) in [
            (Key::Scheme, 1.0),
            (Key::Drift, 0.0),
            (Key::CountsPerInch, 800.0),
        ] {
            assert_eq!(
                parse_pair(&format!("{k}={}", show(k, v))).ok(),
                Some((k, v))
            );
        }
    }

    #[test]
    fn refusals_say_what_the_key_takes() {
        for (pair, want) in [
            ("drift=maybe", "must be on or off"),
            ("scheme=rk4", "must be euler or trapezoid"),
            ("lowpass_fc_hz=low", "a finite number or off"),
            ("fs_hz=off", "must be a finite number"),
        ] {
            let e = parse_pair(pair).expect_err(pair).to_string();
            assert!(e.contains(want) && e.starts_with("config set "), "{e}");
            assert!(!e.starts_with("--"), "{e}");
        }
        let twice = [
            "counts_per_inch=800".to_string(),
            "counts_per_inch=1600".to_string(),
        ];
        let e = parse_pairs(&twice).expect_err("twice").to_string();
        assert!(e.contains("counts_per_inch is given twice"), "{e}");
    }
}
