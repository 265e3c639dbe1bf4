//! The scenario's schema, declared once: every table and key of the format with its
//! unit, kind, value when absent and a one-line description.
//!
//! Derived from it: the keys each table accepts (and so the "did you mean" candidates
//! of an unknown key), the units of a study's axis columns ([`unit`]), the fuzzer's key
//! names and the key reference of `docs/scenarios.md` ([`reference`], checked against
//! the document by a test). A new key is one entry here and its reading in `format`; an
//! effect's keys are read by its entry of the effect list (`crate::effects`).

use crate::error::number;
use crate::geometry;
use crate::integrate::Method;
use crate::model::contensou;
use crate::simulate::{ContactModel, LiftOff};

use super::path::{KeyPath, Seg};

/// What a key holds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kind {
    /// A number (integer or float).
    Number,
    /// A whole number.
    Count,
    /// An array of exactly N numbers.
    Numbers(usize),
    /// An array of numbers of any length.
    List,
    /// One of the given strings.
    Choice(&'static [&'static str]),
    /// The name of a numeric output column.
    Column,
    /// A string.
    Text,
    /// true or false.
    Bool,
    /// A table of the keys declared under its path.
    Table,
    /// An array of tables of the keys declared under its path (`[[body.sphere]]`).
    Tables,
    /// A number, or a table of the keys declared under its path.
    NumberOrTable,
    /// The inertia: three principal moments, a symmetric 3×3 array, or "uniform".
    Inertia,
}

/// What an absent key means.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Absent {
    /// The key must be given.
    Required,
    /// The key is optional and has no value of its own (the feature it turns on is off,
    /// or another key gives the quantity).
    Unset,
    /// This number.
    Value(f64),
    /// This value or rule, in words.
    Means(&'static str),
}

/// One key of the format.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Key {
    /// The dotted path of its table (`""` for the top level, `body.sphere` for the
    /// tables of the `[[body.sphere]]` array).
    pub table: &'static str,
    pub name: &'static str,
    /// SI unit ("1" for dimensionless numbers); `None` for names, counts and tables.
    pub unit: Option<&'static str>,
    pub kind: Kind,
    pub absent: Absent,
    /// What it is, in one line.
    pub doc: &'static str,
}

/// `[[observe]] direction` values.
pub const DIRECTIONS: [&str; 3] = ["up", "down", "either"];
/// `axis` values of `initial.rotation` entries.
pub const ROTATION_AXES: [&str; 3] = ["x", "y", "z"];

/// One entry of [`SCHEMA`].
const fn key(
    table: &'static str,
    name: &'static str,
    unit: Option<&'static str>,
    kind: Kind,
    absent: Absent,
    doc: &'static str,
) -> Key {
    Key {
        table,
        name,
        unit,
        kind,
        absent,
        doc,
    }
}

const M: Option<&str> = Some("m");
const RAD: Option<&str> = Some("rad");
const DEG: Option<&str> = Some("deg");
const RAD_S: Option<&str> = Some("rad/s");
const DEG_S: Option<&str> = Some("deg/s");
const S: Option<&str> = Some("s");
const ONE: Option<&str> = Some("1");
const DRIFT: &str = "the largest allowed relative drift of this invariant";

use Absent::*;
use Kind::*;

