//! A seeded property run over random valid configurations and adversarial inputs: rest and
//! strokes, random codes, rails, alternating rails, button edges, lost samples, restarts,
//! recalibrations, good and bad reconfigurations, and a USB host that refuses pushes, resets
//! and suspends. Overflow checks are on in the test profile, so a wrap panics.
//!
//! The properties, at every step:
//! - nothing panics and nothing wraps;
//! - a refused reconfiguration changes nothing at all (the whole tracker compared);
//! - every count the tracker moved is accounted for exactly: sent to the host, discarded
//!   while it was not listening, or still owed;
//! - no report carries more than 127 counts on an axis, and every report was asked for.
//!
//! Volume: `STEPS` operations (1.2 M, about 2.8 M samples), in well under a second at the
//! test profile's opt-level 3.

use imu_core::hid::{screen_motion, Reporter};
use imu_core::{Config, Drift, Phase, Scheme, Tracker};

/// Operations in the whole run.
const STEPS: u64 = 1_200_000;
/// Operations per configuration before a new one is drawn.
const PER_CONFIG: u64 = 20_000;

/// SplitMix64: the run's own generator, so the core's tests need no dependency.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Log-uniform in `[lo, hi)`.
    fn log_uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo * (hi / lo).powf(self.unit())
    }
    fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }
}

/// A random configuration: rates from 100 Hz to 100 kHz, any cut-off, either scheme, 8- to
/// 16-bit ADCs, 100 to 12 800 cpi, calibration windows of 20 to 300 ms, drift control on or
/// off. Some are invalid; the caller keeps the valid ones.
fn random_config(rng: &mut Rng) -> Config {
    let fs_hz = rng.log_uniform(100.0, 100_000.0) as u32;
    let fs = f64::from(fs_hz);
    let lsb = rng.log_uniform(1e-4, 0.1);
    Config {
        fs_hz,
        lowpass_fc_hz: rng.chance(0.5).then(|| fs * rng.log_uniform(1e-6, 0.5)),
        m_s2_per_lsb: lsb,
        adc_bits: 8 + rng.below(9) as u8,
        counts_per_inch: rng.log_uniform(100.0, 12_800.0) as u32,
        scheme: if rng.chance(0.5) {
            Scheme::Euler
        } else {
            Scheme::Trapezoid
        },
        calibration_s: rng.log_uniform(0.02, 0.3),
        // Mostly above the rest scenes' noise (up to 1.4 LSB rms), sometimes below it.
        rest_noise_max_m_s2: lsb * rng.log_uniform(0.5, 50.0),
        drift: rng.chance(0.8).then(Drift::default),
    }
}

/// A configuration that validation must refuse: one field of a valid one broken.
fn broken(rng: &mut Rng, good: &Config) -> Config {
    let mut c = *good;
    match rng.below(7) {
        0 => c.fs_hz = 0,
        1 => c.fs_hz = 100_001 + rng.below(1_000_000) as u32,
        2 => c.lowpass_fc_hz = Some(f64::from(c.fs_hz) * (0.5 + rng.unit())),
        3 => c.m_s2_per_lsb = [0.0, -1.0, f64::NAN, f64::INFINITY][rng.below(4) as usize],
        4 => c.adc_bits = [0, 1, 17, 255][rng.below(4) as usize],
        5 => c.counts_per_inch = 0,
        _ => c.calibration_s = [0.0, -1.0, f64::NAN, 1e9][rng.below(4) as usize],
    }
    c
}

/// What the sensor does for a while.
#[derive(Clone, Copy, Debug)]
enum Scene {
    /// Mid-scale with +-`noise` codes of noise.
    Rest { noise: u16 },
    /// A sinusoidal stroke of `amp` codes over `period` samples.
    Stroke { amp: f64, period: f64 },
    /// Uniform random codes over the whole range.
    Random,
    /// Stuck on the low or the high rail.
    Rail { high: bool },
    /// Low and high rail in turn.
    Alternating,
}

impl Scene {
    fn draw(rng: &mut Rng) -> Self {
        match rng.below(10) {
            0..=4 => Scene::Rest {
                noise: rng.below(3) as u16,
            },
            5..=6 => Scene::Stroke {
                amp: rng.log_uniform(1.0, 2000.0),
                period: rng.log_uniform(10.0, 50_000.0),
            },
            7 => Scene::Random,
            8 => Scene::Rail {
                high: rng.chance(0.5),
            },
            _ => Scene::Alternating,
        }
    }

    fn code(self, rng: &mut Rng, i: u64, top: u16) -> [u16; 3] {
        let mid = top / 2;
        let clamp = |v: f64| v.round().clamp(0.0, f64::from(top)) as u16;
        match self {
            Scene::Rest { noise } => {
                let mut c = || mid + rng.below(u64::from(2 * noise + 1)) as u16 - noise;
                [c(), c(), c()]
            }
            Scene::Stroke { amp, period } => {
                let s = amp * (std::f64::consts::TAU * i as f64 / period).sin();
                [
                    clamp(f64::from(mid) + s),
                    clamp(f64::from(mid) - 0.5 * s),
                    mid,
                ]
            }
            Scene::Random => {
                let mut c = || rng.below(u64::from(top) + 1) as u16;
                [c(), c(), c()]
            }
            Scene::Rail { high } => [if high { top } else { 0 }; 3],
            Scene::Alternating => [if i.is_multiple_of(2) { top } else { 0 }; 3],
        }
    }
}

