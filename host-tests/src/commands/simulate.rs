//! `cargo lab simulate`: one scene of the catalogue through the whole device
//! ([`crate::device::track`]): the cursor's track and what the device sends.

use crate::device::profile;
use crate::device::track;
use crate::formats::recording;
use crate::world::scene;

use super::{positive, Error, Outcome};

/// One example, for `cargo lab` alone.
pub const EXAMPLE: &str = "cargo lab simulate --scene adxl335-stroke --seconds 3";

/// The longest scene [s]: an hour at 3 kHz is 32 M codes, 65 MB.
pub const MAX_SECONDS: f64 = 3600.0;

/// `cargo lab simulate`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene name (an unknown name lists them).
    #[arg(long)]
    pub scene: String,
    /// Length [s], including the 1 s calibration at the start.
    #[arg(long, allow_negative_numbers = true, default_value_t = 5.0)]
    pub seconds: f64,
    /// Seed of every random draw (the same seed, the same output).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Interval of the printed track [s].
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.5)]
    pub every: f64,
    /// Print JSON instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Directory for the charts (the cursor's path, the acceleration).
    #[arg(long, default_value = "target/lab/simulate")]
    pub out: std::path::PathBuf,
    /// Also write the codes as a recording (`fs,<Hz>` line, `n,x,y,z` header), for
    /// `cargo lab allan` / `drift` / `replay`.
    #[arg(long)]
    pub csv: Option<std::path::PathBuf>,
}

/// Runs `cargo lab simulate`.
///
/// # Errors
/// An unknown scene, a bad length or interval, an unwritable `--csv`.
pub fn run(a: &Args) -> Outcome {
    super::folder("out", &a.out)?;
    let scenes = scene::catalogue();
    let Some(sc) = scenes.iter().find(|s| s.name == a.scene) else {
        let names: Vec<&str> = scenes.iter().map(|s| s.name).collect();
        return Err(Error::arg(
            "scene",
            &a.scene,
            format!("unknown; the scenes are {}", names.join(", ")),
        ));
    };
    let seconds = positive("seconds", a.seconds)?;
    if seconds > MAX_SECONDS {
        return Err(Error::arg(
            "seconds",
            crate::formats::number::Num(seconds),
            format!("at most {MAX_SECONDS} s: the scene is held in memory (3 axes at its rate)"),
        ));
    }
    let every = positive("every", a.every)?;
    if let Some(path) = &a.csv {
        super::writable("csv", path)?;
    }
    let config = track::scene_config(sc);
    let samples = sc.three_axes(seconds, a.seed);
    if let Some(path) = &a.csv {
        // The scene's device settings go with its codes: `replay` runs them as simulated.
        let rec = recording::Recording {
            fs: config.fs_hz,
            samples: samples.clone(),
            profile: Some(profile::to_text(&profile::pairs_of(
                &imu_core::Profile::new(config),
            ))),
        };
        let csv = format!(
            "# cargo lab simulate --scene {} --seconds {seconds} --seed {}\n{}",
            sc.name,
            a.seed,
            recording::write(&rec)
        );
        std::fs::write(path, csv).map_err(|e| Error::file(path, e))?;
    }
    let map = imu_core::AxisMap::default();
    let accel = track::acceleration(&config, &map, &samples);
    let t = track::run(&config, samples, every).map_err(|e| Error::Run(e.to_string()))?;
    let (path, acc) = track::charts(&t, &accel, sc.name);
    let path = super::write_out(&a.out, "path.svg", &path.to_svg())?;
    let acc = super::write_out(&a.out, "acceleration.svg", &acc.to_svg())?;
    if a.json {
        return super::tracked(&t, super::json(&t)?);
    }
    let mut header = format!("scene {}: {}\n", sc.name, sc.about);
    let d = sc.stroke_distance_m();
    if d != 0.0 {
        header += &format!(
            "true motion: {:.1} mm right = {:.1} counts at {} cpi\n",
            d * 1e3,
            d / 0.0254 * f64::from(config.counts_per_inch),
            config.counts_per_inch
        );
    }
    let plots = format!("plots: {} and {}", path.display(), acc.display());
    super::tracked(&t, header + &track::table(&t) + &plots)
}
