//! `cargo lab drift`: the paper's experiment on a recording. The recording is cut into
//! independent segments; in each, the core's calibration estimates the bias over the first
//! `TC` seconds and the core's pipeline (pure double integration, as in the paper)
//! integrates the next `T`. The RMS of the positions over segments, with its 95 % interval,
//! is the measured error. Beside it, the error predicted from the Allan figures alone:
//!
//! ```text
//! white noise (eq 27):              N_v T^1.5 / sqrt(3)
//! the calibration's own bias error: (N_v / sqrt(TC)) T^2 / 2   (the mean of TC s of white noise)
//! bias instability, growing as T^2:  B T^2 / 2
//! predicted = the three in quadrature
//! ```

use imu_core::{AdcCode, Axis, Config};
use serde::Serialize;

use crate::stats::allan::Figures;
use crate::stats::MeanSquare;

/// One row: one axis at one T.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Row {
    /// Column name.
    pub axis: String,
    /// Integration time [s].
    pub t_s: f64,
    /// Segments measured.
    pub segments: usize,
    /// RMS position over segments [m].
    pub measured_m: f64,
    /// 95 % interval [m].
    pub ci_low_m: f64,
    /// 95 % interval [m].
    pub ci_high_m: f64,
    /// Predicted RMS [m].
    pub predicted_m: f64,
    /// Its white-noise part [m].
    pub white_m: f64,
    /// Its calibration-bias part [m].
    pub calibration_m: f64,
    /// Its bias-instability part [m].
    pub instability_m: f64,
    /// z-score of the prediction (normal approximation: rough with few segments); `None`
    /// where there is none to take: an axis that never moved (its codes constant, or railed:
    /// no noise the ADC resolves, so the prediction is 0).
    pub z: Option<f64>,
}

/// Fewer segments than this give an interval too wide to judge a law by (the table says so).
pub const FEW_SEGMENTS: usize = 10;

/// A refusal of the core's, in the experiment's arguments: the user gave `--calibrate-s`
/// and `--scale`, not the core's keys.
fn argument(e: imu_core::ConfigError, c: &Config) -> String {
    use imu_core::config::{
        ConfigError, CALIBRATION_SAMPLES_MIN, CALIBRATION_S_MAX, FULL_SCALE_MAX_M_S2,
        FULL_SCALE_MIN_M_S2,
    };
    use imu_core::profile::Shown as Num;
    let codes = f64::from(1u32 << c.adc_bits);
    match e {
        ConfigError::CalibrationWindow => format!(
            "--calibrate-s {}: the window must hold at least {CALIBRATION_SAMPLES_MIN} samples \
             ({} s at {} Hz) and last at most {CALIBRATION_S_MAX} s",
            Num(c.calibration_s),
            Num(f64::from(CALIBRATION_SAMPLES_MIN) / f64::from(c.fs_hz)),
            c.fs_hz
        ),
        ConfigError::Scale => format!(
            "--scale {}: the experiment runs the core on {}-bit codes, so the scale must be \
             {}..={} m/s^2 per count (a full scale of 2 to 1000 g)",
            Num(c.m_s2_per_lsb),
            c.adc_bits,
            Num(FULL_SCALE_MIN_M_S2 / codes),
            Num(FULL_SCALE_MAX_M_S2 / codes)
        ),
        other => other.to_string(),
    }
}

