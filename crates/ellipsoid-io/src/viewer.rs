//! The 3-D viewer: one self-contained HTML page (no network: three.js r170 and its MIT
//! licence are inlined from `assets/three/`, the trajectory is embedded) showing the
//! body as it is — its semi-axes, meridians and an equatorial band that make the spin
//! visible, the symmetry axis and G, its contact spheres (a tippe top's stem, a top's
//! peg) and rims (a coin's edge, drawn as its torus; a sharp edge with a thin tube), each
//! surface marked while it touches the plane — on the plane with the trace of
//! the contact point; play/pause, speed, a time slider, events, and θ(t) and energy plots
//! (and, for a body with contact spheres, the normal force of each surface) whose cursor
//! follows the 3-D view. Shared by `ellipsoid view` and Python's `Trajectory.view()`.
//!
//! Decimation: at most [`MAX_FRAMES`] poses, spread evenly in time, plus the samples on
//! both sides of every event and mode change (the page interpolates between poses); the
//! plots get the min/max envelope of every sample in [`PLOT_BUCKETS`] buckets, so no peak
//! is lost. A 10⁶-sample run makes a page of about 2 MB.

use crate::table::{self, ELLIPSOID, Table};

/// Most poses embedded in a page (plus the samples kept around events).
pub const MAX_FRAMES: usize = 20_000;
/// Buckets of the plots' min/max envelope (two points each).
pub const PLOT_BUCKETS: usize = 1_500;

const THREE: &str = include_str!("../assets/three/three.module.min.js");
const THREE_LICENSE: &str = include_str!("../assets/three/LICENSE");
const TEMPLATE: &str = include_str!("../assets/viewer.html");
const SCRIPT: &str = include_str!("../assets/viewer.js");

/// Indices of the rows shown as poses: all of them if there are at most `max`; else `max`
/// evenly spaced in time, plus the rows on both sides of each event time and mode change.
pub fn frame_indices(table: &Table, max: usize) -> Vec<usize> {
    let t = table.t();
    let n = t.len();
    if n <= max.max(2) {
        return (0..n).collect();
    }
    let (t0, t1) = (t[0], t[n - 1]);
    let mut keep: Vec<usize> = Vec::with_capacity(max + 16);
    for k in 0..max {
        let target = t0 + (t1 - t0) * k as f64 / (max - 1) as f64;
        keep.push(t.partition_point(|v| *v < target).min(n - 1));
    }
    let mut around = |i: usize| {
        keep.push(i.saturating_sub(1));
        keep.push(i.min(n - 1));
    };
    for e in &table.events {
        around(t.partition_point(|v| *v < e.t));
    }
    if let Some(m) = &table.modes {
        let mut extra = 0;
        for i in 1..m.len() {
            if m[i] != m[i - 1] && extra < max {
                around(i);
                extra += 1;
            }
        }
    }
    keep.push(n - 1);
    keep.sort_unstable();
    keep.dedup();
    keep
}

/// The min/max envelope of `v` against `t`: for each of `buckets` runs of consecutive
/// rows, its smallest and largest value in time order (all rows if there are few).
pub fn envelope(t: &[f64], v: &[f64], buckets: usize) -> (Vec<f64>, Vec<f64>) {
    let n = t.len().min(v.len());
    if n <= 2 * buckets {
        return (t[..n].to_vec(), v[..n].to_vec());
    }
    let (mut ts, mut vs) = (
        Vec::with_capacity(2 * buckets),
        Vec::with_capacity(2 * buckets),
    );
    for b in 0..buckets {
        let (lo, hi) = (
            b * n / buckets,
            ((b + 1) * n / buckets).max(b * n / buckets + 1),
        );
        let (mut imin, mut imax) = (lo, lo);
        for i in lo..hi {
            if v[i] < v[imin] {
                imin = i;
            }
            if v[i] > v[imax] {
                imax = i;
            }
        }
        for i in if imin <= imax {
            [imin, imax]
        } else {
            [imax, imin]
        } {
            ts.push(t[i]);
            vs.push(v[i]);
        }
    }
    (ts, vs)
}

