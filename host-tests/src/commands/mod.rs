//! One module per `cargo lab` subcommand: its arguments (`Args`), its `run`, its table.
//!
//! # Conventions, the same in every command
//! - the result goes to stdout, as a table or, with `--json`, as JSON only;
//! - `--seed N` seeds every random draw of the run: the same seed gives the same output;
//! - `--out DIR` is the directory for the files a command writes (plots), created if missing,
//!   `target/lab/<command>` unless given; a relative `target/...` is the workspace's target
//!   folder wherever the lab runs from ([`resolve`]);
//! - errors go to stderr as `error: ...` naming the bad argument or file; the exit status is 2
//!   for a bad argument, 1 for a run that failed (a file, a check);
//! - a run that fails its own check (`reproduce`, `speed`) still prints its table, then fails;
//! - long runs show progress on stderr when it is a terminal, never with `--json`;
//! - a closed stdout (`cargo lab ... | head`) ends the run quietly.
//!
//! Commands never use each other; what two share lives in the layers below (or here, for
//! argument groups such as [`Recording`]).

use std::fmt;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use indicatif::{ProgressBar, ProgressStyle};

pub mod allan;
pub mod budget;
pub mod device;
pub mod drift;
pub mod hid;
pub mod mouse;
pub mod predict;
pub mod replay;
pub mod reproduce;
pub mod simulate;
pub mod speed;
pub mod twin;
pub mod ui;

/// Why a command failed.
#[derive(Debug)]
pub enum Error {
    /// An argument out of its range: `--{name} {value}: {why}`.
    Arg {
        /// The argument's long name, without dashes.
        name: &'static str,
        /// The value given.
        value: String,
        /// What is wrong with it.
        why: String,
    },
    /// Inputs that the run's own validation refused; the message names the argument.
    Input(String),
    /// A file that could not be read, parsed or written.
    File {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        why: String,
    },
    /// The run completed but did not come out as it must; `report` is still printed.
    Check {
        /// The full report (table or JSON).
        report: String,
        /// What failed.
        why: String,
    },
    /// Anything else, with its message.
    Run(String),
}

impl Error {
    /// A bad argument `--{name} {value}`.
    pub fn arg(name: &'static str, value: impl fmt::Display, why: impl Into<String>) -> Self {
        Self::Arg {
            name,
            value: value.to_string(),
            why: why.into(),
        }
    }

    /// A file error.
    pub fn file(path: &Path, why: impl fmt::Display) -> Self {
        Self::File {
            path: path.to_path_buf(),
            why: why.to_string(),
        }
    }

    /// The process exit status for this error: 2 for a bad argument, else 1.
    pub fn exit_code(&self) -> u8 {
        match self {
            Self::Arg { .. } | Self::Input(_) => 2,
            _ => 1,
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Arg { name, value, why } => write!(f, "--{name} {value}: {why}"),
            Self::File { path, why } => write!(f, "{}: {why}", path.display()),
            Self::Input(why) | Self::Check { why, .. } | Self::Run(why) => f.write_str(why),
        }
    }
}

impl std::error::Error for Error {}

impl From<serde_json::Error> for Error {
    fn from(e: serde_json::Error) -> Self {
        Self::Run(format!("JSON: {e}"))
    }
}

/// What a command returns: the text for stdout, or why it failed.
pub type Outcome = Result<String, Error>;

/// `v` if it is finite and > 0, else an error naming `--{name}`.
pub fn positive(name: &'static str, v: f64) -> Result<f64, Error> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(Error::arg(
            name,
            crate::formats::number::Num(v),
            "must be a finite number > 0",
        ))
    }
}

/// A run whose calibration never succeeded (`replay`, `simulate`): its `report`, and why,
/// as a failed run (status 1).
///
/// # Errors
/// [`Error::Check`] when nothing was tracked.
pub fn tracked(t: &crate::device::track::Track, report: String) -> Outcome {
    match &t.calibration_failure {
        None => Ok(report),
        Some(why) => Err(Error::Check {
            report,
            why: format!("calibration never succeeded, so nothing was tracked: {why}"),
        }),
    }
}

