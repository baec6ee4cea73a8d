//! `cargo lab device check`'s judgement of a board from what it recorded: at rest (noise,
//! zero, rails, gravity), then moved right and then away (which sensor axis, which sign), and
//! a verdict a person can act on.
//!
//! # What is compared with what
//! The ADXL335 data sheet (Rev. B, Table 1, at Vs = 3 V) gives typical noise densities of
//! 150 ug/sqrt(Hz) on X and Y and 300 on Z (no maximum), and a zero-g output of Vs/2 +-150 mV
//! on X and Y, +-300 mV on Z: +-0.5 g and +-1 g at 300 mV/g. The board's ADC is ratiometric,
//! so its mid-scale code is the zero-g output. So:
//! - an axis whose codes never change is dead (no noise is not a quiet sensor);
//! - an axis with more than 1 % of its samples at a rail code is clipped;
//! - a noise density over [`NOISY`] times the typical one is flagged (a supply or ground
//!   problem; the data sheet states no maximum to hold it to);
//! - a zero outside the data sheet's range is flagged (a level board reads 0 g on X and Y);
//! - the gravity axis is the one reading 1 g within [`GRAVITY_TOLERANCE_G`] (a level desk,
//!   the scale right); none is a wrong scale or a board on its edge.
//!
//! A rest that moved says nothing of the noise or the zero, so the rest step is tested first:
//! its 10 ms means must stay within [`MOTION_SDS`] sd of their median on every axis, the sd
//! taken from the median of successive differences (`median |m[i+1] - m[i]| / (0.6745
//! sqrt 2)` for Gaussian means), which a stroke filling under half the window does not move.
//! The same sd sizes the stroke threshold below, so a rest that moved cannot raise it.
//!
//! The noise density is read from the Allan deviation at [`ND_TAU_S`], where the
//! sensor's filtered noise is white (a few seconds at rest are too short for the full fit
//! of `cargo lab allan`). A stroke is found on the 10 ms means of each axis less
//! its rest level: the axis whose peak is largest, if that peak is over [`MOTION_SDS`] sd of
//! the rest's 10 ms means and over twice any other axis's (one edge of the desk, not a
//! diagonal). Its sign is that of its first excursion past the threshold: a stroke speeds up
//! in the direction it goes.

use serde::Serialize;

use crate::stats::allan;

/// Standard gravity [m/s^2].
const G: f64 = 9.806_65;
/// The ADXL335's typical noise densities, X, Y, Z [ug/sqrt(Hz)] (data sheet, Vs = 3 V).
pub const TYPICAL_ND_UG: [f64; 3] = [150.0, 150.0, 300.0];
/// The ADXL335's zero-g range about mid-supply, X, Y, Z [g] (+-150, +-150, +-300 mV at
/// 300 mV/g).
pub const ZERO_G_RANGE_G: [f64; 3] = [0.5, 0.5, 1.0];
/// A noise density this many times the typical one is flagged.
pub const NOISY: f64 = 3.0;
/// How far from 1 g the gravity axis may read [g]: half the way to the next reading a
/// board could give (0 g on edge), so a wrong scale by a factor of 1.5 or more is caught.
pub const GRAVITY_TOLERANCE_G: f64 = 0.5;
/// A stroke's peak must exceed this many sd of the rest's 10 ms means: at 10, noise alone
/// reaches it with a chance far under 1e-9 per window.
pub const MOTION_SDS: f64 = 10.0;
/// Share of samples at a rail code that makes an axis clipped.
pub const RAIL_SHARE: f64 = 0.01;
/// The means a stroke is looked for on [s].
const BIN_S: f64 = 0.01;
/// The tau the noise density is read at [s]: 30 times the correlation time of the sensor's
/// 50 Hz output pole (3.2 ms), where its filtered noise is white (REFERENCE (f)), and short
/// enough that a 4 s record holds 40 independent averages (a 16 % sd) and the bias walk
/// does not show. (A board with a slower output filter reads low here.)
pub const ND_TAU_S: f64 = 0.1;

/// The sensor axes' names, in the ADC's scan order.
pub const AXES: [&str; 3] = ["X", "Y", "Z"];

