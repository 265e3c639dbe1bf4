//! `ellipsoid plot`'s multi-panel figure, in the paper's style, as SVG (plotters' SVG
//! backend; text sizes estimated, no font read), PNG (the same SVG rendered by resvg
//! with a system sans-serif font, e.g. Debian's fonts-dejavu-core) and PDF (the same SVG
//! as vector PDF by svg2pdf, the font's subset embedded).
//!
//! The panels — their axes, titles, labels with units, series, colours and shading — are
//! declared once in `ellipsoid_io::panels` (`assets/panels.json`), which `Trajectory.plot`
//! (matplotlib) draws from too:
//!
//! ```text
//! panel    draws                                                         needs
//! theta    θ(t)                                                          theta
//! rates    θ̇, φ̇, ψ̇ (and the world-frame vertical spin ω_z if present;    theta_dot, phi_dot, psi_dot
//!          φ̇, ψ̇ left out where sin θ < 0.1: they diverge as 1/sin θ)
//! energy   E (and E + W when work is dissipated); the relative drift      energy
//!          of the conserved quantity, |ΔE|/|E0| or |Δ(E + W)|/|E0 + W0|
//!          (the `drift` column when present), on a log axis
//! forces   normal force N and slip speed, contact mode shaded            normal_force, slip_speed
//! surfaces the normal force of each surface of a body with contact        normal_force_S of each
//!          spheres, one line per surface, contact phase shaded            surface S (drawn by default
//!                                                                         only when present)
//! path     the paths on the plane of the contact point, G and C0         x, y (contact: contact_x/y,
//!                                                                        or the body's shape)
//! COLUMN   any numeric output column against time (`--columns`)          COLUMN
//! ```
//! Every time axis marks the events (dashed purple lines; at most [`EVENT_LINES`] of them:
//! events closer together than that fraction of the axis share one line, so a chattering
//! run's 20,000 events draw as a band of lines, not 20,000). Long runs are drawn from the
//! min/max envelope of each series (`ellipsoid_io::viewer::envelope`), so peaks survive.

use ellipsoid_io::panels;
use ellipsoid_io::table::{self, Table};
use ellipsoid_io::viewer::envelope;
use plotters::coord::Shift;
use plotters::prelude::*;

/// Points per series after decimation (two per bucket).
const BUCKETS: usize = 2_000;
/// Most event lines on one time axis (about one per 4 px of its width).
const EVENT_LINES: usize = 250;
/// Figure width and height of one panel row (px).
const WIDTH: u32 = 1100;
const ROW: u32 = 300;
/// Drift values below this are drawn at it (an exact zero has no place on a log axis).
const FLOOR: f64 = 1e-17;

/// A declared `#rrggbb` colour.
fn color(hex: &str) -> RGBColor {
    let (r, g, b) = panels::rgb(hex);
    RGBColor(r, g, b)
}

/// Parses `--columns a,b,c`: numeric output columns other than `t`, or a body's
/// per-surface columns (`normal_force_stem`; whether the run has one is checked once it is
/// read, [`check_columns`]), no repeats; each is drawn as a panel of its own against time.
pub fn parse_columns(spec: &str) -> Result<Vec<&str>, String> {
    let names = ellipsoid_io::columns::NUMERIC_COLUMNS.map(|c| c.0);
    let mut out = Vec::new();
    for name in spec.split(',').map(str::trim) {
        if !names[1..].contains(&name) && table::surface_column(name).is_none() {
            return Err(format!(
                "--columns: {name:?} is not a numeric output column; the columns are {}, and for a body with contact spheres those of each surface S (normal_force_S, slip_speed_S, gap_S, contact_x_S, contact_y_S)",
                names[1..].join(", ")
            ));
        }
        if out.contains(&name) {
            return Err(format!("--columns: {name:?} is named twice"));
        }
        out.push(name);
    }
    Ok(out)
}

/// The panels drawn unless asked otherwise: every declared one, those of per-surface
/// columns only when `table` has them (a body with contact spheres).
pub fn default_panels(table: &Table) -> Vec<&'static str> {
    panels::declaration()
        .panels
        .iter()
        .filter(|p| !p.per_surface || p.needs.iter().all(|n| has(table, n)))
        .map(|p| p.name.as_str())
        .collect()
}

/// Whether `table` has the column `name`, or for `QUANTITY_*` that quantity of some surface.
fn has(table: &Table, name: &str) -> bool {
    match name.strip_suffix("_*") {
        Some(quantity) => !table.per_surface(quantity).is_empty(),
        None => table.column(name).is_some(),
    }
}

/// Parses `--panels a,b,c`: declared names, no repeats, at least one.
pub fn parse_panels(spec: &str) -> Result<Vec<&'static str>, String> {
    let known = panels::declaration().names();
    let mut out = Vec::new();
    for name in spec.split(',').map(str::trim) {
        let Some(p) = known.iter().find(|p| **p == name) else {
            return Err(format!(
                "--panels: unknown panel {name:?}; the panels are {}",
                known.join(", ")
            ));
        };
        if out.contains(p) {
            return Err(format!("--panels: {name:?} is named twice"));
        }
        out.push(*p);
    }
    Ok(out)
}

