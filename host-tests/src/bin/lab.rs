//! The imu-mouse lab: `cargo lab <command>`. Run `cargo lab --help` for the commands.

use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use host_tests::{
    allan, budget, columns, device_twin, drift, hid, mouse, plot, pointing, predict, recording,
    reproduce, scene, speed, track,
};

#[derive(Parser)]
#[command(
    name = "lab",
    about = "imu-mouse lab: inertial position error, predicted and measured"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// RMS position error predicted by the paper's laws and the exact finite-N results.
    Predict(PredictArgs),
    /// Fixed-point error of each core stage against its f64 twin, with derived bounds.
    Budget(BudgetArgs),
    /// The USB HID report descriptor and the reports the device sends for a motion.
    Hid(HidArgs),
    /// The paper's laws by Monte Carlo through the real core: table, plots, JSON.
    Reproduce(ReproduceArgs),
    /// One simulated scene through the whole device: the cursor's track and what it sends.
    Simulate(SimulateArgs),
    /// A recorded trace (CSV of ADC codes) through the whole device.
    Replay(ReplayArgs),
    /// Speed against error: QEMU instruction counts, host ns, error vs f64.
    Speed(SpeedArgs),
    /// The mouse on a desk: strokes, rests, clicks, with and without drift control.
    Mouse(MouseArgs),
    /// Overlapping Allan deviation of a recording, and the noise figures read from it.
    Allan(AllanArgs),
    /// The paper's experiment on a recording: calibrate, integrate, RMS over segments.
    Drift(DriftArgs),
    /// The firmware's app as a USB/IP mouse on this host, fed in real time by a scene or a
    /// recording (`usbip attach -r 127.0.0.1 -b 1-1` makes it a mouse of a Linux desktop).
    Twin(TwinArgs),
}

#[derive(Args)]
struct TwinArgs {
    /// The scene: `desk` (strokes, rests and clicks) or `rest` (the hand still).
    #[arg(long, default_value = "desk", conflicts_with = "replay")]
    scene: String,
    /// Play a recording (CSV of ADC codes, as `cargo lab replay`) instead of a scene.
    #[arg(long)]
    replay: Option<std::path::PathBuf>,
    /// Play at most this long [s] (default: the whole scene or recording).
    #[arg(long)]
    seconds: Option<f64>,
    /// Strokes in the desk scene.
    #[arg(long, default_value_t = 20)]
    strokes: usize,
    /// Seed of the scene.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// USB/IP address to listen on.
    #[arg(long, default_value = "127.0.0.1:3240")]
    addr: std::net::SocketAddr,
    /// How long to wait for a host to configure the device [s].
    #[arg(long, default_value_t = 60.0)]
    wait_host: f64,
    /// Print JSON instead of the table.
    #[arg(long)]
    json: bool,
}

