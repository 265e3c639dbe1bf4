//! `ellipsoid plot SECTIONS.csv --section --x COL --y COL -o FIG.svg|png|pdf`: the points
//! of a Poincaré section table (`ellipsoid run --sections`, docs/scenarios.md, "Poincaré
//! sections") drawn as a scatter of two of its columns, one colour per section, with the
//! plotters SVG backend of `ellipsoid plot` and rendered to PNG or PDF by the same
//! functions ([`figure::png`], [`figure::pdf`]).

use std::io::Read as _;
use std::path::Path;
use std::process::ExitCode;

use ellipsoid_core::scenario;
use plotters::prelude::*;

use crate::cli::PlotArgs;
use crate::error::CliError;
use crate::figure::{self, bounds, err, tick};
use crate::visual::put;

/// Most points a section figure reads.
pub const MAX_POINTS: usize = 1_000_000;
/// Most points drawn one marker each (an SVG of about 1.6 MB, a marker being about 80
/// bytes).
pub const MAX_MARKERS: usize = 20_000;
/// More points than [`MAX_MARKERS`] are drawn from a grid of GRID.0 × GRID.1 cells over
/// the points' range (about the markers' 4 px diameter each): a cell draws one marker, of
/// the last section drawn there (the one on top), so the figure has at most
/// GRID.0 · GRID.1 markers (an SVG of at most about 3 MB) whatever the number of points,
/// and looks as the figure of every point would: markers closer than their size overlap.
pub const GRID: (usize, usize) = (225, 175);
/// Largest section table read (a million rows of every column is about 600 MB).
const MAX_BYTES: u64 = 1 << 30;
const WIDTH: u32 = 900;
const HEIGHT: u32 = 700;
/// The sections' colours, in the order the table first names them (then again).
const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
];

/// Two columns of a section table: each point's (x, y) and the index of its section in
/// `names`, and each axis's label (the column with its unit).
#[derive(Debug)]
pub struct Points {
    pub xy: Vec<(f64, f64)>,
    pub section: Vec<usize>,
    pub names: Vec<String>,
    pub x_label: String,
    pub y_label: String,
    /// The scenario's file name, from the table's comment line.
    pub scenario: Option<String>,
}

