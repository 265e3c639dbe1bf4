//! Log–log work–precision plots as SVG text (plotters, SVG backend only; text sizes are
//! estimated, so no font files are read).

use plotters::prelude::*;

/// One method's points (x, error), in grid order.
pub struct Series {
    pub name: &'static str,
    pub points: Vec<(f64, f64)>,
}

/// Errors below this are drawn at it (an exact zero has no place on a log axis).
const FLOOR: f64 = 1e-17;

const COLORS: [RGBColor; 3] = [
    RGBColor(0x1f, 0x77, 0xb4),
    RGBColor(0xff, 0x7f, 0x0e),
    RGBColor(0x2c, 0xa0, 0x2c),
];
const PAPER: RGBColor = RGBColor(0xd6, 0x27, 0x28);

/// The bounds of a log axis holding `values` (positive, finite), padded by a factor 2
/// and widened to whole decades.
fn log_bounds(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::MAX, f64::MIN_POSITIVE), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return (1e-3, 1.0);
    }
    let lo = 10f64.powf((lo / 2.0).log10().floor());
    let hi = 10f64.powf((hi * 2.0).log10().ceil());
    (lo, hi.max(lo * 10.0))
}

fn decade_label(v: f64) -> String {
    let e = v.log10().round() + 0.0; // + 0.0: no "1e-0"
    if (v / 10f64.powf(e) - 1.0).abs() < 1e-9 {
        format!("1e{e}")
    } else {
        String::new()
    }
}

/// An SVG of error against `x_desc` for each series, the paper's point (RK4, h = 1e-4 s)
/// circled, and dashed lines at the `targets`.
pub fn svg(
    title: &str,
    x_desc: &str,
    series: &[Series],
    paper: Option<(f64, f64)>,
    targets: &[f64],
) -> Result<String, String> {
    let clamp = |(x, e): (f64, f64)| (x, e.max(FLOOR));
    let (x0, x1) = log_bounds(series.iter().flat_map(|s| s.points.iter().map(|p| p.0)));
    let (y0, y1) = log_bounds(
        series
            .iter()
            .flat_map(|s| s.points.iter().map(|p| clamp(*p).1))
            .chain(targets.iter().copied()),
    );
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (860, 600)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 18))
            .margin(16)
            .x_label_area_size(48)
            .y_label_area_size(64)
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_desc(x_desc)
            .y_desc("error")
            .x_label_formatter(&|v| decade_label(*v))
            .y_label_formatter(&|v| decade_label(*v))
            .light_line_style(WHITE.mix(0.0))
            .draw()
            .map_err(|e| e.to_string())?;
        for &t in targets.iter().filter(|t| **t >= y0 && **t <= y1) {
            chart
                .draw_series(DashedLineSeries::new(
                    [(x0, t), (x1, t)],
                    4,
                    4,
                    BLACK.mix(0.35).stroke_width(1),
                ))
                .map_err(|e| e.to_string())?;
        }
        for (s, color) in series.iter().zip(COLORS) {
            let pts: Vec<(f64, f64)> = s.points.iter().copied().map(clamp).collect();
            chart
                .draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))
                .map_err(|e| e.to_string())?
                .label(s.name)
                .legend(move |(x, y)| {
                    PathElement::new([(x, y), (x + 20, y)], color.stroke_width(2))
                });
            chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled())))
                .map_err(|e| e.to_string())?;
        }
        if let Some(p) = paper {
            let p = clamp(p);
            chart
                .draw_series([Circle::new(p, 9, PAPER.stroke_width(2))])
                .map_err(|e| e.to_string())?
                .label("paper: RK4, h = 1e-4 s")
                .legend(|(x, y)| Circle::new((x + 10, y), 6, PAPER.stroke_width(2)));
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.5))
            .draw()
            .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_svg_with_every_series_the_paper_point_and_decade_labels() {
        let series = [
            Series {
                name: "rk4",
                points: vec![(1e-3, 1e-2), (1e-2, 1e-6)],
            },
            Series {
                name: "dopri5",
                points: vec![(1e-4, 1e-3), (1e-3, 1e-9)],
            },
            Series {
                name: "dop853",
                points: vec![(1e-4, 1e-5), (2e-4, 0.0)],
            },
        ];
        let svg = svg(
            "t",
            "wall time (s)",
            &series,
            Some((1e-3, 1e-2)),
            &[1e-3, 1e-6],
        )
        .unwrap();
        assert!(svg.starts_with("<svg"), "{}", &svg[..40]);
        for text in [
            "rk4",
            "dopri5",
            "dop853",
            "paper: RK4, h = 1e-4 s",
            "wall time (s)",
        ] {
            assert!(svg.contains(text), "missing {text}");
        }
        let decades = svg.lines().filter(|l| l.starts_with("1e")).count();
        assert!(decades >= 6, "{decades} decade labels");
        assert_eq!(decade_label(1.0), "1e0");
        assert_eq!(decade_label(1e-3), "1e-3");
        assert_eq!(decade_label(2e-3), "");
    }

    #[test]
    fn log_bounds_are_whole_decades_around_the_data() {
        let (lo, hi) = log_bounds([3e-5, 2e-2].into_iter());
        assert!(
            (lo / 1e-5 - 1.0).abs() < 1e-12 && (hi / 1e-1 - 1.0).abs() < 1e-12,
            "{lo} {hi}"
        );
        assert_eq!(log_bounds(std::iter::empty()), (1e-3, 1.0));
    }
}