/// One sensor axis at rest.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AxisAtRest {
    /// Mean code [LSB].
    pub mean_lsb: f64,
    /// Standard deviation [LSB].
    pub sd_lsb: f64,
    /// Reading relative to mid-scale [g].
    pub reading_g: f64,
    /// White noise density (one-sided) [ug/sqrt(Hz)], if the axis has noise to read.
    pub noise_density_ug: Option<f64>,
    /// Share of samples at a rail code (0 or the top code).
    pub rail_share: f64,
    /// Whether every code was the same.
    pub constant: bool,
}

/// The board at rest.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AtRest {
    /// The axes X, Y, Z.
    pub axes: Vec<AxisAtRest>,
    /// The sensor axis reading 1 g (within [`GRAVITY_TOLERANCE_G`]) and its sign, if one does.
    pub gravity: Option<(usize, f64)>,
    /// Sd of a 10 ms mean at rest, per axis [m/s^2], from successive differences (robust
    /// to a short motion in the window).
    pub bin_sd_m_s2: Vec<f64>,
    /// The axis whose 10 ms means went furthest past [`MOTION_SDS`] sd of their median, and
    /// how many sd: the board moved while it should have been still.
    pub moved: Option<(usize, f64)>,
}

/// A stroke found in a recording.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Stroke {
    /// The sensor axis it moved.
    pub axis: usize,
    /// +1 if the axis's positive direction is the stroke's, else -1.
    pub sign: f64,
    /// Its peak acceleration [m/s^2].
    pub peak_m_s2: f64,
}

/// `codes` at rest at `fs` [Hz], with `m_s2_per_lsb` on a `bits`-bit ADC.
pub fn at_rest(codes: &[[u16; 3]], fs: f64, m_s2_per_lsb: f64, bits: u8) -> AtRest {
    let mid = f64::from(1u32 << (bits - 1));
    let top = f64::from((1u32 << bits) - 1);
    let n = codes.len().max(1) as f64;
    let axes: Vec<AxisAtRest> = (0..3)
        .map(|k| {
            let v: Vec<f64> = codes.iter().map(|c| f64::from(c[k])).collect();
            let mean = v.iter().sum::<f64>() / n;
            let sd = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n).sqrt();
            let constant = v.windows(2).all(|w| w[0] == w[1]);
            let nd = (!constant)
                .then(|| {
                    let m: Vec<f64> = v.iter().map(|x| x * m_s2_per_lsb).collect();
                    white_density(&allan::oadev(&m, fs))
                })
                .flatten()
                .map(|nd| nd / G * 1e6);
            let rails = v.iter().filter(|&&x| x == 0.0 || x == top).count() as f64;
            AxisAtRest {
                mean_lsb: mean,
                sd_lsb: sd,
                reading_g: (mean - mid) * m_s2_per_lsb / G,
                noise_density_ug: nd,
                rail_share: rails / n,
                constant,
            }
        })
        .collect();
    let gravity = axes
        .iter()
        .enumerate()
        .filter(|(_, a)| (a.reading_g.abs() - 1.0).abs() <= GRAVITY_TOLERANCE_G)
        .min_by(|a, b| {
            (a.1.reading_g.abs() - 1.0)
                .abs()
                .total_cmp(&(b.1.reading_g.abs() - 1.0).abs())
        })
        .map(|(k, a)| (k, a.reading_g.signum()));
    let bin = ((BIN_S * fs).round() as usize).max(1);
    let means: Vec<Vec<f64>> = (0..3).map(|k| bin_means(codes, k, bin)).collect();
    // A 10 ms mean resolves a tenth of a step at worst (10 samples at 1 kHz): the floor for an
    // axis whose noise is under a step, so a lone step is not taken for motion.
    let floor = m_s2_per_lsb / 10.0;
    let bin_sd_m_s2: Vec<f64> = means.iter().map(|m| robust_sd(m) * m_s2_per_lsb).collect();
    let moved = (0..3)
        .filter_map(|k| {
            let mid = median(&means[k])?;
            let peak = means[k].iter().fold(0.0f64, |p, m| p.max((m - mid).abs()));
            let sds = peak * m_s2_per_lsb / bin_sd_m_s2[k].max(floor);
            (sds > MOTION_SDS).then_some((k, sds))
        })
        .max_by(|a, b| a.1.total_cmp(&b.1));
    AtRest {
        axes,
        gravity,
        bin_sd_m_s2,
        moved,
    }
}

