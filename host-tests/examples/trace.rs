// Scratch: one stroke through pure integration and through drift control, the final velocity.
use host_tests::commands::mouse::families::config_for;
use host_tests::world::hand::{Motion, Scenario, Sensor, SensorSpec};
use host_tests::world::noise;
use imu_core::{Config, Drift, Event, Tracker};

fn main() {
    for drift in [None, Some(Drift::default())] {
        for fs in [1000.0, 3000.0] {
            let spec = SensorSpec { nd_ug: 10.0, bits: 16, fs, walk_ug: 0.0, ..SensorSpec::ADXL335 };
            let cfg = config_for(spec, Config { drift, ..Config::default() });
            let mut rng = noise::rng(5);
            let mut sensor = Sensor::new(spec, &mut rng);
            let mut t = Tracker::new(&cfg).unwrap();
            loop {
                let c = sensor.codes([0.0; 3], [0.0; 3], [0.0; 2], &mut rng);
                if let Some(Event::Calibrated(_)) = t.feed(&[c]) { break; }
            }
            for _ in 0..(10.0 * fs) as usize { t.feed(&[sensor.codes([0.0; 3], [0.0; 3], [0.0; 2], &mut rng)]); }
            t.take_counts();
            let sc = Scenario { motions: vec![Motion::Stroke { t0: 0.4, dur: 1.39, d: 0.12, dir: 1.0 }], edges: vec![], seconds: 2.4 };
            let n = (sc.seconds * fs) as usize;
            let mut pos = [0i64; 2];
            for i in 0..n {
                let (a, r, tilt) = sc.at(i as f64 / fs);
                t.feed(&[sensor.codes(a, r, tilt, &mut rng)]);
                let c = t.take_counts();
                pos[0] += c[0] as i64; pos[1] += c[1] as i64;
                if i % (fs as usize / 5) == 0 && i as f64 / fs > 1.6 {
                    let v = t.axes().each_ref().map(|a| a.integrator().velocity() as f64 / 2.0 / 65536.0 * t.settings().m_s2_per_lsb() / fs * 1e3);
                    println!("drift {} fs {fs} t {:.2} v [{:.3}, {:.3}] mm/s state {:?}", drift.is_some(), i as f64 / fs, v[0], v[1], t.drift_state());
                }
            }
            println!("  pos {:?} mm truth {:?}", pos.map(|p| p as f64 * 0.03175), sc.displacement().map(|d| d * 1e3));
        }
    }
}
