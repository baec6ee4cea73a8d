//! Drift control's derived coefficients against an independent derivation
//! (`host-tests/tools/drift_settings_truth.py`: mpmath's root finder for the CUSUM alarms
//! and the lift test's tail, a brute-force frequency scan for the disturbance's gains),
//! for the default limits at four rates and every limit changed at two.
//!
//! Tolerances: counts of ticks, blocks and samples exact; a value the core keeps in Q8 or
//! Q16 within half its step of the real value (the core rounds it), plus 1e-6 for the
//! alarms (the core's bisection stops at 2^-200 of its bracket, the truth's root finder at
//! 40 digits: both far below a step); the gains within 0.2 % below and 0.01 % above the
//! scan (the core's residue grid misses a lobe's peak by at most 0.12 %, `gains.rs`; the
//! scan, at 1/64 of the narrowest lobe, by at most 0.2 %), plus half a Q16 step.

use std::collections::BTreeMap;

use imu_core::drift::DriftSettings;
use imu_core::{Drift, DriftError};

const TRUTH: &str = include_str!("data/drift_settings.csv");

/// The configurations of the truth script, by its names.
fn drift(name: &str) -> Drift {
    match name {
        "default" => Drift::default(),
        "variant" => Drift {
            false_start_hours: 100.0,
            hold_s: 0.01,
            knock_hz: 35.0,
            stroke_max_s: 1.2,
            glide_max_s: 2.5,
            lift_rise_s: Some(0.3),
            mount_tilt_deg: 2.0,
            bias_tau_s: Some(3.0),
            click_freeze_s: 0.1,
            ..Drift::default()
        },
        other => panic!("the truth names an unknown configuration {other}"),
    }
}

fn derived(s: &DriftSettings) -> BTreeMap<(String, usize), f64> {
    let mut out = BTreeMap::new();
    s.for_each_derived(|name, i, v| {
        assert!(
            out.insert((name.to_string(), i), v).is_none(),
            "{name}[{i}] twice"
        );
    });
    out
}

/// Whether `core` agrees with the truth `want` for the coefficient `name`.
fn agrees(name: &str, core: f64, want: f64) -> bool {
    const Q8: f64 = 0.5 / 256.0;
    const Q16: f64 = 0.5 / 65_536.0;
    match name {
        "alarm" => (core - want).abs() <= Q8 + 1e-6,
        "dist_margin" | "dist_margin_short" | "burst_k2" | "kappa" | "lobe" | "lone" | "k2"
        | "chi2" | "fade_chi2" | "calm_chi2" | "inflation" | "lift_k2" => {
            (core - want).abs() <= Q8 + 1e-9
        }
        "bin_ratio" | "lift_mount" | "lift_two_g" => (core - want).abs() <= Q16 + 1e-12,
        // Q32: half its step.
        "alias" => (core - want).abs() <= 0.5 / 4_294_967_296.0 + 1e-15,
        "gain_band_run" | "gain_quiet" | "gain_sub_short" | "gain_sub_long" | "gain_land"
        | "gain_velocity" => core >= want * (1.0 - 2e-3) - Q16 && core <= want * (1.0 + 1e-4) + Q16,
        "gain_displacement" => {
            core >= want * (1.0 - 2e-3) - 0.5 && core <= want * (1.0 + 1e-4) + 0.5
        }
        _ => core == want,
    }
}

#[test]
fn every_derived_coefficient_agrees_with_the_independent_derivation() {
    let mut truth: BTreeMap<String, BTreeMap<(String, usize), f64>> = BTreeMap::new();
    for line in TRUTH.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let [config, name, i, v] = f[..] else {
            panic!("bad line {line}");
        };
        truth.entry(config.to_string()).or_default().insert(
            (name.to_string(), i.parse().expect("an index")),
            v.parse().expect("a value"),
        );
    }
    assert_eq!(truth.len(), 6, "the truth's configurations");
    for (config, want) in &truth {
        let (name, fs) = config.split_once('@').expect("name@rate");
        let s = drift(name)
            .validate(fs.parse().expect("a rate"), 9.806_65 * 10.0 / 4096.0)
            .unwrap_or_else(|e| panic!("{config}: {e:?}"));
        let got = derived(&s);
        assert_eq!(
            got.keys().collect::<Vec<_>>(),
            want.keys().collect::<Vec<_>>(),
            "{config}: the same coefficients"
        );
        for (key, &w) in want {
            let c = got[key];
            assert!(
                agrees(&key.0, c, w),
                "{config}: {}[{}] is {c}, the truth {w}",
                key.0,
                key.1
            );
        }
    }
}

