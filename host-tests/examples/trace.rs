// Scratch: one scenario through a device, printing drift control's state changes.
use host_tests::commands::mouse::families::{config_for, Device};
use host_tests::world::hand::{Motion, Scenario, SensorSpec};
use host_tests::world::noise;
use imu_core::{Config, Drift, Event, Tracker};

fn main() {
    let args: Vec<f64> = std::env::args().skip(1).map(|a| a.parse().unwrap()).collect();
    let (d, dur, dir, seed) = (args[0], args[1], args[2], args[3] as u64);
    let spec = SensorSpec::ADXL335;
    let cfg = config_for(spec, Config { drift: Some(Drift::default()), ..Config::default() });
    let _ = Device::calibrated(spec, cfg, seed);
    let mut rng = noise::rng(seed ^ 0xCA11);
    let mut sensor = host_tests::world::hand::Sensor::new(spec, &mut rng);
    let mut t = Tracker::new(&cfg).unwrap();
    loop {
        let c = sensor.codes([0.0; 3], [0.0; 3], [0.0; 2], &mut rng);
        if let Some(Event::Calibrated(_)) = t.feed(&[c]) { break; }
    }
    for _ in 0..30000 { t.feed(&[sensor.codes([0.0; 3], [0.0; 3], [0.0; 2], &mut rng)]); }
    t.take_counts();
    let sc = Scenario { motions: vec![Motion::Stroke { t0: 0.4, dur, d, dir }], edges: vec![], seconds: 0.4 + dur + 0.6 };
    let mut rng = noise::rng(seed + 99);
    let n = (sc.seconds * 3000.0) as usize;
    let mut pos = [0i64; 2];
    let mut last = None;
    let mut c0 = t.counters();
    for i in 0..n {
        let time = i as f64 / 3000.0;
        let (a, r, tilt) = sc.at(time);
        t.feed(&[sensor.codes(a, r, tilt, &mut rng)]);
        if i % 3 == 2 {
            let c = t.take_counts();
            pos[0] += c[0] as i64; pos[1] += c[1] as i64;
        }
        let st = t.drift_state();
        let cc = t.counters();
        if st != last || cc.motions != c0.motions || cc.discarded != c0.discarded || cc.rebiases != c0.rebiases {
            println!("{:7.4} {:?} pos {:?} mm [{:.2}, {:.2}] v {:?} m{} d{} r{}", time, st, pos, pos[0] as f64*0.03175, pos[1] as f64*0.03175,
              t.axes().each_ref().map(|a| a.integrator().velocity() >> 16), cc.motions, cc.discarded, cc.rebiases);
            last = st; c0 = cc;
        }
    }
    println!("end pos {:?} = [{:.2}, {:.2}] mm; truth [{:.2}, {:.2}]", pos, pos[0] as f64*0.03175, pos[1] as f64*0.03175, d*1e3*dir.cos(), d*1e3*dir.sin());
}