/// The columns the figure of `panels` draws from (besides `mode`; a caller reads these
/// alone, `ellipsoid_io::table::read_columns`): `t`, those every time axis's title needs
/// (`energy`, `work`, `drift`: the conserved quantity), and per declared panel the columns
/// of its series, derived ones by what they are computed from; a column's panel: that
/// column.
pub fn columns_for<'a>(panels: &[&'a str]) -> Vec<&'a str> {
    let decl = panels::declaration();
    let mut cols = vec!["t", "energy", "work", "drift"];
    for p in panels {
        let Some(panel) = decl.panel(p) else {
            cols.push(*p);
            continue;
        };
        cols.extend(panel.needs.iter().map(String::as_str));
        for s in panel.axes.iter().flat_map(|a| &a.series) {
            if s.euler {
                cols.push("theta");
            }
            let derived: &[&str] = match s.data.as_str() {
                "energy_plus_work" => &["energy", "work"],
                "drift" => &["drift", "energy", "work"],
                "G" | "start" => &["x", "y"],
                "contact" => &[
                    "contact_x",
                    "contact_y",
                    "x",
                    "y",
                    "z",
                    "theta",
                    "phi",
                    "psi",
                ],
                "centre" => &["x", "y", "theta", "phi", "psi"],
                column => {
                    cols.push(column);
                    continue;
                }
            };
            cols.extend_from_slice(derived);
        }
    }
    cols.sort_unstable();
    cols.dedup();
    cols
}

/// The columns each panel needs (a column's panel: that column), checked before anything
/// is drawn.
pub fn check_columns(table: &Table, panels: &[&str]) -> Result<(), String> {
    for p in panels {
        let need: Vec<&str> = match panels::declaration().panel(p) {
            Some(panel) => panel.needs.iter().map(String::as_str).collect(),
            None => vec![*p],
        };
        if let Some(q) = need.iter().find(|n| n.ends_with("_*") && !has(table, n)) {
            return Err(format!(
                "the {p} panel needs the per-surface columns `{}S` of a body with contact spheres, which {} does not have",
                q.trim_end_matches('*'),
                table.source
            ));
        }
        let need: Vec<&str> = need.into_iter().filter(|n| !n.ends_with("_*")).collect();
        table.require(&need, &format!("the {p} panel"))?;
    }
    Ok(())
}

pub(crate) type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;
type Res = Result<(), String>;
pub(crate) fn err<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}

/// A short tick label: at most 4 significant digits, scientific outside 1e-3..1e4.
pub(crate) fn tick(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if !(1e-3..1e4).contains(&a) {
        format!("{v:.1e}")
    } else {
        let s = format!("{:.*}", (3 - a.log10().floor() as i32).max(0) as usize, v);
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_owned()
        } else {
            s
        }
    }
}

/// Bounds of `values` padded by 5 %, never empty.
pub(crate) fn bounds<'a>(values: impl Iterator<Item = &'a f64>) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(*v), hi.max(*v))
    });
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let pad = ((hi - lo) * 0.05)
        .max(hi.abs().max(lo.abs()) * 1e-9)
        .max(1e-12);
    (lo - pad, hi + pad)
}

struct Series {
    name: String,
    color: RGBColor,
    /// The line's pieces: runs of samples with a value, each drawn on its own, so that a
    /// gap (NaN: a value left out) is not bridged by a straight line that looks like data.
    pieces: Vec<Vec<(f64, f64)>>,
}

/// The series `v(t)`, NaN where it has no value, as the min/max envelope of each run of
/// values ([`envelope`], [`BUCKETS`] in all, shared by length).
fn series(name: &str, color: RGBColor, t: &[f64], v: &[f64]) -> Series {
    let n = t.len().min(v.len()).max(1);
    let mut pieces = Vec::new();
    let mut start = 0;
    while start < t.len().min(v.len()) {
        if v[start].is_nan() {
            start += 1;
            continue;
        }
        let end = (start..v.len().min(t.len()))
            .find(|&i| v[i].is_nan())
            .unwrap_or(v.len().min(t.len()));
        let buckets = (BUCKETS * (end - start)).div_ceil(n).max(1);
        let (ts, vs) = envelope(&t[start..end], &v[start..end], buckets);
        pieces.push(ts.into_iter().zip(vs).collect());
        start = end;
    }
    Series {
        name: name.to_owned(),
        color,
        pieces,
    }
}

/// Spans of constant mode, as (t_start, t_end, mode name).
fn mode_spans(table: &Table) -> Vec<(f64, f64, String)> {
    let t = table.t();
    let Some(m) = &table.modes else {
        return Vec::new();
    };
    let mut spans = Vec::new();
    let mut start = 0;
    for i in 1..=m.len() {
        if i == m.len() || m[i] != m[start] {
            let end = if i == m.len() { t[i - 1] } else { t[i] };
            spans.push((t[start], end, table.mode(start).unwrap_or("").to_owned()));
            start = i;
        }
    }
    spans
}