/// One setting's documented range: a setter, its ends, the error outside them, the rate at
/// which the whole range is usable.
struct Range {
    name: &'static str,
    set: fn(&mut Drift, f64),
    lo: f64,
    hi: f64,
    /// Whether `hi` itself is outside (a half-open range).
    hi_open: bool,
    error: DriftError,
    fs: u32,
}

fn ranges() -> Vec<Range> {
    let r = |name, set, lo, hi, error| Range {
        name,
        set,
        lo,
        hi,
        hi_open: false,
        error,
        fs: 3000,
    };
    let t = |name: &'static str, set: fn(&mut Drift, f64), lo, hi| Range {
        name,
        set,
        lo,
        hi,
        hi_open: false,
        error: DriftError::Tuning(name),
        fs: 3000,
    };
    vec![
        r(
            "false_start_hours",
            |d, v| d.false_start_hours = v,
            1.0,
            1e9,
            DriftError::FalseStart,
        ),
        r("hold_s", |d, v| d.hold_s = v, 0.0, 0.1, DriftError::Hold),
        // At 3 kHz the hand band's boxcars of 5 Hz do not fit the tick ring; at 100 Hz
        // (10 ms ticks) they do.
        Range {
            fs: 100,
            ..r(
                "knock_hz",
                |d, v| d.knock_hz = v,
                5.0,
                200.0,
                DriftError::Knock,
            )
        },
        r(
            "stroke_max_s",
            |d, v| d.stroke_max_s = v,
            0.2,
            2.4,
            DriftError::Stroke,
        ),
        r(
            "glide_max_s",
            |d, v| d.glide_max_s = v,
            0.0,
            60.0,
            DriftError::Glide,
        ),
        r(
            "lift_rise_s",
            |d, v| d.lift_rise_s = Some(v),
            0.05,
            0.5,
            DriftError::Lift,
        ),
        r(
            "mount_tilt_deg",
            |d, v| d.mount_tilt_deg = v,
            0.0,
            30.0,
            DriftError::MountTilt,
        ),
        Range {
            hi_open: true,
            ..r(
                "bias_tau_s",
                |d, v| d.bias_tau_s = Some(v),
                0.2,
                1e6,
                DriftError::BiasTau,
            )
        },
        r(
            "click_freeze_s",
            |d, v| d.click_freeze_s = v,
            0.0,
            2.0,
            DriftError::ClickFreeze,
        ),
        t("k_sd", |d, v| d.tuning.k_sd = v, 1.0, 20.0),
        t("chi2", |d, v| d.tuning.chi2 = v, 1.0, 1e6),
        t("kappa", |d, v| d.tuning.kappa[0] = v, 0.05, 10.0),
        t("kappa", |d, v| d.tuning.kappa[1] = v, 0.05, 10.0),
        t("lobe_sd", |d, v| d.tuning.lobe_sd = v, 0.0, 100.0),
        // The short sub-window's upper end (0.6 s) is the long one's: four short ones must
        // fit the block ring (tested below).
        Range {
            hi: f64::NAN,
            ..t("sub_s", |d, v| d.tuning.sub_s[0] = v, 0.02, 0.6)
        },
        t("sub_s", |d, v| d.tuning.sub_s[1] = v, 0.02, 0.6),
        t("hold_fraction", |d, v| d.tuning.hold_fraction = v, 0.0, 0.5),
        t("fade_fraction", |d, v| d.tuning.fade_fraction = v, 0.0, 1.0),
        t(
            "confirm_fraction",
            |d, v| d.tuning.confirm_fraction = v,
            0.25,
            1.5,
        ),
        t("quiet_s", |d, v| d.tuning.quiet_s = v, 0.005, 0.3),
        t(
            "disturbance_s",
            |d, v| d.tuning.disturbance_s = v,
            0.02,
            2.0,
        ),
        t(
            "disturbance_sigmas",
            |d, v| d.tuning.disturbance_sigmas = v,
            0.0,
            20.0,
        ),
        // With a rise of 0.15 s, so that the longest window (0.3 s) fits the tick ring.
        t(
            "lift_window",
            |d, v| {
                d.tuning.lift_window = v;
                d.lift_rise_s = Some(0.15);
            },
            0.1,
            2.0,
        ),
        t(
            "q_inflation_sd",
            |d, v| d.tuning.q_inflation_sd = v,
            0.0,
            10.0,
        ),
    ]
}