fn b64_f32(values: impl Iterator<Item = f64>) -> String {
    let bytes: Vec<u8> = values.flat_map(|v| (v as f32).to_le_bytes()).collect();
    base64(&bytes)
}

/// Standard base64 with padding.
fn base64(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for c in bytes.chunks(3) {
        let n = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for k in 0..4 {
            if k <= c.len() {
                out.push(A[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// Escapes text for HTML element content and attribute values.
fn html_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Why a page could not be made.
#[derive(Debug, thiserror::Error)]
pub enum ViewError {
    /// A column the viewer needs is absent.
    #[error("{0}")]
    Missing(String),
}

/// The columns every page draws (with `mode`): the body's frames and the contact path.
/// A caller reads these and the side plots' alone ([`columns`],
/// [`crate::table::read_columns`]).
pub const COLUMNS: [&str; 9] = [
    "t",
    "x",
    "y",
    "z",
    "theta",
    "phi",
    "psi",
    "contact_x",
    "contact_y",
];

/// The columns the page with side plots `plots` draws from: [`COLUMNS`], the plots' own,
/// `work` for the energy's E + W, and every surface's gap (which surfaces touch, where the
/// mode does not say).
pub fn columns<'a>(plots: &[&'a str]) -> Vec<&'a str> {
    let mut cols: Vec<&str> = COLUMNS.to_vec();
    cols.extend_from_slice(plots);
    if plots.contains(&"energy") {
        cols.push("work");
    }
    cols.push("gap_*");
    cols
}

/// The side plots a page shows unless asked otherwise: θ(t) and the energy.
pub const DEFAULT_PLOTS: [&str; 2] = ["theta", "energy"];

/// The side plot of every surface's normal force, one line each.
pub const SURFACE_FORCES: &str = "normal_force_*";

/// The side plots of a page of `table` unless asked otherwise: [`DEFAULT_PLOTS`], and for
/// a body with contact spheres the normal force of each surface ([`SURFACE_FORCES`]).
pub fn default_plots(table: &Table) -> Vec<String> {
    let mut plots: Vec<String> = DEFAULT_PLOTS.map(String::from).to_vec();
    if !table.per_surface("normal_force").is_empty() {
        plots.push(SURFACE_FORCES.into());
    }
    plots
}

/// Checks the side plots asked for, comma-separated: numeric output columns other than `t`
/// (`energy` gets E + W too), a body's per-surface columns (`normal_force_stem`), or
/// `QUANTITY_*`, that quantity of every surface in one plot (`normal_force_*`); no
/// repeats, at most six. The error is the rule broken (the caller names its flag or
/// argument). Whether the run has a per-surface column is known once it is read
/// ([`html`] leaves out a column the run lacks).
pub fn parse_plots(spec: &str) -> Result<Vec<String>, String> {
    let names: Vec<&str> = crate::columns::NUMERIC_COLUMNS[1..]
        .iter()
        .map(|c| c.0)
        .collect();
    let mut out: Vec<String> = Vec::new();
    for name in spec.split(',').map(str::trim) {
        let every_surface = name
            .strip_suffix("_*")
            .is_some_and(|q| crate::columns::SURFACE_COLUMNS.iter().any(|c| c.0 == q));
        if !names.contains(&name) && !every_surface && table::surface_column(name).is_none() {
            let quantities: Vec<&str> = crate::columns::SURFACE_COLUMNS
                .iter()
                .map(|c| c.0)
                .collect();
            return Err(format!(
                "{name:?} is not a numeric output column; the columns are {}, and for a body with contact spheres {}_S of each surface S (or QUANTITY_* for all of them)",
                names.join(", "),
                quantities.join("_S, ")
            ));
        }
        if out.iter().any(|o| o == name) {
            return Err(format!("{name:?} is named twice"));
        }
        out.push(name.to_owned());
    }
    if out.len() > 6 {
        return Err(format!("{} columns asked for; at most 6", out.len()));
    }
    Ok(out)
}

/// Checks that the run in `table` has the per-surface columns among `plots` (which
/// [`parse_plots`] can only check by their form): the error names the first one missing
/// and the surfaces the run has.
pub fn check_plots(table: &Table, plots: &[&str]) -> Result<(), String> {
    for name in plots {
        let quantity = match name.strip_suffix("_*") {
            Some(q) => q,
            None if table::surface_column(name).is_some() && table.column(name).is_none() => "",
            None => continue,
        };
        if quantity.is_empty() || table.per_surface(quantity).is_empty() {
            let surfaces = table.surfaces();
            let has = if surfaces.is_empty() {
                "no per-surface columns (its body has no contact spheres)".to_owned()
            } else {
                format!("the per-surface columns of {}", surfaces.join(", "))
            };
            return Err(format!("{name:?}: {} has {has}", table.source));
        }
    }
    Ok(())
}

/// The energy's side plot: E, and E + W when work is dissipated; a conserving scene's
/// relative deviation (E − E(0)) / |E(0)| when E is constant to display precision, which
/// shows the drift instead of a flat line with identical tick labels.
fn energy_plot(table: &Table, e: &[f64]) -> serde_json::Value {
    let t = table.t();
    let work = table.column("work").filter(|w| w.iter().any(|v| *v != 0.0));
    let (lo, hi) = e
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(*v), hi.max(*v))
        });
    let scale = e[0].abs().max(f64::MIN_POSITIVE);
    let relative: Option<Vec<f64>> = (work.is_none() && hi - lo <= 1e-6 * scale)
        .then(|| e.iter().map(|v| (v - e[0]) / scale).collect());
    let shown = relative.as_deref().unwrap_or(e);
    let label = if relative.is_some() {
        "energy: (E − E(0)) / |E(0)| (1)"
    } else {
        "energy E (J)"
    };
    let mut energy = plot_series("energy", label, t, shown);
    if let Some(w) = work {
        let ew: Vec<f64> = e.iter().zip(w).map(|(e, w)| e + w).collect();
        let (ts, vs) = envelope(t, &ew, PLOT_BUCKETS);
        energy["t2"] = b64_f32(ts.iter().copied()).into();
        energy["v2"] = b64_f32(vs.into_iter()).into();
        energy["n2"] = ts.len().into();
        energy["label"] = "energy E, E + W (J)".into();
    }
    energy
}

