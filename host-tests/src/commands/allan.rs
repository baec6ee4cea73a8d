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

/// Per column, the rail code (0 or `2^adc_bits - 1`, from the recording's profile) that more
/// than 1 % of its samples sit at, and that share; `None` without a profile.
fn rails(d: &crate::formats::columns::Data) -> Vec<Option<(f64, f64)>> {
    let bits = d
        .profile
        .as_ref()
        .and_then(|p| crate::formats::recording::profile_number(p, "adc_bits"))
        .filter(|b| b.fract() == 0.0 && (2.0..=16.0).contains(b))
        .map(|b| b as u32);
    d.raw
        .iter()
        .map(|col| {
            let top = f64::from((1u32 << bits?) - 1);
            [0.0, top].into_iter().find_map(|code| {
                let share = col.iter().filter(|&&v| v == code).count() as f64 / col.len() as f64;
                (share > 0.01).then_some((code, share))
            })
        })
        .collect()
}

/// Runs `cargo lab allan`.
///
/// # Errors
/// A bad argument, an unreadable recording, or one too short for the noise figures.
pub fn run(a: &Args) -> Outcome {
    super::folder("out", &a.out)?;
    let d = a.rec.read()?;
    let file = &a.rec.file;
    let results = a.rec.allan(&d)?;
    let mut axes = serde_json::Map::new();
    let mut text = format!(
        "{}: {} samples at {} Hz (from {}); {}\n",
        file.display(),
        d.m_s2[0].len(),
        // A rate from a time column is a mean of steps: shown to 6 digits, not 3000.0000000003.
        imu_core::profile::Shown(d.fs),
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
    let rails = rails(&d);
    for (k, (name, (a, f))) in d.names.iter().zip(results).enumerate() {
        let raw = &d.raw[k];
        if raw.iter().all(|&v| v == raw[0]) {
            // No noise is not a quiet sensor: an axis at a rail or not connected.
            text += &format!(
                "{name}: constant at {} for all {} samples: a railed or dead axis has no noise \
                 figures\n",
                raw[0],
                raw.len()
            );
            axes.insert(
                name.clone(),
                serde_json::json!({ "constant": raw[0], "samples": raw.len() }),
            );
            continue;
        }
        let bound = if f.bias_is_bound { "<= " } else { "" };
        text += &format!(
            "{name}: N_v (VRW) {:.4e} m/s/sqrt(s) = {:.4e} m/s/sqrt(h); ND (one-sided) {:.4e} m/s^2/sqrt(Hz) = {:.0} ug/sqrt(Hz); bias instability {bound}{:.4e} m/s^2 = {bound}{:.1} ug at tau {} s\n",
            f.vrw_m_s_rts,
            60.0 * f.vrw_m_s_rts,
            f.noise_density_m_s2_rthz,
            f.noise_density_m_s2_rthz / 9.806_65e-6,
            f.bias_instability_m_s2,
            f.bias_instability_m_s2 / 9.806_65e-6,
            imu_core::profile::Shown(f.tau_min_s)
        );
        if f.fit_is_short {
            text += &format!(
                "{name}: a short record: no tau on the white-noise line has 100 averages, so \
                 the figures are rough (record a minute or more)\n"
            );
        }
        if f.bias_is_bound {
            text += &format!(
                "{name}: the deviation still falls at the longest tau ({} s): the bias \
                 instability is an upper bound; a record over {} s would find the minimum\n",
                imu_core::profile::Shown(f.tau_min_s),
                (f.tau_min_s * 4.0).ceil()
            );
        }
        if let Some((code, share)) = rails.get(k).copied().flatten() {
            text += &format!(
                "{name}: {:.1} % of samples at the rail code {code}: clipped, the figures \
                 understate the noise\n",
                100.0 * share
            );
        }
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
                "bias_instability_is_upper_bound": f.bias_is_bound,
            }),
        );
    }
    if p.points.is_empty() {
        // Nothing to draw, and nothing measured: a run that failed, not an empty chart.
        let report = if a.json {
            serde_json::to_string_pretty(&serde_json::json!({ "axes": axes, "fs": d.fs }))?
        } else {
            text
        };
        return Err(super::Error::Check {
            report,
            why: "every axis is constant: no noise to measure and no plot (is the sensor \
                  powered, and are these its columns?)"
                .into(),
        });
    }
    let path = super::write_out(&a.out, "allan.svg", &p.to_svg())?;
    if a.json {
        return super::json(&serde_json::json!({ "axes": axes, "fs": d.fs }));
    }
    text += &format!("conventions: sigma(tau) = N_v / sqrt(tau) on the white part; ND = sqrt(2) N_v (one-sided); B = min / 0.664\nplot: {}", path.display());
    Ok(text)
}
