//! The panels of a trajectory's figure, declared once (`assets/panels.json`) for both
//! renderers: `ellipsoid plot` (plotters) and `Trajectory.plot` (matplotlib, which reads
//! the same text through the Python extension). A panel is a row of one or two axes; each
//! axis has its title, labels with units, series and whether the contact mode is shaded.

use std::sync::OnceLock;

use serde::Deserialize;

/// The declaration's text, as embedded in the command-line tool and the Python extension.
pub const JSON: &str = include_str!("../assets/panels.json");

/// The whole declaration.
#[derive(Debug, Deserialize)]
pub struct Declaration {
    /// Label of every time axis.
    pub time_label: String,
    pub events: Events,
    /// Shading per contact mode, in legend order.
    pub modes: Vec<ModeShade>,
    /// Appended to a shaded axis's title; `{modes}` is "sliding orange, rolling green".
    pub shaded_suffix: String,
    /// Below this |sin θ| the series marked `euler` are not drawn (z-x-z singularity).
    pub euler_min_sin_theta: f64,
    /// Appended to the title when such samples were left out.
    pub euler_singular_suffix: String,
    /// Colour of a panel of one output column (`--columns`).
    pub column_color: String,
    /// Colours of the lines of a per-surface series (`QUANTITY_*`), surface by surface.
    pub surface_colors: Vec<String>,
    pub panels: Vec<Panel>,
}

/// How events are drawn (dashed vertical lines).
#[derive(Debug, Deserialize)]
pub struct Events {
    pub color: String,
    pub label: String,
}

/// The fill behind samples of one contact mode, and its colour's name for the title.
#[derive(Debug, Deserialize)]
pub struct ModeShade {
    pub mode: String,
    pub fill: String,
    pub name: String,
}

/// One row of the figure.
#[derive(Debug, Deserialize)]
pub struct Panel {
    pub name: String,
    /// Columns the panel needs (checked before drawing).
    pub needs: Vec<String>,
    /// One or two axes, left to right.
    pub axes: Vec<Axis>,
    /// It draws per-surface columns: drawn by default only for a trajectory that has them.
    #[serde(default)]
    pub per_surface: bool,
}

/// One axes of a panel.
#[derive(Debug, Deserialize)]
pub struct Axis {
    /// `{conserved}` is E, or E + W when work is dissipated.
    pub title: String,
    /// The horizontal axis's label; `None` for time.
    #[serde(default)]
    pub xlabel: Option<String>,
    pub ylabel: String,
    #[serde(default)]
    pub log: bool,
    #[serde(default)]
    pub shade: bool,
    /// The path panel's: appended to the title when the contact point's path is unknown;
    /// `{note}` says why.
    #[serde(default)]
    pub unknown_contact_suffix: String,
    pub series: Vec<Series>,
}

/// One curve: a column, or a derived quantity named in `data`.
#[derive(Debug, Deserialize)]
pub struct Series {
    pub data: String,
    pub label: String,
    pub color: String,
    /// Drawn only where |sin θ| ≥ `euler_min_sin_theta`.
    #[serde(default)]
    pub euler: bool,
    /// Left out when the trajectory lacks it (no error).
    #[serde(default)]
    pub optional: bool,
    /// Appended to the axis's title when the series is drawn.
    #[serde(default)]
    pub title_suffix: String,
}

/// The parsed declaration (parsed once; a test checks that it parses).
pub fn declaration() -> &'static Declaration {
    static DECL: OnceLock<Declaration> = OnceLock::new();
    DECL.get_or_init(|| serde_json::from_str(JSON).expect("assets/panels.json is valid"))
}

impl Declaration {
    /// The panel of this name.
    pub fn panel(&self, name: &str) -> Option<&Panel> {
        self.panels.iter().find(|p| p.name == name)
    }

    /// Panel names, in drawing order.
    pub fn names(&self) -> Vec<&str> {
        self.panels.iter().map(|p| p.name.as_str()).collect()
    }

    /// The shading of `mode`, by its contact phase (the label before `@`: `sliding@stem`
    /// is shaded as sliding; the last entry for a phase not listed).
    pub fn shade(&self, mode: &str) -> &ModeShade {
        let phase = phase(mode);
        self.modes
            .iter()
            .find(|m| m.mode == phase)
            .unwrap_or_else(|| self.modes.last().expect("modes declared"))
    }

    /// The suffix of a shaded axis's title for the modes present, e.g.
    /// " (shaded: sliding orange, rolling green)", each contact phase once; empty without
    /// modes.
    pub fn shaded_title(&self, modes: &[&str]) -> String {
        let mut phases: Vec<&str> = Vec::new();
        for m in modes.iter().map(|m| phase(m)) {
            if !phases.contains(&m) {
                phases.push(m);
            }
        }
        if phases.is_empty() {
            return String::new();
        }
        let names: Vec<String> = phases
            .iter()
            .map(|m| format!("{m} {}", self.shade(m).name))
            .collect();
        self.shaded_suffix.replace("{modes}", &names.join(", "))
    }
}

/// The contact phase of a mode label: the label before `@` (`two_contacts@ellipsoid+stem`
/// → `two_contacts`), the label itself without one.
pub fn phase(mode: &str) -> &str {
    mode.split_once('@').map_or(mode, |p| p.0)
}

/// `#rrggbb` as (r, g, b).
pub fn rgb(hex: &str) -> (u8, u8, u8) {
    let v = u32::from_str_radix(hex.trim_start_matches('#'), 16).unwrap_or(0);
    ((v >> 16) as u8, (v >> 8) as u8, v as u8)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_declaration_parses_and_names_real_columns() {
        let d = declaration();
        assert_eq!(
            d.names(),
            ["theta", "rates", "energy", "forces", "surfaces", "path"]
        );
        let columns: Vec<&str> = crate::columns::NUMERIC_COLUMNS
            .iter()
            .map(|c| c.0)
            .collect();
        let derived = [
            "energy_plus_work",
            "drift",
            "G",
            "contact",
            "centre",
            "start",
        ];
        // `QUANTITY_*`: a per-surface quantity.
        let known = |c: &str| {
            columns.contains(&c)
                || c.strip_suffix("_*")
                    .is_some_and(|q| crate::columns::SURFACE_COLUMNS.iter().any(|s| s.0 == q))
        };
        for p in &d.panels {
            assert!(p.needs.iter().all(|c| known(c)), "{}", p.name);
            assert!(!p.axes.is_empty() && p.axes.len() <= 2, "{}", p.name);
            for s in p.axes.iter().flat_map(|a| &a.series) {
                assert!(
                    known(&s.data) || derived.contains(&s.data.as_str()),
                    "{}",
                    s.data
                );
                assert_eq!(s.color.len(), 7, "{}", s.color);
            }
        }
        assert_eq!(
            d.shaded_title(&["sliding", "rolling"]),
            " (shaded: sliding orange, rolling green)"
        );
        // A body with contact spheres: shaded by phase, each phase named once.
        assert_eq!(
            d.shaded_title(&[
                "sliding@ellipsoid",
                "sliding@stem",
                "two_contacts@ellipsoid+stem"
            ]),
            " (shaded: sliding orange, two_contacts pink)"
        );
        assert_eq!(d.shade("rolling@peg").fill, d.shade("rolling").fill);
        assert!(d.surface_colors.iter().all(|c| c.len() == 7));
        assert_eq!(rgb("#8040a0"), (0x80, 0x40, 0xa0));
    }
}