#[derive(Args, Clone)]
struct RecordingArgs {
    /// The CSV file (a header row; metadata lines before it are skipped).
    file: std::path::PathBuf,
    /// Columns to analyse, by header name.
    #[arg(long, value_delimiter = ',', required = true)]
    columns: Vec<String>,
    /// Sampling rate [Hz] (else a time column or an `fs,<Hz>` metadata line).
    #[arg(long)]
    fs: Option<f64>,
    /// A time column [s] to take the rate from (gaps and jitter are reported).
    #[arg(long)]
    time_column: Option<String>,
    /// Values are raw counts of this many m/s^2 each.
    #[arg(long, conflicts_with = "units")]
    scale: Option<f64>,
    /// Values are already in `g` or `m_s2`.
    #[arg(long)]
    units: Option<String>,
    /// Directory for the plot.
    #[arg(long, default_value = "target/lab/recording")]
    out: std::path::PathBuf,
    /// Print JSON instead of the table.
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
struct AllanArgs {
    #[command(flatten)]
    rec: RecordingArgs,
}

#[derive(Args)]
struct DriftArgs {
    #[command(flatten)]
    rec: RecordingArgs,
    /// Calibration window at the start of each segment [s].
    #[arg(long)]
    calibrate_s: f64,
    /// Integration times [s], comma separated.
    #[arg(long = "t", value_delimiter = ',', required = true)]
    t: Vec<f64>,
}

#[derive(Args)]
struct MouseArgs {
    /// Strokes in the desk scene.
    #[arg(long, default_value_t = 60)]
    strokes: usize,
    /// Length of the at-rest scene [min].
    #[arg(long, default_value_t = 10.0)]
    rest_minutes: f64,
    /// Seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Smaller pointing scenes (for CI).
    #[arg(long)]
    quick: bool,
    /// Directory for the path plot and the detectability map.
    #[arg(long, default_value = "target/lab/mouse")]
    out: std::path::PathBuf,
    /// Print JSON instead of the table.
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
struct SpeedArgs {
    /// Skip the QEMU run (no instruction counts).
    #[arg(long)]
    host_only: bool,
    /// Trials for the error columns.
    #[arg(long, default_value_t = 3)]
    trials: u64,
    /// Measure errors only up to this T [s] (3600 for the full table).
    #[arg(long, default_value_t = 3600.0)]
    max_t: f64,
    /// Directory for the Pareto plot.
    #[arg(long, default_value = "target/lab/speed")]
    out: std::path::PathBuf,
    /// Print JSON instead of the table.
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
struct SimulateArgs {
    /// Scene name (an unknown name lists them).
    #[arg(long)]
    scene: String,
    /// Length [s], including the 1 s calibration at the start.
    #[arg(long, default_value_t = 5.0)]
    seconds: f64,
    /// Seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Interval of the printed track [s].
    #[arg(long, default_value_t = 0.5)]
    every: f64,
    /// Print JSON instead of the table.
    #[arg(long)]
    json: bool,
    /// Also write the codes as a recording (`fs,<Hz>` line, `n,x,y,z` header), for
    /// `cargo lab allan` / `drift` / `replay`.
    #[arg(long)]
    csv: Option<std::path::PathBuf>,
}

#[derive(Args)]
struct ReplayArgs {
    /// The recording (format: `cargo lab replay --help` and the README).
    file: std::path::PathBuf,
    /// Sampling rate [Hz], if the file does not say.
    #[arg(long)]
    fs: Option<f64>,
    /// Acceleration per ADC code [m/s^2] (default: ADXL335 on a 12-bit ratiometric ADC).
    #[arg(long, default_value_t = scene::ADXL335_LSB)]
    m_s2_per_lsb: f64,
    /// ADC resolution [bits].
    #[arg(long, default_value_t = 12)]
    adc_bits: u8,
    /// Interval of the printed track [s].
    #[arg(long, default_value_t = 0.5)]
    every: f64,
    /// Print JSON instead of the table.
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
struct ReproduceArgs {
    /// CI-sized run: 1000 trials per sweep instead of 10 000, the same rows.
    #[arg(long)]
    quick: bool,
    /// Trials per sweep (overrides --quick).
    #[arg(long)]
    trials: Option<usize>,
    /// Seed of the whole run.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Directory for the SVG plots.
    #[arg(long, default_value = "target/lab/reproduce")]
    out: std::path::PathBuf,
    /// Print `{"rows": [..], "plots": [..], "trials": ..}` instead of the table.
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
struct HidArgs {
    /// Motion to the right [counts].
    #[arg(long, allow_negative_numbers = true)]
    dx: i64,
    /// Motion downwards [counts] (HID convention).
    #[arg(long, allow_negative_numbers = true)]
    dy: i64,
    /// Buttons held: 1 left, 2 right, 4 middle, summed.
    #[arg(long, default_value_t = 0)]
    buttons: u32,
    /// Print `{"descriptor_hex": .., "reports_hex": [..]}` instead of the listing.
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
struct BudgetArgs {
    /// Fewer samples (the test suite's size) and no 1 h pipeline run.
    #[arg(long)]
    quick: bool,
    /// Print JSON rows instead of the Markdown table.
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
struct PredictArgs {
    /// Sampling rate [Hz].
    #[arg(long)]
    fs: f64,
    /// Duration [s]; repeat or separate by commas for several. t * fs must be whole.
    #[arg(
        long = "t",
        value_delimiter = ',',
        required = true,
        allow_negative_numbers = true
    )]
    t: Vec<f64>,
    /// Per-sample white-noise std [m/s^2].
    #[arg(long, allow_negative_numbers = true)]
    sigma_d: Option<f64>,
    /// One-sided noise density into a single-pole filter [m/s^2/sqrt(Hz)]; needs --fc.
    #[arg(long, allow_negative_numbers = true)]
    sigma_c: Option<f64>,
    /// The single-pole filter's cut-off [Hz]; needs --sigma-c.
    #[arg(long, allow_negative_numbers = true)]
    fc: Option<f64>,
    /// Constant acceleration bias [m/s^2].
    #[arg(long, allow_negative_numbers = true)]
    bias: Option<f64>,
    /// Print a JSON array, one object per --t, instead of the table.
    #[arg(long)]
    json: bool,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Predict(a) => run_predict(a),
        Command::Budget(a) => run_budget(&a),
        Command::Hid(a) => run_hid(&a),
        Command::Reproduce(a) => run_reproduce(&a),
        Command::Simulate(a) => run_simulate(&a),
        Command::Replay(a) => run_replay(&a),
        Command::Speed(a) => run_speed(&a),
        Command::Mouse(a) => run_mouse(&a),
        Command::Allan(a) => run_allan(&a.rec).map(|x| x.0),
        Command::Drift(a) => run_drift(&a),
        Command::Twin(a) => run_twin(&a),
    };
    match result {
        Ok(text) => {
            println!("{text}");
            ExitCode::SUCCESS
        }
        Err(msg) => {
            eprintln!("error: {msg}");
            ExitCode::from(2)
        }
    }
}

fn run_predict(a: PredictArgs) -> Result<String, String> {
    let inputs = predict::Inputs {
        fs: a.fs,
        t: a.t,
        sigma_d: a.sigma_d,
        sigma_c: a.sigma_c,
        fc: a.fc,
        bias: a.bias,
    };
    let rows = predict::predict(&inputs).map_err(|e| e.to_string())?;
    if a.json {
        serde_json::to_string_pretty(&rows).map_err(|e| e.to_string())
    } else {
        Ok(predict::table(&rows))
    }
}

fn run_budget(a: &BudgetArgs) -> Result<String, String> {
    let rows = budget::all(a.quick);
    if a.json {
        serde_json::to_string_pretty(&rows).map_err(|e| e.to_string())
    } else {
        Ok(budget::table(&rows))
    }
}

fn run_hid(a: &HidArgs) -> Result<String, String> {
    let wire = hid::wire(a.dx, a.dy, a.buttons).map_err(|e| e.to_string())?;
    if a.json {
        serde_json::to_string(&wire).map_err(|e| e.to_string())
    } else {
        Ok(hid::listing(&wire))
    }
}

fn run_reproduce(a: &ReproduceArgs) -> Result<String, String> {
    let trials = a.trials.unwrap_or(if a.quick { 1000 } else { 10_000 });
    if trials < 100 {
        return Err(format!("--trials {trials}: at least 100, or the normal approximation behind the z-scores fails"));
    }
    let progress = std::io::IsTerminal::is_terminal(&std::io::stderr());
    let report = reproduce::reproduce(trials, a.seed, Some(&a.out), progress)?;
    let bad = report.rows.iter().filter(|r| !r.pass).count();
    let text = if a.json {
        serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?
    } else {
        reproduce::table(&report)
    };
    if bad > 0 {
        println!("{text}");
        return Err(format!("{bad} rows did not come out as expected"));
    }
    Ok(text)
}

fn positive(name: &str, v: f64) -> Result<f64, String> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(format!("--{name} {v}: must be a finite number > 0"))
    }
}

fn show_track(t: &track::Track, json: bool, header: String) -> Result<String, String> {
    if json {
        serde_json::to_string_pretty(t).map_err(|e| e.to_string())
    } else {
        Ok(header + &track::table(t))
    }
}

fn run_simulate(a: &SimulateArgs) -> Result<String, String> {
    let scenes = scene::catalogue();
    let Some(sc) = scenes.iter().find(|s| s.name == a.scene) else {
        let names: Vec<&str> = scenes.iter().map(|s| s.name).collect();
        return Err(format!(
            "--scene {}: unknown; the scenes are {}",
            a.scene,
            names.join(", ")
        ));
    };
    let seconds = positive("seconds", a.seconds)?;
    let every = positive("every", a.every)?;
    let config = sc.config();
    let samples = sc.three_axes(seconds, a.seed);
    if let Some(path) = &a.csv {
        let mut csv = format!(
            "# cargo lab simulate --scene {} --seconds {seconds} --seed {}\nfs,{}\nn,x,y,z\n",
            sc.name, a.seed, sc.fs
        );
        for (i, s) in samples.iter().enumerate() {
            csv += &format!("{i},{},{},{}\n", s[0], s[1], s[2]);
        }
        std::fs::write(path, csv).map_err(|e| format!("--csv {}: {e}", path.display()))?;
    }
    let t = track::run(&config, samples, every).map_err(|e| e.to_string())?;
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
    show_track(&t, a.json, header)
}

fn run_replay(a: &ReplayArgs) -> Result<String, String> {
    let text =
        std::fs::read_to_string(&a.file).map_err(|e| format!("{}: {e}", a.file.display()))?;
    let rec = recording::parse(&text, a.fs).map_err(|e| format!("{}: {e}", a.file.display()))?;
    let every = positive("every", a.every)?;
    let config = imu_core::Config {
        fs_hz: rec.fs,
        m_s2_per_lsb: a.m_s2_per_lsb,
        adc_bits: a.adc_bits,
        ..imu_core::Config::default()
    };
    let t = track::run(&config, rec.samples, every).map_err(|e| e.to_string())?;
    show_track(&t, a.json, format!("{}\n", a.file.display()))
}

fn run_speed(a: &SpeedArgs) -> Result<String, String> {
    if a.trials == 0 {
        return Err("--trials 0: at least one trial".into());
    }
    positive("max-t", a.max_t)?;
    let workspace = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .ok_or("no workspace directory")?;
    let target = if a.host_only {
        None
    } else {
        Some(speed::run_target(workspace).map_err(|e| e.to_string())?)
    };
    let report = speed::report(target, a.trials, a.max_t);
    if let Some(plot) = speed::pareto(&report) {
        std::fs::create_dir_all(&a.out).map_err(|e| format!("--out {}: {e}", a.out.display()))?;
        let path = a.out.join("pareto.svg");
        std::fs::write(&path, plot.to_svg()).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    let mismatch = report.target.as_ref().is_some_and(|t| !t.bit_exact);
    let text = if a.json {
        serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?
    } else {
        speed::table(&report)
    };
    if mismatch {
        println!("{text}");
        return Err("target and host checksums differ".into());
    }
    Ok(text)
}

fn run_twin(a: &TwinArgs) -> Result<String, String> {
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Arc;
    let mut input = match &a.replay {
        Some(file) => {
            let text =
                std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))?;
            let rec =
                recording::parse(&text, None).map_err(|e| format!("{}: {e}", file.display()))?;
            device_twin::Input {
                fs_hz: rec.fs,
                codes: rec.samples,
                held: Vec::new(),
            }
        }
        None => {
            let strokes = match a.scene.as_str() {
                "desk" => a.strokes,
                "rest" => 0,
                other => return Err(format!("--scene {other}: `desk` or `rest`")),
            };
            let (codes, held) = mouse::desk_stream(strokes, a.seed);
            device_twin::Input {
                fs_hz: 3000,
                codes,
                held,
            }
        }
    };
    if let Some(s) = a.seconds {
        positive("seconds", s)?;
        let n = (s * f64::from(input.fs_hz)) as usize;
        input.codes.truncate(n);
        input.held.truncate(n);
    }
    positive("wait-host", a.wait_host)?;
    // KEY from standard input: `press` and `release` lines.
    let operator = Arc::new(AtomicBool::new(false));
    let key = operator.clone();
    std::thread::spawn(move || {
        for line in std::io::stdin().lines().map_while(Result::ok) {
            match line.trim() {
                "press" => key.store(true, Ordering::Relaxed),
                "release" => key.store(false, Ordering::Relaxed),
                _ => {}
            }
        }
    });
    eprintln!(
        "twin: USB/IP device on {} (bus id 1-1); waiting for a host",
        a.addr
    );
    let settings = device_twin::Settings {
        addr: a.addr,
        wait_host_s: a.wait_host,
        drain_s: 2.0,
    };
    let s = device_twin::run(&input, settings, operator).map_err(|e| e.to_string())?;
    if a.json {
        return serde_json::to_string(&s).map_err(|e| e.to_string());
    }
    Ok(format!(
        "twin: {:.1} s at {} Hz, {} reports (peak {} per s), {} URBs, {} stalls\n\
         counts (x, y): produced {:?}, sent {:?}, discarded {:?}, owed {:?}; accounted: {}\n\
         late housekeeping ticks: {}",
        s.scene_s,
        s.fs_hz,
        s.reports,
        s.peak_report_rate_hz,
        s.urbs,
        s.stalls,
        s.produced,
        s.sent,
        s.discarded,
        s.undelivered,
        s.accounted,
        s.late_ticks
    ))
}

fn run_mouse(a: &MouseArgs) -> Result<String, String> {
    if a.strokes == 0 || a.strokes > 10_000 {
        return Err(format!("--strokes {}: 1..=10000", a.strokes));
    }
    positive("rest-minutes", a.rest_minutes)?;
    let report = mouse::run(a.strokes, a.rest_minutes, a.seed);
    let sizes = if a.quick {
        pointing::Sizes::quick(a.rest_minutes)
    } else {
        pointing::Sizes::full(a.rest_minutes)
    };
    let scenes = pointing::scenes(Some(imu_core::Drift::default()), sizes, a.seed);
    std::fs::create_dir_all(&a.out).map_err(|e| format!("--out {}: {e}", a.out.display()))?;
    let path = a.out.join("path.svg");
    std::fs::write(&path, mouse::path_svg(12, a.seed))
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let map = a.out.join("map.svg");
    std::fs::write(&map, pointing::map_svg(&scenes.map))
        .map_err(|e| format!("{}: {e}", map.display()))?;
    if a.json {
        let mut v = serde_json::to_value(&report).map_err(|e| e.to_string())?;
        v["scenes"] = serde_json::to_value(&scenes).map_err(|e| e.to_string())?;
        serde_json::to_string_pretty(&v).map_err(|e| e.to_string())
    } else {
        Ok(format!(
            "{}\n{}plots: {}, {}",
            mouse::table(&report),
            pointing::table(&scenes),
            path.display(),
            map.display()
        ))
    }
}

fn read_recording(r: &RecordingArgs) -> Result<columns::Data, String> {
    let units = match (r.scale, r.units.as_deref()) {
        (Some(s), _) => columns::Units::Counts(s),
        (None, Some("g")) => columns::Units::G,
        (None, Some("m_s2")) => columns::Units::MS2,
        (None, Some(u)) => return Err(format!("--units {u}: `g` or `m_s2`")),
        (None, None) => {
            return Err("give --scale M_S2_PER_COUNT for raw counts, or --units g|m_s2".into())
        }
    };
    let text =
        std::fs::read_to_string(&r.file).map_err(|e| format!("{}: {e}", r.file.display()))?;
    columns::read(
        &text,
        &columns::Options {
            columns: r.columns.clone(),
            fs: r.fs,
            time_column: r.time_column.clone(),
            units,
        },
    )
    .map_err(|e| format!("{}: {e}", r.file.display()))
}

const COLORS: [&str; 6] = [
    "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b",
];

fn run_allan(r: &RecordingArgs) -> Result<(String, Vec<allan::Figures>), String> {
    let d = read_recording(r)?;
    if d.m_s2[0].len() < 4 {
        return Err(format!(
            "{}: {} samples; the Allan deviation needs at least 4",
            r.file.display(),
            d.m_s2[0].len()
        ));
    }
    let mut axes = serde_json::Map::new();
    let mut figs = vec![];
    let mut text = format!(
        "{}: {} samples at {} Hz (from {}); {}\n",
        r.file.display(),
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
    for (k, (name, y)) in d.names.iter().zip(&d.m_s2).enumerate() {
        let a = allan::oadev(y, d.fs);
        let f = allan::figures(&a).ok_or("too few taus for the noise figures")?;
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
        figs.push(f);
    }
    std::fs::create_dir_all(&r.out).map_err(|e| format!("--out {}: {e}", r.out.display()))?;
    let path = r.out.join("allan.svg");
    std::fs::write(&path, p.to_svg()).map_err(|e| format!("{}: {e}", path.display()))?;
    text += &format!("conventions: sigma(tau) = N_v / sqrt(tau) on the white part; ND = sqrt(2) N_v (one-sided); B = min / 0.664\nplot: {}", path.display());
    if r.json {
        let json = serde_json::json!({ "axes": axes, "fs": d.fs });
        return Ok((
            serde_json::to_string_pretty(&json).map_err(|e| e.to_string())?,
            figs,
        ));
    }
    Ok((text, figs))
}

fn run_drift(a: &DriftArgs) -> Result<String, String> {
    let Some(scale) = a.rec.scale else {
        return Err(
            "--scale: the drift experiment runs the core on raw counts; give their scale".into(),
        );
    };
    positive("calibrate-s", a.calibrate_s)?;
    for &t in &a.t {
        positive("t", t)?;
    }
    let d = read_recording(&a.rec)?;
    let figs = {
        let quiet = RecordingArgs {
            json: false,
            ..a.rec.clone()
        };
        run_allan(&quiet)?.1
    };
    let rows = drift::experiment(&d.names, &d.raw, d.fs, scale, a.calibrate_s, &a.t, &figs)?;
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
        let mine: Vec<&drift::Row> = rows.iter().filter(|r| &r.axis == name).collect();
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
    std::fs::create_dir_all(&a.rec.out)
        .map_err(|e| format!("--out {}: {e}", a.rec.out.display()))?;
    let path = a.rec.out.join("drift.svg");
    std::fs::write(&path, p.to_svg()).map_err(|e| format!("{}: {e}", path.display()))?;
    if a.rec.json {
        return serde_json::to_string_pretty(
            &serde_json::json!({ "rows": rows, "calibrate_s": a.calibrate_s }),
        )
        .map_err(|e| e.to_string());
    }
    Ok(format!("{}plot: {}", drift::table(&rows), path.display()))
}
