//! `cargo lab simulate` and `cargo lab replay`: the whole device on scenes and recordings.

use host_tests::device::track;
use host_tests::formats::recording;
use host_tests::world::scene::catalogue;
use imu_core::Config;

fn scene(name: &str) -> host_tests::world::scene::Scene {
    catalogue()
        .into_iter()
        .find(|s| s.name == name)
        .expect("scene exists")
}

fn config_for(sc: &host_tests::world::scene::Scene) -> Config {
    track::scene_config(sc)
}

#[test]
fn a_ten_centimetre_stroke_arrives_within_its_error_budget() {
    // Tracking starts at 1 s; the stroke ends at 2 s, so 1 s of integration. Error budget at
    // that point (ADXL335, REFERENCE (g)): sensor noise ND T^1.5 / sqrt 6 = 1.2 mm rms, plus
    // the bias left by a 1 s calibration, sd = ND / sqrt(2 T_cal) = 2.1e-3 m/s^2, i.e.
    // 1.0 mm at T = 1 s: 1.6 mm rms together. 5 mm is 3.1 sigma.
    let sc = scene("adxl335-stroke");
    let t = track::run(&config_for(&sc), sc.three_axes(2.0, 7), 0.5).expect("valid config");
    assert_eq!(t.tracking_from_s, Some(1.0));
    let last = t.points.last().expect("tracked");
    assert!((last.t_s - 2.0).abs() < 1e-9);
    assert!((last.x_mm - 100.0).abs() < 5.0, "x = {} mm", last.x_mm);
    assert!(last.y_mm.abs() < 5.0, "y = {} mm", last.y_mm);
}

#[test]
fn replaying_a_written_recording_is_the_same_as_running_it() {
    let sc = scene("adxl335-rest");
    let samples = sc.three_axes(2.0, 3);
    let mut csv = String::from("# adxl335-rest, 2 s\nfs,3000\nn,x,y,z\n");
    for (i, s) in samples.iter().enumerate() {
        csv += &format!("{i},{},{},{}\n", s[0], s[1], s[2]);
    }
    let rec = recording::parse(csv.as_bytes(), None).expect("valid file");
    assert_eq!(rec.fs, 3000);
    let config = config_for(&sc);
    let direct = track::run(&config, samples, 0.25).expect("valid");
    let replayed = track::run(&config, rec.samples, 0.25).expect("valid");
    assert_eq!(direct, replayed);
    assert_eq!(direct.points.len(), 5); // 1.0, 1.25, ..., 2.0 s
}

#[test]
fn a_recording_shorter_than_the_calibration_never_tracks() {
    let rec =
        recording::parse("n,x,y,z\n0,2048,2048,2048\n".as_bytes(), Some(3000.0)).expect("valid");
    let t = track::run(&Config::default(), rec.samples, 0.1).expect("valid");
    assert_eq!((t.tracking_from_s, t.points.len(), t.reports), (None, 0, 0));
}

#[test]
fn every_scene_runs_and_calibrates() {
    for sc in catalogue() {
        let t = track::run(&config_for(&sc), sc.three_axes(1.5, 1), 0.5).expect("valid");
        assert!(
            t.tracking_from_s.is_some(),
            "{}: {} rejected",
            sc.name,
            t.rejected_windows
        );
    }
}

#[test]
fn a_replay_applies_the_axis_mapping_as_the_device_does() {
    // The stroke moves sensor X right. The codes go through AxisMap::route (sensor order to
    // the tracker's) and the counts through AxisMap::screen (the signs), as on the device.
    use imu_core::profile::AxisMap;
    let sc = scene("adxl335-stroke");
    let codes = sc.three_axes(2.0, 7);
    let plain = track::run(&config_for(&sc), codes.clone(), 0.5).expect("valid");
    let last = |t: &track::Track| {
        let p = t.points.last().expect("tracked");
        (p.x_counts, p.y_counts)
    };
    let (x, y) = last(&plain);
    assert!(x > 2000 && y.abs() < 100, "{x}, {y}");
    // The same board mounted with X and Y swapped, told so by the map: the same track.
    let swapped: Vec<[u16; 3]> = codes.iter().map(|&[x, y, z]| [y, x, z]).collect();
    let across = AxisMap {
        x_axis: 1,
        x_flip: false,
        y_axis: 0,
        y_flip: false,
    };
    let t = track::run_mapped(&config_for(&sc), &across, swapped, 0.5).expect("valid");
    assert_eq!(last(&t), (x, y));
    // Sensor X as the cursor's up axis, flipped: the stroke moves the cursor down (HID y > 0)
    // by the same counts.
    let down = AxisMap {
        x_axis: 1,
        x_flip: false,
        y_axis: 0,
        y_flip: true,
    };
    let t = track::run_mapped(&config_for(&sc), &down, codes, 0.5).expect("valid");
    assert_eq!(last(&t).1, x);
}

#[test]
fn the_acceleration_chart_holds_the_stroke_s_peak() {
    // A minimum-jerk stroke of D in T peaks at 10 / sqrt(3) D / T^2 = 2.309 m/s^2 for 10 cm
    // in 0.5 s. A 10 ms mean of the ADXL335's noise (ND 300 ug/sqrt(Hz), one-sided) has
    // sd ND / sqrt(2 x 10 ms) = 0.021 m/s^2, and the bin shaves the peak by under 0.1 % (its
    // curvature over 10 ms): 5 sd (0.104 m/s^2; exceeded by one of 300 bins with chance
    // 2e-4) for the peak and for the still axis.
    let sc = scene("adxl335-stroke");
    let codes = sc.three_axes(3.0, 7);
    let a = track::acceleration(&config_for(&sc), &imu_core::AxisMap::default(), &codes);
    assert_eq!(a.len(), 300, "10 ms bins over 3 s");
    let peak = a.iter().map(|(_, v)| v[0]).fold(f64::MIN, f64::max);
    let want = 10.0 / 3f64.sqrt() * 0.1 / 0.25;
    assert!(
        (peak - want).abs() < 0.104,
        "peak {peak} m/s^2, want {want}"
    );
    // The other axis stays at its zero; the stroke starts at 1.5 s.
    assert!(a.iter().all(|(_, v)| v[1].abs() < 0.104), "cursor up moved");
    let (t_peak, _) =
        a.iter().copied().fold(
            (0.0, f64::MIN),
            |m, (t, v)| {
                if v[0] > m.1 {
                    (t, v[0])
                } else {
                    m
                }
            },
        );
    assert!(
        (t_peak - (1.5 + 0.5 * (0.5 - 1.0 / 12f64.sqrt()))).abs() < 0.02,
        "{t_peak}"
    );
}