/// One chart of quantities against time: title, y label (with unit), series, the mode
/// shading, the events; `log` draws log10 of the values with decade labels.
fn time_chart(
    area: &Area<'_>,
    table: &Table,
    title: &str,
    y_desc: &str,
    series: &[Series],
    log: bool,
    shade: bool,
) -> Res {
    let t = table.t();
    let (t0, t1) = (t[0], t[t.len() - 1].max(t[0] + 1e-12));
    let (mut y0, mut y1) = bounds(
        series
            .iter()
            .flat_map(|s| s.pieces.iter().flatten().map(|p| &p.1)),
    );
    if log {
        (y0, y1) = (y0.floor(), y1.ceil().max(y0.floor() + 1.0));
    }
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 19))
        .margin(10)
        .x_label_area_size(46)
        .y_label_area_size(84)
        .build_cartesian_2d(t0..t1, y0..y1)
        .map_err(err)?;
    if shade {
        for (a, b, mode) in mode_spans(table) {
            chart
                .draw_series([Rectangle::new(
                    [(a, y0), (b, y1)],
                    color(&panels::declaration().shade(&mode).fill).filled(),
                )])
                .map_err(err)?;
        }
    }
    let decade = |v: &f64| {
        if (v - v.round()).abs() < 1e-9 {
            format!("1e{}", v.round() as i64)
        } else {
            String::new()
        }
    };
    let yscale = y0.abs().max(y1.abs());
    let linear = |v: &f64| tick(*v);
    let ylinear = move |v: &f64| tick(if v.abs() < 1e-9 * yscale { 0.0 } else { *v });
    let ylab: &dyn Fn(&f64) -> String = if log { &decade } else { &ylinear };
    chart
        .configure_mesh()
        .x_desc(&panels::declaration().time_label)
        .y_desc(y_desc)
        .x_label_formatter(&linear)
        .y_label_formatter(ylab)
        .y_labels(if log { (y1 - y0) as usize + 1 } else { 6 })
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 16))
        .light_line_style(WHITE.mix(0.0))
        .bold_line_style(BLACK.mix(0.08))
        .draw()
        .map_err(err)?;
    for t in event_lines(table, t0, t1) {
        chart
            .draw_series(DashedLineSeries::new(
                [(t, y0), (t, y1)],
                5,
                4,
                color(&panels::declaration().events.color).stroke_width(1),
            ))
            .map_err(err)?;
    }
    for s in series {
        let color = s.color;
        for (k, piece) in s.pieces.iter().enumerate() {
            let drawn = chart
                .draw_series(LineSeries::new(
                    piece.iter().copied(),
                    color.stroke_width(2),
                ))
                .map_err(err)?;
            if k == 0 {
                drawn.label(s.name.clone()).legend(move |(x, y)| {
                    PathElement::new([(x, y), (x + 22, y)], color.stroke_width(2))
                });
            }
        }
    }
    let mut labels = chart.configure_series_labels();
    labels
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.4))
        .label_font(("sans-serif", 15));
    if series.len() > 1 || !table.events.is_empty() {
        labels.draw().map_err(err)?;
    }
    Ok(())
}

/// The times of the event lines on an axis from `t0` to `t1`: the axis cut into
/// [`EVENT_LINES`] equal bins, the first event (in the summary's order) of each bin that
/// has one.
fn event_lines(table: &Table, t0: f64, t1: f64) -> Vec<f64> {
    let mut taken = [false; EVENT_LINES + 1];
    let mut lines = Vec::new();
    for e in &table.events {
        let bin = ((e.t - t0) / (t1 - t0) * EVENT_LINES as f64).clamp(0.0, EVENT_LINES as f64);
        // `as` maps NaN to 0: such an event shares the first bin.
        if !std::mem::replace(&mut taken[bin as usize], true) {
            lines.push(e.t);
        }
    }
    lines
}

/// Any numeric column against time, labelled with its unit.
fn column_panel(area: &Area<'_>, table: &Table, name: &str) -> Res {
    let unit = table::unit(name).unwrap_or("1");
    time_chart(
        area,
        table,
        name,
        &format!("{name} ({unit})"),
        &[series(
            name,
            color(&panels::declaration().column_color),
            table.t(),
            table.column(name).expect("checked"),
        )],
        false,
        false,
    )
}

/// A declared series' samples as (times, values): a column, or a derived quantity
/// (`energy_plus_work` when work is dissipated, `drift`); `euler` series NaN (left out,
/// the line broken there) where |sin θ| is below the declared threshold. `None` when the
/// trajectory lacks it.
fn series_data(table: &Table, s: &panels::Series) -> Option<(Vec<f64>, Vec<f64>)> {
    let t = table.t();
    let values: Vec<f64> = match s.data.as_str() {
        "energy_plus_work" => {
            let w = table.column("work")?;
            if w.iter().all(|v| *v == 0.0) {
                return None;
            }
            let e = table.column("energy")?;
            e.iter().zip(w).map(|(e, w)| e + w).collect()
        }
        "drift" => table.drift()?.0,
        column => table.column(column)?.to_vec(),
    };
    let mut values = values;
    if let Some(theta) = table.column("theta").filter(|_| s.euler) {
        let min = panels::declaration().euler_min_sin_theta;
        for (v, th) in values.iter_mut().zip(theta) {
            if th.sin().abs() < min {
                *v = f64::NAN;
            }
        }
    }
    Some((t.to_vec(), values))
}

