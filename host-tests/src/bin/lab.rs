//! The imu-mouse lab: `cargo lab <command>`. Run `cargo lab --help` for the commands.

use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use host_tests::{budget, hid, predict, reproduce};

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