/// Every key of the format, table by table, each table's keys in the order messages
/// list them.
#[rustfmt::skip]
pub const SCHEMA: &[Key] = &[
    key("", "body", None, Table, Required, "the body: semi-axes, mass, centre of mass, inertia"),
    key("", "initial", None, Table, Means("every key 0"), "the initial state: angles, rates, position, velocity"),
    key("", "contact", None, Table, Required, "the contact with the plane: model and friction"),
    key("", "effects", None, Table, Means("standard gravity, no dissipation"), "gravity and optional dissipation"),
    key("", "solver", None, Table, Means("dop853 at its default tolerances"), "the integration method, tolerances and step"),
    key("", "output", None, Table, Required, "the end time and the sampling"),
    key("", "check", None, Table, Unset, "what a run is expected to achieve (changes nothing in the run)"),
    key("", "observe", None, Tables, Unset, "events on output columns, at most 64"),
    key("", "section", None, Tables, Unset, "Poincaré sections: the full state at each crossing, at most 16"),
    key("body", "a", M, Number, Required, "the semi-axis along body x"),
    key("body", "b", M, Number, Means("a"), "the semi-axis along body y"),
    key("body", "c", M, Number, Required, "the semi-axis along the symmetry axis, body z"),
    key("body", "mass", Some("kg"), Number, Required, "the mass"),
    key("body", "com_offset", M, Number, Means("0"), "D2: the centre of mass G lies this far below the geometric centre C0 on the axis"),
    key("body", "com_offset_vector", M, Numbers(3), Means("[0, 0, 0]"), "G − C0 in body axes (exclusive with com_offset)"),
    key("body", "inertia", Some("kg m^2"), Inertia, Required, "about G in body axes: [I1, I2, I3], a symmetric 3×3 array, or \"uniform\""),
    key("body", "sphere", None, Tables, Unset, "contact spheres fixed in the body, at most 8"),
    key("body.sphere", "name", None, Text, Required, "1 to 24 ASCII letters, digits or _ (it names output columns); unique, not \"ellipsoid\""),
    key("body.sphere", "center", M, Numbers(3), Required, "the sphere's centre in body axes, from the ellipsoid's centre C0; at most 1e3 L from it (L the largest semi-axis)"),
    key("body.sphere", "radius", M, Number, Required, "the sphere's radius, 1e-6 L to 1e3 L (L the largest semi-axis)"),
    key("body", "rim", None, Tables, Unset, "rims (circular edges, sharp or rounded) fixed in the body, at most 4"),
    key("body.rim", "name", None, Text, Required, "1 to 24 ASCII letters, digits or _ (it names output columns); unique among spheres and rims, not \"ellipsoid\""),
    key("body.rim", "center", M, Numbers(3), Required, "the centre of the rim's circle in body axes, on the symmetry axis: [0.0, 0.0, z]"),
    key("body.rim", "radius", M, Number, Required, "R: the radius of the circle through the centres of the edge's cross-section, 1e-6 L to 1e3 L"),
    key("body.rim", "edge", M, Number, Required, "r: the radius of the rounded edge, 0 (sharp) or 1e-6 L to 1e3 L"),
    key("body", "ellipsoid_contact", None, Bool, Means("true"), "whether the ellipsoid itself touches the plane; false: only the spheres and rims touch (a coin is its rim)"),
    key("initial", "theta", RAD, Number, Value(0.0), "θ, the tilt of the symmetry axis from the vertical"),
    key("initial", "theta_deg", DEG, Number, Unset, "θ in degrees (exclusive with theta)"),
    key("initial", "phi", RAD, Number, Value(0.0), "φ, the precession angle"),
    key("initial", "phi_deg", DEG, Number, Unset, "φ in degrees (exclusive with phi)"),
    key("initial", "psi", RAD, Number, Value(0.0), "ψ, the spin angle"),
    key("initial", "psi_deg", DEG, Number, Unset, "ψ in degrees (exclusive with psi)"),
    key("initial", "theta_dot", RAD_S, Number, Value(0.0), "θ̇, the rate of θ"),
    key("initial", "theta_dot_deg", DEG_S, Number, Unset, "θ̇ in degrees per second"),
    key("initial", "phi_dot", RAD_S, Number, Value(0.0), "φ̇, the precession rate"),
    key("initial", "phi_dot_deg", DEG_S, Number, Unset, "φ̇ in degrees per second"),
    key("initial", "psi_dot", RAD_S, Number, Value(0.0), "ψ̇, the spin rate"),
    key("initial", "psi_dot_deg", DEG_S, Number, Unset, "ψ̇ in degrees per second"),
    key("initial", "omega_body", RAD_S, Numbers(3), Unset, "the body angular velocity, instead of the three rates"),
    key("initial", "omega_body_deg", DEG_S, Numbers(3), Unset, "omega_body in degrees per second"),
    key("initial", "rotation", None, Tables, Unset, "the orientation as R = R1 R2 … (body → world), instead of theta, phi, psi"),
    key("initial", "position", M, Numbers(2), Means("[0, 0]"), "x, y of G"),
    key("initial", "velocity", Some("m/s"), List, Means("[0, 0]"), "the velocity of G: [vx, vy], or [vx, vy, vz] in flight"),
    key("initial", "height", M, Number, Value(0.0), "the gap of the lowest point above the plane; > 0 starts in flight"),
    key("initial.rotation", "axis", None, Choice(&ROTATION_AXES), Required, "the axis of this elementary rotation"),
    key("initial.rotation", "angle", RAD, Number, Required, "its angle"),
    key("initial.rotation", "angle_deg", DEG, Number, Unset, "its angle in degrees (instead of angle)"),
    key("contact", "model", None, Choice(&ContactModel::NAMES), Required, "the contact model (docs/physics.md)"),
    key("contact", "friction", ONE, Number, Unset, "μ, the Coulomb coefficient: required by sliding and coulomb, rejected by the others"),
    key("contact", "viscous_friction", Some("s/m"), Number, Unset, "μ_v, the viscous coefficient (tangential force −μ_v N v_C): required by viscous, rejected by the others"),
    key("contact", "restitution", ONE, Number, Value(0.0), "e ∈ [0, 1], the energetic coefficient of restitution at touchdowns"),
    key("contact", "on_lift_off", None, Choice(&LiftOff::NAMES), Means("fly"), "what happens when the normal force reaches zero"),
    key("contact", "flat_tilt", ONE, Number, Value(geometry::FLAT_TILT), "sin α below which a rim lies on its face: its far side within 2R sin α of the plane, the surfaces' roughness"),
    key("contact", "contact_radius", M, Number, Value(0.0), "R, the radius of a flat contact disc (0: a point contact)"),
    key("contact", "contact_law", None, Choice(&contensou::Law::NAMES), Means("exact"), "the contact disc's friction law"),
    key("effects", "gravity", Some("m/s^2"), Number, Value(super::DEFAULT_GRAVITY), "g"),
    key("effects", "rolling_resistance", M, NumberOrTable, Unset, "c_r, the rolling-resistance length (or a table of coefficient, regularisation)"),
    key("effects", "spin_friction", M, NumberOrTable, Unset, "c_s, the spin-friction length (or a table of coefficient, regularisation)"),
    key("effects", "air_drag", None, Table, Unset, "linear and angular air drag"),
    key("effects.rolling_resistance", "coefficient", M, Number, Required, "c_r"),
    key("effects.rolling_resistance", "regularisation", RAD_S, Number, Value(super::DEFAULT_REGULARISATION), "ε, the rate below which the torque is regularised"),
    key("effects.spin_friction", "coefficient", M, Number, Required, "c_s"),
    key("effects.spin_friction", "regularisation", RAD_S, Number, Value(super::DEFAULT_REGULARISATION), "ε, the rate below which the torque is regularised"),
    key("effects.air_drag", "linear", Some("kg/s"), Number, Value(0.0), "k, the linear drag coefficient"),
    key("effects.air_drag", "angular", Some("kg m^2/s"), Number, Value(0.0), "k_ω, the angular drag coefficient"),
    key("effects", "rolling_friction", ONE, NumberOrTable, Unset, "μ_r, the force μ_r N resisting the contact point's travel (or a table of coefficient, regularisation)"),
    key("effects", "air_film", None, Table, Unset, "Moffatt's air film under a rim's face (a body with rims)"),
    key("effects", "air_boundary_layer", None, Table, Unset, "Bildsten's air boundary layer under a rim's face (a body with rims)"),
    key("effects.rolling_friction", "coefficient", ONE, Number, Required, "μ_r"),
    key("effects.rolling_friction", "regularisation", RAD_S, Number, Value(super::DEFAULT_REGULARISATION), "ε, the rate below which the torque is regularised"),
    key("effects.air_film", "viscosity", Some("Pa s"), Number, Required, "μ, the air's dynamic viscosity"),
    key("effects.air_boundary_layer", "viscosity", Some("Pa s"), Number, Required, "μ, the air's dynamic viscosity"),
    key("effects.air_boundary_layer", "density", Some("kg/m^3"), Number, Required, "ρ, the air's density"),
    key("solver", "method", None, Choice(&Method::NAMES), Means(super::DEFAULT_METHOD), "the integration method"),
    key("solver", "rtol", ONE, Number, Value(super::DEFAULT_RTOL), "the relative tolerance (10·EPS to 1e-2)"),
    key("solver", "atol", ONE, Number, Value(super::DEFAULT_ATOL), "the absolute tolerance, in each state component's unit"),
    key("solver", "step", S, Number, Unset, "rk4's fixed step (required there); an initial step hint otherwise"),
    key("solver", "max_steps", None, Count, Value(super::DEFAULT_MAX_STEPS as f64), "accepted + rejected steps per contact-mode segment"),
    key("output", "t_end", S, Number, Required, "the end time"),
    key("output", "dt", S, Number, Unset, "the sampling interval: samples at k·dt and at t_end (exclusive with times)"),
    key("output", "times", S, List, Unset, "explicit output times, strictly increasing in [0, t_end]"),
    key("check", "status", None, Choice(&super::STATUS_NAMES), Unset, "the expected status of the run"),
    key("check", "energy", ONE, Number, Unset, DRIFT),
    key("check", "energy_plus_work", ONE, Number, Unset, DRIFT),
    key("check", "momentum", ONE, Number, Unset, DRIFT),
    key("check", "angular_momentum_z", ONE, Number, Unset, DRIFT),
    key("check", "axial_spin", ONE, Number, Unset, DRIFT),
    key("check", "jellett", ONE, Number, Unset, DRIFT),
    key("observe", "name", None, Text, Required, "a unique name, reported with the event"),
    key("observe", "column", None, Column, Required, "the numeric output column watched (a body with contact spheres: its per-surface columns too)"),
    key("observe", "crosses", None, Number, Required, "the value crossed, in the column's unit"),
    key("observe", "direction", None, Choice(&DIRECTIONS), Means("either"), "up (increasing through the value), down or either"),
    key("observe", "terminal", None, Bool, Means("false"), "whether the run ends at the first crossing (status observed)"),
    key("section", "name", None, Text, Required, "a unique name (the `section` column of the sections table)"),
    key("section", "column", None, Column, Required, "the numeric output column whose crossing defines the section"),
    key("section", "crosses", None, Number, Required, "the value crossed, in the column's unit"),
    key("section", "direction", None, Choice(&DIRECTIONS), Means("either"), "up (increasing through the value), down or either"),
    key("section", "max_points", None, Count, Means("1000000 / the number of sections"), "the most points kept: the run ends at the last one (status section_full); 1 to 1000000, all sections together at most 1000000"),
];

