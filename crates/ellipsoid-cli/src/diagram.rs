//! `ellipsoid steady --vary … --plot OUT.svg|png|pdf`: a family's stability diagram
//! (docs/steady.md, "Stability diagrams"), drawn with the plotters SVG backend of
//! `ellipsoid plot` and rendered to PNG or PDF by the same functions ([`figure::png`],
//! [`figure::pdf`]).
//!
//! Two panels against the varied parameter: the growth rates (every Re λ, the largest
//! bold) and the angular frequencies |Im λ| (one point per pair). The parameter's
//! stable ranges are shaded green and the unstable ones red, each range ending at the
//! located critical value (midway between two values where none was located); every
//! critical value is a dashed vertical line labelled with its value and kind.

use ellipsoid_core::steady::sweep::Stability;
use ellipsoid_core::steady::{Critical, Sweep};
use plotters::prelude::*;

use crate::figure::{self, Area, bounds, err, tick};

/// Most values a diagram draws (its SVG grows by about 0.2 kB per value).
pub const MAX_VALUES: usize = 10_000;
const WIDTH: u32 = 1000;
const ROW: u32 = 330;
const HEAD: u32 = 40;
const STABLE: RGBColor = RGBColor(214, 240, 214);
const UNSTABLE: RGBColor = RGBColor(250, 214, 214);
const GROWTH: RGBColor = RGBColor(31, 119, 180);
const OTHERS: RGBColor = RGBColor(140, 170, 200);
const FREQUENCY: RGBColor = RGBColor(214, 39, 40);
const CRITICAL: RGBColor = RGBColor(110, 40, 150);

/// One value's eigenvalues (Re λ, Im λ) by decreasing real part, and its verdict.
type Row = (Vec<(f64, f64)>, bool);

/// What the diagram draws of a sweep: per value its eigenvalues and verdict (`None`
/// where the value has no steady motion), and the critical values.
pub struct Diagram {
    /// The varied key, with its unit if the schema gives one.
    pub axis: String,
    pub values: Vec<f64>,
    /// Per value its [`Row`] (`None` where it has no steady motion).
    pub rows: Vec<Option<Row>>,
    pub critical: Vec<Critical>,
}

impl Diagram {
    pub fn of<T: Stability>(sw: &Sweep<T>) -> Diagram {
        let unit = ellipsoid_core::scenario::schema::unit(&sw.key);
        Diagram {
            axis: match unit {
                Some(u) => format!("{} ({u})", sw.key),
                None => sw.key.clone(),
            },
            values: sw.values.clone(),
            rows: sw
                .rows
                .iter()
                .map(|r| {
                    r.as_ref().ok().map(|a| {
                        let eig = a.eigenvalues().iter().map(|z| (z.re, z.im)).collect();
                        (eig, a.stable())
                    })
                })
                .collect(),
            critical: sw.critical.clone(),
        }
    }

    /// The shaded ranges (from, to, stable), in the order of the values: each value's
    /// verdict from midway to its neighbours, or from a critical value located between
    /// them.
    fn ranges(&self) -> Vec<(f64, f64, bool)> {
        let points: Vec<(f64, bool)> = self
            .values
            .iter()
            .zip(&self.rows)
            .filter_map(|(v, r)| r.as_ref().map(|(_, s)| (*v, *s)))
            .collect();
        let mut out: Vec<(f64, f64, bool)> = Vec::new();
        for (k, &(v, stable)) in points.iter().enumerate() {
            // Where this value's range meets its neighbour (w, its verdict).
            let edge = |(w, other): (f64, bool)| {
                let (lo, hi) = (v.min(w), v.max(w));
                self.critical
                    .iter()
                    .map(|c| c.value)
                    .find(|c| stable != other && (lo..=hi).contains(c))
                    .unwrap_or(0.5 * (v + w))
            };
            let from = if k == 0 { v } else { edge(points[k - 1]) };
            let to = points.get(k + 1).map_or(v, |&p| edge(p));
            match out.last_mut() {
                Some(last) if last.2 == stable && last.1 == from => last.1 = to,
                _ => out.push((from, to, stable)),
            }
        }
        out
    }
}

/// The diagram as SVG text.
pub fn svg(d: &Diagram, title: &str) -> Result<String, String> {
    if d.rows.iter().all(Option::is_none) {
        return Err("no value of the sweep has a steady motion: there is nothing to draw".into());
    }
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (WIDTH, HEAD + 2 * ROW)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let (top, body) = root.split_vertically(HEAD);
        top.draw(&Text::new(
            title.to_owned(),
            (14, 10),
            ("sans-serif", 18).into_font(),
        ))
        .map_err(err)?;
        let (upper, lower) = body.split_vertically(ROW);
        let (mut growth, mut freq) = (Vec::new(), Vec::new());
        let k_max = d
            .rows
            .iter()
            .flatten()
            .map(|r| r.0.len())
            .max()
            .unwrap_or(0);
        for k in 0..k_max {
            growth.push(
                d.values
                    .iter()
                    .zip(&d.rows)
                    .filter_map(|(v, r)| Some((*v, r.as_ref()?.0.get(k)?.0)))
                    .collect::<Vec<_>>(),
            );
        }
        for (v, r) in d.values.iter().zip(&d.rows) {
            if let Some((eig, _)) = r {
                // One point per conjugate pair (and per real eigenvalue at 0).
                let mut f: Vec<f64> = eig.iter().map(|z| z.1.abs()).collect();
                f.sort_by(f64::total_cmp);
                f.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * b.abs().max(1e-300));
                freq.extend(f.into_iter().map(|f| (*v, f)));
            }
        }
        chart(
            &upper,
            d,
            "Growth rates Re λ",
            "Re λ (1/s)",
            &growth,
            &[],
            true,
        )?;
        chart(
            &lower,
            d,
            "Angular frequencies |Im λ|",
            "|Im λ| (1/s)",
            &[],
            &freq,
            false,
        )?;
        root.present().map_err(err)?;
    }
    Ok(out)
}