/// One declared axis against time: its series, its title with the suffixes of what is
/// drawn (optional series present, Euler rates left out, the modes shaded).
fn time_axis(area: &Area<'_>, table: &Table, axis: &panels::Axis) -> Res {
    let decl = panels::declaration();
    let conserved = table.drift().map_or("E", |d| d.1);
    let mut title = axis.title.replace("{conserved}", conserved);
    let mut drawn = Vec::new();
    let mut left_out = false;
    for s in &axis.series {
        if let Some(quantity) = s.data.strip_suffix("_*") {
            let colors = &decl.surface_colors;
            for (k, (surface, v)) in table.per_surface(quantity).into_iter().enumerate() {
                let label = s.label.replace("{surface}", surface);
                let c = color(&colors[k % colors.len()]);
                drawn.push(series(&label, c, table.t(), v));
            }
            continue;
        }
        let Some((t, mut v)) = series_data(table, s) else {
            if s.optional {
                continue;
            }
            return Err(format!("the {} series has no data", s.data));
        };
        left_out |= s.euler && v.iter().any(|x| x.is_nan());
        if v.iter().all(|x| x.is_nan()) {
            continue;
        }
        if axis.log {
            // NaN (a value left out) stays NaN: f64::max would make it the floor.
            v.iter_mut()
                .filter(|x| !x.is_nan())
                .for_each(|x| *x = x.abs().max(FLOOR).log10());
        }
        title.push_str(&s.title_suffix);
        let label = s.label.replace("{conserved}", conserved);
        drawn.push(series(&label, color(&s.color), &t, &v));
    }
    if left_out {
        title.push_str(&decl.euler_singular_suffix);
    }
    if axis.shade {
        let modes: Vec<&str> = table
            .mode_names
            .iter()
            .filter(|m| !m.is_empty())
            .map(String::as_str)
            .collect();
        title.push_str(&decl.shaded_title(&modes));
    }
    time_chart(
        area,
        table,
        &title,
        &axis.ylabel,
        &drawn,
        axis.log,
        axis.shade,
    )
}

/// A declared panel of time axes: one across the row, or two side by side.
fn time_panel(area: &Area<'_>, table: &Table, panel: &panels::Panel) -> Res {
    if let [left, right] = panel.axes.as_slice() {
        let (a, b) = area.split_horizontally(WIDTH / 2);
        time_axis(&a, table, left)?;
        time_axis(&b, table, right)
    } else {
        time_axis(area, table, &panel.axes[0])
    }
}

/// The declared path panel: the paths on the plane of G, the contact point and the
/// geometric centre (those the trajectory gives), the start marked; equal scales.
fn path_panel(area: &Area<'_>, table: &Table, axis: &panels::Axis) -> Res {
    let x = table.column("x").expect("checked");
    let y = table.column("y").expect("checked");
    let contact = table.contact_path();
    let centre = table.centre_path();
    // The declared series present, in legend order, with their colours.
    let present: Vec<(&str, &str, RGBColor)> = axis
        .series
        .iter()
        .filter(|s| match s.data.as_str() {
            "contact" => contact.is_some(),
            "centre" => centre.is_some(),
            _ => true,
        })
        .map(|s| (s.data.as_str(), s.label.as_str(), color(&s.color)))
        .collect();
    let color_of = |data: &str| present.iter().find(|p| p.0 == data).map(|p| p.2);
    let mut title = axis.title.clone();
    if contact.is_none() {
        title.push_str(
            &axis
                .unknown_contact_suffix
                .replace("{note}", &table.shape_note),
        );
    }
    // Equal scales on both axes: a square plot area in the middle of the row.
    let (w, h) = area.dim_in_pixel();
    let side = h.min(w) as i32;
    let pad = ((w as i32 - side) / 2).max(0);
    let row = area;
    let area = area.margin(0, 0, pad, pad);
    let mut xs: Vec<&f64> = x.iter().collect();
    let mut ys: Vec<&f64> = y.iter().collect();
    for (cx, cy) in contact.iter().chain(centre.iter()) {
        xs.extend(cx.iter());
        ys.extend(cy.iter());
    }
    let (mut x0, mut x1) = bounds(xs.into_iter());
    let (mut y0, mut y1) = bounds(ys.into_iter());
    let half = ((x1 - x0).max(y1 - y0)) / 2.0;
    let (mx, my) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    (x0, x1, y0, y1) = (mx - half, mx + half, my - half, my + half);
    let mut chart = ChartBuilder::on(&area)
        .caption(&title, ("sans-serif", 19))
        .margin(10)
        .x_label_area_size(46)
        .y_label_area_size(84)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(err)?;
    let scale = x0.abs().max(x1.abs()).max(y0.abs()).max(y1.abs());
    let fmt = move |v: &f64| tick(if v.abs() < 1e-9 * scale { 0.0 } else { *v });
    chart
        .configure_mesh()
        .x_desc(axis.xlabel.as_deref().unwrap_or("x (m)"))
        .y_desc(&axis.ylabel)
        .x_label_formatter(&fmt)
        .y_label_formatter(&fmt)
        .x_labels(4)
        .y_labels(6)
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 16))
        .light_line_style(WHITE.mix(0.0))
        .bold_line_style(BLACK.mix(0.08))
        .draw()
        .map_err(err)?;
    let decimate = |xs: &[f64], ys: &[f64]| -> Vec<(f64, f64)> {
        let step = (xs.len() / (4 * BUCKETS)).max(1);
        let mut p: Vec<(f64, f64)> = xs
            .iter()
            .zip(ys)
            .step_by(step)
            .map(|(a, b)| (*a, *b))
            .collect();
        p.push((xs[xs.len() - 1], ys[ys.len() - 1]));
        p
    };
    let paths = [
        ("G", Some((x, y)), 2),
        ("centre", centre.as_ref().map(|(a, b)| (&a[..], &b[..])), 1),
        (
            "contact",
            contact.as_ref().map(|(a, b)| (&a[..], &b[..])),
            1,
        ),
    ];
    for (data, xy, width) in paths {
        if let (Some((px, py)), Some(c)) = (xy, color_of(data)) {
            chart
                .draw_series(LineSeries::new(decimate(px, py), c.stroke_width(width)))
                .map_err(err)?;
        }
    }
    if let Some(c) = color_of("start") {
        chart
            .draw_series([Circle::new((x[0], y[0]), 5, c.filled())])
            .map_err(err)?;
    }
    // The legend beside the square, where it hides nothing.
    let (lx, ly) = (pad + side + 10, 60);
    for (k, (data, label, c)) in present.iter().enumerate() {
        let y = ly + 24 * k as i32;
        if *data == "start" {
            row.draw(&Circle::new((lx + 11, y), 5, c.filled()))
                .map_err(err)?;
        } else {
            row.draw(&Rectangle::new([(lx, y - 1), (lx + 22, y + 1)], c.filled()))
                .map_err(err)?;
        }
        row.draw(&Text::new(
            label.to_string(),
            (lx + 30, y - 9),
            ("sans-serif", 15).into_font(),
        ))
        .map_err(err)?;
    }
    Ok(())
}

