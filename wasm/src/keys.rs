//! The device's key table for the page: each key's name, unit, description and the values it
//! takes given the rest of a profile (`imu_app::device::range`, the code the firmware runs),
//! and a value shown with the words a user types (`off`, `on`, `euler`, `trapezoid`: the
//! core's [`Key::word`], which `cargo lab device config` uses too).

use core::fmt::{self, Write};

use imu_core::profile::{Key, Kind, Profile};

use crate::json::Json;

/// The profile whose values are `values`, in [`Key::ALL`]'s order (the defaults if empty; a
/// value a key does not take leaves that key's default).
pub fn profile_of(values: &[f64]) -> Profile {
    let mut p = Profile::default();
    for (&k, &v) in Key::ALL.iter().zip(values) {
        let _ = p.set(k, v);
    }
    p
}

/// A key's value as a user reads and types it: its word ([`Key::word`]: `off`, `on`, a
/// scheme) or the number (Rust's shortest form that reads back exactly).
pub fn show(out: &mut impl Write, key: Key, v: f64) -> fmt::Result {
    match key.word(v) {
        Some(w) => out.write_str(w),
        None => write!(out, "{v}"),
    }
}

/// A text of at most 160 bytes (a range, a shown value) for the JSON writer.
struct Text(heapless::String<160>);

impl Write for Text {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        self.0.push_str(s).map_err(|_| fmt::Error)
    }
}

fn text(f: impl FnOnce(&mut Text) -> fmt::Result) -> Result<Text, fmt::Error> {
    let mut t = Text(heapless::String::new());
    f(&mut t)?;
    Ok(t)
}

/// The key table of profile `p` as a JSON array: per key `id`, `name`, `unit`, `about`,
/// `kind` (`integer`, `real`, `optional`, `flag`, `sign`, or `word` for the scheme), `words`
/// (what a word key takes), `takes` (`imu_app::device::takes`, as the CLI says it), `value` (a number, `null` for off)
/// and `shown` (as a user types it).
pub fn table(j: &mut Json<'_>, p: &Profile) -> fmt::Result {
    j.raw("[")?;
    for (i, &key) in Key::ALL.iter().enumerate() {
        if i > 0 {
            j.raw(",")?;
        }
        let v = p.get(key);
        j.raw("{")?;
        j.key("id")?;
        write!(j, "{}", key as u8)?;
        for (name, s) in [
            ("name", key.name()),
            ("unit", key.unit()),
            ("about", key.about()),
        ] {
            j.raw(",")?;
            j.key(name)?;
            j.string(s)?;
        }
        let kind = match key.kind() {
            _ if key == Key::Scheme => "word",
            Kind::Integer { .. } => "integer",
            Kind::Real => "real",
            Kind::Optional => "optional",
            Kind::Flag => "flag",
            Kind::Sign => "sign",
        };
        j.raw(",")?;
        j.key("kind")?;
        j.string(kind)?;
        j.raw(",\"words\":[")?;
        for (n, w) in key.words().iter().enumerate() {
            if n > 0 {
                j.raw(",")?;
            }
            j.string(w)?;
        }
        j.raw("],")?;
        j.key("takes")?;
        j.string(&text(|t| imu_app::device::takes(t, p, key, true))?.0)?;
        j.raw(",")?;
        j.key("value")?;
        j.number(v)?;
        j.raw(",")?;
        j.key("shown")?;
        j.string(&text(|t| show(t, key, v))?.0)?;
        j.raw("}")?;
    }
    j.raw("]")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_and_numbers_read_back_as_shown() {
        let p = Profile::default();
        for &k in &Key::ALL {
            let v = p.get(k);
            let t = text(|t| show(t, k, v)).expect("short");
            let back = k.read(&t.0).expect("reads");
            assert!(back == v || (back.is_nan() && v.is_nan()), "{k}: {}", t.0);
        }
        assert_eq!(Key::Drift.read("maybe"), None);
    }

    #[test]
    fn the_table_lists_every_key_with_its_range_as_the_cli_says_it() {
        let mut b = [0u8; 16_384];
        let mut j = Json::new(&mut b);
        table(&mut j, &Profile::default()).expect("fits");
        let n = j.len();
        let s = core::str::from_utf8(&b[..n]).expect("UTF-8");
        assert_eq!(s.matches("\"id\":").count(), Key::ALL.len());
        // The board's rates and ADC, from imu_app::device::range.
        let fs = imu_app::device::range(&Profile::default(), Key::FsHz).expect("a range");
        assert!(s.contains("\"name\":\"fs_hz\""), "{s}");
        assert!(s.contains(&format!("\"takes\":\"{fs} Hz\"")), "{s}");
        assert!(s.contains("\"takes\":\"euler, trapezoid\""), "{s}");
    }
}