/// `value` as pretty JSON.
pub fn json(value: &impl serde::Serialize) -> Outcome {
    Ok(serde_json::to_string_pretty(value)?)
}

/// Opens a file to be read as a stream (the recording readers read it line by line).
pub fn open(path: &Path) -> Result<std::io::BufReader<std::fs::File>, Error> {
    std::fs::File::open(path)
        .map(std::io::BufReader::new)
        .map_err(|e| Error::file(path, io_words(&e)))
}

/// Why a file could not be read or written, in words (the OS's own text for the rare kinds).
pub fn io_words(e: &std::io::Error) -> String {
    use std::io::ErrorKind as K;
    match e.kind() {
        K::NotFound => "no such file".into(),
        K::PermissionDenied => "permission denied (see the file's owner and mode)".into(),
        K::IsADirectory => "is a folder; give a file".into(),
        K::NotADirectory => "a part of the path is a file, not a folder".into(),
        _ => e.to_string(),
    }
}

/// A folder to write into (`--out`), checked before any work: a path that is a file, or
/// runs through one, is refused here rather than when the run ends.
pub fn folder(name: &'static str, dir: &Path) -> Result<(), Error> {
    let dir = resolve(dir);
    match dir.ancestors().find(|d| d.exists()) {
        Some(d) if !d.is_dir() => Err(Error::arg(
            name,
            dir.display(),
            format!("{} is a file; give a folder", d.display()),
        )),
        _ => Ok(()),
    }
}

/// A file to be written, checked before any work: not a folder, and its folder exists (a
/// typo in a path is not created silently, and a long run does not fail at its end); under
/// `target/` ([`resolve`]) the lab makes its own folders.
///
/// # Errors
/// [`Error::Arg`] naming `--{name}`.
pub fn writable(name: &'static str, out: &Path) -> Result<(), Error> {
    // The lab's own folders under target/ are made; a user's folder must exist.
    if out.is_relative() && out.starts_with("target") {
        if let Some(dir) = resolve(out).parent() {
            std::fs::create_dir_all(dir).map_err(|e| Error::file(dir, e))?;
        }
    }
    let out = &resolve(out);
    if out.is_dir() {
        return Err(Error::arg(
            name,
            out.display(),
            "is a folder; give a file name",
        ));
    }
    match out.parent().filter(|d| !d.as_os_str().is_empty()) {
        Some(dir) if !dir.is_dir() => Err(Error::arg(
            name,
            out.display(),
            format!("its folder {} does not exist", dir.display()),
        )),
        _ => Ok(()),
    }
}

/// `path` as the lab writes to it: a relative path under `target/` is the workspace's
/// `target` folder (the nearest folder up from here holding a `Cargo.lock`, as cargo's is),
/// wherever the lab runs from; any other path is as given.
pub fn resolve(path: &Path) -> PathBuf {
    if path.is_relative() && path.starts_with("target") {
        if let Some(root) = std::env::current_dir().ok().and_then(|cwd| {
            cwd.ancestors()
                .find(|d| d.join("Cargo.lock").is_file())
                .map(Path::to_path_buf)
        }) {
            return root.join(path);
        }
    }
    path.to_path_buf()
}

/// Writes `name` into the `--out` directory `dir` (created if missing, [`resolve`]d);
/// returns its path.
pub fn write_out(dir: &Path, name: &str, contents: &str) -> Result<PathBuf, Error> {
    let dir = &resolve(dir);
    std::fs::create_dir_all(dir).map_err(|e| Error::file(dir, io_words(&e)))?;
    let path = dir.join(name);
    std::fs::write(&path, contents).map_err(|e| Error::file(&path, io_words(&e)))?;
    Ok(path)
}

