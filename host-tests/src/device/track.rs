//! The whole device on the host: samples go through `imu_core::Tracker` (calibration, then
//! tracking) and a USB poll every millisecond moves the counts into the core's `Reporter`,
//! exactly as the firmware does. Used by `cargo lab simulate` and `cargo lab replay`.

use imu_core::hid::{screen_motion, Reporter};
use imu_core::{AxisMap, Config, ConfigError, Event, Phase, Tracker};
use serde::Serialize;

use crate::world::scene::Scene;

/// The device configuration for a scene's sensor: its rate, scale and ADC, and an at-rest
/// noise bound of 4x its own noise (a recording of the scene carries it in its profile: a
/// replay of a noisier sensor under it is refused as too noisy); everything else the
/// default.
pub fn scene_config(scene: &Scene) -> Config {
    Config {
        fs_hz: scene.fs as u32,
        m_s2_per_lsb: scene.adc.m_s2_per_lsb,
        adc_bits: scene.adc.bits,
        rest_noise_max_m_s2: 4.0 * scene.noise_rms_m_s2(),
        ..Config::default()
    }
}

/// The cursor's position at one time.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TrackPoint {
    /// Time since the first sample [s].
    pub t_s: f64,
    /// Counts sent to the right since tracking began.
    pub x_counts: i64,
    /// Counts sent downwards since tracking began.
    pub y_counts: i64,
    /// The same in millimetres at the configured counts per inch.
    pub x_mm: f64,
    /// The same in millimetres.
    pub y_mm: f64,
    /// What drift control was doing at that moment: `still`, `moving`, `held` (a motion
    /// integrated but not yet delivered: younger than its hold, or held by the tilt tests),
    /// `lifted` (tracking suspended until the device rests on the desk) or `frozen` (after a
    /// button edge); `None` without drift control.
    pub state: Option<&'static str>,
}

/// Drift control's state as [`TrackPoint::state`] names it.
fn state_name(tracker: &Tracker) -> Option<&'static str> {
    use imu_core::drift::State;
    Some(match tracker.drift_state()? {
        State::Still => "still",
        State::Moving if tracker.is_holding() => "held",
        State::Moving => "moving",
        State::Lifted => "lifted",
        State::Frozen => "frozen",
    })
}

/// What the device did with a stream of samples.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Track {
    /// Sampling rate [Hz].
    pub fs: f64,
    /// Samples processed.
    pub samples: u64,
    /// Calibration windows rejected (motion or clipping).
    pub rejected_windows: u32,
    /// Time tracking began [s], or `None` if calibration never succeeded.
    pub tracking_from_s: Option<f64>,
    /// Why calibration never succeeded, in words (`None` once it did).
    pub calibration_failure: Option<String>,
    /// The cursor every `every_s` seconds.
    pub points: Vec<TrackPoint>,
    /// HID reports sent.
    pub reports: u32,
    /// Total counts sent (right, down).
    pub counts: (i64, i64),
    /// The cursor every [`TRACE_S`] while tracking, for a chart (not in the JSON).
    #[serde(skip)]
    pub trace: Vec<TrackPoint>,
}

/// The interval of [`Track::trace`] [s]: 10 ms, finer than a hand's strokes.
pub const TRACE_S: f64 = 0.01;

/// Runs `samples` (`[x, y, z]` codes at `config.fs_hz`) through the device, recording the
/// cursor every `every_s` seconds, with the board's axis mapping.
///
/// # Errors
/// The configuration's first invalid field.
pub fn run(
    config: &Config,
    samples: impl IntoIterator<Item = [u16; 3]>,
    every_s: f64,
) -> Result<Track, ConfigError> {
    run_mapped(config, &AxisMap::default(), samples, every_s)
}

/// [`run`] with the axis mapping `map`, as the device applies it: each sample triple in
/// sensor order routed to the tracker's order ([`AxisMap::route`]), the counts given their
/// signs ([`AxisMap::screen`]) before they become HID motion.
///
/// # Errors
/// The configuration's first invalid field.
pub fn run_mapped(
    config: &Config,
    map: &AxisMap,
    samples: impl IntoIterator<Item = [u16; 3]>,
    every_s: f64,
) -> Result<Track, ConfigError> {
    let mut tracker = Tracker::new(config)?;
    let mut reporter = Reporter::default();
    let fs = f64::from(config.fs_hz);
    let per_poll = u64::from((config.fs_hz / 1000).max(1));
    let per_point = ((every_s * fs).round() as u64).max(1);
    let per_trace = ((TRACE_S * fs).round() as u64).max(1);
    let mut trace = vec![];
    let mm_per_count = 25.4 / f64::from(config.counts_per_inch);
    let (mut n, mut sent, mut from) = (0u64, (0i64, 0i64), None);
    let mut points = vec![];
    let mut last_rejection = None;
    for s in samples {
        n += 1;
        match tracker.feed(&[map.route(s)]) {
            Some(Event::Calibrated(_)) => from = Some(n as f64 / fs),
            Some(Event::Rejected { axis, error }) => {
                let name = ["x", "y", "z"]
                    .get(usize::from(axis))
                    .copied()
                    .unwrap_or("?");
                last_rejection = Some(format!("the last window failed on {name}: {error}"));
            }
            None => {}
        }
        if n % per_poll == 0 {
            let (dx, dy) = screen_motion(map.screen(tracker.take_counts()));
            reporter.add_motion(dx, dy);
            while let Some(r) = reporter.pending() {
                reporter.sent(&r);
                sent.0 += i64::from(r.x);
                sent.1 += i64::from(r.y);
            }
        }
        let point = || TrackPoint {
            t_s: n as f64 / fs,
            x_counts: sent.0,
            y_counts: sent.1,
            x_mm: sent.0 as f64 * mm_per_count,
            y_mm: sent.1 as f64 * mm_per_count,
            state: state_name(&tracker),
        };
        if tracker.phase() == Phase::Tracking {
            if n % per_point == 0 {
                points.push(point());
            }
            if n % per_trace == 0 {
                trace.push(point());
            }
        }
    }
    let calibration_failure = match (from, last_rejection) {
        (Some(_), _) => None,
        (None, Some(why)) => Some(why),
        (None, None) => Some(format!(
            "the {:.3} s played are shorter than the calibration window ({} s)",
            n as f64 / fs,
            config.calibration_s
        )),
    };
    Ok(Track {
        fs,
        samples: n,
        rejected_windows: tracker.counters().rejected_windows,
        tracking_from_s: from,
        calibration_failure,
        points,
        reports: reporter.reports(),
        counts: sent,
        trace,
    })
}