/// Runs the experiment on counts `raw` (one vector per axis) at `fs` with `scale`
/// [m/s^2 per count].
///
/// # Errors
/// A message naming the argument that makes the experiment impossible.
pub fn experiment(
    names: &[String],
    raw: &[Vec<f64>],
    fs: f64,
    scale: f64,
    calibrate_s: f64,
    ts: &[f64],
    figures: &[Figures],
) -> Result<Vec<Row>, String> {
    let fs_hz = fs.round();
    if (fs - fs_hz).abs() > 1e-9 * fs {
        return Err(format!(
            "sampling rate {fs} Hz: the core needs a whole number of Hz"
        ));
    }
    if let Some(t) = ts.iter().find(|&&t| (t * fs).round() < 1.0) {
        return Err(format!(
            "--t {t}: shorter than one sample at {fs} Hz ({} s)",
            1.0 / fs
        ));
    }
    let t_max = ts.iter().copied().fold(0.0, f64::max);
    let cal_n = (calibrate_s * fs).round() as usize;
    let seg = cal_n + (t_max * fs).round() as usize;
    let n = raw.first().map_or(0, Vec::len);
    let segments = n / seg.max(1);
    if segments < 2 {
        return Err(format!(
            "--calibrate-s {calibrate_s} and --t up to {t_max}: a segment is {} s, and the recording ({:.1} s) holds {segments}; at least 2 are needed",
            seg as f64 / fs,
            n as f64 / fs
        ));
    }
    let config = Config {
        fs_hz: fs_hz as u32,
        m_s2_per_lsb: scale,
        adc_bits: 16,
        calibration_s: calibrate_s,
        // The recording is at rest by construction: every window is taken as rest.
        rest_noise_max_m_s2: imu_core::config::REST_NOISE_MAX_M_S2,
        drift: None,
        ..Config::default()
    };
    let settings = config.validate().map_err(|e| argument(e, &config))?;
    let signed = raw.iter().flatten().any(|&v| v < 0.0);
    let offset = if signed { 32_768.0 } else { 0.0 };
    let to_code = |v: f64| -> Result<AdcCode, String> {
        let c = (v + offset).round();
        if (0.0..=65_535.0).contains(&c) {
            Ok(AdcCode(c as u16))
        } else {
            Err(format!("value {v} does not fit a 16-bit code"))
        }
    };
    let steps: Vec<usize> = ts.iter().map(|&t| (t * fs).round() as usize).collect();
    let mut rows = vec![];
    for (k, (name, col)) in names.iter().zip(raw).enumerate() {
        let mut pos = vec![vec![]; ts.len()];
        for s in 0..segments {
            let chunk = &col[s * seg..(s + 1) * seg];
            let mut cal = settings.calibrator();
            for &v in &chunk[..cal_n] {
                cal.push(to_code(v)?);
            }
            let Ok(c) = cal.finish() else { continue };
            let mut axis = Axis::new(c.bias_q16);
            for (i, &v) in chunk[cal_n..].iter().enumerate() {
                axis.update(&settings, to_code(v)?);
                for (j, &st) in steps.iter().enumerate() {
                    if i + 1 == st {
                        pos[j].push(
                            axis.integrator().position() as f64
                                * settings.metres_per_position_unit(),
                        );
                    }
                }
            }
        }
        let f = &figures[k];
        for (j, &t) in ts.iter().enumerate() {
            let ms = MeanSquare::of(&pos[j]);
            let white = f.vrw_m_s_rts * t.powf(1.5) / 3f64.sqrt();
            let calibration = f.vrw_m_s_rts / calibrate_s.sqrt() * t * t / 2.0;
            let instability = f.bias_instability_m_s2 * t * t / 2.0;
            let predicted =
                (white * white + calibration * calibration + instability * instability).sqrt();
            let (lo, hi) = ms.ci95();
            rows.push(Row {
                axis: name.clone(),
                t_s: t,
                segments: pos[j].len(),
                measured_m: ms.rms(),
                ci_low_m: lo,
                ci_high_m: hi,
                predicted_m: predicted,
                white_m: white,
                calibration_m: calibration,
                instability_m: instability,
                z: Some(ms.z(predicted)).filter(|z| z.is_finite()),
            });
        }
    }
    Ok(rows)
}

/// The rows as a table.
pub fn table(rows: &[Row]) -> String {
    let mut out = format!(
        "{:<6} {:>7} {:>5} {:>11} {:>23} {:>11} {:>10} {:>10} {:>10} {:>7}\n",
        "axis",
        "T [s]",
        "segs",
        "measured",
        "95 % interval",
        "predicted",
        "white",
        "calib",
        "instab",
        "z"
    );
    for r in rows {
        let z = r.z.map_or_else(|| "n/a".into(), |z| format!("{z:+.2}"));
        out += &format!(
            "{:<6} {:>7} {:>5} {:>11.3e} [{:>9.3e}, {:>9.3e}] {:>11.3e} {:>10.2e} {:>10.2e} {:>10.2e} {:>7}\n",
            r.axis, r.t_s, r.segments, r.measured_m, r.ci_low_m, r.ci_high_m, r.predicted_m, r.white_m, r.calibration_m, r.instability_m, z
        );
    }
    out += "RMS position error [m] of pure double integration after calibration, over independent segments.\n";
    if rows.iter().any(|r| r.z.is_none()) {
        out += "z n/a: the axis never moved (constant or railed codes: no noise the ADC resolves, so nothing to predict).\n";
    }
    if rows.iter().any(|r| r.segments < FEW_SEGMENTS) {
        out += &format!("Rows from fewer than {FEW_SEGMENTS} segments: their interval is wide and their z rough; record longer to judge a law.\n");
    }
    out
}

/// One example, for `cargo lab` alone.
pub const EXAMPLE: &str = "cargo lab drift host-tests/data/mpu6050-static-100hz.csv --columns ax,ay,az --scale 0.000598550415039 --calibrate-s 10 --t 1,5,20";

/// The longest integration time `--t` [s].
const T_MAX_S: f64 = 86_400.0;

/// `cargo lab drift`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The recording.
    #[command(flatten)]
    pub rec: super::Recording,
    /// Calibration window at the start of each segment [s], `0 < TC <= 60` (default: the
    /// device's own window).
    #[arg(long, allow_negative_numbers = true, default_value_t = imu_core::Config::default().calibration_s)]
    pub calibrate_s: f64,
    /// Integration times [s], comma separated, each at most a day (default: the 1-2-5
    /// series from 0.1 s to the longest T of which the recording holds 10 segments).
    #[arg(long = "t", allow_negative_numbers = true, value_delimiter = ',')]
    pub t: Vec<f64>,
    /// Directory for the plot.
    #[arg(long, default_value = "target/lab/drift")]
    pub out: std::path::PathBuf,
    /// Print JSON instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// The integration times [s] a recording of `seconds` is measured at when `--t` is not