/// One side plot: `v` against `t` as its min/max envelope, named and labelled.
fn plot_series(name: &str, label: &str, t: &[f64], v: &[f64]) -> serde_json::Value {
    with_line(serde_json::json!({ "name": name, "label": label }), t, v)
}

/// `head` (a JSON object) with the line `v` against `t` as its min/max envelope: `n`
/// points, `t` and `v` as base64 float32.
fn with_line(mut head: serde_json::Value, t: &[f64], v: &[f64]) -> serde_json::Value {
    let (ts, vs) = envelope(t, v, PLOT_BUCKETS);
    head["n"] = ts.len().into();
    head["t"] = b64_f32(ts.into_iter()).into();
    head["v"] = b64_f32(vs.into_iter()).into();
    head
}

/// The side plot `QUANTITY_*`: that quantity of every surface, one line each named by its
/// surface (`lines`, in file order); `None` when the run has no such columns.
fn surfaces_plot(table: &Table, name: &str, quantity: &str) -> Option<serde_json::Value> {
    let columns = table.per_surface(quantity);
    if columns.is_empty() {
        return None;
    }
    let lines: Vec<serde_json::Value> = columns
        .iter()
        .map(|(surface, v)| with_line(serde_json::json!({ "label": surface }), table.t(), v))
        .collect();
    let unit = table::unit(&format!("{quantity}_{ELLIPSOID}")).unwrap_or("1");
    let label = format!("{quantity} of each surface ({unit})");
    Some(serde_json::json!({ "name": name, "label": label, "lines": lines }))
}

