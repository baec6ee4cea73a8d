//! `cargo lab hid`: the report descriptor the device presents and the exact reports it would
//! send to move the cursor by `(dx, dy)` counts with some buttons held, using the core's own
//! descriptor and report scheduler.

use imu_core::hid::{buttons, Reporter, MOUSE_REPORT_DESCRIPTOR};
use serde::Serialize;

/// Largest `|dx|` or `|dy|` accepted [counts]: 8 000 reports at most.
pub const MAX_MOTION: i32 = 1_000_000;

/// Why the request cannot be shown.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum HidError {
    /// `--dx` or `--dy` beyond [`MAX_MOTION`].
    #[error("--{axis} {value}: motion must be within +-{MAX_MOTION} counts")]
    Motion {
        /// `dx` or `dy`.
        axis: &'static str,
        /// The rejected value.
        value: i64,
    },
    /// `--buttons` has bits the descriptor does not declare.
    #[error("--buttons {0}: the mouse has buttons 1 (left), 2 (right) and 4 (middle): 0..=7")]
    Buttons(u32),
}

/// What the device would put on the wire.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Wire {
    /// The report descriptor, lowercase hex without separators.
    pub descriptor_hex: String,
    /// Each input report, in order, as hex.
    pub reports_hex: Vec<String>,
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// The reports for a motion of `(dx, dy)` counts with `held` buttons, from rest with nothing
/// held; the USB stack accepts every report.
///
/// # Errors
/// A [`HidError`] naming the out-of-range argument.
pub fn wire(dx: i64, dy: i64, held: u32) -> Result<Wire, HidError> {
    for (axis, value) in [("dx", dx), ("dy", dy)] {
        if value.abs() > i64::from(MAX_MOTION) {
            return Err(HidError::Motion { axis, value });
        }
    }
    let held = u8::try_from(held)
        .ok()
        .filter(|b| b & !buttons::ALL == 0)
        .ok_or(HidError::Buttons(held))?;
    let mut reporter = Reporter::default();
    reporter.set_buttons(held);
    reporter.add_motion(dx as i32, dy as i32); // within +-1e6: exact
    let mut reports_hex = vec![];
    while let Some(report) = reporter.pending() {
        reports_hex.push(hex(&report.to_bytes()));
        reporter.sent(&report);
    }
    Ok(Wire {
        descriptor_hex: hex(&MOUSE_REPORT_DESCRIPTOR),
        reports_hex,
    })
}

/// A readable listing of the wire bytes.
pub fn listing(w: &Wire) -> String {
    let mut out = format!(
        "report descriptor ({} bytes): {}\n{} report(s), 4 bytes each: buttons, x, y, wheel\n",
        w.descriptor_hex.len() / 2,
        w.descriptor_hex,
        w.reports_hex.len()
    );
    for r in &w.reports_hex {
        out += &format!("  {r}\n");
    }
    out
}

/// One example, for `cargo lab` alone.
pub const EXAMPLE: &str = "cargo lab hid --dx 300 --dy -5 --buttons 1";

/// `cargo lab hid`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Motion to the right [counts].
    #[arg(long, allow_negative_numbers = true)]
    pub dx: i64,
    /// Motion downwards [counts] (HID convention).
    #[arg(long, allow_negative_numbers = true)]
    pub dy: i64,
    /// Buttons held: 1 left, 2 right, 4 middle, summed.
    #[arg(long, default_value_t = 0)]
    pub buttons: u32,
    /// Print `{"descriptor_hex": .., "reports_hex": [..]}` instead of the listing.
    #[arg(long)]
    pub json: bool,
}

/// Runs `cargo lab hid`.
///
/// # Errors
/// A motion or a button set out of range.
pub fn run(a: &Args) -> super::Outcome {
    let w = wire(a.dx, a.dy, a.buttons).map_err(|e| super::Error::Input(e.to_string()))?;
    if a.json {
        Ok(serde_json::to_string(&w)?)
    } else {
        Ok(listing(&w))
    }
}
