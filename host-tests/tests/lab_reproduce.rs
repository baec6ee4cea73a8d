//! `cargo lab reproduce` at the `--quick` size: every law holds, every control is rejected,
//! the JSON is as documented and each prediction can be recomputed from its params.

use host_tests::commands::reproduce::{reproduce, z_crit, Report};
use host_tests::oracle::predict::predict;

fn quick() -> Report {
    reproduce(1000, 1, None, &indicatif::ProgressBar::hidden())
        .expect("no plots written, nothing to fail")
}

#[test]
fn every_law_holds_and_every_control_is_rejected() {
    let r = quick();
    for row in &r.rows {
        assert!(row.pass, "{} ({}): z = {:.2}", row.name, row.law, row.z);
    }
    let laws: std::collections::BTreeSet<&str> = r.rows.iter().map(|x| x.law).collect();
    for law in [
        "eq2",
        "eq23",
        "eq27",
        "euler",
        "trapezoid",
        "eq32",
        "ar1_euler",
        "trapezoid_bias",
    ] {
        assert!(laws.contains(law), "no row for {law}");
    }
    assert!(r.rows.iter().filter(|x| x.control).count() >= 5);
}

#[test]
fn json_rows_have_the_documented_keys() {
    let r = quick();
    let json = serde_json::to_value(&r).expect("serialisable");
    let mut top: Vec<&str> = json
        .as_object()
        .expect("object")
        .keys()
        .map(String::as_str)
        .collect();
    top.sort_unstable();
    assert_eq!(top, ["plots", "rows", "trials", "z_crit"]);
    let row = json["rows"][0].as_object().expect("row object");
    let mut keys: Vec<&str> = row.keys().map(String::as_str).collect();
    keys.sort_unstable();
    assert_eq!(
        keys,
        [
            "ci_high_m",
            "ci_low_m",
            "control",
            "detectable_pct",
            "law",
            "measured_m",
            "name",
            "params",
            "pass",
            "predicted_m",
            "z"
        ]
    );
}

#[test]
fn each_prediction_is_the_predictor_at_the_rows_params() {
    for row in quick().rows {
        let out = predict(&row.params.inputs()).expect("params are valid predictor inputs");
        let json = serde_json::to_value(&out[0]).expect("serialisable");
        assert_eq!(
            json[format!("{}_m", row.law)].as_f64(),
            Some(row.predicted_m),
            "{}",
            row.name
        );
    }
}

#[test]
fn critical_z_is_the_bonferroni_quantile() {
    // One row: the two-sided 1 % point; 55 rows: the 1 - 0.01/110 quantile. Values from
    // mpmath, sqrt(2) erfinv(1 - 0.01 / k): 2.5758293, 3.7430249.
    assert!((z_crit(1) - 2.575_829_3).abs() < 1e-6);
    assert!((z_crit(55) - 3.743_024_9).abs() < 1e-6);
}
