//! The lines of a CSV read as a stream, each bounded in length, for the recording readers
//! ([`super::recording`], [`super::columns`]).
//!
//! # Design
//! A recording can be larger than memory would like, and a file that is not a recording at
//! all (`/dev/zero`, a binary) has no line ends: reading it whole, or a line of it whole,
//! takes as much memory as it is long. So lines are read one at a time and none may be longer
//! than [`MAX_LINE_BYTES`]; a longer one is an error at its number, quoted by its first
//! [`QUOTE_CHARS`] characters only. The widest row the readers meet is a logger's few dozen
//! columns of numbers (the MPU6050 recording's rows are under 100 bytes), so 64 KiB is a
//! bound no recording reaches and little memory.

use std::io::BufRead;

use super::recording::RecordingError;

/// The longest line read [bytes], its end included.
pub const MAX_LINE_BYTES: usize = 64 * 1024;

/// How many characters of a line an error message quotes.
pub const QUOTE_CHARS: usize = 40;

/// `s` for an error message: whole if short, else its first [`QUOTE_CHARS`] characters and
/// `...` with the length.
pub fn quote(s: &str) -> String {
    match s.char_indices().nth(QUOTE_CHARS) {
        None => s.to_string(),
        Some((cut, _)) => format!("{}... ({} bytes)", &s[..cut], s.len()),
    }
}

/// One line that carries content: its 1-based number and its text, trimmed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Line {
    /// The line's number in the file (1-based).
    pub number: usize,
    /// Its text, trimmed of surrounding white space.
    pub text: String,
}

impl Line {
    /// Its comma-separated fields, each trimmed.
    pub fn fields(&self) -> Vec<&str> {
        self.text.split(',').map(str::trim).collect()
    }
}

/// The lines of `input` that carry content, in order: blank lines and `#` comments are
/// skipped, a UTF-8 byte-order mark before the first line is dropped.
///
/// # Errors
/// An item is an error (and the last one) for a line longer than [`MAX_LINE_BYTES`], a line
/// that is not UTF-8, or a read that failed.
pub fn content_lines<R: BufRead>(input: R) -> ContentLines<R> {
    ContentLines {
        input,
        number: 0,
        done: false,
    }
}

/// The iterator [`content_lines`] returns.
#[derive(Debug)]
pub struct ContentLines<R> {
    input: R,
    number: usize,
    done: bool,
}

impl<R: BufRead> ContentLines<R> {
    fn fail(&mut self, problem: String) -> Option<Result<Line, RecordingError>> {
        self.done = true;
        Some(Err(RecordingError {
            line: self.number,
            problem,
        }))
    }
}

impl<R: BufRead> Iterator for ContentLines<R> {
    type Item = Result<Line, RecordingError>;

    fn next(&mut self) -> Option<Self::Item> {
        let mut buf = Vec::new();
        while !self.done {
            buf.clear();
            let limit = (MAX_LINE_BYTES + 1) as u64;
            let read = std::io::Read::take(&mut self.input, limit).read_until(b'\n', &mut buf);
            self.number += 1;
            match read {
                Err(e) => return self.fail(format!("could not be read: {e}")),
                Ok(0) => {
                    self.done = true;
                    return None;
                }
                Ok(_) => {}
            }
            if buf.len() > MAX_LINE_BYTES {
                let head = String::from_utf8_lossy(&buf[..QUOTE_CHARS.min(buf.len())]);
                return self.fail(format!(
                    "longer than {MAX_LINE_BYTES} bytes (not a recording's row?): `{}...`",
                    head.escape_debug()
                ));
            }
            let Ok(text) = std::str::from_utf8(&buf) else {
                return self.fail("not UTF-8 text (not a CSV file?)".into());
            };
            let text = if self.number == 1 {
                text.strip_prefix('\u{feff}').unwrap_or(text)
            } else {
                text
            };
            let text = text.trim();
            if !text.is_empty() && !text.starts_with('#') {
                return Some(Ok(Line {
                    number: self.number,
                    text: text.to_string(),
                }));
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all(input: &[u8]) -> Vec<Result<Line, RecordingError>> {
        content_lines(input).collect()
    }

    #[test]
    fn skips_blanks_comments_and_a_byte_order_mark() {
        let got = all("\u{feff}fs,1\n\n  # note\n n,x \r\n1,2".as_bytes());
        let lines: Vec<(usize, String)> = got
            .into_iter()
            .map(|l| l.map(|l| (l.number, l.text)).expect("valid"))
            .collect();
        assert_eq!(
            lines,
            vec![(1, "fs,1".into()), (4, "n,x".into()), (5, "1,2".into())]
        );
    }

    #[test]
    fn a_line_without_an_end_is_refused_after_the_bound_not_read_whole() {
        // An endless input (as /dev/zero is): the reader must stop at the bound.
        let endless = std::io::BufReader::new(std::io::repeat(0));
        let got: Vec<_> = content_lines(endless).collect();
        assert_eq!(got.len(), 1);
        let e = got[0].clone().expect_err("too long");
        assert_eq!(e.line, 1);
        assert!(e.problem.contains("longer than 65536 bytes"), "{e}");
        assert!(e.problem.len() < 200, "quoted short: {e}");
        // A line exactly at the bound is read.
        let mut at = vec![b'1'; MAX_LINE_BYTES - 1];
        at.push(b'\n');
        assert!(all(&at)[0].is_ok());
        at.insert(0, b'1');
        assert!(all(&at)[0].is_err());
    }

    #[test]
    fn binary_input_is_refused_with_its_line() {
        let got = all(b"fs,1\n\xff\xfe\n");
        assert!(got[0].is_ok());
        let e = got[1].clone().expect_err("not text");
        assert_eq!(e.line, 2);
        assert!(e.problem.contains("not UTF-8"), "{e}");
        assert_eq!(got.len(), 2, "nothing after the error");
    }

    #[test]
    fn long_text_is_quoted_by_its_beginning() {
        assert_eq!(quote("short"), "short");
        let q = quote(&"a".repeat(1000));
        assert!(
            q.starts_with(&"a".repeat(QUOTE_CHARS)) && q.ends_with("(1000 bytes)"),
            "{q}"
        );
        assert!(q.len() < 60);
    }
}