/// The figure as SVG text: one row per panel, a title line on top.
pub fn svg(table: &Table, panels: &[&str], title: &str) -> Result<String, String> {
    check_columns(table, panels)?;
    let head = 40;
    let height = head + ROW * panels.len() as u32;
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (WIDTH, height)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let (top, body) = root.split_vertically(head);
        top.draw(&Text::new(
            title.to_owned(),
            (14, 10),
            ("sans-serif", 18).into_font(),
        ))
        .map_err(err)?;
        let rows = body.split_evenly((panels.len(), 1));
        for (area, p) in rows.iter().zip(panels) {
            match panels::declaration().panel(p) {
                Some(panel) if panel.name == "path" => path_panel(area, table, &panel.axes[0])?,
                Some(panel) => time_panel(area, table, panel)?,
                None => column_panel(area, table, p)?,
            }
        }
        root.present().map_err(err)?;
    }
    Ok(out)
}

/// The SVG reader's options: text in a system sans-serif font (DejaVu Sans when
/// installed). Fails, saying what to install, when no font is found.
fn svg_options() -> Result<resvg::usvg::Options<'static>, String> {
    let mut opt = resvg::usvg::Options::default();
    let db = opt.fontdb_mut();
    db.load_system_fonts();
    if let Ok(dir) = std::env::var("ELLIPSOID_FONT_DIR") {
        db.load_fonts_dir(dir);
    }
    let family = ["DejaVu Sans", "Liberation Sans", "Noto Sans", "FreeSans"]
        .into_iter()
        .find(|f| {
            db.faces()
                .any(|face| face.families.iter().any(|(n, _)| n == f))
        });
    match family {
        Some(f) => db.set_sans_serif_family(f),
        None if db.is_empty() => {
            return Err("no font found to draw the figure's text (install one, e.g. `apt-get install -y fonts-dejavu-core`, or set ELLIPSOID_FONT_DIR), or write SVG with -o FIG.svg".into());
        }
        None => {
            let first = db
                .faces()
                .next()
                .and_then(|f| f.families.first().map(|n| n.0.clone()))
                .unwrap_or_default();
            db.set_sans_serif_family(first);
        }
    }
    Ok(opt)
}

fn parse(svg: &str) -> Result<resvg::usvg::Tree, String> {
    resvg::usvg::Tree::from_str(svg, &svg_options()?)
        .map_err(|e| format!("cannot read the SVG: {e}"))
}

/// The resolution of a figure's PNG unless `--dpi` says otherwise: 1 px of the SVG per
/// pixel, the SVG's 1 px being 1/96 inch.
pub const DEFAULT_DPI: f64 = 96.0;
/// The range of `--dpi` [pixels per inch].
pub const DPI_RANGE: (f64, f64) = (24.0, 1200.0);
/// Most pixels of a PNG (200 MB of pixmap): a tall figure at a high `--dpi` beyond it is
/// refused before it is drawn.
pub const MAX_PIXELS: f64 = 5e7;

