//! Numbers in messages as a person reads them: a value given as `1e300` is quoted as
//! `1e300`, not as its 301 digits.

use std::fmt;

/// `v` shown plainly between 1e-6 and 1e9 in magnitude (and 0), in exponent form outside.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Num(pub f64);

impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let a = self.0.abs();
        if self.0 == 0.0 || !a.is_finite() || (1e-6..1e9).contains(&a) {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Num;

    #[test]
    fn huge_and_tiny_values_are_quoted_short() {
        assert_eq!(Num(1e300).to_string(), "1e300");
        assert_eq!(Num(1e-300).to_string(), "1e-300");
        assert_eq!(Num(-2.5e12).to_string(), "-2.5e12");
        assert_eq!(Num(3000.0).to_string(), "3000");
        assert_eq!(Num(0.25).to_string(), "0.25");
        assert_eq!(Num(0.0).to_string(), "0");
        assert_eq!(Num(f64::NAN).to_string(), "NaN");
    }
}
