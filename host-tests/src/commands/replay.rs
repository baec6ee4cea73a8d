//! `cargo lab replay`: a recording of ADC codes ([`crate::formats::recording`]) through the
//! whole device ([`crate::device::track`]).

use crate::device::track;
use crate::formats::recording;
use crate::world::scene;

use super::{positive, Error, Outcome};

/// One example, for `cargo lab` alone.
pub const EXAMPLE: &str =
    "cargo lab replay stroke.csv   (one to play: cargo lab simulate --scene adxl335-stroke --csv stroke.csv)";

/// `cargo lab replay`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The recording (format: `cargo lab replay --help` and the README).
    pub file: std::path::PathBuf,
    /// Sampling rate [Hz], if the file does not say.
    #[arg(long, allow_negative_numbers = true)]
    pub fs: Option<f64>,
    /// Acceleration per ADC code [m/s^2] (default: ADXL335 on a 12-bit ratiometric ADC).
    #[arg(long, allow_negative_numbers = true, default_value_t = scene::ADXL335_LSB)]
    pub m_s2_per_lsb: f64,
    /// ADC resolution [bits].
    #[arg(long, default_value_t = 12)]
    pub adc_bits: u8,
    /// Interval of the printed track [s].
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.5)]
    pub every: f64,
    /// Print JSON instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// Runs `cargo lab replay`.
///
/// # Errors
/// An unreadable or malformed recording, a bad interval, a configuration the core refuses.
pub fn run(a: &Args) -> Outcome {
    // The arguments first (status 2), before the file is read.
    let fs_arg = a.fs.map(|fs| positive("fs", fs)).transpose()?;
    let every = positive("every", a.every)?;
    let rec =
        recording::parse(super::open(&a.file)?, fs_arg).map_err(|e| Error::file(&a.file, e))?;
    let config = imu_core::Config {
        fs_hz: rec.fs,
        m_s2_per_lsb: a.m_s2_per_lsb,
        adc_bits: a.adc_bits,
        ..imu_core::Config::default()
    };
    let t = track::run(&config, rec.samples, every).map_err(|e| Error::Input(e.to_string()))?;
    let report = if a.json {
        super::json(&t)?
    } else {
        format!("{}\n{}", a.file.display(), track::table(&t))
    };
    super::tracked(&t, report)
}
