//! Reading a recorded trace for `cargo lab replay` (and `allan`, `drift`), and writing one
//! (`cargo lab device record`).
//!
//! # Format
//! ```text
//! # comments and blank lines are skipped anywhere
//! fs,3000          <- optional: the sampling rate [Hz], before the header
//! profile,fs_hz=3000,m_s2_per_lsb=0.0239...,adc_bits=12,...   <- optional: the device's
//!                     settings while it recorded (every key, as `config get` prints them)
//! n,x,y,z          <- header: first column `n` (sample index) or `t` (time [s])
//! 0,2048,2051,2457 <- X, Y, Z as ADC codes, integers 0..=65535
//! 1,2049,2050,2456
//! ```
//! The sampling rate comes from `--fs`, else the `fs,` line, else the `t` column's mean
//! step; two sources that disagree are an error. Sample indices must run on without gaps
//! (a gap is lost time, and lost time is a position error); times must increase with a
//! step within 1 % of the mean; a `profile` line's `fs_hz` must agree with them too. Every
//! problem is reported with its line number. The file is
//! read as a stream of bounded lines ([`super::lines`]).

use std::fmt;
use std::io::BufRead;

use super::lines::{content_lines, quote};

/// A recorded trace.
#[derive(Clone, Debug, PartialEq)]
pub struct Recording {
    /// Sampling rate [Hz] (whole).
    pub fs: u32,
    /// `[x, y, z]` codes in order.
    pub samples: Vec<[u16; 3]>,
    /// The device's settings while it recorded, `(key name, value)` as `config get` shows
    /// them, if the file carries them (`device record` and `simulate --csv` write them;
    /// `replay`, `allan` and `drift` read them; `crate::device::profile` reads the values).
    pub profile: Option<Vec<(String, String)>>,
}

/// What is wrong with a file, and where (1-based line numbers).
#[derive(Clone, Debug, PartialEq)]
pub struct RecordingError {
    /// The line, or 0 for the file as a whole.
    pub line: usize,
    /// The problem.
    pub problem: String,
}

impl fmt::Display for RecordingError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.line == 0 {
            write!(f, "{}", self.problem)
        } else {
            write!(f, "line {}: {}", self.line, self.problem)
        }
    }
}

/// An error at `line` (0: the file as a whole).
pub(crate) fn err<T>(line: usize, problem: impl Into<String>) -> Result<T, RecordingError> {
    Err(RecordingError {
        line,
        problem: problem.into(),
    })
}

#[derive(Clone, Copy, PartialEq)]
enum Clock {
    Index,
    Time,
}

/// The recording in the format [`parse`] reads: the `fs,` line, the header `n,x,y,z`, one
/// row per sample.
pub fn write(rec: &Recording) -> String {
    let mut s = format!("# raw ADC codes, as sampled\nfs,{}\n", rec.fs);
    if let Some(pairs) = &rec.profile {
        s += "# the device's settings while it recorded\n";
        s += &profile_line(pairs);
        s.push('\n');
    }
    s += "n,x,y,z\n";
    for (i, [x, y, z]) in rec.samples.iter().enumerate() {
        s += &format!("{i},{x},{y},{z}\n");
    }
    s
}

/// The `profile,KEY=VALUE,...` line of `pairs`.
pub fn profile_line(pairs: &[(String, String)]) -> String {
    let mut s = String::from("profile");
    for (k, v) in pairs {
        s += &format!(",{k}={v}");
    }
    s
}

/// The rate [Hz] an `fs,<Hz>` line's `value` gives, or why not: a finite number above 0,
/// and the same as an earlier `fs` line's (`before`), if there was one.
pub(crate) fn read_fs(before: Option<f64>, value: &str) -> Result<f64, String> {
    match value.parse::<f64>() {
        Ok(v) if before.is_some_and(|f| f != v) => Err(format!(
            "a second `fs` line says {} Hz: which rate is it?",
            quote(value)
        )),
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!(
            "`fs,{}`: the sampling rate must be a number > 0 Hz",
            quote(value)
        )),
    }
}