/// The track as a readable table.
pub fn table(t: &Track) -> String {
    let mut out = format!(
        "{} samples at {} Hz; calibration {}; {} rejected window(s)\n{:>9} {:>11} {:>11} {:>11} {:>11}  {}\n",
        t.samples,
        t.fs,
        match (t.tracking_from_s, &t.calibration_failure) {
            (Some(s), _) => format!("done at {s:.3} s"),
            (None, Some(why)) => format!("never succeeded ({why})"),
            (None, None) => "never succeeded".to_string(),
        },
        t.rejected_windows,
        "t [s]",
        "right [cnt]",
        "down [cnt]",
        "right [mm]",
        "down [mm]",
        "drift control"
    );
    for p in &t.points {
        out += &format!(
            "{:>9.3} {:>11} {:>11} {:>11.2} {:>11.2}  {}\n",
            p.t_s,
            p.x_counts,
            p.y_counts,
            p.x_mm,
            p.y_mm,
            p.state.unwrap_or("off")
        );
    }
    out += &format!(
        "sent {} HID reports: {} counts right, {} counts down\n",
        t.reports, t.counts.0, t.counts.1
    );
    out
}

/// The acceleration of the cursor's two axes over time, for a chart: `samples` (sensor order)
/// routed by `map` and signed as the cursor moves (right, up), less the mean of the first
/// calibration window, in m/s^2, as means over bins of at least [`TRACE_S`] (at most 2000
/// bins). `(t [s], [right, up])` per bin.
pub fn acceleration(config: &Config, map: &AxisMap, samples: &[[u16; 3]]) -> Vec<(f64, [f64; 2])> {
    let fs = f64::from(config.fs_hz);
    let routed = |s: &[u16; 3]| {
        let r = map.route(*s);
        let sign = |flip: bool| if flip { -1.0 } else { 1.0 };
        [
            sign(map.x_flip) * f64::from(r[0]),
            sign(map.y_flip) * f64::from(r[1]),
        ]
    };
    let window = ((config.calibration_s * fs).round() as usize).clamp(1, samples.len().max(1));
    let mut zero = [0.0; 2];
    for s in samples.iter().take(window) {
        let r = routed(s);
        zero = [zero[0] + r[0], zero[1] + r[1]];
    }
    let zero = zero.map(|z| z / window as f64);
    let bin = ((TRACE_S * fs).round() as usize)
        .max(samples.len().div_ceil(2000))
        .max(1);
    samples
        .chunks(bin)
        .enumerate()
        .map(|(i, chunk)| {
            let mut sum = [0.0; 2];
            for s in chunk {
                let r = routed(s);
                sum = [sum[0] + r[0], sum[1] + r[1]];
            }
            let n = chunk.len() as f64;
            let t = (i * bin) as f64 / fs + n / (2.0 * fs);
            (
                t,
                [0, 1].map(|k| (sum[k] / n - zero[k]) * config.m_s2_per_lsb),
            )
        })
        .collect()
}

/// The track and the acceleration as two charts: the cursor's path in the plane (right
/// and up, mm, one unit as long on both) and the acceleration over time.
pub fn charts(
    t: &Track,
    accel: &[(f64, [f64; 2])],
    title: &str,
) -> (crate::formats::chart::Chart, crate::formats::chart::Chart) {
    use crate::formats::chart::{Chart, Trace};
    let path = Chart {
        title: format!("{title}: the cursor's path"),
        x_label: "right [mm]".into(),
        y_label: "up [mm]".into(),
        traces: vec![Trace {
            label: format!("every {} ms while tracking", TRACE_S * 1000.0),
            color: "#1f77b4",
            pts: t.trace.iter().map(|p| (p.x_mm, -p.y_mm)).collect(),
        }],
        equal_aspect: true,
    };
    let acc = Chart {
        title: format!("{title}: acceleration less the calibration's zero"),
        x_label: "t [s]".into(),
        y_label: "acceleration [m/s^2]".into(),
        traces: ["right", "up"]
            .iter()
            .enumerate()
            .map(|(k, name)| Trace {
                label: format!("cursor {name}"),
                color: ["#1f77b4", "#d62728"][k],
                pts: accel.iter().map(|(t, a)| (*t, a[k])).collect(),
            })
            .collect(),
        equal_aspect: false,
    };
    (path, acc)
}