/// The body's contact spheres and rims, whether its ellipsoid touches, and per pose which
/// surfaces touch the plane (bit k of `touch[i]` for surface k of `names`, in the body's
/// order: the ellipsoid unless it does not touch, the spheres, the rims), for the page's
/// data; `None` for a one-surface body (its page is as it always was).
fn surfaces_data(table: &Table, idx: &[usize]) -> Option<serde_json::Value> {
    let shape = table.shape.as_ref().filter(|s| s.several())?;
    let names = shape.surface_names();
    let touch = b64_f32(idx.iter().map(|&i| f64::from(table.in_contact(i, &names))));
    let spheres: Vec<serde_json::Value> = shape
        .spheres
        .iter()
        .map(|s| serde_json::json!({ "name": s.name, "center": s.center, "radius": s.radius }))
        .collect();
    let rims: Vec<serde_json::Value> = shape
        .rims
        .iter()
        .map(|r| {
            serde_json::json!({ "name": r.name, "center": r.center, "radius": r.radius, "edge": r.edge })
        })
        .collect();
    Some(serde_json::json!({
        "names": names,
        "ellipsoid": shape.ellipsoid_contact,
        "spheres": spheres,
        "rims": rims,
        "touch": touch,
    }))
}

/// The viewer page for `table`, titled `title`, with a side plot against time of each of
/// `plots` (output columns, e.g. [`DEFAULT_PLOTS`] or [`default_plots`]; `energy` with
/// E + W, or its relative deviation when conserved; `QUANTITY_*` that quantity of every
/// surface, one line each; a column the table lacks is left out). A body with contact
/// spheres carries them and, per pose, which surfaces touch the plane
/// ([`Table::in_contact`]); a one-surface body's data is as it always was.
pub fn html(table: &Table, title: &str, plots: &[&str]) -> Result<String, ViewError> {
    let need = ["t", "x", "y", "z", "theta", "phi", "psi"];
    let cols = table
        .require(&need, "the viewer")
        .map_err(ViewError::Missing)?;
    let idx = frame_indices(table, MAX_FRAMES);
    let pick = |c: &[f64]| b64_f32(idx.iter().map(|&i| c[i]));
    let mut frames = serde_json::Map::new();
    frames.insert("n".into(), idx.len().into());
    for (name, c) in need.iter().zip(&cols) {
        frames.insert((*name).into(), pick(c).into());
    }
    let contact = table.contact_path();
    if let Some((cx, cy)) = &contact {
        frames.insert("cx".into(), pick(cx).into());
        frames.insert("cy".into(), pick(cy).into());
    }
    if let Some(m) = &table.modes {
        frames.insert(
            "mode".into(),
            b64_f32(idx.iter().map(|&i| f64::from(m[i]))).into(),
        );
    }
    let t = table.t();
    let plots: Vec<serde_json::Value> = plots
        .iter()
        .filter_map(|name| {
            if let Some(quantity) = name.strip_suffix("_*") {
                return surfaces_plot(table, name, quantity);
            }
            let v = table.column(name)?;
            Some(match *name {
                "energy" => energy_plot(table, v),
                "theta" => plot_series(name, "θ (rad)", t, v),
                _ => plot_series(
                    name,
                    &format!("{name} ({})", table::unit(name).unwrap_or("1")),
                    t,
                    v,
                ),
            })
        })
        .collect();
    let shape = table
        .shape
        .as_ref()
        .map(|s| serde_json::json!({ "semi_axes": s.semi_axes, "com_offset": s.com_offset }));
    let mut data = serde_json::json!({
        "title": title,
        "rows": table.rows(),
        "t0": t[0],
        "t1": t[t.len() - 1],
        "status": table.status,
        "shape": shape,
        "shape_note": table.shape_note,
        "contact": contact.is_some(),
        "modes": table.mode_names,
        "events": table.events.iter().map(|e| serde_json::json!({ "t": e.t, "kind": e.kind, "label": e.label })).collect::<Vec<_>>(),
        "frames": frames,
        "plots": plots,
    });
    if let Some(surfaces) = surfaces_data(table, &idx) {
        data["surfaces"] = surfaces;
    }
    // Inside a script element `</script` would end it and `<!--` change how it is parsed;
    // JSON never needs `<` outside strings, and inside them `\u003c` is the same text.
    let data = data.to_string().replace('<', "\\u003c");
    Ok(fill(
        TEMPLATE,
        &[
            ("TITLE", &html_escape(title)),
            ("THREE_LICENSE", THREE_LICENSE),
            ("DATA", &data),
            ("VIEWER", SCRIPT),
            ("THREE", THREE),
        ],
    ))
}