/// The sd of Gaussian values `m` from their successive differences: `median |m[i+1] - m[i]|
/// / (0.6745 sqrt 2)` (a difference of two has sd `sqrt 2` times theirs; 0.6745 is the median
/// of a standard normal's absolute value), 0 for under two values.
fn robust_sd(m: &[f64]) -> f64 {
    let d: Vec<f64> = m.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
    median(&d).map_or(0.0, |d| d / (0.674_489_75 * std::f64::consts::SQRT_2))
}

fn median(v: &[f64]) -> Option<f64> {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    (n > 0).then(|| (v[(n - 1) / 2] + v[n / 2]) / 2.0)
}

/// The one-sided white noise density [m/s^2/sqrt(Hz)] read from the Allan deviation at the
/// tau nearest [`ND_TAU_S`]: `sqrt(2) sigma(tau) sqrt(tau)` (REFERENCE (f)).
fn white_density(a: &allan::Adev) -> Option<f64> {
    let (t, s) = a.taus_s.iter().zip(&a.adev).min_by(|x, y| {
        (x.0 / ND_TAU_S)
            .ln()
            .abs()
            .total_cmp(&(y.0 / ND_TAU_S).ln().abs())
    })?;
    Some(std::f64::consts::SQRT_2 * s * t.sqrt())
}

fn bin_means(codes: &[[u16; 3]], k: usize, bin: usize) -> Vec<f64> {
    codes
        .chunks(bin)
        .filter(|c| c.len() == bin)
        .map(|c| c.iter().map(|s| f64::from(s[k])).sum::<f64>() / bin as f64)
        .collect()
}

/// The stroke in `codes` (at `fs` [Hz]) among the sensor axes not in `exclude`, measured
/// against `rest`; `None` if no axis moved clearly, or two moved alike (a diagonal).
pub fn stroke(
    codes: &[[u16; 3]],
    fs: f64,
    m_s2_per_lsb: f64,
    rest: &AtRest,
    exclude: &[usize],
) -> Option<Stroke> {
    let bin = ((BIN_S * fs).round() as usize).max(1);
    let mut found: Vec<(usize, f64, f64)> = (0..3)
        .filter(|k| !exclude.contains(k))
        .map(|k| {
            let a: Vec<f64> = bin_means(codes, k, bin)
                .iter()
                .map(|m| (m - rest.axes[k].mean_lsb) * m_s2_per_lsb)
                .collect();
            let peak = a.iter().fold(0.0f64, |p, x| p.max(x.abs()));
            let threshold = MOTION_SDS * rest.bin_sd_m_s2[k].max(m_s2_per_lsb / 10.0);
            let sign = a
                .iter()
                .find(|x| x.abs() > threshold)
                .map_or(0.0, |x| x.signum());
            (k, peak, if peak > threshold { sign } else { 0.0 })
        })
        .collect();
    found.sort_by(|a, b| b.1.total_cmp(&a.1));
    let (axis, peak, sign) = *found.first()?;
    let clear = found.get(1).is_none_or(|second| second.1 * 2.0 < peak);
    (sign != 0.0 && clear).then_some(Stroke {
        axis,
        sign,
        peak_m_s2: peak,
    })
}

/// What the check concluded.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Verdict {
    /// What is wrong, each with what to do; empty when the board looks right.
    pub problems: Vec<String>,
    /// Observations that need no action.
    pub notes: Vec<String>,
    /// The axis mapping the strokes show, as `(x_axis, x_sign, y_axis, y_sign)`, if both
    /// were found.
    pub mapping: Option<(usize, f64, usize, f64)>,
}

