//! Linear SVG charts of traces: the cursor's path and the acceleration over time, for
//! `cargo lab replay` and `simulate` (`--out DIR`). ([`super::plot`] draws the log-log
//! charts of the noise analyses.)

use std::fmt::Write as _;

use super::plot::{esc, svg_open};

/// One trace of a chart.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Trace {
    /// Legend text.
    pub label: String,
    /// SVG colour.
    pub color: &'static str,
    /// `(x, y)` points, in order; non-finite points are skipped.
    pub pts: Vec<(f64, f64)>,
}

/// A chart with linear axes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Chart {
    /// Title.
    pub title: String,
    /// x-axis label, with its unit.
    pub x_label: String,
    /// y-axis label, with its unit.
    pub y_label: String,
    /// The traces.
    pub traces: Vec<Trace>,
    /// Whether one unit is as long on both axes (a path in the plane keeps its shape).
    pub equal_aspect: bool,
}

const W: f64 = 720.0;
const H: f64 = 480.0;
const L: f64 = 70.0;
const R: f64 = 20.0;
const T: f64 = 40.0;
const B: f64 = 50.0;

/// A tick step of 1, 2 or 5 times a power of ten giving about six ticks over `span`.
fn step(span: f64) -> f64 {
    let raw = span / 6.0;
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * p)
}

/// `(lo, hi)` of `vals`, widened to a nonzero span and rounded out to ticks.
fn range(vals: impl Iterator<Item = f64>) -> (f64, f64, f64) {
    let (lo, hi) = vals
        .filter(|v| v.is_finite())
        .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)));
    let (lo, hi) = if lo > hi {
        (0.0, 1.0)
    } else if hi - lo < 1e-12 * hi.abs().max(1.0) {
        (lo - 0.5, hi + 0.5)
    } else {
        (lo, hi)
    };
    let s = step(hi - lo);
    ((lo / s).floor() * s, (hi / s).ceil() * s, s)
}

/// A tick's label: no `0.30000000000000004`.
fn label(v: f64, step: f64) -> String {
    let digits = (-step.log10().floor()).max(0.0) as usize;
    format!("{v:.digits$}")
}

impl Chart {
    /// The chart as an SVG document (the same chart, the same bytes).
    pub fn to_svg(&self) -> String {
        let pts = || self.traces.iter().flat_map(|t| t.pts.iter().copied());
        let (mut x0, mut x1, mut xs) = range(pts().map(|p| p.0));
        let (mut y0, mut y1, mut ys) = range(pts().map(|p| p.1));
        let (pw, ph) = (W - L - R, H - T - B);
        if self.equal_aspect {
            // Widen the axis with fewer units per pixel so both have the same.
            let per = ((x1 - x0) / pw).max((y1 - y0) / ph);
            let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
            (x0, x1) = (cx - per * pw / 2.0, cx + per * pw / 2.0);
            (y0, y1) = (cy - per * ph / 2.0, cy + per * ph / 2.0);
            xs = step(x1 - x0);
            ys = step(y1 - y0);
        }
        let px = |x: f64| L + (x - x0) / (x1 - x0) * pw;
        let py = |y: f64| T + (y1 - y) / (y1 - y0) * ph;
        let mut s = svg_open(W, H, &self.title);
        let mut x = (x0 / xs).ceil() * xs;
        while x <= x1 + 1e-9 * xs {
            let _ = writeln!(
                s,
                r##"<line x1="{0:.1}" y1="{T}" x2="{0:.1}" y2="{1}" stroke="#ddd"/><text x="{0:.1}" y="{2}" text-anchor="middle">{3}</text>"##,
                px(x),
                H - B,
                H - B + 16.0,
                label(x, xs)
            );
            x += xs;
        }
        let mut y = (y0 / ys).ceil() * ys;
        while y <= y1 + 1e-9 * ys {
            let _ = writeln!(
                s,
                r##"<line x1="{L}" y1="{0:.1}" x2="{1}" y2="{0:.1}" stroke="#ddd"/><text x="{2}" y="{3:.1}" text-anchor="end">{4}</text>"##,
                py(y),
                W - R,
                L - 6.0,
                py(y) + 4.0,
                label(y, ys)
            );
            y += ys;
        }
        let _ = writeln!(
            s,
            r##"<rect x="{L}" y="{T}" width="{pw}" height="{ph}" fill="none" stroke="#888"/>
<text x="{}" y="{}" text-anchor="middle">{}</text>
<text x="16" y="{}" text-anchor="middle" transform="rotate(-90 16 {})">{}</text>"##,
            L + pw / 2.0,
            H - 12.0,
            esc(&self.x_label),
            T + ph / 2.0,
            T + ph / 2.0,
            esc(&self.y_label)
        );
        for (k, t) in self.traces.iter().enumerate() {
            let d: Vec<String> = t
                .pts
                .iter()
                .filter(|p| p.0.is_finite() && p.1.is_finite())
                .map(|p| format!("{:.1},{:.1}", px(p.0), py(p.1)))
                .collect();
            let (color, ly) = (t.color, T + 14.0 + 16.0 * k as f64);
            let _ = writeln!(
                s,
                r#"<polyline fill="none" stroke="{color}" stroke-width="1.5" points="{pts}"/>
<line x1="{a}" y1="{ly}" x2="{b}" y2="{ly}" stroke="{color}" stroke-width="2"/><text x="{c}" y="{ty}">{text}</text>"#,
                pts = d.join(" "),
                a = L + 10.0,
                b = L + 30.0,
                c = L + 36.0,
                ty = ly + 4.0,
                text = esc(&t.label)
            );
        }
        s.push_str("</svg>\n");
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_chart_is_well_formed_deterministic_and_keeps_its_points() {
        let c = Chart {
            title: "path <mm>".into(),
            x_label: "right [mm]".into(),
            y_label: "up [mm]".into(),
            traces: vec![Trace {
                label: "cursor".into(),
                color: "black",
                pts: vec![(0.0, 0.0), (100.0, 5.0), (f64::NAN, 1.0)],
            }],
            equal_aspect: true,
        };
        let a = c.to_svg();
        assert_eq!(a, c.to_svg());
        assert!(a.starts_with("<svg") && a.ends_with("</svg>\n"));
        assert!(a.contains("path &lt;mm&gt;"));
        // Two finite points on the polyline, the NaN one skipped.
        let line = a
            .lines()
            .find(|l| l.starts_with("<polyline"))
            .expect("a trace");
        assert_eq!(line.matches(',').count(), 2, "{line}");
    }

    #[test]
    fn ticks_are_round_numbers_over_any_span() {
        assert_eq!(step(6.0), 1.0);
        assert_eq!(step(0.3), 0.05);
        assert_eq!(step(900.0), 200.0);
        let (lo, hi, _) = range([0.0, 0.0].into_iter());
        assert!(lo <= -0.5 && hi >= 0.5, "{lo}..{hi}");
        assert_eq!(label(0.30000000000000004, 0.1), "0.3");
    }
}
