// Scratch: the desk scene's clicks, one by one: counts moved around each and drift states.
use host_tests::world::desk::{Plan, Sensor, FS};
use host_tests::world::noise;
use imu_core::{Config, Drift, Tracker};

fn main() {
    let seed = 1;
    let p = Plan::new(60, seed);
    let mut rng = noise::rng(seed);
    let mut sensor = Sensor::new(&mut rng);
    let mut t = Tracker::new(&Config { drift: Some(Drift::default()), ..Config::default() }).unwrap();
    let late = (0.006 * FS) as usize;
    let mut moved = vec![0i64; p.n / 3 + 1];
    let mut states = vec![String::new(); p.n / 3 + 1];
    for i in 0..p.n {
        let (ax, ay) = p.accel(i);
        if p.clicks.iter().any(|c| c.press + late == i || c.release + late == i) { t.button_edge(); }
        let codes = sensor.codes([ax, ay, 0.0], [0.0; 3], &mut rng);
        t.feed(&[codes]);
        if i % 3 == 2 {
            let c = t.take_counts();
            moved[i / 3] = (c[0].abs() + c[1].abs()) as i64;
            states[i / 3] = format!("{:?}{}", t.drift_state(), if t.is_holding() { " held" } else { "" });
        }
    }
    for c in &p.clicks {
        let (a, b) = (c.press / 3, ((c.release + 900) / 3).min(moved.len()));
        let drag: i64 = moved[a..b].iter().sum();
        if drag > 0 {
            println!("click at {:.3} s: {} counts", c.press as f64 / FS, drag);
            let prev = p.strokes.iter().filter(|s| s.start < c.press).last().unwrap();
            println!("  previous stroke ends {:.3} s", (prev.start + prev.len) as f64 / FS);
            let mut last = String::new();
            for q in a.saturating_sub(150)..b {
                if states[q] != last || moved[q] != 0 { println!("  {:.4} {} {}", q as f64 * 3.0 / FS, states[q], moved[q]); last = states[q].clone(); }
            }
        }
    }
}
