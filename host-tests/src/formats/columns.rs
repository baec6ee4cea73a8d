//! Reading recordings for `cargo lab allan` and `cargo lab drift`: a CSV with a header row,
//! columns chosen by name.
//!
//! # Format
//! - Lines before the header are metadata and are skipped; a metadata line `fs,<Hz>`
//!   (any case) gives the sampling rate. Blank lines and lines starting with `#` are skipped
//!   everywhere.
//! - The header is the first line whose fields are all names (none is a number) and which
//!   holds every requested column.
//! - Every data row has as many fields as the header; the requested columns are numbers.
//! - A column named `n` (the recording format's sample index) must count up by one: a jump
//!   is samples missing, refused where it is.
//! - The sampling rate: `--fs`, else a time column (`--time-column NAME`, seconds), else the
//!   `fs` metadata line. A time column's steps are checked: gaps (a step over 1.5x the
//!   median) and jitter (a step more than 1 % off the median) are counted and reported.
//! - Units: `--scale M_S2_PER_LSB` for raw counts, or `--units g` / `--units m_s2`.
//! - A recording of the device (`device record`, `simulate --csv`) carries a `profile,` line
//!   ([`super::recording`]): then the columns default to `x,y,z` and the scale to its
//!   `m_s2_per_lsb`.
//!
//! Every problem is an error naming the line; nothing panics. The file is read as a stream
//! of bounded lines ([`super::lines`]); only the requested columns are kept.

use std::io::BufRead;

use crate::formats::lines::{content_lines, quote};
use crate::formats::recording::{
    err, profile_number, read_fs, read_second_profile, RecordingError,
};

/// How the values become m/s^2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Units {
    /// Raw counts times this scale [m/s^2 per count].
    Counts(f64),
    /// Standard gravities.
    G,
    /// Already m/s^2.
    MS2,
}

/// What to read.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// Column names, in order.
    pub columns: Vec<String>,
    /// Sampling rate [Hz], if given.
    pub fs: Option<f64>,
    /// Name of a time column [s], if any.
    pub time_column: Option<String>,
    /// Units of the values; `None` takes the recording's profile's scale.
    pub units: Option<Units>,
}

/// The columns read.
#[derive(Clone, Debug, PartialEq)]
pub struct Data {
    /// Column names.
    pub names: Vec<String>,
    /// Values as read (counts, g or m/s^2), one vector per column.
    pub raw: Vec<Vec<f64>>,
    /// Values in m/s^2.
    pub m_s2: Vec<Vec<f64>>,
    /// Sampling rate [Hz].
    pub fs: f64,
    /// Where the rate came from.
    pub fs_source: &'static str,
    /// Findings about the time column (gaps, jitter), for the report.
    pub notes: Vec<String>,
    /// The device's settings, `(key name, value)`, if the file carries them.
    pub profile: Option<Vec<(String, String)>>,
    /// Where the units came from.
    pub units_source: &'static str,
    /// The scale of raw counts [m/s^2 per count], when the values are counts.
    pub counts_scale: Option<f64>,
}

fn is_number(s: &str) -> bool {
    s.parse::<f64>().is_ok()
}

/// The header found, and what each data row is checked against.
struct Header {
    /// Its line.
    line: usize,
    /// Its names.
    names: Vec<String>,
    /// The requested columns' positions.
    idx: Vec<usize>,
    /// The time column's position.
    t_idx: Option<usize>,
    /// The sample index column's position.
    n_idx: Option<usize>,
    /// The last sample index seen.
    last_n: Option<u64>,
}

impl Header {
    fn new(line: usize, fields: &[&str], o: &Options) -> Result<Self, RecordingError> {
        let names: Vec<String> = fields.iter().map(|f| f.to_string()).collect();
        let index = |name: &str| names.iter().position(|x| x == name);
        let idx = o.columns.iter().filter_map(|c| index(c)).collect();
        let t_idx = match &o.time_column {
            Some(t) => Some(index(t).ok_or_else(|| RecordingError {
                line,
                problem: format!("--time-column {t}: not in the header"),
            })?),
            None => None,
        };
        // The recording format's sample index: a jump is samples missing, which an Allan
        // deviation or a drift experiment over an unbroken record would silently hide.
        let n_idx = index("n");
        Ok(Self {
            line,
            names,
            idx,
            t_idx,
            n_idx,
            last_n: None,
        })
    }

