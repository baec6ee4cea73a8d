//! `cargo lab predict`: the RMS position error each of the paper's laws predicts, for the
//! noise and rate given (the predictor is [`crate::oracle::predict`]).

use crate::oracle::predict;

use super::{json, Error, Outcome};

/// One example, for `cargo lab` alone.
pub const EXAMPLE: &str = "cargo lab predict --fs 3000 --t 1,60 --sigma-c 2.942e-3 --fc 50";

/// `cargo lab predict`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Sampling rate [Hz].
    #[arg(long, allow_negative_numbers = true)]
    pub fs: f64,
    /// Duration [s]; repeat or separate by commas for several. t * fs must be whole.
    #[arg(
        long = "t",
        value_delimiter = ',',
        required = true,
        allow_negative_numbers = true
    )]
    pub t: Vec<f64>,
    /// Per-sample white-noise std [m/s^2].
    #[arg(long, allow_negative_numbers = true)]
    pub sigma_d: Option<f64>,
    /// One-sided noise density into a single-pole filter [m/s^2/sqrt(Hz)]; needs --fc.
    #[arg(long, allow_negative_numbers = true)]
    pub sigma_c: Option<f64>,
    /// The single-pole filter's cut-off [Hz], `0 < fc <= fs / 2` (the paper's analog model
    /// takes fs / 2; the device's own filter, `lowpass_fc_hz`, stays below it); needs --sigma-c.
    #[arg(long, allow_negative_numbers = true)]
    pub fc: Option<f64>,
    /// Constant acceleration bias [m/s^2].
    #[arg(long, allow_negative_numbers = true)]
    pub bias: Option<f64>,
    /// Print a JSON array, one object per --t, instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// Runs `cargo lab predict`.
///
/// # Errors
/// The first invalid input, as the predictor names it.
pub fn run(a: &Args) -> Outcome {
    let inputs = predict::Inputs {
        fs: a.fs,
        t: a.t.clone(),
        sigma_d: a.sigma_d,
        sigma_c: a.sigma_c,
        fc: a.fc,
        bias: a.bias,
    };
    let rows = predict::predict(&inputs).map_err(|e| Error::Input(e.to_string()))?;
    if a.json {
        json(&rows)
    } else {
        Ok(predict::table(&rows))
    }
}