pub fn plot_section(args: &PlotArgs) -> Result<ExitCode, CliError> {
    let (Some(x), Some(y)) = (&args.x, &args.y) else {
        return Err(CliError::Usage(
            "--section draws one column against another: give --x COL and --y COL".into(),
        ));
    };
    let format = figure::Format::of(&args.output, args.dpi)?;
    let wrap: Vec<&str> = args
        .wrap
        .as_deref()
        .map_or_else(Vec::new, |w| w.split(',').map(str::trim).collect());
    if let Some(w) = wrap.iter().find(|w| **w != x.as_str() && **w != y.as_str()) {
        return Err(CliError::Usage(format!(
            "--wrap {w:?}: not a column of this plot (--x {x:?}, --y {y:?})"
        )));
    }
    let wrapped = (wrap.contains(&x.as_str()), wrap.contains(&y.as_str()));
    let points = read(&args.input, (x, y), wrapped).map_err(CliError::Usage)?;
    let title = args.title.clone().unwrap_or_else(|| {
        let source = points.scenario.clone().unwrap_or_else(|| {
            args.input
                .file_name()
                .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
        });
        format!("Poincaré section of {source}: {y} against {x}")
    });
    let (svg, markers) = svg(&points, &title).map_err(CliError::Plot)?;
    let bytes = format.encode(svg).map_err(CliError::Plot)?;
    put(&args.output, &bytes)?;
    if !args.quiet {
        let drawn = if markers < points.xy.len() {
            format!("; drawn as {markers} markers, points closer than a marker sharing one")
        } else {
            String::new()
        };
        eprintln!(
            "wrote {} ({} points of {} section{}: {}{drawn})",
            args.output.display(),
            points.xy.len(),
            points.names.len(),
            if points.names.len() == 1 { "" } else { "s" },
            points.names.join(", ")
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// Reads the columns `x` and `y` of the section table at `path`: a comment line
/// (`# ellipsoid {json}`, its `units` and `scenario` used if present), a header whose
/// first column is `section`, one row per crossing, the section's name quoted if it
/// holds a comma, a quote or a line break (RFC 4180). The columns `wrap` marks, angles
/// (rad), are taken modulo 2π, in [0, 2π) (`--wrap`).
pub fn read(path: &Path, (x, y): (&str, &str), wrap: (bool, bool)) -> Result<Points, String> {
    let at = |line: Option<usize>| match line {
        Some(l) => format!("{}:{l}", path.display()),
        None => path.display().to_string(),
    };
    let file = scenario::open_regular(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let len = file.metadata().map_or(0, |m| m.len());
    if len > MAX_BYTES {
        return Err(format!(
            "{}: {len} bytes, more than the {MAX_BYTES} a section table is read up to",
            at(None)
        ));
    }
    let mut text = String::new();
    file.take(MAX_BYTES)
        .read_to_string(&mut text)
        .map_err(|e| format!("{}: {e} (is this a CSV file?)", at(None)))?;
    // Comment lines before the header: ours names the scenario and the columns' units.
    let (mut comment, mut rest, mut skipped) = (None, text.as_str(), 0);
    while rest.starts_with('#') {
        let (line, tail) = rest.split_once('\n').unwrap_or((rest, ""));
        if let Some(json) = line.strip_prefix(ellipsoid_io::csv::COMMENT) {
            comment = serde_json::from_str::<serde_json::Value>(json.trim()).ok();
        }
        (rest, skipped) = (tail, skipped + 1);
    }
    let mut records = Records::new(rest, skipped + 1);
    let Some((header_line, header)) = records.next() else {
        return Err(format!(
            "{}: no header; expected `section,t,…` as `ellipsoid run --sections` writes",
            at(None)
        ));
    };
    if header.first().map(String::as_str) != Some("section") {
        return Err(format!(
            "{}: the header's first column is {:?}, not `section`: is this a Poincaré section table written by `ellipsoid run --sections`?",
            at(Some(header_line)),
            header.first().map_or("", String::as_str)
        ));
    }
    let column = |flag: &str, name: &str| {
        header
            .iter()
            .position(|h| h == name)
            .filter(|&k| k > 0)
            .ok_or_else(|| {
                format!(
                    "--{flag} {name:?}: {} has no column {name:?}; its columns: {}",
                    path.display(),
                    header[1..].join(", ")
                )
            })
    };
    let (kx, ky) = (column("x", x)?, column("y", y)?);
    let label = |name: &str, wrapped: bool| {
        let unit = comment
            .as_ref()
            .and_then(|c| c.get("units")?.get(name)?.as_str().map(str::to_owned))
            .filter(|u| !u.is_empty() && u != "1");
        match (unit, wrapped) {
            (Some(u), true) if u != "rad" => Err(format!(
                "--wrap {name:?}: not an angle: its unit is {u}, and only angles (rad) are taken modulo 2π"
            )),
            (Some(u), true) => Ok(format!("{name} ({u}, modulo 2π)")),
            (None, true) => Ok(format!("{name} (modulo 2π)")),
            (Some(u), false) => Ok(format!("{name} ({u})")),
            (None, false) => Ok(name.to_owned()),
        }
    };
    let mut points = Points {
        xy: Vec::new(),
        section: Vec::new(),
        names: Vec::new(),
        x_label: label(x, wrap.0)?,
        y_label: label(y, wrap.1)?,
        scenario: comment.as_ref().and_then(|c| {
            let s = c.get("scenario")?.as_str()?;
            Some(Path::new(s).file_name()?.to_string_lossy().into_owned())
        }),
    };
    for (line, fields) in records {
        if fields.len() == 1 && fields[0].is_empty() {
            continue;
        }
        if fields.len() != header.len() {
            return Err(format!(
                "{}: {} fields where the header has {}",
                at(Some(line)),
                fields.len(),
                header.len()
            ));
        }
        if points.xy.len() >= MAX_POINTS {
            return Err(format!(
                "{}: more than {MAX_POINTS} points, the most a section figure draws; reading stopped at this row",
                at(Some(line))
            ));
        }
        let value = |k: usize| {
            let f = fields[k].trim();
            f.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    format!(
                        "{}: column `{}` = {f:?} is not a finite number; --x and --y take numeric columns",
                        at(Some(line)),
                        header[k]
                    )
                })
        };
        let turn = std::f64::consts::TAU;
        let modulo = |v: f64, wrapped: bool| {
            if wrapped {
                v.rem_euclid(turn) % turn
            } else {
                v
            }
        };
        points
            .xy
            .push((modulo(value(kx)?, wrap.0), modulo(value(ky)?, wrap.1)));
        let name = &fields[0];
        let index = match points.names.iter().position(|n| n == name) {
            Some(i) => i,
            None => {
                points.names.push(name.clone());
                points.names.len() - 1
            }
        };
        points.section.push(index);
    }
    if points.xy.is_empty() {
        return Err(format!(
            "{}: no points after the header (the run crossed no section)",
            at(None)
        ));
    }
    Ok(points)
}

/// The records of CSV text (RFC 4180: a quoted field may hold commas, doubled quotes and
/// line breaks), each with the line it starts on.
struct Records<'a> {
    chars: std::iter::Peekable<std::str::Chars<'a>>,
    line: usize,
}

impl<'a> Records<'a> {
    /// The records of `text`, its first line numbered `line`.
    fn new(text: &'a str, line: usize) -> Self {
        Records {
            chars: text.chars().peekable(),
            line,
        }
    }
}

impl Iterator for Records<'_> {
    type Item = (usize, Vec<String>);

    fn next(&mut self) -> Option<Self::Item> {
        self.chars.peek()?;
        let start = self.line;
        let (mut fields, mut field, mut quoted) = (Vec::new(), String::new(), false);
        while let Some(c) = self.chars.next() {
            match c {
                '"' if quoted && self.chars.peek() == Some(&'"') => {
                    self.chars.next();
                    field.push('"');
                }
                '"' if quoted => quoted = false,
                '"' if field.is_empty() => quoted = true,
                ',' if !quoted => fields.push(std::mem::take(&mut field)),
                '\n' if !quoted => {
                    self.line += 1;
                    break;
                }
                '\r' if !quoted && self.chars.peek() == Some(&'\n') => {}
                c => {
                    if c == '\n' {
                        self.line += 1;
                    }
                    field.push(c);
                }
            }
        }
        fields.push(field);
        Some((start, fields))
    }
}