    /// One data row at `line` checked and its values appended.
    fn row(
        &mut self,
        line: usize,
        f: &[&str],
        raw: &mut [Vec<f64>],
        times: &mut Vec<(usize, f64)>,
    ) -> Result<(), RecordingError> {
        if f.len() != self.names.len() {
            return err(
                line,
                format!("{} fields, the header has {}", f.len(), self.names.len()),
            );
        }
        if let Some(c) = self.n_idx {
            let Ok(n) = f[c].parse::<u64>() else {
                return err(line, format!("n = `{}` is not a sample index", quote(f[c])));
            };
            if let Some(prev) = self.last_n.filter(|&p| n != p + 1) {
                return err(
                    line,
                    format!("n jumps from {prev} to {n}: samples are missing (a gap the analysis would hide)"),
                );
            }
            self.last_n = Some(n);
        }
        for (k, &c) in self.idx.iter().enumerate() {
            match f[c].parse::<f64>() {
                Ok(v) if v.is_finite() => raw[k].push(v),
                _ => {
                    return err(
                        line,
                        format!("{} = `{}` is not a number", self.names[c], quote(f[c])),
                    )
                }
            }
        }
        if let Some(t) = self.t_idx {
            match f[t].parse::<f64>() {
                Ok(v) if v.is_finite() => times.push((line, v)),
                _ => return err(line, format!("time `{}` is not a number", quote(f[t]))),
            }
        }
        Ok(())
    }
}