/// A figure's file format, by the output's extension, and a PNG's resolution.
#[derive(Debug, Clone)]
pub struct Format {
    /// "svg", "png" or "pdf".
    pub ext: String,
    /// Pixels per inch of a PNG.
    pub dpi: f64,
}

impl Format {
    /// The format of `output` (`.svg`, `.png` or `.pdf`) and `--dpi` `dpi` (a PNG's
    /// resolution, [`DPI_RANGE`]; SVG and PDF are vector formats and take none): an error
    /// naming `--dpi`, its value and the rule otherwise.
    pub fn of(
        output: &std::path::Path,
        dpi: Option<f64>,
    ) -> Result<Format, crate::error::CliError> {
        let ext = crate::visual::check_output(output, &["svg", "png", "pdf"], "figure")?;
        let usage = |rule: String| crate::error::CliError::Usage(rule);
        let dpi = match dpi {
            None => DEFAULT_DPI,
            Some(d) if ext != "png" => {
                return Err(usage(format!(
                    "--dpi {d}: a resolution applies to PNG figures only ({} is a vector format, sharp at any size)",
                    output.display()
                )));
            }
            Some(d) if !(DPI_RANGE.0..=DPI_RANGE.1).contains(&d) => {
                return Err(usage(format!(
                    "--dpi {d}: must be from {} to {} pixels per inch",
                    DPI_RANGE.0, DPI_RANGE.1
                )));
            }
            Some(d) => d,
        };
        Ok(Format { ext, dpi })
    }

    /// The figure `svg` in this format: SVG as is, PNG rendered at [`Format::dpi`], PDF.
    pub fn encode(&self, svg: String) -> Result<Vec<u8>, String> {
        match self.ext.as_str() {
            "png" => png(&svg, self.dpi),
            "pdf" => pdf(&svg),
            _ => Ok(svg.into_bytes()),
        }
    }
}

/// Renders SVG text to PNG bytes with resvg (fonts as [`svg_options`] finds them) at
/// `dpi` pixels per inch (1 px of the SVG = 1/96 inch), at most [`MAX_PIXELS`].
pub fn png(svg: &str, dpi: f64) -> Result<Vec<u8>, String> {
    use resvg::tiny_skia;
    let tree = parse(svg)?;
    let scale = (dpi / DEFAULT_DPI) as f32;
    let size = tree.size();
    let (width, height) = (
        (size.width() * scale).ceil(),
        (size.height() * scale).ceil(),
    );
    if f64::from(width) * f64::from(height) > MAX_PIXELS {
        return Err(format!(
            "the PNG would be {width} × {height} pixels at {dpi} dpi, more than {MAX_PIXELS:e}: use a lower --dpi, or write SVG or PDF"
        ));
    }
    let mut pixmap =
        tiny_skia::Pixmap::new(width as u32, height as u32).ok_or("the figure has no size")?;
    pixmap.fill(tiny_skia::Color::WHITE);
    resvg::render(
        &tree,
        tiny_skia::Transform::from_scale(scale, scale),
        &mut pixmap.as_mut(),
    );
    pixmap
        .encode_png()
        .map_err(|e| format!("cannot encode the PNG: {e}"))
}