/// The template with each `{{KEY}}` replaced by its value (values are not scanned again).
fn fill(template: &str, values: &[(&str, &str)]) -> String {
    let mut out =
        String::with_capacity(template.len() + values.iter().map(|v| v.1.len()).sum::<usize>());
    let mut rest = template;
    while let Some(start) = rest.find("{{") {
        out.push_str(&rest[..start]);
        let after = &rest[start + 2..];
        match after.find("}}").and_then(|end| {
            values
                .iter()
                .find(|v| v.0 == &after[..end])
                .map(|v| (end, v.1))
        }) {
            Some((end, value)) => {
                out.push_str(value);
                rest = &after[end + 2..];
            }
            None => {
                out.push_str("{{");
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::table::Event;

    fn table(n: usize) -> Table {
        Table::from_rows(
            "mem",
            &["t", "x", "y", "z", "theta", "phi", "psi", "energy"],
            n,
            |i| {
                let t = i as f64 * 1e-3;
                (
                    vec![
                        t,
                        0.0,
                        0.0,
                        0.01,
                        0.1 + (t * 50.0).sin() * 0.05,
                        t,
                        60.0 * t,
                        1.0,
                    ],
                    if i < n / 3 {
                        "sliding".into()
                    } else {
                        "rolling".into()
                    },
                )
            },
        )
    }

    #[test]
    fn frames_are_bounded_and_keep_events_and_mode_changes() {
        let mut t = table(100_000);
        t.events.push(Event {
            t: 12.3456,
            kind: "slip_stop".into(),
            label: "slip stop".into(),
        });
        let idx = frame_indices(&t, 1000);
        assert!(idx.len() <= 1000 + 8 && idx.len() >= 990, "{}", idx.len());
        assert!(idx.windows(2).all(|w| w[0] < w[1]));
        assert_eq!((idx[0], *idx.last().unwrap()), (0, 99_999));
        let ts = t.t();
        assert!(
            idx.iter().any(|&i| ts[i] < 12.3456 && ts[i + 1] >= 12.3456),
            "the sample before the event is kept"
        );
        assert!(
            idx.contains(&(100_000 / 3)) && idx.contains(&(100_000 / 3 - 1)),
            "both sides of the mode change"
        );
        assert_eq!(frame_indices(&table(50), 1000).len(), 50);
    }

    #[test]
    fn the_envelope_keeps_every_extreme() {
        let t: Vec<f64> = (0..100_000).map(|i| i as f64).collect();
        let mut v = vec![0.0; 100_000];
        v[77_777] = 5.0;
        v[12_345] = -3.0;
        let (ts, vs) = envelope(&t, &v, 100);
        assert!(ts.len() <= 200 && ts.windows(2).all(|w| w[0] <= w[1]));
        assert!(vs.contains(&5.0) && vs.contains(&-3.0));
    }

    #[test]
    fn base64_matches_the_standard() {
        assert_eq!(base64(b""), "");
        assert_eq!(base64(b"f"), "Zg==");
        assert_eq!(base64(b"fo"), "Zm8=");
        assert_eq!(base64(b"foo"), "Zm9v");
        assert_eq!(base64(b"foobar"), "Zm9vYmFy");
    }

    #[test]
    fn the_page_is_self_contained_and_escaped() {
        let page = html(&table(10), "a </script><b> & c <!--", &DEFAULT_PLOTS).unwrap();
        assert!(!page.contains("c <!--"), "no comment opener in the data");
        assert!(page.contains("a &lt;/script&gt;&lt;b&gt; &amp; c"));
        assert_eq!(
            page.matches("</script>").count(),
            page.matches("<script").count(),
            "every script closed once"
        );
        assert!(
            page.contains("Copyright © 2010-2024 three.js authors"),
            "licence inlined"
        );
        for remote in ["http://", "https://", "//cdn", "src=\""] {
            assert!(
                !page.contains(&format!("<script {remote}"))
                    && !page.contains(&format!("<link href=\"{remote}")),
                "{remote}"
            );
        }
        for key in [
            "{{TITLE}}",
            "{{DATA}}",
            "{{VIEWER}}",
            "{{THREE}}",
            "{{THREE_LICENSE}}",
        ] {
            assert!(!page.contains(key), "{key} filled");
        }
        assert!(
            html(&table(10), "{{DATA}}", &DEFAULT_PLOTS)
                .unwrap()
                .contains("<title>{{DATA}}"),
            "values are not filled again"
        );
        let mut t = table(10);
        t.columns.retain(|c| c.0 != "psi");
        assert!(
            html(&t, "x", &DEFAULT_PLOTS)
                .unwrap_err()
                .to_string()
                .contains("`psi`")
        );
    }

    /// The page's embedded data: its side plots' names and labels, in order.
    fn plot_labels(page: &str) -> Vec<(String, String)> {
        let start = page
            .find("<script type=\"application/json\" id=\"data\">")
            .unwrap();
        let json = &page[start..];
        let json = &json[json.find('>').unwrap() + 1..json.find("</script>").unwrap()];
        let data: serde_json::Value = serde_json::from_str(json).unwrap();
        data["plots"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| {
                (
                    p["name"].as_str().unwrap().to_owned(),
                    p["label"].as_str().unwrap().to_owned(),
                )
            })
            .collect()
    }

    #[test]
    fn the_side_plots_are_the_columns_asked_for() {
        let t = table(10);
        let labels = |plots: &[&str]| plot_labels(&html(&t, "x", plots).unwrap());
        assert_eq!(
            labels(&DEFAULT_PLOTS),
            [
                ("theta".into(), "θ (rad)".into()),
                ("energy".into(), "energy: (E − E(0)) / |E(0)| (1)".into())
            ]
        );
        assert_eq!(
            labels(&["z", "theta"]),
            [
                ("z".into(), "z (m)".into()),
                ("theta".into(), "θ (rad)".into())
            ]
        );
        // A column the run lacks is left out, not an error.
        assert_eq!(labels(&["omega_world_z", "z"]).len(), 1);
        assert_eq!(
            parse_plots("omega_world_z, theta").unwrap(),
            ["omega_world_z", "theta"]
        );
        for (spec, rule) in [
            ("thetaa", "\"thetaa\" is not a numeric output column"),
            ("t", "\"t\" is not a numeric output column"),
            ("z,z", "\"z\" is named twice"),
            (
                "x,y,z,theta,phi,psi,energy",
                "7 columns asked for; at most 6",
            ),
        ] {
            let err = parse_plots(spec).unwrap_err();
            assert!(err.starts_with(rule), "{err}");
        }
    }

    /// The page's embedded data.
    fn data(page: &str) -> serde_json::Value {
        let start = page
            .find("<script type=\"application/json\" id=\"data\">")
            .unwrap();
        let json = &page[start..];
        let json = &json[json.find('>').unwrap() + 1..json.find("</script>").unwrap()];
        serde_json::from_str(json).unwrap()
    }

    /// [`table`] as a body with a contact sphere `stem` writes it: the stem takes the load
    /// at row 4 (mode `two_contacts@ellipsoid+stem`) and alone from row 6 on.
    fn with_stem() -> Table {
        let mut t = table(10);
        let stem: Vec<f64> = (0..10).map(|i| if i < 4 { 0.0 } else { 0.05 }).collect();
        let ball: Vec<f64> = (0..10).map(|i| if i < 6 { 0.05 } else { 0.0 }).collect();
        t.columns.push(("normal_force_ellipsoid".into(), ball));
        t.columns.push(("normal_force_stem".into(), stem));
        t.mode_names = vec![
            "sliding@ellipsoid".into(),
            "two_contacts@ellipsoid+stem".into(),
            "sliding@stem".into(),
        ];
        t.modes = Some(
            (0..10)
                .map(|i| u8::from(i >= 4) + u8::from(i >= 6))
                .collect(),
        );
        t.shape = Some(crate::table::Shape {
            semi_axes: [0.015; 3],
            com_offset: [0.0, 0.0, -0.003],
            spheres: vec![crate::table::SphereShape {
                name: "stem".into(),
                center: [0.0, 0.0, 0.013],
                radius: 0.005,
            }],
            rims: Vec::new(),
            ellipsoid_contact: true,
        });
        t
    }

    /// A coin (its ellipsoid does not touch) with two rims, the lower touching alone up to
    /// row 5 and both from row 5 on: the page names the rims only, carries them, and bit
    /// k of each pose is rim k (not the ellipsoid's bit 0 of a body whose ellipsoid
    /// touches).
    #[test]
    fn a_body_with_rims_carries_them_and_its_ellipsoid_takes_no_bit() {
        let mut t = table(10);
        t.mode_names = vec!["rolling@bottom".into(), "two_contacts@bottom+top".into()];
        t.modes = Some((0..10).map(|i| u8::from(i >= 5)).collect());
        let rim = |name: &str, z: f64| crate::table::RimShape {
            name: name.into(),
            center: [0.0, 0.0, z],
            radius: 0.03,
            edge: 0.001,
        };
        t.shape = Some(crate::table::Shape {
            semi_axes: [0.031, 0.031, 0.005],
            com_offset: [0.0; 3],
            spheres: Vec::new(),
            rims: vec![rim("bottom", -0.004), rim("top", 0.004)],
            ellipsoid_contact: false,
        });
        let d = data(&html(&t, "x", &DEFAULT_PLOTS).unwrap());
        let s = &d["surfaces"];
        assert_eq!(s["names"], serde_json::json!(["bottom", "top"]));
        assert_eq!(s["ellipsoid"], serde_json::json!(false));
        assert_eq!(
            s["rims"][1],
            serde_json::json!({"name": "top", "center": [0.0, 0.0, 0.004], "radius": 0.03, "edge": 0.001})
        );
        let touch: Vec<f32> = base64_decode(s["touch"].as_str().unwrap())
            .chunks(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect();
        assert_eq!(touch, [1., 1., 1., 1., 1., 3., 3., 3., 3., 3.]);
    }

    /// A body with contact spheres: the page carries them and which surfaces touch per
    /// pose, and by default the normal force of each surface, one line per surface; a
    /// one-surface body's page carries none of it.
    #[test]
    fn a_body_with_spheres_carries_them_and_each_surface_s_normal_force() {
        let t = with_stem();
        let plots = default_plots(&t);
        assert_eq!(plots, ["theta", "energy", "normal_force_*"]);
        let plots: Vec<&str> = plots.iter().map(String::as_str).collect();
        let d = data(&html(&t, "x", &plots).unwrap());
        let s = &d["surfaces"];
        assert_eq!(s["names"], serde_json::json!(["ellipsoid", "stem"]));
        assert_eq!(
            s["spheres"],
            serde_json::json!([{"name": "stem", "center": [0.0, 0.0, 0.013], "radius": 0.005}])
        );
        let touch: Vec<f32> = base64_decode(s["touch"].as_str().unwrap())
            .chunks(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect();
        assert_eq!(touch, [1., 1., 1., 1., 3., 3., 2., 2., 2., 2.]);
        let forces = &d["plots"][2];
        assert_eq!(forces["label"], "normal_force of each surface (N)");
        let lines: Vec<&str> = forces["lines"]
            .as_array()
            .unwrap()
            .iter()
            .map(|l| l["label"].as_str().unwrap())
            .collect();
        assert_eq!(lines, ["ellipsoid", "stem"]);
        // A per-surface column alone, with its unit.
        let d = data(&html(&t, "x", &["normal_force_stem"]).unwrap());
        assert_eq!(d["plots"][0]["label"], "normal_force_stem (N)");
        // One surface: the page as it always was.
        let one = table(10);
        assert_eq!(default_plots(&one), DEFAULT_PLOTS);
        let d = data(&html(&one, "x", &DEFAULT_PLOTS).unwrap());
        assert!(d.get("surfaces").is_none());
        assert_eq!(
            d.as_object().unwrap().keys().collect::<Vec<_>>(),
            [
                "title",
                "rows",
                "t0",
                "t1",
                "status",
                "shape",
                "shape_note",
                "contact",
                "modes",
                "events",
                "frames",
                "plots"
            ]
        );
    }

    #[test]
    fn per_surface_plots_are_parsed_by_form_and_checked_against_the_run() {
        assert_eq!(
            parse_plots("theta, normal_force_stem, gap_*").unwrap(),
            ["theta", "normal_force_stem", "gap_*"]
        );
        for (spec, rule) in [
            ("wobble_*", "\"wobble_*\" is not a numeric output column"),
            (
                "normal_force_a-b",
                "\"normal_force_a-b\" is not a numeric output column",
            ),
            ("gap_*,gap_*", "\"gap_*\" is named twice"),
        ] {
            let err = parse_plots(spec).unwrap_err();
            assert!(err.starts_with(rule), "{err}");
        }
        let t = with_stem();
        assert!(check_plots(&t, &["theta", "normal_force_stem", "normal_force_*"]).is_ok());
        let err = check_plots(&t, &["normal_force_stme"]).unwrap_err();
        assert!(
            err.contains(
                "\"normal_force_stme\": mem has the per-surface columns of ellipsoid, stem"
            ),
            "{err}"
        );
        let err = check_plots(&table(10), &["gap_*"]).unwrap_err();
        assert!(err.contains("has no per-surface columns"), "{err}");
    }

    /// Decodes standard base64 (the inverse of [`base64`], for the tests).
    fn base64_decode(s: &str) -> Vec<u8> {
        const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        let six: Vec<u32> = s
            .bytes()
            .filter(|c| *c != b'=')
            .map(|c| A.iter().position(|a| *a == c).unwrap() as u32)
            .collect();
        let mut out = Vec::new();
        for q in six.chunks(4) {
            let n = q
                .iter()
                .enumerate()
                .fold(0, |n, (k, v)| n | v << (18 - 6 * k));
            out.extend(&n.to_be_bytes()[1..q.len()]);
        }
        out
    }

    #[test]
    fn the_vendored_library_cannot_end_its_script_element() {
        for text in [THREE, SCRIPT, THREE_LICENSE] {
            let lower = text.to_ascii_lowercase();
            assert!(!lower.contains("</script") && !lower.contains("<!--"));
        }
    }
}