/// [`read_profile`], refused if the file had a `profile` line already (`seen`).
pub(crate) fn read_second_profile(
    seen: bool,
    fields: &[&str],
) -> Result<Vec<(String, String)>, String> {
    if seen {
        return Err("a second `profile` line: which settings are they?".into());
    }
    read_profile(fields)
}

/// The pairs of a `profile` line's `fields` (the word `profile` first), or why not: each
/// `KEY=VALUE`, no key twice.
pub(crate) fn read_profile(fields: &[&str]) -> Result<Vec<(String, String)>, String> {
    let mut pairs: Vec<(String, String)> = Vec::with_capacity(fields.len());
    for f in &fields[1..] {
        let Some((k, v)) = f.split_once('=') else {
            return Err(format!("profile: `{}` is not KEY=VALUE", quote(f)));
        };
        let (k, v) = (k.trim(), v.trim());
        if pairs.iter().any(|(j, _)| j == k) {
            return Err(format!("profile: {} is given twice", quote(k)));
        }
        pairs.push((k.to_string(), v.to_string()));
    }
    Ok(pairs)
}

/// The number a profile's `key` holds, if it has that key and it is a number.
pub(crate) fn profile_number(pairs: &[(String, String)], key: &str) -> Option<f64> {
    pairs
        .iter()
        .find(|(k, _)| k == key)
        .and_then(|(_, v)| v.parse().ok())
}