#[test]
fn every_setting_is_accepted_at_the_ends_of_its_range_and_refused_outside_by_name() {
    let m = 9.806_65 * 10.0 / 4096.0;
    let with = |r: &Range, v: f64| {
        let mut d = Drift::default();
        (r.set)(&mut d, v);
        d.validate(r.fs, m).err()
    };
    for r in ranges() {
        let below = if r.lo == 0.0 {
            -1e-9
        } else {
            r.lo * (1.0 - 1e-9)
        };
        assert_eq!(with(&r, r.lo), None, "{} at its lower end {}", r.name, r.lo);
        assert_eq!(with(&r, below), Some(r.error), "{} below {}", r.name, r.lo);
        if r.hi.is_nan() {
            continue;
        }
        let top = if r.hi_open { r.hi * (1.0 - 1e-9) } else { r.hi };
        assert_eq!(with(&r, top), None, "{} at its upper end {top}", r.name);
        assert_eq!(
            with(&r, r.hi * (1.0 + 1e-9)),
            Some(r.error),
            "{} above {}",
            r.name,
            r.hi
        );
        if r.hi_open {
            assert_eq!(
                with(&r, r.hi),
                Some(r.error),
                "{} at its open end {}",
                r.name,
                r.hi
            );
        }
        assert_eq!(with(&r, f64::NAN), Some(r.error), "{} NaN", r.name);
    }
}

#[test]
fn windows_that_do_not_fit_the_rings_are_refused() {
    let m = 9.806_65 * 10.0 / 4096.0;
    let short = |w: f64| {
        let mut d = Drift::default();
        d.tuning.sub_s[0] = w;
        d.validate(3000, m).err()
    };
    // Four short sub-windows of 15 blocks (0.3 s) fit the 63 a tilt test may look back
    // over; of 16 they do not.
    assert_eq!(short(0.3), None);
    assert_eq!(short(0.32), Some(DriftError::Stroke));
    assert_eq!(short(0.6), Some(DriftError::Stroke));
    // The hand band at 3 kHz: boxcars of 1 / knock_hz and two thirds of it, at most 62
    // ticks together (37 + 25 at 5.4 Hz; 38 + 25 at 5.3 Hz).
    let knock = |k: f64| {
        let d = Drift {
            knock_hz: k,
            ..Drift::default()
        };
        d.validate(3000, m).err()
    };
    assert_eq!(knock(5.4), None);
    assert_eq!(knock(5.3), Some(DriftError::Knock));
    // The lift test's window, below the 64-tick ring: 63 ticks of a 0.5 s rise, not 64.
    let lift = |w: f64| {
        let mut d = Drift::default();
        d.tuning.lift_window = w;
        d.validate(3000, m).err()
    };
    assert_eq!(lift(0.63), None);
    assert_eq!(lift(0.64), Some(DriftError::Lift));
}

#[test]
fn the_cusum_run_length_is_siegmunds() {
    // (e^(2 kappa b) - 1 - 2 kappa b) / (2 kappa^2), at small arguments where each term
    // counts.
    let e = std::f64::consts::E;
    let arl = imu_core::drift::cusum_arl(0.5, 1.0);
    assert!((arl - 2.0 * (e - 2.0)).abs() < 1e-12, "{arl}");
    let arl = imu_core::drift::cusum_arl(1.5, 2.0);
    assert!((arl - (e.powi(6) - 7.0) / 4.5).abs() < 1e-9, "{arl}");
}
