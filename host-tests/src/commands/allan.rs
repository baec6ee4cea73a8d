//! `cargo lab allan`: the overlapping Allan deviation of a recording, the noise figures read
//! from it, and their chart (the statistics are `crate::stats::allan`).

use crate::formats::plot;

use super::{Outcome, COLORS};

/// One example, for `cargo lab` alone.
pub const EXAMPLE: &str = "cargo lab allan host-tests/data/mpu6050-static-100hz.csv --columns ax,ay,az --scale 0.000598550415039";

/// `cargo lab allan`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The recording.
    #[command(flatten)]
    pub rec: super::Recording,
    /// Directory for the plot.
    #[arg(long, default_value = "target/lab/allan")]
    pub out: std::path::PathBuf,
    /// Print JSON instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// Runs `cargo lab allan`.
///
/// # Errors
/// A bad argument, an unreadable recording, or one too short for the noise figures.
pub fn run(a: &Args) -> Outcome {
    let d = a.rec.read()?;
    let file = &a.rec.file;
    let results = a.rec.allan(&d)?;
    let mut axes = serde_json::Map::new();
    let mut text = format!(
        "{}: {} samples at {} Hz (from {}); {}\n",
        file.display(),
        d.m_s2[0].len(),
        d.fs,
        d.fs_source,
        if d.notes.is_empty() {
            "no gaps or jitter".to_string()
        } else {
            d.notes.join("; ")
        }
    );
    let mut p = plot::Plot {
        title: "Overlapping Allan deviation".into(),
        x_label: "tau [s]".into(),
        y_label: "Allan deviation [m/s^2]".into(),
        ..Default::default()
    };
    for (k, (name, (a, f))) in d.names.iter().zip(results).enumerate() {
        text += &format!(
            "{name}: N_v (VRW) {:.4e} m/s/sqrt(s) = {:.4e} m/s/sqrt(h); ND (one-sided) {:.4e} m/s^2/sqrt(Hz) = {:.0} ug/sqrt(Hz); bias instability {:.4e} m/s^2 = {:.1} ug at tau {} s\n",
            f.vrw_m_s_rts,
            60.0 * f.vrw_m_s_rts,
            f.noise_density_m_s2_rthz,
            f.noise_density_m_s2_rthz / 9.806_65e-6,
            f.bias_instability_m_s2,
            f.bias_instability_m_s2 / 9.806_65e-6,
            f.tau_min_s
        );
        let color = COLORS[k % COLORS.len()];
        p.points.push(plot::Points {
            label: name.to_string(),
            color,
            pts: a
                .taus_s
                .iter()
                .zip(&a.adev)
                .zip(&a.n)
                .map(|((&t, &s), &n)| {
                    // 1-sigma-ish band from the number of independent differences (n / m).
                    let e = s / ((n as f64) / (t * d.fs)).max(1.0).sqrt();
                    (t, s, (s - e).max(s * 0.1), s + e)
                })
                .collect(),
        });
        p.lines.push(plot::Line {
            label: format!("{name}: N_v / sqrt(tau)"),
            color,
            dashed: true,
            pts: a
                .taus_s
                .iter()
                .map(|&t| (t, f.vrw_m_s_rts / t.sqrt()))
                .collect(),
        });
        axes.insert(
            name.clone(),
            serde_json::json!({
                "taus_s": a.taus_s,
                "adev_m_s2": a.adev,
                "noise_density_m_s2_rthz": f.noise_density_m_s2_rthz,
                "vrw_m_s_rts": f.vrw_m_s_rts,
                "bias_instability_m_s2": f.bias_instability_m_s2,
            }),
        );
    }
    let path = super::write_out(&a.out, "allan.svg", &p.to_svg())?;
    if a.json {
        return super::json(&serde_json::json!({ "axes": axes, "fs": d.fs }));
    }
    text += &format!("conventions: sigma(tau) = N_v / sqrt(tau) on the white part; ND = sqrt(2) N_v (one-sided); B = min / 0.664\nplot: {}", path.display());
    Ok(text)
}
