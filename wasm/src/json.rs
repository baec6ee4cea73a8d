//! A JSON writer into a fixed buffer, for answers to the page: no allocator, and a buffer
//! too small is an error the caller sees (never a truncated document).

use core::fmt::{self, Write};

/// Writes into `buf` from the start; [`Json::len`] bytes are valid.
pub struct Json<'a> {
    buf: &'a mut [u8],
    len: usize,
}

impl<'a> Json<'a> {
    /// An empty document over `buf`.
    pub fn new(buf: &'a mut [u8]) -> Self {
        Self { buf, len: 0 }
    }

    /// Bytes written.
    pub const fn len(&self) -> usize {
        self.len
    }

    /// Whether nothing is written yet.
    pub const fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Raw text (punctuation, keys already quoted).
    pub fn raw(&mut self, s: &str) -> fmt::Result {
        self.write_str(s)
    }

    /// `s` as a JSON string, escaped.
    pub fn string(&mut self, s: &str) -> fmt::Result {
        self.write_char('"')?;
        for c in s.chars() {
            match c {
                '"' => self.write_str("\\\"")?,
                '\\' => self.write_str("\\\\")?,
                '\n' => self.write_str("\\n")?,
                c if (c as u32) < 0x20 => write!(self, "\\u{:04x}", c as u32)?,
                c => self.write_char(c)?,
            }
        }
        self.write_char('"')
    }

    /// `"name":` then the caller's value.
    pub fn key(&mut self, name: &str) -> fmt::Result {
        self.string(name)?;
        self.write_char(':')
    }

    /// A number; NaN and the infinities (not JSON) as `null`.
    pub fn number(&mut self, v: f64) -> fmt::Result {
        if v.is_finite() {
            write!(self, "{v}")
        } else {
            self.write_str("null")
        }
    }

    /// `true` or `false`.
    pub fn boolean(&mut self, b: bool) -> fmt::Result {
        self.write_str(if b { "true" } else { "false" })
    }
}

impl Write for Json<'_> {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        let end = self.len + s.len();
        let room = self.buf.get_mut(self.len..end).ok_or(fmt::Error)?;
        room.copy_from_slice(s.as_bytes());
        self.len = end;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strings_are_escaped_numbers_are_json_and_overflow_is_an_error() {
        let mut b = [0u8; 64];
        let mut j = Json::new(&mut b);
        j.string("a \"b\" \\ \n\u{1}").expect("fits");
        j.raw(",").expect("fits");
        j.number(f64::NAN).expect("fits");
        j.raw(",").expect("fits");
        j.number(0.1).expect("fits");
        let n = j.len();
        assert_eq!(
            core::str::from_utf8(&b[..n]).expect("fits"),
            r#""a \"b\" \\ \n\u0001",null,0.1"#
        );
        let mut small = [0u8; 3];
        assert!(Json::new(&mut small).string("abc").is_err());
    }
}