/// The keys the table at `table` (a dotted path without indexes) accepts, in order.
pub fn keys(table: &str) -> Vec<&'static str> {
    SCHEMA
        .iter()
        .filter(|k| k.table == table)
        .map(|k| k.name)
        .collect()
}

/// The declaration of the key at `path` (a dotted path, `[i]` indexes allowed and
/// ignored: `body.sphere[1].radius`, `body.inertia[0]`).
pub fn find(path: &str) -> Option<&'static Key> {
    let path = KeyPath::parse(path).ok()?;
    let names: Vec<&str> = path
        .segs()
        .iter()
        .filter_map(|s| match s {
            Seg::Name(n) => Some(n.as_str()),
            Seg::Index(_) => None,
        })
        .collect();
    let (name, table) = names.split_last()?;
    let table = table.join(".");
    SCHEMA.iter().find(|k| k.table == table && k.name == *name)
}

/// The unit of the key at `path` (see [`find`]); `None` for a key without one or not
/// of the format. The unit of a table form's key (`effects.spin_friction.coefficient`)
/// is declared like any other.
pub fn unit(path: &str) -> Option<&'static str> {
    find(path).and_then(|k| k.unit)
}

/// The name of every key of the format, each once, in declaration order.
pub fn names() -> Vec<&'static str> {
    let mut out: Vec<&'static str> = Vec::new();
    for k in SCHEMA {
        if !out.contains(&k.name) {
            out.push(k.name);
        }
    }
    out
}

