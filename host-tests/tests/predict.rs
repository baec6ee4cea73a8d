//! `cargo lab predict`: accuracy against mpmath over the promised range, and its errors.

use host_tests::oracle::predict::{predict, Inputs, PredictError};

fn inputs(fs: f64, t: &[f64]) -> Inputs {
    Inputs {
        fs,
        t: t.to_vec(),
        ..Inputs::default()
    }
}

/// Promised accuracy of every predicted value: 1e-9 relative.
const PROMISE: f64 = 1e-9;

#[test]
fn filtered_laws_are_within_1e_9_of_mpmath_over_the_whole_range() {
    // Every (alpha, N) of the truth table (alpha 1e-9..3.14159, N 1..1e9), at fs 1 Hz, 1 kHz
    // and 100 kHz, recomputed from the mpmath B and V with the defining formulas.
    let text = include_str!("../data/reference_truth.csv");
    let sigma_c = 3e-3;
    let mut checked = 0;
    for line in text.lines().skip(1) {
        let f: Vec<f64> = line
            .split(',')
            .map(|x| x.parse().expect("number"))
            .collect();
        let (alpha, n, b, v) = (f[0], f[1], f[2], f[3]);
        for fs in [1.0, 1e3, 1e5] {
            let fc = alpha * fs / (2.0 * std::f64::consts::PI);
            let t = n / fs;
            let rows = predict(&Inputs {
                sigma_c: Some(sigma_c),
                fc: Some(fc),
                ..inputs(fs, &[t])
            })
            .expect("valid inputs");
            let row = &rows[0];
            assert_eq!(row.n as f64, n);
            let eq32 = t * t / 2.0 * (alpha * sigma_c * sigma_c * fs * b / (2.0 * n * n)).sqrt();
            let r0 = sigma_c * sigma_c * alpha * fs / 4.0;
            let ar1 = (r0 * v).sqrt() / (fs * fs);
            for (got, want) in [(row.eq32_m, eq32), (row.ar1_euler_m, ar1)] {
                let got = got.expect("filtered inputs give eq32 and ar1_euler");
                let rel = ((got - want) / want).abs();
                assert!(rel < PROMISE, "alpha {alpha} N {n} fs {fs}: rel {rel:e}");
            }
            checked += 1;
        }
    }
    assert_eq!(checked, 363);
}

#[test]
fn white_and_bias_laws_match_their_closed_forms() {
    let rows = predict(&Inputs {
        sigma_d: Some(0.05),
        bias: Some(-0.01),
        ..inputs(100.0, &[0.05, 10.0])
    })
    .expect("valid");
    let r = &rows[1]; // N = 1000
    assert_eq!(r.n, 1000);
    assert!((r.eq2_m.expect("bias") - 0.5).abs() < 1e-15); // 0.01 * 100 / 2
    assert!((r.eq23_m.expect("white") - 0.079_056_941_504_209_48).abs() < 1e-15);
    assert!((r.eq27_m.expect("white") - 0.091_287_092_917_527_69).abs() < 1e-15);
    let euler = 0.05 * (1000.0f64 * 1001.0 * 2001.0 / 6.0).sqrt() / 1e4;
    assert!((r.euler_m.expect("white") / euler - 1.0).abs() < 1e-15);
    let trap = 0.05 * ((8e9 - 6e6 - 2e3 + 3.0) / 24.0f64).sqrt() / 1e4;
    assert!((r.trapezoid_m.expect("white") / trap - 1.0).abs() < 1e-15);
    assert!(r.eq32_m.is_none() && r.ar1_euler_m.is_none());
    assert_eq!(rows[0].n, 5);
}