/// Converts SVG text to a vector PDF of one page (svg2pdf; the text's font subset
/// embedded, fonts as [`svg_options`] finds them), 1 px of the SVG = 1/96 inch.
pub fn pdf(svg: &str) -> Result<Vec<u8>, String> {
    let tree = parse(svg)?;
    svg2pdf::to_pdf(
        &tree,
        svg2pdf::ConversionOptions::default(),
        svg2pdf::PageOptions { dpi: 96.0 },
    )
    .map_err(|e| format!("cannot write the PDF: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table() -> Table {
        let names = [
            "t",
            "x",
            "y",
            "z",
            "theta",
            "phi",
            "psi",
            "theta_dot",
            "phi_dot",
            "psi_dot",
            "energy",
            "normal_force",
            "slip_speed",
            "work",
            "omega_world_z",
        ];
        let mut t = Table::from_rows("mem.csv", &names, 500, |i| {
            let t = i as f64 * 1e-3;
            let v = vec![
                t,
                0.01 * t.cos(),
                0.01 * t.sin(),
                0.02,
                0.2 + 0.1 * (40.0 * t).sin(),
                t,
                60.0 * t,
                4.0 * (40.0 * t).cos(),
                1.0,
                60.0,
                0.03 - 1e-3 * t,
                0.5,
                0.1 * (1.0 - t),
                1e-3 * t * (1.0 + 1e-12),
                60.0 * (0.2 + 0.1 * (40.0 * t).sin()).cos(),
            ];
            (
                v,
                if i < 300 {
                    "sliding".into()
                } else {
                    "rolling".into()
                },
            )
        });
        t.events.push(ellipsoid_io::table::Event {
            t: 0.3,
            kind: "mode_switch".into(),
            label: "sliding → rolling".into(),
        });
        t
    }

    /// [`table`] as a body with a contact sphere `stem` writes it: the normal force of
    /// each surface (the stem takes the load from 0.2 s on), modes naming the surfaces.
    fn with_stem() -> Table {
        let mut t = table();
        let n = t.rows();
        let s: Vec<f64> = t
            .t()
            .iter()
            .map(|t| if *t < 0.2 { 0.0 } else { 0.5 })
            .collect();
        let e: Vec<f64> = s.iter().map(|s| 0.5 - s).collect();
        t.columns.push(("normal_force_ellipsoid".into(), e));
        t.columns.push(("normal_force_stem".into(), s));
        t.mode_names = vec![
            "sliding@ellipsoid".into(),
            "two_contacts@ellipsoid+stem".into(),
            "rolling@stem".into(),
        ];
        t.modes = Some((0..n).map(|i| (i * 3 / n) as u8).collect());
        t
    }

    /// Every declared axis is drawn with its title, its labels and its series' labels
    /// (`Trajectory.plot` is held to the same declaration by the Python tests).
    #[test]
    fn every_declared_axis_is_drawn_with_its_labels() {
        let svg = svg(&with_stem(), &panels::declaration().names(), "test").unwrap();
        let text = |s: &str| s.replace('&', "&amp;").replace('<', "&lt;");
        for axis in panels::declaration().panels.iter().flat_map(|p| &p.axes) {
            let title = axis.title.replace("{conserved}", "E + W");
            assert!(svg.contains(&text(&title)), "missing title {title}");
            assert!(svg.contains(&text(&axis.ylabel)), "missing {}", axis.ylabel);
            for s in &axis.series {
                let label = s
                    .label
                    .replace("{conserved}", "E + W")
                    .replace("{surface}", "stem");
                assert!(
                    s.optional || svg.contains(&text(&label)),
                    "missing series {label}"
                );
            }
        }
    }

    #[test]
    fn every_panel_names_its_axes_with_units() {
        let svg = svg(&with_stem(), &panels::declaration().names(), "test").unwrap();
        for label in [
            "time t (s)",
            "θ (rad)",
            "rate (rad/s)",
            "energy (J)",
            "|relative drift| (1, log)",
            "normal force N (N)",
            "slip speed |v_C| (m/s)",
            "x (m)",
            "y (m)",
            "E + W",
            "sliding orange",
            "normal force N_S (N)",
        ] {
            assert!(
                svg.contains(&label.replace('&', "&amp;")),
                "missing {label}"
            );
        }
        assert!(svg.contains("1e-"), "decade labels on the drift axis");
    }

    /// A chattering run's events: each panel draws at most [`EVENT_LINES`] lines, where
    /// 20,000 events made a 282 MB SVG whose PNG failed.
    #[test]
    fn dense_events_share_lines() {
        let mut t = table();
        let lone = t.events[0].t;
        for k in 0..20_000 {
            t.events.push(ellipsoid_io::table::Event {
                t: 0.5 + 1e-6 * k as f64,
                kind: "mode_switch".into(),
                label: "sliding → rolling".into(),
            });
        }
        let (t0, t1) = (t.t()[0], *t.t().last().unwrap());
        let lines = event_lines(&t, t0, t1);
        assert_eq!(lines[0], lone, "a lone event keeps its line");
        assert!(lines.len() <= 4, "{} lines", lines.len());
        let svg = svg(&t, &default_panels(&t), "test").unwrap();
        assert!(svg.len() < 2_000_000, "{} bytes", svg.len());
        png(&svg, DEFAULT_DPI).unwrap();
    }

    /// A table of only the columns `columns_for` names draws each panel as the whole
    /// table does (what `ellipsoid plot` reads is enough), and leaves others out.
    #[test]
    fn the_columns_read_for_a_panel_draw_it_whole() {
        let full = with_stem();
        for p in panels::declaration().names().into_iter().chain(["vx"]) {
            let keep = columns_for(&[p]);
            let mut part = with_stem();
            part.columns
                .retain(|c| table::keeps(Some(&keep), c.0.as_str()));
            if p == "vx" {
                assert_eq!(keep, ["drift", "energy", "t", "vx", "work"]);
                continue;
            }
            assert!(part.columns.len() < full.columns.len(), "{p}: {keep:?}");
            assert_eq!(
                svg(&part, &[p], "x").unwrap(),
                svg(&full, &[p], "x").unwrap(),
                "{p}: {keep:?}"
            );
        }
        assert!(columns_for(&["rates"]).contains(&"omega_world_z"));
    }

    /// A body with contact spheres: the surfaces panel draws a line per surface, named by
    /// it, and shades the contact phases (each once in the title); it is drawn by default
    /// only for such a body, and asked of another it says what is missing.
    #[test]
    fn the_surfaces_panel_draws_each_surface_and_only_for_bodies_with_spheres() {
        let svg = svg(&with_stem(), &["surfaces"], "x").unwrap();
        for text in [
            "normal force of each surface (shaded: sliding orange, two_contacts pink, rolling green)",
            "N, ellipsoid",
            "N, stem",
        ] {
            assert!(svg.contains(text), "missing {text}");
        }
        let (ellipsoid, stem) = (
            panels::declaration().surface_colors[0].to_lowercase(),
            panels::declaration().surface_colors[1].to_lowercase(),
        );
        assert!(
            svg.to_lowercase()
                .contains(&format!("stroke=\"{ellipsoid}\""))
                && svg.to_lowercase().contains(&format!("stroke=\"{stem}\"")),
            "a line of each surface's colour"
        );
        assert!(default_panels(&with_stem()).contains(&"surfaces"));
        assert_eq!(
            default_panels(&table()),
            ["theta", "rates", "energy", "forces", "path"]
        );
        let err = super::svg(&table(), &["surfaces"], "x").unwrap_err();
        assert!(
            err.contains("the surfaces panel needs the per-surface columns `normal_force_S`"),
            "{err}"
        );
        assert_eq!(
            parse_columns("normal_force_stem,theta").unwrap(),
            ["normal_force_stem", "theta"]
        );
        let svg = super::svg(&with_stem(), &["normal_force_stem"], "x").unwrap();
        assert!(svg.contains("normal_force_stem (N)"));
    }

    #[test]
    fn panels_are_parsed_strictly() {
        assert_eq!(parse_panels("theta, path").unwrap(), ["theta", "path"]);
        assert!(
            parse_panels("theta,thetaa")
                .unwrap_err()
                .contains("unknown panel \"thetaa\"")
        );
        assert!(parse_panels("path,path").unwrap_err().contains("twice"));
        let mut t = table();
        t.columns.retain(|c| c.0 != "slip_speed");
        assert!(
            svg(&t, &["forces"], "x")
                .unwrap_err()
                .contains("the forces panel needs the column `slip_speed`")
        );
    }

    #[test]
    fn columns_are_panels_of_their_own_with_units() {
        assert_eq!(
            parse_columns("energy, slip_speed").unwrap(),
            ["energy", "slip_speed"]
        );
        assert!(
            parse_columns("t")
                .unwrap_err()
                .contains("not a numeric output column")
        );
        assert!(parse_columns("work,work").unwrap_err().contains("twice"));
        let svg = svg(&table(), &["work", "slip_speed"], "x").unwrap();
        assert!(svg.contains("work (J)") && svg.contains("slip_speed (m/s)"));
        assert!(
            super::svg(&table(), &["omega_world_x"], "x")
                .unwrap_err()
                .contains("omega_world_x")
        );
    }

    #[test]
    fn euler_rates_are_left_out_near_the_singularity() {
        // θ passes through 0 at i = 250, where φ̇ = −ψ̇ = 1/θ diverges (as z-x-z rates do).
        let names = ["t", "theta", "theta_dot", "phi_dot", "psi_dot"];
        let t = Table::from_rows("mem.csv", &names, 501, |i| {
            let th = (i as f64 - 250.0) * 1e-3;
            let big = if th == 0.0 { 1e6 } else { 1.0 / th };
            (vec![i as f64 * 1e-3, th, 1.0, big, -big], "sliding".into())
        });
        let svg = svg(&t, &["rates"], "x").unwrap();
        assert!(
            svg.contains("left out where sin θ &lt; 0.1"),
            "{}",
            &svg[..300]
        );
        // the rate axis ends near ±10 (1/0.1), not at ±1e6
        assert!(!svg.contains(">1e6<") && !svg.contains("1000000"));
        // φ̇ and ψ̇ are broken where they are left out, as Trajectory.plot breaks them:
        // two pieces each (and a legend mark), where θ̇ is one line (and its mark).
        let lines = |color: &str| {
            svg.split("<polyline")
                .skip(1)
                .filter(|l| l.split("/>").next().unwrap_or("").contains(color))
                .count()
        };
        assert_eq!(lines("#1F77B4"), 2, "θ̇");
        assert_eq!(lines("#FF7F0E"), 3, "φ̇");
        assert_eq!(lines("#2CA02C"), 3, "ψ̇");
    }

    /// `--dpi` takes 24 to 1200 for a PNG only, and a PNG beyond [`MAX_PIXELS`] is refused
    /// before a pixmap is made.
    #[test]
    fn the_resolution_is_bounded_and_for_png_only() {
        let dir = std::env::temp_dir();
        let fail = |name: &str, dpi: f64| match Format::of(&dir.join(name), Some(dpi)) {
            Err(crate::error::CliError::Usage(e)) => e,
            other => panic!("{name} at {dpi}: {other:?}"),
        };
        assert!(fail("f.svg", 200.0).contains("PNG figures only"));
        assert!(fail("f.pdf", 200.0).contains("PNG figures only"));
        for dpi in [10.0, 5000.0, f64::NAN, f64::INFINITY] {
            assert!(
                fail("f.png", dpi).contains("must be from 24 to 1200"),
                "{dpi}"
            );
        }
        assert_eq!(Format::of(&dir.join("f.png"), None).unwrap().dpi, 96.0);
        let t = table();
        let svg = svg(&t, &default_panels(&t), "test").unwrap();
        let e = png(&svg, 1200.0).unwrap_err();
        assert!(e.contains("pixels at 1200 dpi"), "{e}");
    }

    #[test]
    fn ticks_are_short() {
        assert_eq!(tick(0.0), "0");
        assert_eq!(tick(0.25), "0.25");
        assert_eq!(tick(12.5), "12.5");
        assert_eq!(tick(1.5e-5), "1.5e-5");
        assert_eq!(tick(-0.000123456), "-1.2e-4");
    }
}
