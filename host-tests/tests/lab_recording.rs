//! `cargo lab allan` and `cargo lab drift` on a synthetic recording whose answer is known,
//! and on the real MPU-6050 recording (figures within what its README states).

use host_tests::commands::drift::experiment;
use host_tests::formats::columns::{read, Options, Units};
use host_tests::stats::allan::{figures, oadev};
use host_tests::world::noise;

#[test]
fn drift_on_white_noise_matches_its_allan_prediction() {
    // 3000 s of white counts (sd 20 counts, scale 1e-3 m/s^2) at 100 Hz, no bias drift:
    // 200 segments of 5 + 10 s. The prediction is white (eq 27) plus the calibration's bias
    // error; bias instability read from the curve is small. Each row must hold at
    // |z| < 3.29 (0.1 % per row, 1 % for the 10 rows).
    let mut rng = noise::rng(9);
    let raw = vec![(0..300_000)
        .map(|_| (20.0 * noise::normal(&mut rng)).round())
        .collect::<Vec<f64>>()];
    let y: Vec<f64> = raw[0].iter().map(|v| v * 1e-3).collect();
    let f = figures(&oadev(&y, 100.0)).expect("enough data");
    let rows = experiment(
        &["x".into()],
        &raw,
        100.0,
        1e-3,
        5.0,
        &[1.0, 2.0, 5.0, 10.0],
        &[f],
    )
    .expect("valid");
    assert_eq!(rows[0].segments, 200);
    for r in &rows {
        let z = r.z.expect("a moving axis has a z-score");
        assert!(
            z.abs() < 3.29,
            "T = {}: measured {:e} predicted {:e} z {z:.2}",
            r.t_s,
            r.measured_m,
            r.predicted_m,
        );
    }
}

#[test]
fn too_short_a_recording_is_a_named_error() {
    let raw = vec![vec![0.0; 1000]];
    let f = figures(&oadev(&[0.0, 1.0, 0.0, 1.0, 0.0, 2.0], 100.0)).expect("figures");
    let e =
        experiment(&["x".into()], &raw, 100.0, 1e-3, 5.0, &[10.0], &[f]).expect_err("one segment");
    assert!(e.contains("at least 2 are needed"), "{e}");
}

#[test]
fn the_real_recording_has_the_noise_its_readme_states() {
    // data/README-mpu6050.md: x and y white, std about 50 LSB, roughly 430-650 ug/sqrt(Hz);
    // z with extra slow drift.
    let text = include_str!("../data/mpu6050-static-100hz.csv");
    let d = read(
        text.as_bytes(),
        &Options {
            columns: vec!["ax".into(), "ay".into(), "az".into()],
            fs: None,
            time_column: None,
            units: Some(Units::Counts(9.806_65 / 16_384.0)),
        },
    )
    .expect("the recording reads");
    assert_eq!((d.fs, d.raw[0].len()), (100.0, 44_930));
    let ug = |v: f64| v / 9.806_65e-6;
    let f: Vec<_> = d
        .m_s2
        .iter()
        .map(|y| figures(&oadev(y, d.fs)).expect("figures"))
        .collect();
    for (k, fig) in f.iter().enumerate() {
        let nd = ug(fig.noise_density_m_s2_rthz);
        assert!((400.0..700.0).contains(&nd), "axis {k}: {nd} ug/sqrt(Hz)");
    }
    // z drifts: its bias instability is well above x's and y's.
    assert!(
        f[2].bias_instability_m_s2
            > 2.0 * f[0].bias_instability_m_s2.max(f[1].bias_instability_m_s2)
    );
}

#[test]
fn a_short_record_s_noise_density_comes_from_its_white_part() {
    // 3 s of the desk's sensor (300 ug/sqrt(Hz) into a 50 Hz pole) at 3 kHz: few taus on
    // the -1/2 line have 100 averages. The first tau (flat, filtered) read 28 ug/sqrt(Hz); the
    // white part reads the truth within its spread: at 0.04 to 0.09 s a 3 s record holds 30
    // to 70 averages, an 18 % sd or less; 3 sd is 54 %.
    use host_tests::world::{desk, scene::ADXL335_LSB};
    for seed in 1..=6 {
        let (codes, _) = desk::rest(3.0, seed);
        for k in 0..3 {
            let m: Vec<f64> = codes
                .iter()
                .map(|c| f64::from(c[k]) * ADXL335_LSB)
                .collect();
            let f = figures(&oadev(&m, desk::FS)).expect("figures");
            let ug = f.noise_density_m_s2_rthz / 9.806_65e-6;
            assert!(
                (ug - 300.0).abs() < 0.54 * 300.0,
                "seed {seed}, axis {k}: {ug} ug/sqrt(Hz)"
            );
        }
    }
}
