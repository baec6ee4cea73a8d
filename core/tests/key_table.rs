//! The device's key table: every key's stated range is what validation accepts, at its ends
//! and just past them, on profiles across the rates and resolutions the core takes; every key
//! has a unit where its value has one and a line for the user.

use imu_core::profile::{Key, Kind, Profile, Range, Shown};

/// Profiles that validate, spanning the rate, the resolution and the scale.
fn bases() -> Vec<(&'static str, Profile)> {
    let with = |pairs: &[(Key, f64)]| {
        let mut p = Profile::default();
        for &(k, v) in pairs {
            p.set(k, v).expect("a base value fits its key");
        }
        p
    };
    vec![
        ("defaults", Profile::default()),
        ("100 kHz", with(&[(Key::FsHz, 100_000.0)])),
        ("200 Hz", with(&[(Key::FsHz, 200.0)])),
        ("16 bits", with(&[(Key::AdcBits, 16.0)])),
        (
            "2 bits",
            with(&[(Key::AdcBits, 2.0), (Key::MS2PerLsb, 100.0)]),
        ),
        ("drift off", with(&[(Key::Drift, 0.0)])),
    ]
}

/// A value a little inside or outside `v`: by one for an integer key, else by a part in 1e9.
fn nudge(key: Key, v: f64, up: bool) -> f64 {
    let step = match key.kind() {
        Kind::Integer { .. } => 1.0,
        _ if v == 0.0 => 1e-12,
        _ => v.abs() * 1e-9,
    };
    if up {
        v + step
    } else {
        v - step
    }
}

/// Whether the profile with `key = v` validates, and if not, the key the refusal names.
fn verdict(base: &Profile, key: Key, v: f64) -> Result<(), Key> {
    let mut p = *base;
    p.set(key, v).map_err(|e| e.key())?;
    p.validate().map_err(|e| e.key())
}

/// `key = v` is taken, or refused only for another key whose value the change has moved out
/// of that key's own range (a rate of 1 Hz leaves a 1 s window 1 sample long: the window's
/// range at 1 Hz says so).
fn taken(base: &Profile, key: Key, v: f64) -> Result<(), String> {
    match verdict(base, key, v) {
        Ok(()) => Ok(()),
        Err(other) if other != key => {
            let mut p = *base;
            p.set(key, v).map_err(|e| format!("{e}"))?;
            match p.range(other) {
                Some(r) if !r.contains(p.get(other)) && !p.get(other).is_nan() => Ok(()),
                _ => Err(format!("refused for {other}, inside its range")),
            }
        }
        Err(k) => Err(format!("refused for {k}")),
    }
}

#[test]
fn every_stated_range_is_what_validation_takes_at_its_ends_and_just_past_them() {
    let mut checked = 0;
    for (name, base) in bases() {
        assert_eq!(base.validate(), Ok(()), "{name}: the base validates");
        for key in Key::ALL {
            let Some(r) = base.range(key) else {
                continue;
            };
            // The ends, moved inside where they are excluded.
            let lo = if r.min_excluded {
                nudge(key, r.min, true)
            } else {
                r.min
            };
            let hi = if r.max_excluded {
                nudge(key, r.max, false)
            } else {
                r.max
            };
            // Past the ends: the excluded end itself, else a step beyond it.
            let below = if r.min_excluded {
                r.min
            } else {
                nudge(key, r.min, false)
            };
            let above = if r.max_excluded {
                r.max
            } else {
                nudge(key, r.max, true)
            };
            for (v, what) in [(lo, "lowest"), (hi, "highest")] {
                // The cursor axes differ: the other axis's value is refused, naming this one.
                let other = match key {
                    Key::XAxis => Some(Key::YAxis),
                    Key::YAxis => Some(Key::XAxis),
                    _ => None,
                };
                if other.is_some_and(|o| base.get(o) == v) {
                    assert_eq!(verdict(&base, key, v), Err(key), "{name}: {key} = {v}");
                    continue;
                }
                let got = taken(&base, key, v);
                assert!(
                    got.is_ok(),
                    "{name}: {key} = {v} ({what} of {r}) refused: {got:?}"
                );
                assert!(r.contains(v), "{name}: {key}: {r} holds its {what} {v}");
            }
            for (v, what) in [(below, "below"), (above, "above")] {
                // A key whose integer type ends where its range does cannot be set past it.
                if matches!(key.kind(), Kind::Integer { min, max }
                    if (what == "below" && r.min <= f64::from(min))
                        || (what == "above" && r.max >= f64::from(max)))
                {
                    continue;
                }
                assert_eq!(
                    verdict(&base, key, v),
                    Err(key),
                    "{name}: {key} = {v} ({what} {r}) must be refused naming {key}"
                );
                assert!(!r.contains(v), "{name}: {key}: {r} excludes {v}");
            }
            checked += 1;
        }
    }
    assert!(checked > 6 * 15, "{checked} ranges checked");
}