/// Reads `input`.
///
/// # Errors
/// The first problem, with its line.
pub fn read(input: impl BufRead, o: &Options) -> Result<Data, RecordingError> {
    let mut fs_meta = None;
    let mut profile: Option<Vec<(String, String)>> = None;
    let mut columns = o.columns.clone();
    let mut header: Option<Header> = None;
    let mut raw: Vec<Vec<f64>> = vec![];
    let mut times = vec![];
    for l in content_lines(input) {
        let l = l?;
        let (line, fields) = (l.number, l.fields());
        match &mut header {
            Some(h) => h.row(line, &fields, &mut raw, &mut times)?,
            None if fields[0].eq_ignore_ascii_case("profile") => {
                profile = Some(
                    read_second_profile(profile.is_some(), &fields).or_else(|e| err(line, e))?,
                );
            }
            None if fields.len() == 2 && fields[0].eq_ignore_ascii_case("fs") => {
                fs_meta = Some(read_fs(fs_meta, fields[1]).or_else(|e| err(line, e))?);
            }
            None => {
                // A device's recording names its axes x, y, z.
                if columns.is_empty() && profile.is_some() {
                    columns = ["x", "y", "z"].map(String::from).to_vec();
                }
                if columns.is_empty() {
                    return err(
                        0,
                        "--columns: name the columns to read (only a device's recording, \
                         with its `profile` line, has x,y,z by default)",
                    );
                }
                let all_names = fields.iter().all(|f| !f.is_empty() && !is_number(f));
                let has_all = columns.iter().all(|c| fields.contains(&c.as_str()));
                if all_names && has_all {
                    let o = Options {
                        columns: columns.clone(),
                        ..o.clone()
                    };
                    header = Some(Header::new(line, &fields, &o)?);
                    raw = vec![Vec::new(); columns.len()];
                } else if all_names && fields.len() > 2 {
                    let missing: Vec<&str> = columns
                        .iter()
                        .map(String::as_str)
                        .filter(|c| !fields.contains(c))
                        .collect();
                    return err(
                        line,
                        format!(
                            "the header `{}` has no column {}",
                            quote(&l.text),
                            missing.join(", ")
                        ),
                    );
                }
            }
        }
    }
    let Some(h) = header else {
        return err(0, format!("no header row naming {}", columns.join(", ")));
    };
    if raw[0].is_empty() {
        return err(h.line, "a header and no data rows");
    }
    let mut notes = vec![];
    let fs_time = if times.len() >= 2 {
        let mut steps: Vec<(usize, f64)> = times
            .windows(2)
            .map(|w| (w[1].0, w[1].1 - w[0].1))
            .collect();
        if let Some(&(line, dt)) = steps.iter().find(|s| s.1 <= 0.0) {
            return err(line, format!("time does not increase (step {dt} s)"));
        }
        let mut sorted: Vec<f64> = steps.iter().map(|s| s.1).collect();
        sorted.sort_by(f64::total_cmp);
        let median = sorted[sorted.len() / 2];
        let gaps: Vec<usize> = steps
            .iter()
            .filter(|s| s.1 > 1.5 * median)
            .map(|s| s.0)
            .collect();
        steps.retain(|s| s.1 <= 1.5 * median && (s.1 - median).abs() > 0.01 * median);
        if let Some(first) = gaps.first() {
            notes.push(format!("{} gap(s) in the time column (steps over 1.5x the median {median} s), the first at line {first}", gaps.len()));
        }
        if let Some(first) = steps.first() {
            notes.push(format!(
                "{} step(s) jitter by more than 1 % of the median, the first at line {}",
                steps.len(),
                first.0
            ));
        }
        Some(1.0 / median)
    } else {
        None
    };
    if let (Some(f), Some(m)) = (o.fs, fs_meta) {
        if (f - m).abs() > 1e-6 * m {
            return err(
                0,
                format!(
                    "--fs says {} Hz but the fs line says {} Hz: which rate is it?",
                    super::number::Num(f),
                    super::number::Num(m)
                ),
            );
        }
    }
    let (fs, fs_source) = match (o.fs, fs_time, fs_meta) {
        (Some(f), _, _) => (f, "--fs"),
        (None, Some(f), _) => (f, "the time column"),
        (None, None, Some(f)) => (f, "the fs metadata line"),
        (None, None, None) => {
            return err(
                0,
                "no sampling rate: give --fs, --time-column, or an `fs,<Hz>` line",
            )
        }
    };
    if !(fs.is_finite() && fs > 0.0) {
        return err(0, format!("sampling rate {fs} Hz: must be > 0"));
    }
    let recorded = profile
        .as_ref()
        .and_then(|p| profile_number(p, "m_s2_per_lsb"))
        .map(Units::Counts);
    let (units, units_source) = match (o.units, recorded) {
        (Some(u), _) => (u, "the arguments"),
        (None, Some(u)) => (u, "the recording's profile"),
        (None, None) => {
            return err(
                0,
                "--scale: give M_S2_PER_COUNT for raw counts, or --units g|m_s2 (the file has \
                 no `profile` line with the device's scale)",
            )
        }
    };
    let factor = match units {
        Units::Counts(s) if s.is_finite() && s > 0.0 => s,
        Units::Counts(s) => return err(0, format!("--scale {s}: must be a finite number > 0")),
        Units::G => 9.806_65,
        Units::MS2 => 1.0,
    };
    let m_s2 = raw
        .iter()
        .map(|c| c.iter().map(|v| v * factor).collect())
        .collect();
    Ok(Data {
        names: columns,
        raw,
        m_s2,
        fs,
        fs_source,
        notes,
        profile,
        units_source,
        counts_scale: match units {
            Units::Counts(s) => Some(s),
            _ => None,
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn opts(cols: &[&str]) -> Options {
        Options {
            columns: cols.iter().map(|s| s.to_string()).collect(),
            fs: None,
            time_column: None,
            units: Some(Units::Counts(0.5)),
        }
    }

    impl Options {
        fn with_units(mut self, units: Option<Units>) -> Self {
            self.units = units;
            self
        }
    }

    #[track_caller]
    fn fails(text: &str, o: &Options, line: usize, words: &str) {
        let e = read(text.as_bytes(), o).expect_err("malformed");
        assert_eq!(e.line, line, "{e}");
        assert!(e.problem.contains(words), "{e}");
    }

    #[test]
    fn reads_the_recordings_layout() {
        let text = "Fs,100\nLogging Type,1\nax,ay,az,gx\n1,2,3,4\n5,6,7,8\n";
        let d = read(text.as_bytes(), &opts(&["az", "ax"])).expect("valid");
        assert_eq!(d.fs, 100.0);
        assert_eq!(d.fs_source, "the fs metadata line");
        assert_eq!(d.raw, vec![vec![3.0, 7.0], vec![1.0, 5.0]]);
        assert_eq!(d.m_s2[0], vec![1.5, 3.5]);
    }

    #[test]
    fn malformed_and_edge_case_files_name_the_problem() {
        let o = opts(&["ax"]);
        fails("", &o, 0, "no header row");
        fails(
            "fs,1\nax\n1\n",
            &opts(&[]),
            0,
            "--columns: name the columns",
        );
        fails("fs,100\nax,ay\n", &o, 2, "no data rows");
        fails("fs,100\nax,ay\n1,x\n2,3\n", &opts(&["ay"]), 3, "ay = `x`");
        fails(
            "fs,100\nax,ay\n1,2\n3\n",
            &o,
            4,
            "1 fields, the header has 2",
        );
        fails("fs,100\nbx,by,bz\n1,2,3\n", &o, 2, "no column ax");
        fails("ax,ay\n1,2\n", &o, 0, "no sampling rate");
        fails("fs,-1\nax\n1\n", &o, 1, "must be a number > 0");
        // docs/lab.md: two rates, or two profiles, are an error, as replay reads them.
        fails(
            "fs,100\nfs,200\nax\n1\n",
            &o,
            2,
            "a second `fs` line says 200 Hz",
        );
        assert!(read("fs,100\nfs,100\nax\n1\n".as_bytes(), &o).is_ok());
        fails(
            "fs,100\nprofile,fs_hz=100\nprofile,fs_hz=100\nax\n1\n",
            &o,
            3,
            "a second `profile` line",
        );
        let mut t = opts(&["ax"]);
        t.time_column = Some("t".into());
        fails("t,ax\n0,1\n0,2\n", &t, 3, "does not increase");
        fails(
            "fs,10\nax\n1\n",
            &Options {
                units: Some(Units::Counts(-1.0)),
                ..opts(&["ax"])
            },
            0,
            "--scale -1",
        );
        // A single sample is a valid file (the commands say what they need).
        assert_eq!(
            read("fs,10\nax\n1\n".as_bytes(), &o).map(|d| d.raw[0].len()),
            Ok(1)
        );
    }

    #[test]
    fn a_rate_given_against_the_file_s_own_is_refused() {
        let o = Options {
            fs: Some(1000.0),
            ..opts(&["x"])
        };
        fails(
            "fs,3000\nx\n1\n",
            &o,
            0,
            "--fs says 1000 Hz but the fs line says 3000 Hz",
        );
    }

    #[test]
    fn a_device_recording_gives_its_columns_and_scale() {
        let o = Options {
            columns: vec![],
            fs: None,
            time_column: None,
            units: None,
        };
        let text = "fs,100\nprofile,fs_hz=100,m_s2_per_lsb=0.5\nn,x,y,z\n0,2,4,6\n";
        let d = read(text.as_bytes(), &o).expect("valid");
        assert_eq!(d.names, ["x", "y", "z"]);
        assert_eq!(
            (d.m_s2[2][0], d.units_source),
            (3.0, "the recording's profile")
        );
        // The arguments still win, and without a profile the scale must be given.
        let given = Options {
            units: Some(Units::Counts(1.0)),
            ..o.clone()
        };
        assert_eq!(
            read(text.as_bytes(), &given).expect("valid").m_s2[2][0],
            6.0
        );
        let bare = "fs,100\nn,x,y,z\n0,2,4,6\n";
        fails(bare, &opts(&["x"]).with_units(None), 0, "no `profile` line");
    }

    #[test]
    fn a_jump_in_the_sample_index_is_refused_where_it_is() {
        let o = opts(&["x"]);
        let text = "fs,100\nn,x,y,z\n4998,1,2,3\n4999,1,2,3\n9000,1,2,3\n";
        fails(text, &o, 5, "n jumps from 4999 to 9000");
        assert!(
            read("fs,100\nn,x,y,z\n7,1,2,3\n8,1,2,3\n".as_bytes(), &o).is_ok(),
            "any start"
        );
    }

    #[test]
    fn time_column_gives_the_rate_and_reports_gaps_and_jitter() {
        let mut o = opts(&["ax"]);
        o.time_column = Some("t".into());
        o.units = Some(Units::G);
        let text = "t,ax\n0.00,1\n0.01,1\n0.02,1\n0.05,1\n0.0605,1\n0.07,1\n";
        let d = read(text.as_bytes(), &o).expect("valid");
        assert!((d.fs - 100.0).abs() < 1e-9);
        assert_eq!(d.notes.len(), 2, "{:?}", d.notes);
        assert!(d.notes[0].contains("1 gap(s)") && d.notes[0].contains("line 5"));
        assert!(d.notes[1].contains("jitter"));
        assert!((d.m_s2[0][0] - 9.806_65).abs() < 1e-12);
    }
}
