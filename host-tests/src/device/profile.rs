//! A device profile as text: `KEY=VALUE` with the words a user writes (`off`, `on`,
//! `euler`, `trapezoid`), as `cargo lab device config` reads and prints it and as a
//! recording's `profile,` line carries it ([`crate::formats::recording`]).

use imu_core::profile::{Key, Profile};

/// A key's value as a user reads it, and writes it: [`read_pair`] takes it back exactly.
pub fn show(key: Key, v: f64) -> String {
    match key.word(v) {
        Some(w) => w.into(),
        // Exact (it reads back as itself), in exponent form when huge or tiny.
        None => crate::formats::number::Num(v).to_string(),
    }
}

/// `KEY=VALUE` read.
///
/// # Errors
/// `"{pair}: why"`: no `=`, an unknown key (the keys are listed), a value the key does not
/// take ([`Key::read`]: a finite number; `off`/`on` where the key takes them;
/// `euler`/`trapezoid`).
pub fn read_pair(pair: &str) -> Result<(Key, f64), String> {
    let bad = |why: &str| format!("{}: {why}", crate::formats::lines::quote(pair));
    let (k, v) = pair
        .split_once('=')
        .ok_or_else(|| bad("must be KEY=VALUE"))?;
    let key = Key::from_name(k.trim()).ok_or_else(|| {
        let names: Vec<&str> = Key::ALL.iter().map(|k| k.name()).collect();
        bad(&format!("unknown key; the keys: {}", names.join(", ")))
    })?;
    Ok((key, key.read(v).ok_or_else(|| bad(key.wanted()))?))
}

/// The profile `pairs` describe: the defaults with each pair set in order. A pair the key
/// does not take is skipped (the key keeps its default); [`Profile::validate`] judges the
/// whole.
pub fn profile_of(pairs: &[(Key, f64)]) -> Profile {
    let mut p = Profile::default();
    for &(k, v) in pairs {
        let _ = p.set(k, v);
    }
    p
}

/// Every key of `p` with its value, in [`Key::ALL`]'s order.
pub fn pairs_of(p: &Profile) -> Vec<(Key, f64)> {
    Key::ALL.iter().map(|&k| (k, p.get(k))).collect()
}

/// `pairs` as a recording's `profile,` line holds them: `(name, value as shown)`.
pub fn to_text(pairs: &[(Key, f64)]) -> Vec<(String, String)> {
    pairs
        .iter()
        .map(|&(k, v)| (k.name().to_string(), show(k, v)))
        .collect()
}

/// A recording's `profile,` pairs read as keys and values.
///
/// # Errors
/// The first pair [`read_pair`] refuses, as `"profile: {pair}: why"`.
pub fn from_text(pairs: &[(String, String)]) -> Result<Vec<(Key, f64)>, String> {
    pairs
        .iter()
        .map(|(k, v)| read_pair(&format!("{k}={v}")).map_err(|e| format!("profile: {e}")))
        .collect()
}

/// A profile file's entries (`config get --json` writes it, `config set --file` reads it), in
/// the file's order, or why not: not JSON, not an object, or a key given twice (a JSON
/// object's reader would keep the last silently).
pub fn file_entries(text: &str) -> Result<Vec<(String, serde_json::Value)>, String> {
    let Entries(entries) = serde_json::from_str(text).map_err(|e| match e.classify() {
        serde_json::error::Category::Data => format!("not a profile: {e}"),
        _ => format!("not JSON: {e}"),
    })?;
    for (i, (name, _)) in entries.iter().enumerate() {
        if entries[..i].iter().any(|(n, _)| n == name) {
            return Err(format!("{name} is given twice: which value is it?"));
        }
    }
    Ok(entries)
}

/// A JSON object's entries with duplicates kept.
struct Entries(Vec<(String, serde_json::Value)>);

impl<'de> serde::Deserialize<'de> for Entries {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Visit;
        impl<'de> serde::de::Visitor<'de> for Visit {
            type Value = Entries;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("an object of key: value, as `config get --json` writes")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                mut m: A,
            ) -> Result<Entries, A::Error> {
                let mut v = Vec::new();
                while let Some(entry) = m.next_entry()? {
                    v.push(entry);
                }
                Ok(Entries(v))
            }
        }
        d.deserialize_map(Visit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_key_s_shown_value_reads_back_as_itself() {
        let mut p = Profile::default();
        p.set(Key::LowpassFcHz, 50.0).expect("fits");
        p.set(Key::Scheme, 1.0).expect("fits");
        p.set(Key::XSign, -1.0).expect("fits");
        for (k, v) in pairs_of(&p) {
            let (k2, v2) = read_pair(&format!("{k}={}", show(k, v))).expect("reads back");
            assert_eq!(k2, k);
            assert!(v2 == v || (v.is_nan() && v2.is_nan()), "{k}: {v} -> {v2}");
        }
        assert_eq!(profile_of(&pairs_of(&p)), p);
        assert_eq!(
            from_text(&to_text(&pairs_of(&p))).map(|q| profile_of(&q)),
            Ok(p)
        );
    }

    #[test]
    fn a_bad_pair_is_quoted_short_with_what_the_key_takes() {
        let e = read_pair(&format!("fs_hz={}", "9".repeat(500))).expect_err("not finite");
        assert!(
            e.len() < 120 && e.contains("must be a finite number"),
            "{e}"
        );
        assert!(read_pair("nope=1")
            .expect_err("unknown")
            .contains("unknown key"));
        assert!(read_pair("drift").expect_err("no =").contains("KEY=VALUE"));
        // Words, in any case, for the keys of words; their numbers are refused.
        assert_eq!(read_pair("scheme=Trapezoid"), Ok((Key::Scheme, 1.0)));
        assert_eq!(read_pair("drift=ON"), Ok((Key::Drift, 1.0)));
        for pair in ["scheme=1", "drift=0", "scheme=0.5", "drift=2"] {
            assert!(
                read_pair(pair).expect_err(pair).contains("must be"),
                "{pair}"
            );
        }
        let (k, v) = read_pair("lowpass_fc_hz=OFF").expect("off");
        assert!(k == Key::LowpassFcHz && v.is_nan());
    }
}