#[test]
fn the_ends_a_range_shows_are_values_it_takes() {
    // A user types back what `config get` shows: each included end, as printed, must be in.
    let mut checked = 0;
    for (name, base) in bases() {
        for key in Key::ALL {
            let Some(r) = base.range(key) else {
                continue;
            };
            let shown = r.to_string();
            let Some((lo, hi)) = shown.split_once("..=") else {
                continue;
            };
            // The cursor axes must differ: the other's value is refused, not out of range.
            if matches!(key, Key::XAxis | Key::YAxis) {
                continue;
            }
            for end in [lo, hi] {
                let v: f64 = end.parse().expect("a number");
                assert!(
                    r.contains(v),
                    "{name}: {key}: {shown} shows {v}, which it refuses"
                );
                assert!(taken(&base, key, v).is_ok(), "{name}: {key} = {v} refused");
            }
            checked += 1;
        }
    }
    assert!(checked > 6 * 12, "{checked}");
}

#[test]
fn ranges_follow_the_keys_they_depend_on() {
    let mut p = Profile::default();
    let cal = |p: &Profile| p.range(Key::CalibrationS).expect("a range");
    assert_eq!(cal(&p).min, 16.0 / 3000.0);
    p.set(Key::FsHz, 100.0).expect("fits");
    assert_eq!((cal(&p).min, cal(&p).max), (0.16, 60.0));
    let lp = p.range(Key::LowpassFcHz).expect("a range");
    assert!((lp.min - 1e-4).abs() < 1e-18, "{lp}");
    assert_eq!((lp.max, lp.max_excluded), (50.0, true));
    p.set(Key::AdcBits, 10.0).expect("fits");
    let m = p.range(Key::MS2PerLsb).expect("a range");
    assert_eq!(
        (m.min, m.max),
        (2.0 * 9.806_65 / 1024.0, 1000.0 * 9.806_65 / 1024.0)
    );
    for k in Key::ALL {
        let listed = matches!(k.kind(), Kind::Flag | Kind::Sign);
        assert_eq!(
            p.range(k).is_none(),
            listed,
            "{k}: a range, or its kind lists its values"
        );
    }
    assert_eq!(p.range(Key::Scheme), Some(Range::within(0.0, 1.0)));
    assert_eq!(p.range(Key::YAxis), Some(Range::within(0.0, 2.0)));
}

#[test]
fn the_issue_s_typos_are_refused_naming_the_key_typed() {
    // A scale of 1e30 once blamed counts_per_inch (the read-out ratio failed first), 1e9 a
    // drift key; a resolution of 1e9 counts/inch and a 1000 s window were accepted.
    for (key, v) in [
        (Key::MS2PerLsb, 1e30),
        (Key::MS2PerLsb, 1e9),
        (Key::MS2PerLsb, 1e-9),
        (Key::CountsPerInch, 1e9),
        (Key::CountsPerInch, 30_000.0),
        (Key::CalibrationS, 1000.0),
        (Key::RestNoiseMaxMS2, 100.0),
    ] {
        assert_eq!(
            verdict(&Profile::default(), key, v),
            Err(key),
            "{key} = {v}"
        );
    }
}

#[test]
fn every_key_has_a_line_and_a_unit_where_its_value_has_one() {
    for key in Key::ALL {
        assert!(key.about().len() > 10, "{key}: {}", key.about());
        let dimensionless = matches!(key.kind(), Kind::Flag | Kind::Sign)
            || matches!(key, Key::Scheme | Key::XAxis | Key::YAxis);
        assert_eq!(
            key.unit().is_empty(),
            dimensionless,
            "{key}: {:?}",
            key.unit()
        );
    }
}

