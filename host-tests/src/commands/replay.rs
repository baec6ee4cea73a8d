//! `cargo lab replay`: a recording of ADC codes ([`crate::formats::recording`]) through the
//! whole device ([`crate::device::track`]).

use crate::device::profile;
use crate::device::track;
use crate::formats::recording;

use super::{positive, Error, Outcome};

/// One example, for `cargo lab` alone.
pub const EXAMPLE: &str =
    "cargo lab replay stroke.csv   (one to play: cargo lab simulate --scene adxl335-stroke --csv stroke.csv)";

/// `cargo lab replay`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The recording: CSV of ADC codes (format: docs/lab.md, "replay"; `device record` and
    /// `simulate --csv` write it).
    pub file: std::path::PathBuf,
    /// Sampling rate [Hz], if the file does not say.
    #[arg(long, allow_negative_numbers = true)]
    pub fs: Option<f64>,
    /// Acceleration per ADC code [m/s^2], instead of the recording's profile (without one:
    /// an ADXL335 on a 12-bit ratiometric ADC, 0.0239 m/s^2).
    #[arg(long, allow_negative_numbers = true)]
    pub m_s2_per_lsb: Option<f64>,
    /// ADC resolution [bits], instead of the recording's profile (without one: 12).
    #[arg(long)]
    pub adc_bits: Option<u8>,
    /// Interval of the printed track [s].
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.5)]
    pub every: f64,
    /// Print JSON instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Directory for the charts (the cursor's path, the acceleration).
    #[arg(long, default_value = "target/lab/replay")]
    pub out: std::path::PathBuf,
}

/// Runs `cargo lab replay`.
///
/// # Errors
/// An unreadable or malformed recording, a bad interval, a configuration the core refuses.
pub fn run(a: &Args) -> Outcome {
    super::folder("out", &a.out)?;
    // The arguments first (status 2), before the file is read.
    let fs_arg = a.fs.map(|fs| positive("fs", fs)).transpose()?;
    let every = positive("every", a.every)?;
    if every > 3600.0 {
        return Err(Error::arg(
            "every",
            crate::formats::number::Num(every),
            "at most 3600 s",
        ));
    }
    let rec =
        recording::parse(super::open(&a.file)?, fs_arg).map_err(|e| Error::file(&a.file, e))?;
    // The device's settings as recorded, else the board's defaults; the flags change them.
    let recorded = rec
        .profile
        .as_deref()
        .map(profile::from_text)
        .transpose()
        .map_err(|e| Error::file(&a.file, e))?;
    let (mut p, from) = match &recorded {
        Some(pairs) => (profile::profile_of(pairs), "the recording's profile"),
        None => (
            imu_core::Profile::default(),
            "the defaults (the file has no profile)",
        ),
    };
    p.config.fs_hz = rec.fs;
    if let Some(m) = a.m_s2_per_lsb {
        p.config.m_s2_per_lsb = m;
    }
    if let Some(b) = a.adc_bits {
        p.config.adc_bits = b;
    }
    p.validate().map_err(|e| argument(e, &p, a, from))?;
    let accel = track::acceleration(&p.config, &p.map, &rec.samples);
    let t = track::run_mapped(&p.config, &p.map, rec.samples, every)
        .map_err(|e| Error::Input(e.to_string()))?;
    let name = a
        .file
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let (path, acc) = track::charts(&t, &accel, &name);
    let path = super::write_out(&a.out, "path.svg", &path.to_svg())?;
    let acc = super::write_out(&a.out, "acceleration.svg", &acc.to_svg())?;
    let overridden: Vec<&str> = [
        a.m_s2_per_lsb.map(|_| "--m-s2-per-lsb"),
        a.adc_bits.map(|_| "--adc-bits"),
    ]
    .into_iter()
    .flatten()
    .collect();
    let report = if a.json {
        super::json(&Replayed {
            settings: Used {
                from,
                changed_by: overridden,
                counts_per_inch: p.config.counts_per_inch,
                m_s2_per_lsb: p.config.m_s2_per_lsb,
                adc_bits: p.config.adc_bits,
                drift_control: p.config.drift.is_some(),
            },
            track: &t,
        })?
    } else {
        let with = if overridden.is_empty() {
            String::new()
        } else {
            format!(", changed by {}", overridden.join(" and "))
        };
        format!(
            "{}\nsettings: {from}{with}: {} counts/inch, {} m/s^2 per code at {} bits, drift \
             control {}\n{}",
            a.file.display(),
            p.config.counts_per_inch,
            imu_core::profile::Shown(p.config.m_s2_per_lsb),
            p.config.adc_bits,
            if p.config.drift.is_some() {
                "on"
            } else {
                "off"
            },
            track::table(&t)
        ) + &format!("plots: {} and {}", path.display(), acc.display())
    };
    super::tracked(&t, report)
}

/// `replay --json`: the settings the recording ran with, then what the device did (its
/// counts right and down: `y` positive down, as the HID report's).
#[derive(serde::Serialize)]
struct Replayed<'a> {
    settings: Used<'a>,
    #[serde(flatten)]
    track: &'a track::Track,
}

/// The settings a replay ran with (the table's `settings:` line).
#[derive(serde::Serialize)]
struct Used<'a> {
    /// Where they came from: the recording's profile or the defaults.
    from: &'a str,
    /// The flags that changed them.
    changed_by: Vec<&'a str>,
    /// The cursor's resolution [counts per inch].
    counts_per_inch: u32,
    /// Acceleration per ADC code [m/s^2].
    m_s2_per_lsb: f64,
    /// The ADC's resolution [bits].
    adc_bits: u8,
    /// Whether drift control ran (`false`: the paper's plain integration).
    drift_control: bool,
}

/// A refusal of the replayed profile, naming the flag the user gave (a resolution that
/// makes the recorded scale span too little names `--adc-bits`), else where the settings came
/// from.
fn argument(e: imu_core::ProfileError, p: &imu_core::Profile, a: &Args, from: &str) -> Error {
    use imu_core::profile::Key;
    let key = match e.key() {
        Key::MS2PerLsb if a.m_s2_per_lsb.is_none() && a.adc_bits.is_some() => Key::AdcBits,
        k => k,
    };
    let flag = match key {
        Key::MS2PerLsb if a.m_s2_per_lsb.is_some() => Some("m-s2-per-lsb"),
        Key::AdcBits if a.adc_bits.is_some() => Some("adc-bits"),
        _ => None,
    };
    match flag {
        Some(name) => Error::arg(
            name,
            imu_core::profile::Shown(p.get(key)),
            format!(
                "{}{}",
                p.range(key)
                    .filter(|_| key == e.key())
                    .map_or_else(String::new, |r| format!("takes {r} here: ")),
                e
            ),
        ),
        None => Error::Input(format!("the settings ({from}) do not run: {e}")),
    }
}