/// given: the 1-2-5 series from 0.1 s up to the longest T whose segments (`calibrate_s + T`)
/// it holds [`FEW_SEGMENTS`] of, so each row's interval is narrow enough to judge a law by.
/// A recording too short for any gets 0.1 s alone (and the experiment says why it cannot run).
pub fn default_ts(seconds: f64, calibrate_s: f64) -> Vec<f64> {
    let fits = |t: f64| seconds / (calibrate_s + t) >= FEW_SEGMENTS as f64;
    let ts: Vec<f64> = (-1..=4)
        .flat_map(|e| [1.0, 2.0, 5.0].map(|m| m * 10f64.powi(e)))
        .take_while(|&t| fits(t))
        .collect();
    if ts.is_empty() {
        vec![0.1]
    } else {
        ts
    }
}

/// Runs `cargo lab drift`.
///
/// # Errors
/// A bad argument, an unreadable recording, or segments too short for the times asked.
pub fn run(a: &Args) -> super::Outcome {
    super::folder("out", &a.out)?;
    use super::{positive, Error, COLORS};
    use crate::formats::plot;
    if let Some(u) = &a.rec.units {
        return Err(Error::arg(
            "units",
            u,
            "the drift experiment runs the core on raw counts; give their --scale",
        ));
    }
    positive("calibrate-s", a.calibrate_s)?;
    if a.calibrate_s > imu_core::config::CALIBRATION_S_MAX {
        return Err(Error::arg(
            "calibrate-s",
            crate::formats::number::Num(a.calibrate_s),
            format!(
                "at most {} s (the core's longest calibration window)",
                imu_core::config::CALIBRATION_S_MAX
            ),
        ));
    }
    for &t in &a.t {
        positive("t", t)?;
        if t > T_MAX_S {
            return Err(Error::arg(
                "t",
                crate::formats::number::Num(t),
                format!("at most {T_MAX_S} s (a day; the recording must hold two segments)"),
            ));
        }
    }
    let d = a.rec.read()?;
    // --scale, else the recording's profile (`read` refused a file with neither).
    let scale = a.rec.scale.or(d.counts_scale);
    let Some(scale) = scale else {
        return Err(Error::arg(
            "scale",
            "missing",
            "give the counts' scale [m/s^2]",
        ));
    };
    let figs: Vec<_> = a.rec.allan(&d)?.into_iter().map(|(_, f)| f).collect();
    let ts = if a.t.is_empty() {
        let n = d.raw.first().map_or(0, Vec::len);
        default_ts(n as f64 / d.fs, a.calibrate_s)
    } else {
        a.t.clone()
    };
    let rows = experiment(&d.names, &d.raw, d.fs, scale, a.calibrate_s, &ts, &figs)
        .map_err(Error::Input)?;
    let mut p = plot::Plot {
        title: format!(
            "Position error after a {} s calibration: measured and predicted",
            a.calibrate_s
        ),
        x_label: "T [s]".into(),
        y_label: "RMS position error [m]".into(),
        ..Default::default()
    };
    for (k, name) in d.names.iter().enumerate() {
        let color = COLORS[k % COLORS.len()];
        let mine: Vec<&Row> = rows.iter().filter(|r| &r.axis == name).collect();
        p.points.push(plot::Points {
            label: format!("{name}: measured, 95 %"),
            color,
            pts: mine
                .iter()
                .map(|r| (r.t_s, r.measured_m, r.ci_low_m, r.ci_high_m))
                .collect(),
        });
        p.lines.push(plot::Line {
            label: format!("{name}: predicted from the Allan figures"),
            color,
            dashed: false,
            pts: mine.iter().map(|r| (r.t_s, r.predicted_m)).collect(),
        });
    }
    let path = super::write_out(&a.out, "drift.svg", &p.to_svg())?;
    if a.json {
        return super::json(&serde_json::json!({ "rows": rows, "calibrate_s": a.calibrate_s }));
    }
    Ok(format!("{}plot: {}", table(&rows), path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_times_stop_where_fewer_than_ten_segments_fit() {
        // 441 s after 10 s windows: 20 s gives 14 segments, 50 s would give 7.
        let ts = default_ts(441.0, 10.0);
        assert_eq!(ts, [0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0]);
        for &t in &ts {
            assert!(441.0 / (10.0 + t) >= FEW_SEGMENTS as f64);
        }
        // Too short for ten: the shortest alone, for the experiment to refuse or run.
        assert_eq!(default_ts(0.5, 1.0), [0.1]);
        // The series' top is 50000 s, under T_MAX_S (a day).
        assert_eq!(default_ts(1e9, 1.0).last(), Some(&50_000.0));
    }
}