/// The host side: the reporter the firmware keeps, and what the host has seen.
#[derive(Default)]
struct Host {
    reporter: Reporter,
    /// Counts the tracker moved into the reporter (x, y), summed.
    moved: (i64, i64),
    /// Counts in the reports the host accepted (x, y), summed.
    received: (i64, i64),
    /// Whether the host listens (configured, not suspended).
    listening: bool,
}

impl Host {
    /// A 1 ms poll: counts from the tracker into the reporter, then one push that the host
    /// accepts or refuses (its buffer busy).
    fn poll(&mut self, tracker: &mut Tracker, rng: &mut Rng) {
        let (dx, dy) = screen_motion(tracker.take_counts());
        self.reporter.add_motion(dx, dy);
        self.moved.0 += i64::from(dx);
        self.moved.1 += i64::from(dy);
        if !self.listening {
            self.reporter.discard_motion();
            return;
        }
        if let Some(report) = self.reporter.pending() {
            if rng.chance(0.8) {
                assert!(report.x != i8::MIN && report.y != i8::MIN, "{report:?}");
                self.received.0 += i64::from(report.x);
                self.received.1 += i64::from(report.y);
                self.reporter.sent(&report);
            }
        }
    }

    fn check_accounts(&self) {
        let r = &self.reporter;
        let (sent, dropped, owed) = (r.sent_total(), r.discarded(), r.undelivered());
        assert_eq!(
            sent, self.received,
            "the reporter's total against the host's"
        );
        assert_eq!(
            self.moved,
            (sent.0 + dropped.0 + owed.0, sent.1 + dropped.1 + owed.1),
            "moved = sent + discarded + owed"
        );
        assert_eq!(r.added(), self.moved, "added = every count moved");
    }
}

#[test]
fn random_configurations_and_hostile_inputs_lose_nothing_and_never_wrap() {
    let mut rng = Rng(0x1A2B_3C4D_5E6F_7081);
    let (mut steps, mut samples, mut configs, mut refused) = (0u64, 0u64, 0u32, 0u32);
    let mut tracked = 0u64;
    while steps < STEPS {
        let config = loop {
            let c = random_config(&mut rng);
            if c.validate().is_ok() {
                break c;
            }
        };
        let mut tracker = Tracker::new(&config).expect("validated");
        configs += 1;
        let top = ((1u32 << config.adc_bits) - 1) as u16;
        let per_poll = (config.fs_hz / 1000).max(1);
        let mut host = Host {
            listening: true,
            ..Host::default()
        };
        let (mut scene, mut scene_left) = (Scene::Rest { noise: 1 }, 0u64);
        let (mut i, mut since_poll) = (0u64, 0u32);
        for _ in 0..PER_CONFIG {
            steps += 1;
            if scene_left == 0 {
                scene = Scene::draw(&mut rng);
                scene_left = rng.log_uniform(10.0, 20_000.0) as u64;
            }
            match rng.below(10_000) {
                0..=9599 => {
                    let n = 1 + rng.below(4);
                    for _ in 0..n {
                        let codes = scene.code(&mut rng, i, top);
                        tracker.feed(&[codes]);
                        i += 1;
                        since_poll += 1;
                        if since_poll >= per_poll {
                            since_poll = 0;
                            host.poll(&mut tracker, &mut rng);
                        }
                    }
                    samples += n;
                    scene_left = scene_left.saturating_sub(n);
                }
                9600..=9699 => tracker.button_edge(),
                9700..=9769 => tracker.lost(rng.below(64) as u32),
                9770..=9789 => tracker.restarted(rng.below(5000) as u32),
                9790..=9791 => tracker.recalibrate(),
                9792..=9891 => {
                    let before = tracker;
                    let bad = broken(&mut rng, &config);
                    assert!(tracker.reconfigure(&bad).is_err(), "{bad:?} was accepted");
                    assert_eq!(
                        tracker, before,
                        "a refused configuration changed the tracker"
                    );
                    refused += 1;
                }
                9892..=9893 => {
                    let next = random_config(&mut rng);
                    let before = tracker;
                    if tracker.reconfigure(&next).is_err() {
                        assert_eq!(tracker, before);
                        refused += 1;
                    }
                }
                9894..=9969 => host.listening = !host.listening,
                9970..=9989 => host.reporter.host_reset(),
                _ => host.reporter.set_buttons(rng.below(8) as u8),
            }
            if tracker.phase() == Phase::Tracking {
                tracked += 1;
            }
            host.check_accounts();
        }
    }
    eprintln!(
        "{steps} steps, {samples} samples, {configs} configurations, {refused} refused \
         reconfigurations, {tracked} steps while tracking"
    );
    // The run must have reached the states it claims to exercise.
    assert!(samples >= 2 * STEPS, "{samples} samples");
    assert!(
        configs >= 50 && refused >= 1000,
        "{configs} configs, {refused} refusals"
    );
    assert!(tracked >= STEPS / 4, "only {tracked} steps while tracking");
}