/// Progress on stderr, shown only when stderr is a terminal and the output is not JSON: a bar
/// of `len` steps of `unit`, or for `len == 0` a spinner with the current stage's message.
pub fn progress(len: u64, json: bool, unit: &str) -> ProgressBar {
    if json || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    if len == 0 {
        let bar = ProgressBar::new_spinner();
        bar.set_style(
            ProgressStyle::with_template("{spinner} {msg} {elapsed}")
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
        );
        bar.enable_steady_tick(std::time::Duration::from_millis(100));
        return bar;
    }
    let bar = ProgressBar::new(len);
    bar.set_style(
        ProgressStyle::with_template(&format!("{{bar:40}} {{pos}}/{{len}} {unit} {{elapsed}}"))
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar
}

/// Colours of the lines of one chart, in order.
pub const COLORS: [&str; 6] = [
    "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b",
];

/// A recording to analyse (`allan`, `drift`): the file, its columns, rate and units.
#[derive(clap::Args, Clone, Debug)]
pub struct Recording {
    /// The CSV file (a header row; metadata lines before it are skipped).
    pub file: PathBuf,
    /// Columns to analyse, by header name (a device's recording: x,y,z unless given).
    #[arg(long, value_delimiter = ',')]
    pub columns: Vec<String>,
    /// Sampling rate [Hz] (else a time column or an `fs,<Hz>` metadata line).
    #[arg(long, allow_negative_numbers = true)]
    pub fs: Option<f64>,
    /// A time column [s] to take the rate from (gaps and jitter are reported).
    #[arg(long)]
    pub time_column: Option<String>,
    /// Values are raw counts of this many m/s^2 each (a device's recording: its profile's
    /// `m_s2_per_lsb` unless given).
    #[arg(long, allow_negative_numbers = true, conflicts_with = "units")]
    pub scale: Option<f64>,
    /// Values are already in `g` or `m_s2`.
    #[arg(long)]
    pub units: Option<String>,
}

impl Recording {
    /// Reads and checks the recording.
    ///
    /// # Errors
    /// Units unknown, or not given for a file without a profile; the file unreadable or not
    /// as described.
    pub fn read(&self) -> Result<crate::formats::columns::Data, Error> {
        use crate::formats::columns::{self, Units};
        if let Some(fs) = self.fs {
            positive("fs", fs)?;
            if fs > 1e6 {
                return Err(Error::arg(
                    "fs",
                    crate::formats::number::Num(fs),
                    "at most 1e6 Hz",
                ));
            }
        }
        if let Some(s) = self.scale {
            if s > 1e3 {
                return Err(Error::arg(
                    "scale",
                    crate::formats::number::Num(s),
                    "at most 1000 m/s^2 per count (100 g a count is no accelerometer's)",
                ));
            }
        }
        let units = match (self.scale, self.units.as_deref()) {
            (Some(s), _) => Some(Units::Counts(positive("scale", s)?)),
            (None, Some("g")) => Some(Units::G),
            (None, Some("m_s2")) => Some(Units::MS2),
            (None, Some(u)) => return Err(Error::arg("units", u, "`g` or `m_s2`")),
            // The recording's profile, or an error naming --scale.
            (None, None) => None,
        };
        columns::read(
            open(&self.file)?,
            &columns::Options {
                columns: self.columns.clone(),
                fs: self.fs,
                time_column: self.time_column.clone(),
                units,
            },
        )
        .map_err(|e| Error::file(&self.file, e))
    }

    /// The overlapping Allan deviation of each column of `d` (read from this recording) and
    /// the noise figures read from it, as `allan` shows them and `drift` predicts from them.
    ///
    /// # Errors
    /// Fewer than 4 samples, or too few taus for the figures.
    pub fn allan(
        &self,
        d: &crate::formats::columns::Data,
    ) -> Result<Vec<(crate::stats::allan::Adev, crate::stats::allan::Figures)>, Error> {
        use crate::stats::allan;
        let n = d.m_s2.first().map_or(0, Vec::len);
        if n < 4 {
            return Err(Error::file(
                &self.file,
                format!("{n} samples; the Allan deviation needs at least 4"),
            ));
        }
        d.m_s2
            .iter()
            .map(|y| {
                let a = allan::oadev(y, d.fs);
                let f = allan::figures(&a)
                    .ok_or_else(|| Error::file(&self.file, "too few taus for the noise figures"))?;
                Ok((a, f))
            })
            .collect()
    }
}
