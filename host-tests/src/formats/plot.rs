//! A small log-log SVG chart: theory lines, Monte Carlo points with 95 % intervals, and
//! vertical markers. Dependency-free, deterministic output (same data, same bytes).

use std::fmt::Write as _;

/// A theory line.
#[derive(Clone, Debug)]
pub struct Line {
    /// Legend text.
    pub label: String,
    /// SVG colour.
    pub color: &'static str,
    /// Dashed (for asymptotes and controls).
    pub dashed: bool,
    /// `(x, y)` points, both > 0.
    pub pts: Vec<(f64, f64)>,
}

/// Measured points with intervals.
#[derive(Clone, Debug)]
pub struct Points {
    /// Legend text.
    pub label: String,
    /// SVG colour.
    pub color: &'static str,
    /// `(x, y, y_low, y_high)`, all > 0 (a zero low end is drawn at the bottom edge).
    pub pts: Vec<(f64, f64, f64, f64)>,
}

/// A log-log chart.
#[derive(Clone, Debug, Default)]
pub struct Plot {
    /// Title.
    pub title: String,
    /// x-axis label.
    pub x_label: String,
    /// y-axis label.
    pub y_label: String,
    /// Theory lines.
    pub lines: Vec<Line>,
    /// Measured points.
    pub points: Vec<Points>,
    /// Vertical markers `(x, label)`.
    pub marks: Vec<(f64, String)>,
}

const W: f64 = 680.0;
const H: f64 = 460.0;
const L: f64 = 80.0; // left margin
const R: f64 = 20.0;
const T: f64 = 40.0;
const B: f64 = 60.0;

fn decades(lo: f64, hi: f64) -> (f64, f64) {
    (
        lo.log10().floor(),
        hi.log10().ceil().max(lo.log10().floor() + 1.0),
    )
}

fn sci(v: f64) -> String {
    let e = v.log10().round() as i32;
    if (-2..=3).contains(&e) {
        format!("{}", 10f64.powi(e))
    } else {
        format!("1e{e}")
    }
}