/// The verdict on a board at `rest` moved `right` and `away`, whose profile maps the axes as
/// `current` `(x_axis, x_sign, y_axis, y_sign)`.
pub fn verdict(
    rest: &AtRest,
    right: Option<&Stroke>,
    away: Option<&Stroke>,
    current: (usize, f64, usize, f64),
) -> Verdict {
    let mut problems = vec![];
    let mut notes = vec![];
    if let Some((k, sds)) = rest.moved {
        problems.push(format!(
            "the mouse moved during the rest step ({} went {sds:.0} sd past its noise): the \
             noise and zero below are read from motion; keep it still, flat on the desk, and \
             run the check again",
            AXES[k]
        ));
    }
    for (k, a) in rest.axes.iter().enumerate() {
        let name = AXES[k];
        if a.rail_share > RAIL_SHARE {
            problems.push(format!(
                "{name}: {:.1} % of its samples at a rail: clipped; a wrong supply or ADC \
                 reference, or a shorted pin",
                100.0 * a.rail_share
            ));
        } else if a.constant {
            problems.push(format!(
                "{name} never changed (every code {:.0}): a dead or disconnected axis; check \
                 its wire to the ADC and the sensor's supply",
                a.mean_lsb
            ));
        }
        if a.constant {
            continue;
        }
        if let Some(nd) = a.noise_density_ug {
            let ratio = nd / TYPICAL_ND_UG[k];
            let said = format!(
                "{name}: noise density {nd:.0} ug/sqrt(Hz), {ratio:.1}x the data sheet's \
                 typical {:.0}",
                TYPICAL_ND_UG[k]
            );
            if ratio > NOISY {
                problems.push(format!(
                    "{said}: look at the supply's ripple, the ground and the wiring's length"
                ));
            } else {
                notes.push(said);
            }
        }
        let is_gravity = rest.gravity.is_some_and(|(g, _)| g == k);
        let zero = if is_gravity {
            a.reading_g - a.reading_g.signum()
        } else {
            a.reading_g
        };
        if zero.abs() > ZERO_G_RANGE_G[k] {
            problems.push(format!(
                "{name} reads {zero:+.2} g off its zero (the data sheet allows +-{} g): a \
                 tilted desk, a wrong m_s2_per_lsb, or a sensor not at Vs/2",
                ZERO_G_RANGE_G[k]
            ));
        }
    }
    match rest.gravity {
        None => problems.push(
            "no axis reads 1 g: the scale (m_s2_per_lsb) is wrong, or the board is not lying \
             flat"
                .into(),
        ),
        Some((g, s)) => notes.push(format!(
            "gravity on {}{} ({:+.3} g)",
            if s > 0.0 { "+" } else { "-" },
            AXES[g],
            rest.axes[g].reading_g
        )),
    }
    if right.is_none() {
        problems.push(
            "no clear move right was seen: slide the mouse straight right, about 10 cm in \
             half a second, when asked"
                .into(),
        );
    }
    if away.is_none() {
        problems.push(
            "no clear move away was seen: slide the mouse straight away from you when asked".into(),
        );
    }
    let mapping = right
        .zip(away)
        .map(|(r, a)| (r.axis, r.sign, a.axis, a.sign));
    if let (Some((x, _, y, _)), Some((g, _))) = (mapping, rest.gravity) {
        if g == x || g == y {
            problems.push(format!(
                "gravity is on {}, a cursor axis: is the board standing on its edge?",
                AXES[g]
            ));
        }
    }
    if let Some(m) = mapping {
        if m != current {
            let (x, xs, y, ys) = m;
            problems.push(format!(
                "the axes are mapped otherwise: set them with `cargo lab device config set \
                 x_axis={x} x_sign={xs} y_axis={y} y_sign={ys}` and keep them with `cargo lab \
                 device save`"
            ));
        } else {
            notes.push("the axis mapping matches the strokes".into());
        }
    }
    Verdict {
        problems,
        notes,
        mapping,
    }
}

/// The whole check: the three steps' recordings judged and drawn.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Checked {
    /// The board at rest.
    pub rest: AtRest,
    /// The move right, if one was seen.
    pub right: Option<Stroke>,
    /// The move away, if one was seen.
    pub away: Option<Stroke>,
    /// What to do.
    pub verdict: Verdict,
}