#[test]
fn json_has_exactly_the_documented_keys() {
    let rows = predict(&Inputs {
        sigma_d: Some(0.05),
        sigma_c: Some(3e-3),
        fc: Some(20.0),
        bias: Some(0.01),
        ..inputs(100.0, &[1.0])
    })
    .expect("valid");
    let json = serde_json::to_value(&rows).expect("serialisable");
    let obj = json[0].as_object().expect("one object per --t");
    let mut keys: Vec<&str> = obj.keys().map(String::as_str).collect();
    keys.sort_unstable();
    assert_eq!(
        keys,
        [
            "ar1_euler_m",
            "eq23_m",
            "eq27_m",
            "eq2_m",
            "eq32_m",
            "euler_m",
            "n",
            "t_s",
            "trapezoid_bias_m",
            "trapezoid_m"
        ]
    );
    let only_bias = predict(&Inputs {
        bias: Some(0.01),
        ..inputs(100.0, &[1.0])
    })
    .expect("valid");
    let json = serde_json::to_value(&only_bias).expect("serialisable");
    assert_eq!(json[0].as_object().map(|o| o.len()), Some(3));
}

#[test]
fn bad_inputs_are_named() {
    let white = |fs: f64, t: &[f64]| Inputs {
        sigma_d: Some(0.05),
        ..inputs(fs, t)
    };
    assert_eq!(predict(&white(0.0, &[1.0])), Err(PredictError::Fs(0.0)));
    assert!(matches!(
        predict(&white(100.0, &[0.015])),
        Err(PredictError::NotWhole { .. })
    ));
    assert_eq!(
        predict(&white(100.0, &[-1.0])),
        Err(PredictError::Duration(-1.0))
    );
    assert_eq!(predict(&white(100.0, &[])), Err(PredictError::NoDuration));
    assert!(matches!(
        predict(&white(1e5, &[1e8])),
        Err(PredictError::TooLong { .. })
    ));
    assert_eq!(predict(&inputs(100.0, &[1.0])), Err(PredictError::NoSource));
    let half = Inputs {
        sigma_c: Some(1e-3),
        ..inputs(100.0, &[1.0])
    };
    assert_eq!(predict(&half), Err(PredictError::FilterPair));
    let above = Inputs {
        sigma_c: Some(1e-3),
        fc: Some(50.1),
        ..inputs(100.0, &[1.0])
    };
    assert!(matches!(predict(&above), Err(PredictError::Cutoff { .. })));
    let neg = Inputs {
        sigma_d: Some(-1.0),
        ..inputs(100.0, &[1.0])
    };
    assert!(predict(&neg).is_err_and(|e| e.to_string().starts_with("--sigma-d -1")));
    // A product with float error still counts as whole: 0.1 * 3000 = 300.00000000000006.
    assert_eq!(predict(&white(3000.0, &[0.1])).map(|r| r[0].n), Ok(300));
}

#[test]
fn bias_and_noise_together_need_both_and_add_in_mean_square() {
    // 0.01 m/s^2 of bias for 1 s: eq 2 gives 5 mm; 0.05 m/s^2 white at 100 Hz through the
    // trapezoid: REFERENCE (c)(ii). Together: the root of the sum of squares, which is
    // larger than either alone and smaller than their sum.
    let both = predict(&Inputs {
        sigma_d: Some(0.05),
        bias: Some(0.01),
        ..inputs(100.0, &[1.0])
    })
    .expect("valid");
    let r = &both[0];
    let (b, w) = (r.eq2_m.expect("bias"), r.trapezoid_m.expect("white"));
    assert!((b - 0.005).abs() < 1e-15);
    let total = r.trapezoid_bias_m.expect("both given");
    assert!((total * total - (b * b + w * w)).abs() < 1e-15 * total * total);
    assert!(total > b.max(w) && total < b + w);
    for alone in [
        Inputs {
            sigma_d: Some(0.05),
            ..inputs(100.0, &[1.0])
        },
        Inputs {
            bias: Some(0.01),
            ..inputs(100.0, &[1.0])
        },
    ] {
        assert!(predict(&alone).expect("valid")[0]
            .trapezoid_bias_m
            .is_none());
    }
}
