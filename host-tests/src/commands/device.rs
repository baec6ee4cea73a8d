//! `cargo lab device`: the device's configuration interface from the command line, on a
//! board (through `hidapi`) or on the twin (`--twin ADDR`, over USB/IP): identity and
//! counters, the configuration by key, save, defaults, recalibrate, and raw recording in the
//! lab's recording format (`allan`, `drift` and `replay` read it).

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use imu_core::profile::{Key, Kind, Profile};
use imu_core::protocol::{ErrorCode, Info, Source};
use serde::Serialize;

use crate::device::client::{Client, ClientError, Found, HidLink, Link, Recorded};
use crate::device::profile::{self, profile_of, show};
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
    /// The device with this USB serial number (`list` shows them); without it, the only one.
    #[arg(long, global = true)]
    pub serial: Option<String>,
    /// What to do.
    #[command(subcommand)]
    pub what: What,
}

/// The device commands.
#[derive(clap::Subcommand, Debug)]
pub enum What {
    /// The imu-mice on this computer (or the twin): serial, product, release, path.
    List,
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
    /// Calibrate again, wait for a window at rest (at most 10 windows) and show the new zero.
    Recalibrate,
    /// Check a board: its noise and zero at rest against the ADXL335 data sheet, rails and
    /// dead axes, gravity, then a move right and one away to find the axis mapping; a verdict
    /// and a chart.
    Check {
        /// Time to record at rest [s].
        #[arg(long, allow_negative_numbers = true, default_value_t = CHECK_REST_S)]
        rest_s: f64,
        /// Time given to each move [s].
        #[arg(long, allow_negative_numbers = true, default_value_t = CHECK_MOVE_S)]
        move_s: f64,
        /// Directory for the chart.
        #[arg(long, default_value = "target/lab/device-check")]
        out: PathBuf,
    },
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

/// How long `check` records at rest, by default [s].
const CHECK_REST_S: f64 = 4.0;
/// How long `check` gives each move, by default [s].
const CHECK_MOVE_S: f64 = 5.0;

/// `cargo lab device config ...`.
#[derive(clap::Subcommand, Debug)]
pub enum ConfigOp {
    /// Every key and its value.
    Get,
    /// `KEY=VALUE ...`, applied as a whole or not at all (`off` for an optional value).
    Set {
        /// `KEY=VALUE` pairs, e.g. `counts_per_inch=1600 lowpass_fc_hz=off`; with `--file`,
        /// they change the file's values.
        #[arg(required_unless_present = "file")]
        pairs: Vec<String>,
        /// A profile written by `config get --json` (a JSON object of key: value).
        #[arg(long)]
        file: Option<PathBuf>,
    },
}

/// `KEY=VALUE` parsed ([`profile::read_pair`]).
///
/// # Errors
/// [`Error::Input`] (exit 2) naming the pair and what the key takes.
pub fn parse_pair(pair: &str) -> Result<(Key, f64), Error> {
    profile::read_pair(pair).map_err(|why| Error::Input(format!("config set {why}")))
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

/// The pairs of a profile file (`config get --json`'s object: a number, `null` for off,
/// `true`/`false` for a flag, a word), then the command line's `pairs`, which replace the
/// file's value of a key they name.
///
/// # Errors
/// [`Error::File`] naming the file and the entry: unreadable, not a JSON object, an unknown
/// key, a value the key does not take; or [`parse_pairs`]' errors.
pub fn profile_pairs(
    file: Option<&std::path::Path>,
    pairs: &[String],
) -> Result<Vec<(Key, f64)>, Error> {
    let cli = parse_pairs(pairs)?;
    let Some(path) = file else {
        return Ok(cli);
    };
    let bad = |why: String| Error::file(path, why);
    let text = std::fs::read_to_string(path).map_err(|e| Error::file(path, super::io_words(&e)))?;
    let map = profile::file_entries(&text).map_err(bad)?;
    let mut out = Vec::with_capacity(map.len() + cli.len());
    for (name, v) in &map {
        let flag = Key::from_name(name).is_some_and(|k| k.kind() == Kind::Flag);
        let word = match v {
            serde_json::Value::Null => "off".to_string(),
            serde_json::Value::Bool(b) if flag => (if *b { "on" } else { "off" }).to_string(),
            serde_json::Value::Number(n) => n.to_string(),
            serde_json::Value::String(w) => w.clone(),
            other => {
                return Err(bad(format!(
                    "{name}: {other} is not a value this key takes"
                )))
            }
        };
        let (key, value) = parse_pair(&format!("{name}={word}"))
            .map_err(|e| bad(e.to_string().replacen("config set ", "", 1)))?;
        if !cli.iter().any(|(k, _)| *k == key) {
            out.push((key, value));
        }
    }
    out.extend(cli);
    Ok(out)
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
    /// The cursor's motion since power-up [counts] (right, down).
    counts: [i64; 2],
    /// What the tracker is doing (`TrackerState::name`).
    tracker: &'static str,
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
        counts: k.counts,
        tracker: k.tracker.name(),
        calibration: cal.map(|axes| zeros(&axes)),
    };
    if json {
        return super::json(&out);
    }
    let mut s = format!(
        "firmware {} (protocol {}), profile: {}\nfs {} Hz, {}\nsamples {} lost {} restarts {} \
         reports {} rejected calibration windows {}\ncursor {}, {} counts since power-up (right, down)",
        out.firmware,
        out.protocol,
        out.profile,
        out.fs_hz,
        if out.tracking {
            format!("tracking ({})", out.tracker)
        } else {
            "calibrating".into()
        },
        out.samples,
        out.lost,
        out.restarts,
        out.reports,
        out.rejected_windows,
        out.counts[0],
        out.counts[1]
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

/// What `key` takes on this device with the rest of `p`, as a user writes it, with the
/// unit after the numbers when `unit` is asked for.
fn takes(p: &Profile, key: Key, unit: bool) -> String {
    let mut s = String::new();
    // Writing into a String cannot fail.
    let _ = imu_app::device::takes(&mut s, p, key, unit);
    s
}

/// A value as JSON: a number, `null` for off, `true`/`false` for a flag, a word for the
/// scheme (what [`profile_pairs`] reads back).
fn json_value(key: Key, v: f64) -> serde_json::Value {
    match key.kind() {
        Kind::Optional if v.is_nan() => serde_json::Value::Null,
        Kind::Flag => serde_json::Value::Bool(v == 1.0),
        _ if key == Key::Scheme => serde_json::Value::String(show(key, v)),
        // Integers as integers (`800`, not `800.0`): carried exactly in the f64.
        Kind::Integer { .. } | Kind::Sign => serde_json::json!(v as i64),
        _ => serde_json::json!(v),
    }
}

fn config_get<L: Link>(c: &mut Client<L>, json: bool) -> Outcome {
    let pairs = c.config()?;
    if json {
        let map: serde_json::Map<String, serde_json::Value> = pairs
            .iter()
            .map(|&(k, v)| (k.name().to_string(), json_value(k, v)))
            .collect();
        return super::json(&map);
    }
    let p = profile_of(&pairs);
    let rows: Vec<[String; 5]> = pairs
        .iter()
        .map(|&(k, v)| {
            [
                k.name().to_string(),
                show(k, v),
                k.unit().to_string(),
                takes(&p, k, false),
                k.about().to_string(),
            ]
        })
        .collect();
    let width = |i: usize| rows.iter().map(|r| r[i].len()).max().unwrap_or(0);
    let (w0, w1, w2, w3) = (width(0), width(1), width(2), width(3));
    let mut out = format!(
        "{:w0$}  {:w1$}  {:w2$}  {:w3$}  what it does\n",
        "key", "value", "unit", "takes"
    );
    for r in &rows {
        out += &format!(
            "{:w0$}  {:w1$}  {:w2$}  {:w3$}  {}\n",
            r[0], r[1], r[2], r[3], r[4]
        );
    }
    out.push_str(
        "(config set KEY=VALUE ...; `takes` is for this profile: some ranges follow fs_hz)",
    );
    Ok(out)
}

/// A refusal of `pairs` by the device, with what the refused key takes there.
fn refused<L: Link>(c: &mut Client<L>, pairs: &[(Key, f64)], code: ErrorCode) -> Error {
    let (ErrorCode::Value(key) | ErrorCode::Invalid(key) | ErrorCode::Unsupported(key)) = code
    else {
        return Error::from(ClientError::Refused(code));
    };
    // The profile the set would have made (the device kept its own).
    let mut p = match c.config() {
        Ok(now) => profile_of(&now),
        Err(_) => Profile::default(),
    };
    for &(k, v) in pairs {
        let _ = p.set(k, v);
    }
    let given = pairs
        .iter()
        .find(|(k, _)| *k == key)
        .map_or_else(String::new, |&(k, v)| format!(" {k}={}", show(k, v)));
    let why = match (code, key) {
        (ErrorCode::Unsupported(_), Key::FsHz) => format!(
            "this board samples at {}, at rates that divide its 96 MHz clock (1000, 3000, \
             20000 do; 7000 does not)",
            takes(&p, key, true)
        ),
        (ErrorCode::Unsupported(_), Key::AdcBits) => {
            format!("this board's ADC has {} bits", imu_app::device::ADC_BITS)
        }
        (ErrorCode::Invalid(_), Key::XAxis | Key::YAxis) => {
            "x_axis and y_axis must be different sensor axes (0 X, 1 Y, 2 Z)".into()
        }
        _ => format!(
            "{}{key} takes {}{}: {}",
            if given.is_empty() {
                format!(
                    "the device's {key}={} would no longer fit; ",
                    show(key, p.get(key))
                )
            } else {
                String::new()
            },
            takes(&p, key, true),
            context(&p, key, pairs),
            key.about()
        ),
    };
    Error::Input(format!("config set:{given} refused by the device: {why}"))
}

/// The settings `key`'s range follows in profile `p`, as ` at fs_hz=100 (given in this set)`:
/// each of fs_hz, adc_bits and m_s2_per_lsb whose change would move the range (found by
/// asking the key table at another value), marked where `pairs` changes it in the same set.
fn context(p: &Profile, key: Key, pairs: &[(Key, f64)]) -> String {
    let range = |p: &Profile| imu_app::device::range(p, key).map(|r| r.to_string());
    let moves = |on: Key| {
        let now = p.get(on);
        // Values far from the profile's (those the key table takes are tried).
        let others = match on {
            Key::FsHz => [100.0, 20_000.0],
            Key::AdcBits => [2.0, 16.0],
            _ => [now / 2.0, now * 2.0],
        };
        others.into_iter().any(|v| {
            let mut q = *p;
            q.set(on, v).is_ok() && range(&q) != range(p)
        })
    };
    let deps: Vec<String> = [Key::FsHz, Key::AdcBits, Key::MS2PerLsb]
        .into_iter()
        .filter(|&on| on != key && moves(on))
        .map(|on| {
            let given = if pairs.iter().any(|(k, _)| *k == on) {
                " (given in this set)"
            } else {
                ""
            };
            format!("{on}={}{given}", show(on, p.get(on)))
        })
        .collect();
    if deps.is_empty() {
        " here".into()
    } else {
        format!(" at {}", deps.join(", "))
    }
}

/// Set by Ctrl-C during a recording.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Records `seconds` (checked by [`check_args`], like `out`) into `out`.
fn record<L: Link>(c: &mut Client<L>, seconds: f64, out: &std::path::Path, json: bool) -> Outcome {
    let fs = c.info()?.fs_hz;
    // The settings it records under go into the file: `replay`, `allan` and `drift` read them.
    let settings = c.config()?;
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
        profile: Some(profile::to_text(&settings)),
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
    let out = &super::resolve(out);
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

/// `seconds` of samples at `fs` [Hz], with the lost ones said (a check on a gap is unsound).
fn take<L: Link>(c: &mut Client<L>, seconds: f64, fs: u32) -> Result<Vec<[u16; 3]>, Error> {
    let n = (seconds * f64::from(fs)).round() as usize;
    let rec = c.record_until(n, |_| {}, &INTERRUPTED)?;
    if rec.interrupted {
        return Err(Error::Run("interrupted".into()));
    }
    if rec.lost() > 0 || rec.missing_frames > 0 {
        return Err(Error::Run(format!(
            "{} samples lost while recording: lower fs_hz (or close other USB traffic) and \
             check again",
            rec.lost()
        )));
    }
    Ok(rec.samples)
}

/// `cargo lab device check`: at rest, then a move right, then one away; the verdict.
fn check<L: Link>(
    c: &mut Client<L>,
    [rest_s, move_s]: [f64; 2],
    out: &std::path::Path,
    json: bool,
) -> Outcome {
    use crate::device::check;
    let fs = c.info()?.fs_hz;
    let p = profile_of(&c.config()?);
    let (m, bits) = (p.config.m_s2_per_lsb, p.config.adc_bits);
    let _ = ctrlc::set_handler(|| INTERRUPTED.store(true, Ordering::Relaxed));
    eprintln!("check 1/3: keep the mouse still, flat on the desk, for {rest_s} s ...");
    let still = take(c, rest_s, fs)?;
    eprintln!(
        "check 2/3: now slide the mouse straight to the RIGHT, about 10 cm (within {move_s} s) ..."
    );
    let moved_right = take(c, move_s, fs)?;
    eprintln!(
        "check 3/3: now slide it straight AWAY from you, about 10 cm (within {move_s} s) ..."
    );
    let moved_away = take(c, move_s, fs)?;
    let sign = |flip: bool| if flip { -1.0 } else { 1.0 };
    let current = (
        usize::from(p.map.x_axis),
        sign(p.map.x_flip),
        usize::from(p.map.y_axis),
        sign(p.map.y_flip),
    );
    let steps: [&[[u16; 3]]; 3] = [&still, &moved_right, &moved_away];
    let fs = f64::from(fs);
    let check::Checked {
        rest,
        right,
        away,
        verdict: v,
    } = check::judge(steps, fs, m, bits, current);
    let colors = [super::COLORS[0], super::COLORS[1], super::COLORS[2]];
    let chart = check::chart(steps, fs, m, &rest, colors);
    let plot = super::write_out(out, "check.svg", &chart.to_svg())?;
    let report = if json {
        super::json(&serde_json::json!({
            "rest": rest, "right": right, "away": away, "verdict": v, "plot": plot,
        }))?
    } else {
        let mut t = String::new();
        for (k, a) in rest.axes.iter().enumerate() {
            t += &format!(
                "{}: {:.1} LSB ({:+.3} g), noise {:.2} LSB rms{}\n",
                check::AXES[k],
                a.mean_lsb,
                a.reading_g,
                a.sd_lsb,
                a.noise_density_ug
                    .map_or_else(String::new, |nd| format!(", {nd:.0} ug/sqrt(Hz)"))
            );
        }
        for (what, s) in [("right", &right), ("away", &away)] {
            t += &match s {
                Some(s) => format!(
                    "moved {what}: sensor {}{} (peak {:.2} m/s^2)\n",
                    if s.sign > 0.0 { "+" } else { "-" },
                    check::AXES[s.axis],
                    s.peak_m_s2
                ),
                None => format!("moved {what}: not seen\n"),
            };
        }
        for n in &v.notes {
            t += &format!("ok: {n}\n");
        }
        for pr in &v.problems {
            t += &format!("PROBLEM: {pr}\n");
        }
        t += &format!(
            "verdict: {}\nplot: {}",
            if v.problems.is_empty() {
                "the board looks right".to_string()
            } else {
                format!("{} problem(s) to fix, above", v.problems.len())
            },
            plot.display()
        );
        t
    };
    if v.problems.is_empty() {
        return Ok(report);
    }
    Err(Error::Check {
        report,
        why: format!("the check found {} problem(s)", v.problems.len()),
    })
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
        // Answered before a device is opened (`run`).
        What::List => Err(Error::Run("list opens no device".into())),
        What::Info => info(&mut c, a.json),
        What::Config { op: ConfigOp::Get } => config_get(&mut c, a.json),
        What::Config {
            op: ConfigOp::Set { pairs, file },
        } => {
            let pairs = profile_pairs(file.as_deref(), pairs)?;
            match c.set(&pairs) {
                Err(ClientError::Refused(code)) => return Err(refused(&mut c, &pairs, code)),
                other => other?,
            }
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
        What::Recalibrate => recalibrate(&mut c, a.json),
        What::Record { seconds, out } => record(&mut c, *seconds, out, a.json),
        What::Check {
            rest_s,
            move_s,
            out,
        } => check(&mut c, [*rest_s, *move_s], out, a.json),
    }
}

/// How many calibration windows `recalibrate` waits through for one at rest.
const RECALIBRATE_WINDOWS: u32 = 10;

/// Per tracker axis (cursor x, cursor y, vertical): the zero and the rms noise [LSB].
fn zeros(axes: &[imu_core::protocol::AxisCalibration; 3]) -> Vec<(f64, f64)> {
    axes.iter()
        .map(|a| {
            (
                a.bias_q16 as f64 / 65_536.0,
                f64::from(a.noise_rms_q16) / 65_536.0,
            )
        })
        .collect()
}

/// Asks for a calibration, waits until a window at rest is taken (at most
/// [`RECALIBRATE_WINDOWS`] windows), and shows the new zero.
fn recalibrate<L: Link>(c: &mut Client<L>, json: bool) -> Outcome {
    let pairs = c.config()?;
    let window_s = pairs
        .iter()
        .find(|(k, _)| *k == Key::CalibrationS)
        .map_or(1.0, |p| p.1);
    let rejected = c.counters()?.rejected_windows;
    c.recalibrate()?;
    let started = std::time::Instant::now();
    let limit = Duration::from_secs_f64(window_s * f64::from(RECALIBRATE_WINDOWS) + 1.0);
    let bar = progress(0, json, "");
    bar.set_message("calibrating: keep the device still");
    while !c.info()?.tracking {
        if started.elapsed() > limit {
            bar.finish_and_clear();
            let n = c.counters()?.rejected_windows.saturating_sub(rejected);
            return Err(Error::Run(format!(
                "no calibration in {:.1} s: {n} window(s) of {window_s} s rejected as motion \
                 or clipping (noise over rest_noise_max_m_s2, or a code at a rail); keep the \
                 device still and on its feet, then run recalibrate again",
                started.elapsed().as_secs_f64()
            )));
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    bar.finish_and_clear();
    let took = started.elapsed().as_secs_f64();
    let axes = c.calibration()?.map(|a| zeros(&a)).unwrap_or_default();
    if json {
        return super::json(&serde_json::json!({
            "done": "recalibrated",
            "seconds": took,
            "calibration": axes,
        }));
    }
    let mut text = format!("recalibrated in {took:.1} s; the new zero:");
    for (name, (bias, rms)) in ["cursor x", "cursor y", "vertical"].iter().zip(&axes) {
        text += &format!("\n{name}: zero {bias:.3} LSB, noise {rms:.3} LSB rms");
    }
    Ok(text)
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
    if a.timeout > 3600.0 {
        return Err(Error::arg(
            "timeout",
            crate::formats::number::Num(a.timeout),
            "at most 3600 s",
        ));
    }
    match &a.what {
        What::Config {
            op: ConfigOp::Set { pairs, file },
        } => profile_pairs(file.as_deref(), pairs).map(|_| ()),
        What::Record { seconds, out } => {
            positive("seconds", *seconds)?;
            super::writable("out", out)
        }
        What::Check {
            rest_s,
            move_s,
            out,
        } => {
            super::folder("out", out)?;
            for (name, v, why) in [
                (
                    "rest-s",
                    *rest_s,
                    "the noise is read at 0.1 s and needs ten of them",
                ),
                (
                    "move-s",
                    *move_s,
                    "a slide of 10 cm takes half a second, and a hand needs a moment to start",
                ),
            ] {
                if !(v.is_finite() && (1.0..=60.0).contains(&v)) {
                    return Err(Error::arg(
                        name,
                        crate::formats::number::Num(v),
                        format!("must be 1 to 60 s ({why}; a minute at most)"),
                    ));
                }
            }
            Ok(())
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
             serves until its scene has played; --repeat keeps it serving)"
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

/// The devices `list` shows: the boards on this host's USB, or the twin at `--twin`.
fn list(a: &Args, timeout: Duration) -> Outcome {
    let found = match a.twin {
        Some(addr) => {
            let mut host = UsbIpHost::connect(addr, BUSID, timeout)
                .map_err(|e| unreachable(addr, timeout, e))?;
            let serial = host.serial().map_err(|e| Error::Run(e.to_string()))?;
            let release = host.release().map_err(|e| Error::Run(e.to_string()))?;
            vec![Found {
                serial: serial.unwrap_or_default(),
                product: imu_app::identity::PRODUCT.into(),
                release: crate::device::client::release_text(release),
                path: format!("usbip://{addr}/{BUSID}"),
            }]
        }
        None => HidLink::list()?.1,
    };
    if a.json {
        return super::json(&found);
    }
    if found.is_empty() {
        return Ok(
            "no imu-mouse found (on Linux a user needs the udev rule of docs/device.md)".into(),
        );
    }
    Ok(found
        .iter()
        .map(|f| format!("{}  {}  {}  {}", f.serial, f.product, f.release, f.path))
        .collect::<Vec<_>>()
        .join("\n"))
}

/// Runs `cargo lab device`.
///
/// # Errors
/// A bad argument, no device (or not the one `--serial` names), a refusal (naming the key),
/// a recording with gaps.
pub fn run(a: &Args) -> Outcome {
    check_args(a)?;
    let timeout = Duration::from_secs_f64(a.timeout);
    if matches!(a.what, What::List) {
        return list(a, timeout);
    }
    match a.twin {
        Some(addr) => {
            let mut host = UsbIpHost::connect(addr, BUSID, timeout)
                .map_err(|e| unreachable(addr, timeout, e))?;
            if let Some(want) = &a.serial {
                let serial = host.serial().map_err(|e| Error::Run(e.to_string()))?;
                if serial.as_deref() != Some(want.as_str()) {
                    return Err(Error::Run(format!(
                        "the twin at {addr} has serial {}, not {want}",
                        serial.as_deref().unwrap_or("(none)")
                    )));
                }
            }
            dispatch(Client::new(host, timeout), a)
        }
        None => dispatch(Client::new(HidLink::open(a.serial.as_deref())?, timeout), a),
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