/// Judges `still`, then `right` and `away` (codes at `fs` [Hz], `m_s2_per_lsb` on a
/// `bits`-bit ADC) for a board whose profile maps the axes as `current` (see [`verdict`]):
/// the right stroke is looked for off the gravity axis, the away stroke off both.
pub fn judge(
    [still, right, away]: [&[[u16; 3]]; 3],
    fs: f64,
    m_s2_per_lsb: f64,
    bits: u8,
    current: (usize, f64, usize, f64),
) -> Checked {
    let rest = at_rest(still, fs, m_s2_per_lsb, bits);
    let gravity: Vec<usize> = rest.gravity.iter().map(|g| g.0).collect();
    let moved_right = stroke(right, fs, m_s2_per_lsb, &rest, &gravity);
    let mut exclude = gravity;
    exclude.extend(moved_right.iter().map(|r| r.axis));
    let moved_away = stroke(away, fs, m_s2_per_lsb, &rest, &exclude);
    let verdict = verdict(&rest, moved_right.as_ref(), moved_away.as_ref(), current);
    Checked {
        rest,
        right: moved_right,
        away: moved_away,
        verdict,
    }
}

/// The check's chart: every sample of the steps in order, as acceleration off the rest level
/// [m/s^2], at most about 3000 points an axis (means of consecutive samples), in `colors`.
pub fn chart(
    steps: [&[[u16; 3]]; 3],
    fs: f64,
    m_s2_per_lsb: f64,
    rest: &AtRest,
    colors: [&'static str; 3],
) -> crate::formats::chart::Chart {
    use crate::formats::chart::{Chart, Trace};
    let all: Vec<[u16; 3]> = steps.concat();
    let step = (all.len() / 3000).max(1);
    Chart {
        title: "device check: at rest, right, away".into(),
        x_label: "t [s]".into(),
        y_label: "acceleration off the rest level [m/s^2]".into(),
        traces: (0..3)
            .map(|k| Trace {
                label: format!("sensor {}", AXES[k]),
                color: colors[k],
                pts: all
                    .chunks(step)
                    .enumerate()
                    .map(|(i, ch)| {
                        let mean =
                            ch.iter().map(|s| f64::from(s[k])).sum::<f64>() / ch.len() as f64;
                        (
                            (i * step) as f64 / fs,
                            (mean - rest.axes[k].mean_lsb) * m_s2_per_lsb,
                        )
                    })
                    .collect(),
            })
            .collect(),
        equal_aspect: false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::desk;

    const LSB: f64 = crate::world::scene::ADXL335_LSB;

    fn rest_of(codes: &[[u16; 3]]) -> AtRest {
        at_rest(codes, desk::FS, LSB, 12)
    }

    #[test]
    fn the_check_scene_reads_as_a_good_board_mapped_as_built() {
        let (codes, _) = desk::check(3);
        let fs = desk::FS as usize;
        let rest = rest_of(&codes[..4 * fs]);
        assert_eq!(rest.gravity, Some((2, 1.0)));
        // The scene's sensor is 300 ug/sqrt(Hz) on every axis; read at 0.1 s from 4 s, the
        // Allan deviation has about 40 independent averages, a 16 % sd (and 12-bit steps
        // add under 1 %): 3 sd is 48 %, and the three axes must all hold it.
        for a in &rest.axes {
            let nd = a.noise_density_ug.expect("noise");
            assert!((nd - 300.0).abs() < 0.48 * 300.0, "{nd}");
        }
        let right = stroke(&codes[5 * fs..10 * fs], desk::FS, LSB, &rest, &[2]).expect("right");
        assert_eq!((right.axis, right.sign), (0, 1.0));
        let away = stroke(&codes[10 * fs..15 * fs], desk::FS, LSB, &rest, &[2, 0]).expect("away");
        assert_eq!((away.axis, away.sign), (1, 1.0));
        let v = verdict(&rest, Some(&right), Some(&away), (0, 1.0, 1, 1.0));
        assert!(v.problems.is_empty(), "{:?}", v.problems);
        assert_eq!(v.mapping, Some((0, 1.0, 1, 1.0)));
        // The same board mapped otherwise is told how to set it.
        let v = verdict(&rest, Some(&right), Some(&away), (1, 1.0, 0, -1.0));
        assert!(
            v.problems[0].contains("config set x_axis=0 x_sign=1 y_axis=1 y_sign=1"),
            "{:?}",
            v.problems
        );
    }

    #[test]
    fn a_mounting_turned_and_flipped_is_found() {
        // The board turned a quarter: the hand's right is sensor -Y, away is sensor +X.
        let (codes, _) = desk::check(4);
        let turned: Vec<[u16; 3]> = codes.iter().map(|&[x, y, z]| [y, 4095 - x, z]).collect();
        let fs = desk::FS as usize;
        let rest = rest_of(&turned[..4 * fs]);
        let right = stroke(&turned[5 * fs..10 * fs], desk::FS, LSB, &rest, &[2]).expect("right");
        let away =
            stroke(&turned[10 * fs..], desk::FS, LSB, &rest, &[2, right.axis]).expect("away");
        assert_eq!(
            (right.axis, right.sign, away.axis, away.sign),
            (1, -1.0, 0, 1.0)
        );
    }

    #[test]
    fn dead_railed_and_tilted_axes_and_no_motion_are_named() {
        let (codes, _) = desk::check(5);
        let fs = desk::FS as usize;
        // X dead at 2048, Y railed at 4095, Z read with a scale twice too small: 0.5 g.
        let bad: Vec<[u16; 3]> = codes[..4 * fs]
            .iter()
            .map(|&[_, _, z]| [2048, 4095, z])
            .collect();
        let rest = at_rest(&bad, desk::FS, LSB / 2.0, 12);
        let v = verdict(&rest, None, None, (0, 1.0, 1, 1.0));
        let all = v.problems.join("\n");
        assert!(all.contains("X never changed"), "{all}");
        assert!(all.contains("Y: 100.0 % of its samples at a rail"), "{all}");
        assert!(all.contains("no axis reads 1 g"), "{all}");
        assert!(all.contains("no clear move right"), "{all}");
        // Still codes hold no stroke.
        assert_eq!(
            stroke(
                &codes[..4 * fs],
                desk::FS,
                LSB,
                &rest_of(&codes[..4 * fs]),
                &[2]
            ),
            None
        );
    }

    #[test]
    fn a_rest_that_moved_is_named_and_keeps_the_threshold_of_a_still_one() {
        let (codes, _) = desk::check(7);
        let fs = desk::FS as usize;
        let still = rest_of(&codes[..4 * fs]);
        assert_eq!(still.moved, None);
        // The move right (0.5 s from 6.5 s) played into the rest's last second.
        let mut moving = codes[..4 * fs].to_vec();
        moving[3 * fs..].copy_from_slice(&codes[6 * fs..7 * fs]);
        let rest = rest_of(&moving);
        let (axis, sds) = rest.moved.expect("the stroke in the rest is seen");
        assert_eq!(axis, 0);
        assert!(sds > MOTION_SDS, "{sds}");
        let v = verdict(&rest, None, None, (0, 1.0, 1, 1.0));
        assert!(
            v.problems[0].starts_with("the mouse moved during the rest step (X went"),
            "{:?}",
            v.problems
        );
        // The sd the moved test and the stroke threshold use comes from the noise, not from
        // the motion. Were a quarter of the successive differences (the moving second) as
        // large as can be, the median would move to the 0.5/0.75 quantile of the rest's:
        // |z| 0.967 for 0.674, 1.43 times; with 4 sd of the estimator's own spread (6.3 % at
        // 400 means, simulated) on top, 1.8 times at most. The plain sd is well over that.
        for k in 0..3 {
            let r = rest.bin_sd_m_s2[k] / still.bin_sd_m_s2[k];
            assert!(r < 1.8, "axis {k}: {r}");
        }
        let x = bin_means(&moving, 0, desk::FS as usize / 100);
        let mean = x.iter().sum::<f64>() / x.len() as f64;
        let plain = (x.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / x.len() as f64).sqrt();
        assert!(plain * LSB > 5.0 * rest.bin_sd_m_s2[0], "{plain}");
    }

    #[test]
    fn a_diagonal_stroke_is_not_taken_for_an_axis() {
        let (codes, _) = desk::check(6);
        let fs = desk::FS as usize;
        let rest = rest_of(&codes[..4 * fs]);
        // The right stroke copied onto Y as well: 45 degrees.
        let diagonal: Vec<[u16; 3]> = codes[5 * fs..10 * fs]
            .iter()
            .map(|&[x, _, z]| [x, x, z])
            .collect();
        assert_eq!(stroke(&diagonal, desk::FS, LSB, &rest, &[2]), None);
    }
}