impl Plot {
    /// The chart as an SVG document.
    pub fn to_svg(&self) -> String {
        let xs = self
            .lines
            .iter()
            .flat_map(|l| l.pts.iter().map(|p| p.0))
            .chain(self.points.iter().flat_map(|p| p.pts.iter().map(|q| q.0)));
        let ys = self
            .lines
            .iter()
            .flat_map(|l| l.pts.iter().map(|p| p.1))
            .chain(self.points.iter().flat_map(|p| p.pts.iter().map(|q| q.1)));
        let fold = |it: &mut dyn Iterator<Item = f64>| {
            it.filter(|v| *v > 0.0 && v.is_finite())
                .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)))
        };
        let (x0, x1) = decades(fold(&mut xs.clone()).0, fold(&mut xs.clone()).1);
        let (y0, y1) = decades(fold(&mut ys.clone()).0, fold(&mut ys.clone()).1);
        let px = |x: f64| L + (x.log10() - x0) / (x1 - x0) * (W - L - R);
        let py = |y: f64| {
            let v = if y > 0.0 { y.log10() } else { y0 };
            T + (y1 - v.clamp(y0, y1)) / (y1 - y0) * (H - T - B)
        };
        let mut s = svg_open(W, H, &self.title);
        // Grid and ticks.
        for d in x0 as i32..=x1 as i32 {
            for m in 1..10 {
                let x = 10f64.powi(d) * f64::from(m);
                if x.log10() > x1 + 1e-9 {
                    break;
                }
                let (stroke, w) = if m == 1 { ("#bbb", 1.0) } else { ("#eee", 0.5) };
                let _ = writeln!(
                    s,
                    r#"<line x1="{0:.1}" y1="{T}" x2="{0:.1}" y2="{1}" stroke="{stroke}" stroke-width="{w}"/>"#,
                    px(x),
                    H - B
                );
                if m == 1 {
                    let _ = writeln!(
                        s,
                        r#"<text x="{:.1}" y="{}" text-anchor="middle">{}</text>"#,
                        px(x),
                        H - B + 16.0,
                        sci(x)
                    );
                }
            }
        }
        for d in y0 as i32..=y1 as i32 {
            for m in 1..10 {
                let y = 10f64.powi(d) * f64::from(m);
                if y.log10() > y1 + 1e-9 {
                    break;
                }
                let (stroke, w) = if m == 1 { ("#bbb", 1.0) } else { ("#eee", 0.5) };
                let _ = writeln!(
                    s,
                    r#"<line x1="{L}" y1="{0:.1}" x2="{1}" y2="{0:.1}" stroke="{stroke}" stroke-width="{w}"/>"#,
                    py(y),
                    W - R
                );
                if m == 1 {
                    let _ = writeln!(
                        s,
                        r#"<text x="{}" y="{:.1}" text-anchor="end">{}</text>"#,
                        L - 6.0,
                        py(y) + 4.0,
                        sci(y)
                    );
                }
            }
        }
        let _ = writeln!(
            s,
            r##"<rect x="{L}" y="{T}" width="{}" height="{}" fill="none" stroke="#333"/>"##,
            W - L - R,
            H - T - B
        );
        let _ = writeln!(
            s,
            r#"<text x="{}" y="{}" text-anchor="middle">{}</text>"#,
            (L + W - R) / 2.0,
            H - 18.0,
            esc(&self.x_label)
        );
        let _ = writeln!(
            s,
            r#"<text x="18" y="{0}" text-anchor="middle" transform="rotate(-90 18 {0})">{1}</text>"#,
            (T + H - B) / 2.0,
            esc(&self.y_label)
        );
        for (x, label) in &self.marks {
            let _ = writeln!(
                s,
                r##"<line x1="{0:.1}" y1="{T}" x2="{0:.1}" y2="{1}" stroke="#888" stroke-dasharray="2,3"/><text x="{2:.1}" y="{3}" fill="#555">{4}</text>"##,
                px(*x),
                H - B,
                px(*x) + 4.0,
                T + 14.0,
                esc(label)
            );
        }
        for l in &self.lines {
            let path: Vec<String> = l
                .pts
                .iter()
                .filter(|p| p.0 > 0.0 && p.1 > 0.0)
                .map(|p| format!("{:.1},{:.1}", px(p.0), py(p.1)))
                .collect();
            let dash = if l.dashed {
                r#" stroke-dasharray="6,4""#
            } else {
                ""
            };
            let _ = writeln!(
                s,
                r#"<polyline points="{}" fill="none" stroke="{}" stroke-width="1.8"{dash}/>"#,
                path.join(" "),
                l.color
            );
        }
        for p in &self.points {
            for &(x, y, lo, hi) in &p.pts {
                let _ = writeln!(
                    s,
                    r#"<line x1="{0:.1}" y1="{1:.1}" x2="{0:.1}" y2="{2:.1}" stroke="{3}" stroke-width="1.5"/><circle cx="{0:.1}" cy="{4:.1}" r="3.5" fill="{3}"/>"#,
                    px(x),
                    py(lo),
                    py(hi),
                    p.color,
                    py(y)
                );
            }
        }
        // Legend.
        let mut ly = T + 14.0;
        for l in &self.lines {
            let dash = if l.dashed {
                r#" stroke-dasharray="6,4""#
            } else {
                ""
            };
            let _ = writeln!(
                s,
                r#"<line x1="{}" y1="{ly:.1}" x2="{}" y2="{ly:.1}" stroke="{}" stroke-width="1.8"{dash}/><text x="{}" y="{:.1}">{}</text>"#,
                L + 10.0,
                L + 34.0,
                l.color,
                L + 40.0,
                ly + 4.0,
                esc(&l.label)
            );
            ly += 16.0;
        }
        for p in &self.points {
            let _ = writeln!(
                s,
                r#"<circle cx="{}" cy="{ly:.1}" r="3.5" fill="{}"/><text x="{}" y="{:.1}">{}</text>"#,
                L + 22.0,
                p.color,
                L + 40.0,
                ly + 4.0,
                esc(&p.label)
            );
            ly += 16.0;
        }
        s.push_str("</svg>\n");
        s
    }
}

/// An SVG document's opening of `w` x `h` pixels: white ground and `title` on top (the
/// charts of [`super::chart`] open the same way).
pub(crate) fn svg_open(w: f64, h: f64, title: &str) -> String {
    format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="12">
<rect width="{w}" height="{h}" fill="white"/>
<text x="{}" y="22" text-anchor="middle" font-size="15" font-weight="bold">{}</text>
"#,
        w / 2.0,
        esc(title)
    )
}

/// `t` with `&`, `<`, `>` escaped for SVG text.
pub(crate) fn esc(t: &str) -> String {
    t.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn svg_is_well_formed_and_deterministic() {
        let p = Plot {
            title: "a < b & c".into(),
            x_label: "T [s]".into(),
            y_label: "rms [m]".into(),
            lines: vec![Line {
                label: "theory".into(),
                color: "black",
                dashed: false,
                pts: vec![(0.1, 1e-4), (10.0, 1e-1)],
            }],
            points: vec![Points {
                label: "MC".into(),
                color: "red",
                pts: vec![(1.0, 3e-3, 2.9e-3, 3.1e-3), (2.0, 8e-3, 0.0, 9e-3)],
            }],
            marks: vec![(0.3, "T_x".into())],
        };
        let a = p.to_svg();
        assert_eq!(a, p.to_svg());
        assert!(a.starts_with("<svg") && a.ends_with("</svg>\n"));
        assert!(a.contains("a &lt; b &amp; c"));
        assert_eq!(a.matches("<circle").count(), 3); // two points + legend
    }
}