impl Kind {
    /// The kind in words, for the key reference.
    fn describe(self) -> String {
        match self {
            Number => "number".into(),
            Count => "whole number".into(),
            Numbers(n) => format!("{n} numbers"),
            List => "array of numbers".into(),
            Choice(names) => names
                .iter()
                .map(|n| format!("`\"{n}\"`"))
                .collect::<Vec<_>>()
                .join(" \\| "),
            Column => "column name".into(),
            Text => "string".into(),
            Bool => "boolean".into(),
            Table => "table".into(),
            Tables => "array of tables".into(),
            NumberOrTable => "number or table".into(),
            Inertia => "3 numbers, 3×3 numbers or `\"uniform\"`".into(),
        }
    }
}

impl Absent {
    /// What absence means, in words, for the key reference.
    fn describe(self) -> String {
        match self {
            Required => "required".into(),
            Unset => "–".into(),
            Value(v) => number(v),
            Means(s) => s.into(),
        }
    }
}

/// The key reference of `docs/scenarios.md`: one Markdown table row per key, by table.
pub fn reference() -> String {
    let mut out =
        String::from("| key | unit | kind | when absent | meaning |\n|---|---|---|---|---|\n");
    for k in SCHEMA {
        let key = match (k.table, k.kind) {
            ("", Tables) => format!("`[[{}]]`", k.name),
            ("", _) => format!("`[{}]`", k.name),
            (t, _) => {
                let t = match t {
                    "body.sphere" | "body.rim" | "initial.rotation" => format!("{t}[i]"),
                    "observe" | "section" => format!("{t}[i]"),
                    t => t.to_owned(),
                };
                format!("`{t}.{}`", k.name)
            }
        };
        out.push_str(&format!(
            "| {key} | {} | {} | {} | {} |\n",
            k.unit.unwrap_or("–"),
            k.kind.describe(),
            k.absent.describe(),
            k.doc.replace('|', "\\|"),
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::EffectSet;
    use crate::scenario::{DRIFT_NAMES, parse};

    /// A scenario of `model` and `method`, with what each needs (μ, rk4's step).
    fn scenario(model: &str, method: &str) -> String {
        let friction = match model {
            "sliding" | "coulomb" => "friction = 0.3\n",
            "viscous" => "viscous_friction = 0.5\n",
            _ => "",
        };
        format!(
            "[body]\na = 0.025\nc = 0.0175\nmass = 0.05\ninertia = \"uniform\"\n\
             [initial]\ntheta = 0.2\npsi_dot = 60.0\n\
             [contact]\nmodel = \"{model}\"\n{friction}\
             [solver]\nmethod = \"{method}\"\nstep = 1e-4\n\
             [output]\nt_end = 0.1\ndt = 0.01\n"
        )
    }

    #[test]
    fn every_table_of_the_schema_is_a_key_of_its_parent() {
        for k in SCHEMA.iter().filter(|k| !k.table.is_empty()) {
            let parent = find(k.table).unwrap_or_else(|| panic!("{}: no table", k.table));
            assert!(
                matches!(parent.kind, Table | Tables | NumberOrTable),
                "{}: {:?}",
                k.table,
                parent.kind
            );
        }
        for t in SCHEMA
            .iter()
            .filter(|k| matches!(k.kind, Table | Tables | NumberOrTable))
        {
            let path = if t.table.is_empty() {
                t.name.to_owned()
            } else {
                format!("{}.{}", t.table, t.name)
            };
            assert!(!keys(&path).is_empty(), "{path} declares no keys");
        }
    }

    #[test]
    fn no_key_is_declared_twice_and_every_doc_is_one_line() {
        for (i, k) in SCHEMA.iter().enumerate() {
            assert!(
                !SCHEMA[..i]
                    .iter()
                    .any(|o| o.table == k.table && o.name == k.name),
                "{}.{} twice",
                k.table,
                k.name
            );
            assert!(!k.doc.is_empty() && !k.doc.contains('\n'), "{}", k.name);
        }
    }

    #[test]
    fn the_check_table_bounds_every_invariant() {
        let mut want = vec!["status"];
        want.extend(DRIFT_NAMES);
        assert_eq!(keys("check"), want);
    }

    /// The keys of `[effects]` but gravity are the effect list's (`crate::effects`), in
    /// order: a key declared without an entry there would be accepted and ignored, an
    /// entry without a key refused as unknown.
    #[test]
    fn the_effects_table_declares_exactly_the_listed_effects() {
        let mut want = vec!["gravity"];
        want.extend(EffectSet::KEYS);
        assert_eq!(keys("effects"), want);
    }

    #[test]
    fn units_of_key_paths_with_indexes() {
        assert_eq!(unit("body.mass"), Some("kg"));
        assert_eq!(unit("body.inertia[1]"), Some("kg m^2"));
        assert_eq!(unit("body.sphere[1].radius"), Some("m"));
        assert_eq!(unit("initial.rotation[0].angle_deg"), Some("deg"));
        assert_eq!(unit("initial.omega_body_deg[2]"), Some("deg/s"));
        assert_eq!(unit("effects.spin_friction.regularisation"), Some("rad/s"));
        assert_eq!(unit("observe[0].crosses"), None);
        assert_eq!(unit("body.name"), None);
        assert_eq!(unit("body"), None);
    }

    /// Each name of a method and of a contact model reads as that method and model: a
    /// name without its own arm would not.
    #[test]
    fn every_method_and_contact_model_name_reads_as_itself() {
        for method in Method::NAMES {
            for model in ContactModel::NAMES {
                let text = scenario(model, method);
                let s = parse(&text, "x.toml", &[] as &[&str]).unwrap_or_else(|e| panic!("{e}"));
                assert_eq!(s.scene.solver.method.name(), method);
                assert_eq!(s.scene.contact.name(), model);
                assert_eq!(
                    s.scene.contact.friction().is_some(),
                    text.contains("\nfriction = ")
                );
            }
        }
    }

    #[test]
    fn an_unknown_name_is_an_error_naming_the_key_the_value_and_the_names() {
        let text = scenario("rolling", "rk5");
        let e = parse(&text, "x.toml", &[] as &[&str])
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "x.toml:12:1: solver.method = \"rk5\": expected one of \"rk4\", \"dopri5\", \"dop853\"; did you mean \"rk4\"?"
        );
        let e = parse(&scenario("rolls", "rk4"), "x.toml", &[] as &[&str])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("contact.model = \"rolls\": expected one of \"frictionless\", \"sliding\", \"rolling\", \"coulomb\""),
            "{e}"
        );
    }
}