#[test]
fn ranges_and_numbers_read_as_a_person_writes_them() {
    let show = |v: f64| Shown(v).to_string();
    assert_eq!(show(1e9), "1e9");
    assert_eq!(show(0.1), "0.1");
    assert_eq!(show(0.023_942_138_671_875), "0.0239421");
    assert_eq!(show(16.0 / 3000.0), "0.00533333");
    assert_eq!(show(25_400.0), "25400");
    assert_eq!(show(0.0), "0");
    assert_eq!(show(-2.5), "-2.5");
    assert_eq!(show(1e-6), "1e-6");
    assert_eq!(show(123_456.7), "123457");
    assert_eq!(show(1e7), "1e7");
    assert_eq!(show(9_999_999.0), "9999999");
    assert_eq!(show(1e-4), "0.0001");
    // Rounded inwards to the digits shown: what is shown lies on the asked side.
    assert_eq!(Shown::inward(16.0 / 3000.0, true), 0.005_333_34);
    assert_eq!(Shown::inward(16.0 / 3000.0, false), 0.005_333_33);
    assert_eq!(Shown::inward(123_456.7, false), 123_456.0);
    assert_eq!(Shown::inward(123_456.2, true), 123_457.0);
    assert_eq!(Shown::inward(0.5, true), 0.5);
    assert_eq!(Shown::inward(0.5, false), 0.5);
    assert_eq!(Shown::inward(1e9, false), 1e9);
    assert_eq!(Shown::inward(0.0, true), 0.0);
    // 0 rounded up is the 0 a person types, not -0 (`0..=2`, not `-0..=2`).
    assert!(Shown::inward(0.0, true).is_sign_positive());
    assert_eq!(show(-0.0), "0");
    let closed = |min, max| Range {
        min,
        min_excluded: false,
        max,
        max_excluded: false,
    };
    assert_eq!(closed(0.0, 2.0).to_string(), "0..=2");
    let r = closed(0.2, 2.4);
    assert_eq!(r.to_string(), "0.2..=2.4");
    let open = Range {
        max_excluded: true,
        ..r
    };
    assert_eq!(open.to_string(), "0.2 to below 2.4");
    assert!(open.contains(0.2) && !open.contains(2.4) && !open.contains(f64::NAN));
    let above = Range {
        min_excluded: true,
        ..r
    };
    assert_eq!(above.to_string(), "above 0.2, up to 2.4");
    assert!(!above.contains(0.2) && above.contains(2.4));
}

#[test]
fn values_read_and_show_as_the_words_a_user_types() {
    use imu_core::profile::{FLAG_WORDS, SCHEMES};
    // Word keys take their words only, in any case; a number is not a flag's word.
    assert_eq!(Key::Drift.words(), &FLAG_WORDS);
    assert_eq!(Key::Scheme.words(), &SCHEMES);
    assert!(Key::CountsPerInch.words().is_empty());
    assert_eq!(Key::Drift.read(" ON "), Some(1.0));
    assert_eq!(Key::Drift.read("off"), Some(0.0));
    assert_eq!(Key::Drift.read("1"), None);
    assert_eq!(Key::Scheme.read("Trapezoid"), Some(1.0));
    assert_eq!(Key::Scheme.read("rk4"), None);
    // Numbers: finite only; `off` only where the key may be off.
    assert_eq!(Key::CountsPerInch.read(" 1600 "), Some(1600.0));
    assert_eq!(Key::CountsPerInch.read("1e400"), None);
    assert_eq!(Key::CountsPerInch.read("NaN"), None);
    assert_eq!(Key::CountsPerInch.read("off"), None);
    assert!(Key::LowpassFcHz.read("OFF").is_some_and(f64::is_nan));
    assert_eq!(Key::LowpassFcHz.read("50"), Some(50.0));
    // Shown: a word where the value is one, else None (the caller formats the number).
    assert_eq!(Key::LowpassFcHz.word(f64::NAN), Some("off"));
    assert_eq!(Key::LowpassFcHz.word(50.0), None);
    assert_eq!(Key::Drift.word(1.0), Some("on"));
    assert_eq!(Key::Drift.word(0.0), Some("off"));
    assert_eq!(Key::Scheme.word(1.0), Some("trapezoid"));
    for v in [0.5, -1.0, 2.0, f64::NAN] {
        assert_eq!(Key::Scheme.word(v), None, "{v}");
    }
    assert_eq!(Key::CountsPerInch.word(0.0), None);
    // What each must be, for a message.
    assert_eq!(Key::Drift.wanted(), "must be on or off");
    assert_eq!(Key::Scheme.wanted(), "must be euler or trapezoid");
    assert_eq!(Key::LowpassFcHz.wanted(), "must be a finite number or off");
    assert_eq!(Key::CountsPerInch.wanted(), "must be a finite number");
    // Every default reads back from its word or number.
    let p = Profile::default();
    for k in Key::ALL {
        let v = p.get(k);
        let shown = k.word(v).map_or_else(|| format!("{v}"), str::to_string);
        let back = k.read(&shown).expect("reads");
        assert!(back == v || (back.is_nan() && v.is_nan()), "{k}: {shown}");
    }
}