/// One panel: the shaded ranges, the critical lines, the lines (`lines[0]` bold: the
/// largest real part) and the points.
fn chart(
    area: &Area<'_>,
    d: &Diagram,
    title: &str,
    y_desc: &str,
    lines: &[Vec<(f64, f64)>],
    points: &[(f64, f64)],
    zero: bool,
) -> Result<(), String> {
    let (x0, x1) = {
        let (lo, hi) = d
            .values
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |a, v| {
                (a.0.min(*v), a.1.max(*v))
            });
        if hi > lo {
            (lo, hi)
        } else {
            (lo - 0.5, lo + 0.5)
        }
    };
    let ys = lines
        .iter()
        .flatten()
        .chain(points)
        .map(|p| &p.1)
        .chain(zero.then_some(&0.0));
    let (y0, y1) = bounds(ys);
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 19))
        .margin(10)
        .x_label_area_size(46)
        .y_label_area_size(84)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(err)?;
    for (a, b, stable) in d.ranges() {
        let fill = if stable { STABLE } else { UNSTABLE };
        chart
            .draw_series([Rectangle::new([(a, y0), (b, y1)], fill.filled())])
            .map_err(err)?;
    }
    let yscale = y0.abs().max(y1.abs());
    let ylab = move |v: &f64| tick(if v.abs() < 1e-9 * yscale { 0.0 } else { *v });
    chart
        .configure_mesh()
        .x_desc(&d.axis)
        .y_desc(y_desc)
        .x_label_formatter(&|v: &f64| tick(*v))
        .y_label_formatter(&ylab)
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 16))
        .light_line_style(WHITE.mix(0.0))
        .bold_line_style(BLACK.mix(0.08))
        .draw()
        .map_err(err)?;
    if zero {
        chart
            .draw_series(LineSeries::new([(x0, 0.0), (x1, 0.0)], BLACK.mix(0.5)))
            .map_err(err)?;
    }
    for c in &d.critical {
        chart
            .draw_series(DashedLineSeries::new(
                [(c.value, y0), (c.value, y1)],
                6,
                4,
                CRITICAL.stroke_width(2),
            ))
            .map_err(err)?;
        chart
            .draw_series([Text::new(
                format!("{} ({})", six(c.value), c.kind.name()),
                (c.value, y1),
                ("sans-serif", 14).into_font().color(&CRITICAL),
            )])
            .map_err(err)?;
    }
    for (k, line) in lines.iter().enumerate().rev() {
        let (color, width, label) = if k == 0 {
            (GROWTH, 3, "largest Re λ")
        } else {
            (OTHERS, 1, "other Re λ")
        };
        let series = chart
            .draw_series(LineSeries::new(
                line.iter().copied(),
                color.stroke_width(width),
            ))
            .map_err(err)?;
        if k <= 1 {
            series.label(label).legend(move |(x, y)| {
                PathElement::new([(x, y), (x + 22, y)], color.stroke_width(width))
            });
        }
    }
    if !points.is_empty() {
        chart
            .draw_series(
                points
                    .iter()
                    .map(|p| Circle::new(*p, 2, FREQUENCY.filled())),
            )
            .map_err(err)?
            .label("|Im λ|")
            .legend(|(x, y)| Circle::new((x + 11, y), 3, FREQUENCY.filled()));
    }
    for (fill, label) in [(STABLE, "stable"), (UNSTABLE, "unstable")] {
        chart
            .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
            .map_err(err)?
            .label(label)
            .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 22, y + 6)], fill.filled()));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.4))
        .label_font(("sans-serif", 15))
        .draw()
        .map_err(err)?;
    Ok(())
}

/// `v` to 6 significant digits, trailing zeros dropped (a critical value's label).
fn six(v: f64) -> String {
    if v == 0.0 || !(1e-3..1e6).contains(&v.abs()) {
        return format!("{v:.5e}");
    }
    let s = format!(
        "{:.*}",
        (5 - v.abs().log10().floor() as i32).max(0) as usize,
        v
    );
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        s
    }
}

/// The diagram in `format`.
pub fn render(d: &Diagram, title: &str, format: &figure::Format) -> Result<Vec<u8>, String> {
    format.encode(svg(d, title)?)
}