/// Parses a recording; `fs_arg` is `--fs`, if given.
///
/// # Errors
/// The first problem, with its line.
pub fn parse(input: impl BufRead, fs_arg: Option<f64>) -> Result<Recording, RecordingError> {
    let mut fs_line: Option<f64> = None;
    let mut profile: Option<Vec<(String, String)>> = None;
    let mut clock = None;
    let mut samples = vec![];
    let mut first_stamp: Option<(usize, f64)> = None;
    let mut last_stamp: Option<f64> = None;
    let mut steps: Vec<(usize, f64)> = vec![];
    for l in content_lines(input) {
        let l = l?;
        let (line, fields) = (l.number, l.fields());
        let Some(clk) = clock else {
            if fields.len() == 2 && fields[0].eq_ignore_ascii_case("fs") {
                fs_line = Some(read_fs(fs_line, fields[1]).or_else(|e| err(line, e))?);
                continue;
            }
            if fields[0].eq_ignore_ascii_case("profile") {
                profile = Some(
                    read_second_profile(profile.is_some(), &fields).or_else(|e| err(line, e))?,
                );
                continue;
            }
            let names: Vec<String> = fields.iter().map(|f| f.to_ascii_lowercase()).collect();
            clock = match names.iter().map(String::as_str).collect::<Vec<_>>()[..] {
                ["n", "x", "y", "z"] => Some(Clock::Index),
                ["t", "x", "y", "z"] => Some(Clock::Time),
                _ => {
                    return err(
                        line,
                        format!(
                            "expected the header `n,x,y,z` or `t,x,y,z`, found `{}`",
                            quote(&l.text)
                        ),
                    )
                }
            };
            continue;
        };
        if fields.len() != 4 {
            return err(line, format!("expected 4 fields, found {}", fields.len()));
        }
        let stamp: f64 = match fields[0].parse::<f64>() {
            Ok(v) if v.is_finite() => v,
            _ => return err(line, format!("`{}` is not a number", quote(fields[0]))),
        };
        if clk == Clock::Index {
            let want = first_stamp.map_or(stamp, |(_, f)| f + samples.len() as f64);
            if stamp != stamp.trunc() || stamp < 0.0 {
                return err(
                    line,
                    format!(
                        "sample index `{}` is not a whole number >= 0",
                        quote(fields[0])
                    ),
                );
            }
            if stamp != want {
                return err(
                    line,
                    format!(
                        "sample index jumps from {} to {stamp}: {} samples missing",
                        want - 1.0,
                        stamp - want
                    ),
                );
            }
        } else if let Some(prev) = last_stamp {
            if stamp <= prev {
                return err(
                    line,
                    format!("time {stamp} s does not increase (previous {prev} s)"),
                );
            }
            steps.push((line, stamp - prev));
        }
        first_stamp.get_or_insert((line, stamp));
        last_stamp = Some(stamp);
        let mut s = [0u16; 3];
        for (k, f) in fields[1..].iter().enumerate() {
            s[k] = f.parse::<u16>().or_else(|_| {
                err(
                    line,
                    format!(
                        "{} = `{}` is not an ADC code (a whole number 0..=65535)",
                        ["x", "y", "z"][k],
                        quote(f)
                    ),
                )
            })?;
        }
        samples.push(s);
    }
    if clock.is_none() {
        return err(0, "no header: expected `n,x,y,z` or `t,x,y,z`");
    }
    if samples.is_empty() {
        return err(0, "no samples after the header");
    }
    let fs_time = if clock == Some(Clock::Time) && !steps.is_empty() {
        // Judged against the median step, which one gap cannot move (it moves the mean, and
        // then every step but the gap's looks off).
        let mut sorted: Vec<f64> = steps.iter().map(|s| s.1).collect();
        sorted.sort_by(f64::total_cmp);
        let median = sorted[sorted.len() / 2];
        if let Some(&(line, dt)) = steps.iter().find(|s| (s.1 - median).abs() > 0.01 * median) {
            return err(line, format!("time step {dt} s differs from the median {median} s by more than 1 %: a gap or jitter"));
        }
        let mean = steps.iter().map(|s| s.1).sum::<f64>() / steps.len() as f64;
        Some(1.0 / mean)
    } else {
        None
    };
    let fs_profile = profile.as_ref().and_then(|p| profile_number(p, "fs_hz"));
    let sources = [
        ("--fs", fs_arg),
        ("the fs line", fs_line),
        ("the t column", fs_time),
        ("the profile's fs_hz", fs_profile),
    ];
    let given: Vec<(&str, f64)> = sources
        .iter()
        .filter_map(|(n, v)| v.map(|v| (*n, v)))
        .collect();
    let Some(&(name, fs)) = given.first() else {
        return err(
            0,
            "no sampling rate: give --fs, an `fs,<Hz>` line, or a `t` column",
        );
    };
    if let Some(&(other, v)) = given[1..]
        .iter()
        .find(|(_, v)| (v - fs).abs() > 1e-6 * fs.abs())
    {
        return err(
            0,
            format!(
                "{name} says {} Hz but {other} says {} Hz",
                super::number::Num(fs),
                super::number::Num(v)
            ),
        );
    }
    let whole = fs.round();
    if (fs - whole).abs() > 1e-6 * fs || !(1.0..=100_000.0).contains(&whole) {
        return err(
            0,
            format!(
                "sampling rate {} Hz: must be a whole number of Hz, 1..=100000",
                super::number::Num(fs)
            ),
        );
    }
    Ok(Recording {
        fs: whole as u32,
        samples,
        profile,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[track_caller]
    fn fails(text: &str, fs: Option<f64>, line: usize, words: &str) {
        let e = parse(text.as_bytes(), fs).expect_err("malformed");
        assert_eq!(e.line, line, "{e}");
        assert!(e.problem.contains(words), "{e}");
    }

    #[test]
    fn a_profile_line_is_read_back_and_must_agree_with_the_rate() {
        let pairs: Vec<(String, String)> = [("fs_hz", "3000"), ("counts_per_inch", "1600")]
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        let rec = Recording {
            fs: 3000,
            samples: vec![[1, 2, 3]],
            profile: Some(pairs),
        };
        assert_eq!(
            parse(write(&rec).as_bytes(), None).expect("reads back"),
            rec
        );
        fails(
            "fs,1000\nprofile,fs_hz=3000\nn,x,y,z\n0,1,2,3\n",
            None,
            0,
            "the fs line says 1000 Hz but the profile's fs_hz says 3000 Hz",
        );
        fails(
            "fs,100\nprofile,cpi\nn,x,y,z\n0,1,2,3\n",
            None,
            2,
            "profile: `cpi` is not KEY=VALUE",
        );
        fails(
            "fs,100\nprofile,a=1,a=2\nn,x,y,z\n0,1,2,3\n",
            None,
            2,
            "profile: a is given twice",
        );
        fails(
            "profile,fs_hz=100\nprofile,fs_hz=100\nn,x,y,z\n0,1,2,3\n",
            None,
            2,
            "a second `profile` line",
        );
        // The profile's rate alone is a rate.
        let r = parse("profile,fs_hz=250\nn,x,y,z\n0,1,2,3\n".as_bytes(), None).expect("valid");
        assert_eq!(r.fs, 250);
    }

    #[test]
    fn reads_index_and_time_files() {
        let r = parse("# x\nfs,1000\nn,x,y,z\n0,1,2,3\n1,4,5,6\n".as_bytes(), None).expect("valid");
        assert_eq!((r.fs, r.samples), (1000, vec![[1, 2, 3], [4, 5, 6]]));
        let r = parse(
            "t,x,y,z\n0.000,1,2,3\n0.001,1,2,3\n0.002,1,2,3\n".as_bytes(),
            None,
        )
        .expect("valid");
        assert_eq!(r.fs, 1000);
    }

    #[test]
    fn malformed_files_name_the_line() {
        fails("", None, 0, "no header");
        fails("n,x,y,z\n", Some(100.0), 0, "no samples");
        fails("a,b,c\n", None, 1, "expected the header");
        fails("n,x,y,z\n0,1,2\n", Some(100.0), 2, "4 fields");
        fails("n,x,y,z\n0,1,2,3\n1,1,two,3\n", Some(100.0), 3, "y = `two`");
        fails("n,x,y,z\n0,1,2,70000\n", Some(100.0), 2, "z = `70000`");
        fails(
            "n,x,y,z\n0,1,2,3\n2,1,2,3\n",
            Some(100.0),
            3,
            "1 samples missing",
        );
        fails("t,x,y,z\n0,1,2,3\n0,1,2,3\n", None, 3, "does not increase");
        fails(
            "t,x,y,z\n0,1,2,3\n0.01,1,2,3\n0.03,1,2,3\n0.04,1,2,3\n",
            None,
            4,
            "gap or jitter",
        );
        fails("n,x,y,z\n0,1,2,3\n", None, 0, "no sampling rate");
        fails(
            "fs,100\nn,x,y,z\n0,1,2,3\n",
            Some(200.0),
            0,
            "says 200 Hz but the fs line says 100 Hz",
        );
        fails("fs,-3\n", None, 1, "must be a number > 0");
        fails("n,x,y,z\n0,1,2,3\n", Some(99.5), 0, "whole number of Hz");
        fails(
            "fs,100\nfs,200\nn,x,y,z\n0,1,2,3\n",
            None,
            2,
            "a second `fs` line",
        );
        // A negative rate is refused as a rate, not as a disagreement with itself.
        fails("n,x,y,z\n0,1,2,3\n", Some(-1.0), 0, "sampling rate -1 Hz");
    }

    #[test]
    fn a_gap_in_time_is_reported_where_it_is() {
        let mut text = String::from("t,x,y,z\n");
        for i in 0..6000 {
            // 0.5 s missing after sample 4999 (line 5001 is sample 4999).
            let t = f64::from(i) / 1000.0 + if i >= 5000 { 0.5 } else { 0.0 };
            text += &format!("{t},1,2,3\n");
        }
        fails(&text, None, 5002, "a gap or jitter");
    }

    #[test]
    fn a_byte_order_mark_is_not_part_of_the_first_line() {
        let r = parse("\u{feff}fs,100\nn,x,y,z\n0,1,2,3\n".as_bytes(), None).expect("parses");
        assert_eq!((r.fs, r.samples.len()), (100, 1));
    }

    #[test]
    fn a_single_sample_is_a_recording() {
        assert_eq!(
            parse("n,x,y,z\n5,1,2,3\n".as_bytes(), Some(100.0)).map(|r| r.samples.len()),
            Ok(1)
        );
    }
}