/// The points to draw, by section: all of them up to [`MAX_MARKERS`]; beyond, on the
/// [`GRID`] over the points' range `x` × `y`, one point per cell, the first of the
/// highest section there (drawn last, so on top).
fn thin(points: &Points, x: (f64, f64), y: (f64, f64)) -> Vec<Vec<(f64, f64)>> {
    let mut by_section = vec![Vec::new(); points.names.len()];
    if points.xy.len() <= MAX_MARKERS {
        for (p, &k) in points.xy.iter().zip(&points.section) {
            by_section[k].push(*p);
        }
        return by_section;
    }
    let cell = |v: f64, (lo, hi): (f64, f64), n: usize| {
        let f = if hi > lo { (v - lo) / (hi - lo) } else { 0.5 };
        ((f * n as f64) as usize).min(n - 1)
    };
    let mut grid: Vec<Option<(usize, (f64, f64))>> = vec![None; GRID.0 * GRID.1];
    for (p, &k) in points.xy.iter().zip(&points.section) {
        let slot = &mut grid[cell(p.1, y, GRID.1) * GRID.0 + cell(p.0, x, GRID.0)];
        match slot {
            Some((s, _)) if *s >= k => {}
            _ => *slot = Some((k, *p)),
        }
    }
    for (k, p) in grid.into_iter().flatten() {
        by_section[k].push(p);
    }
    by_section
}

/// The points as SVG text, coloured by section, one marker (a circle) per point, or per
/// cell of the [`GRID`] that holds points beyond [`MAX_MARKERS`] points; and the number
/// of markers drawn.
pub fn svg(points: &Points, title: &str) -> Result<(String, usize), String> {
    let mut out = String::new();
    let markers;
    {
        let root = SVGBackend::with_string(&mut out, (WIDTH, HEIGHT)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let (x0, x1) = bounds(points.xy.iter().map(|p| &p.0));
        let (y0, y1) = bounds(points.xy.iter().map(|p| &p.1));
        let drawn = thin(points, (x0, x1), (y0, y1));
        markers = drawn.iter().map(Vec::len).sum();
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 18))
            .margin(14)
            .x_label_area_size(46)
            .y_label_area_size(84)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc(&points.x_label)
            .y_desc(&points.y_label)
            .x_label_formatter(&|v: &f64| tick(*v))
            .y_label_formatter(&|v: &f64| tick(*v))
            .label_style(("sans-serif", 15))
            .axis_desc_style(("sans-serif", 16))
            .light_line_style(WHITE.mix(0.0))
            .bold_line_style(BLACK.mix(0.08))
            .draw()
            .map_err(err)?;
        for (k, name) in points.names.iter().enumerate() {
            let color = PALETTE[k % PALETTE.len()];
            let count = points.section.iter().filter(|&&s| s == k).count();
            chart
                .draw_series(drawn[k].iter().map(|p| Circle::new(*p, 2, color.filled())))
                .map_err(err)?
                .label(format!("{name} ({count} points)"))
                // A square, so that the figure's circles are its points.
                .legend(move |(x, y)| Rectangle::new([(x, y - 4), (x + 8, y + 4)], color.filled()));
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.4))
            .label_font(("sans-serif", 15))
            .draw()
            .map_err(err)?;
        root.present().map_err(err)?;
    }
    Ok((out, markers))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_keep_quoted_commas_quotes_and_line_breaks() {
        let text = "a,b\n\"x,\"\"y\"\"\nz\",2\r\nw,3\n";
        let got: Vec<(usize, Vec<String>)> = Records::new(text, 1).collect();
        assert_eq!(
            got,
            vec![
                (1, vec!["a".into(), "b".into()]),
                (2, vec!["x,\"y\"\nz".into(), "2".into()]),
                (4, vec!["w".into(), "3".into()]),
            ]
        );
    }
}
