//! Plausibility warnings: values that are valid but almost surely a unit slip (degrees
//! typed in a radian key, grams in a kilogram key, rpm in a rad/s key). They never stop
//! a run: the command-line tool prints them on standard error and Python raises them as
//! `ellipsoid.PlausibilityWarning`; both can silence them (`docs/scenarios.md`,
//! "Plausibility warnings").
//!
//! The rules, each on the scenario as parsed (after `--set` and Python's changes):
//!
//! - **Angle beyond a turn.** A radian key of the schema (unit `rad`: `initial.theta`,
//!   `initial.phi`, `initial.psi`, `initial.rotation[i].angle`) whose magnitude exceeds
//!   [`MAX_ANGLE`] = 2π: an orientation needs no more, so the number was likely degrees.
//! - **Density no solid has.** The mass over the ellipsoid's volume (4/3)π a b c outside
//!   [[`MIN_DENSITY`], [`MAX_DENSITY`]] = [10, 3e4] kg/m³: from the lightest rigid foams
//!   (expanded polystyrene, about 11 kg/m³) to beyond osmium, the densest element (22 590
//!   kg/m³). The hint: grams typed as kg when a thousandth of the mass is plausible,
//!   semi-axes in cm or mm typed as m when 10⁶ or 10⁹ times the density is. Contact spheres (a stem) are not counted in the volume: they add
//!   little to it in every bundled body.
//! - **Spin energy that dwarfs gravity.** The initial rotational energy ½ ωᵀ I ω above
//!   [`MAX_SPIN_ENERGY`] = 100 times m g L (L the largest semi-axis, the energy that lifts
//!   the body by its size; not checked without gravity). A hand-spun top or egg has a
//!   ratio below about 30 (a 15 mm tippe top at 300 rad/s: 28; the bundled scenarios: at
//!   most 24), while rpm typed as rad/s multiplies the energy by (60 / 2π)² ≈ 91: the
//!   issue's egg laid at 80° with phi_dot = 1600 has about 1100 (the hint "rpm typed as rad/s?"
//!   is given when undoing that factor leaves a plausible spin).

use nalgebra::Vector3;

use super::schema::{Kind, SCHEMA};
use super::*;

/// The largest plausible magnitude of an angle in radians: one turn.
pub const MAX_ANGLE: f64 = std::f64::consts::TAU;
/// The lightest plausible density of the body [kg/m³] (the lightest rigid foams).
pub const MIN_DENSITY: f64 = 10.0;
/// The heaviest plausible density of the body [kg/m³] (beyond osmium, 22 590 kg/m³).
pub const MAX_DENSITY: f64 = 3e4;
/// The largest plausible initial rotational energy, in units of m g L.
pub const MAX_SPIN_ENERGY: f64 = 100.0;

/// The keys whose value sets the initial angular velocity (the rate keys of `[initial]`).
const RATE_KEYS: [&str; 8] = [
    "theta_dot",
    "phi_dot",
    "psi_dot",
    "theta_dot_deg",
    "phi_dot_deg",
    "psi_dot_deg",
    "omega_body",
    "omega_body_deg",
];

/// A valid value that is likely a unit slip. Displays as one line:
/// `file:line:col: warning: key = value: message`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Warning {
    /// Where the value was written (or the `--set` that gave it).
    pub location: Location,
    /// The full dotted key (`initial.theta`).
    pub key: String,
    /// The value as written.
    pub value: String,
    /// What is implausible, and the likely slip.
    pub message: String,
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}: warning: {} = {}: {}",
            self.location,
            cut(&self.key),
            self.value,
            self.message
        )
    }
}

/// Every plausibility warning of `scenario`, in the order of the rules above.
pub fn warnings(scenario: &Scenario) -> Vec<Warning> {
    let ctx = Ctx {
        source: &scenario.source,
        text: &scenario.text,
    };
    let mut out = angles(&ctx, &scenario.tree);
    out.extend(density(&ctx, scenario));
    out.extend(spin(&ctx, scenario));
    out
}

/// A warning on the key at `path` of `tree`, if the document has it.
fn warn(ctx: &Ctx<'_>, tree: &Node, path: &str, message: String) -> Option<Warning> {
    let key = KeyPath::parse(path).ok()?;
    let node = tree.get(&key)?;
    let segs: Vec<String> = path.split('.').map(str::to_owned).collect();
    let origin = tree.find(&segs).unwrap_or_else(|| node.origin.clone());
    Some(Warning {
        location: ctx.locate(&origin),
        key: path.to_owned(),
        value: ctx.value_text(node),
        message,
    })
}

/// A number in three significant digits (`1.19e6`, `700`, `0.0628`).
fn short(x: f64) -> String {
    let a = x.abs();
    if a == 0.0 {
        "0".to_owned()
    } else if !(1e-3..1e5).contains(&a) {
        let s = format!("{x:.2e}");
        // 1.20e6 → 1.2e6, 1.00e6 → 1e6
        match s.split_once('e') {
            Some((m, e)) => {
                let m = m.trim_end_matches('0').trim_end_matches('.');
                format!("{m}e{e}")
            }
            None => s,
        }
    } else {
        let digits = (2 - a.log10().floor() as i32).max(0) as usize;
        let s = format!("{x:.digits$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_owned()
        } else {
            s
        }
    }
}

/// Rule 1: every radian key of the schema (each `initial.rotation` element too) whose
/// magnitude exceeds [`MAX_ANGLE`].
fn angles(ctx: &Ctx<'_>, tree: &Node) -> Vec<Warning> {
    let mut paths = Vec::new();
    for k in SCHEMA
        .iter()
        .filter(|k| k.unit == Some("rad") && k.kind == Kind::Number)
    {
        if k.table == "initial.rotation" {
            let n = match tree
                .get(&KeyPath::parse("initial.rotation").expect("a key path"))
                .map(|n| &n.value)
            {
                Some(Value::Array(a)) => a.len(),
                _ => 0,
            };
            paths.extend((0..n).map(|i| format!("initial.rotation[{i}].{}", k.name)));
        } else {
            paths.push(format!("{}.{}", k.table, k.name));
        }
    }
    paths
        .iter()
        .filter_map(|path| {
            let node = tree.get(&KeyPath::parse(path).ok()?)?;
            let x = node.as_f64()?;
            if x.abs() <= MAX_ANGLE {
                return None;
            }
            let name = path.rsplit('.').next().unwrap_or(path);
            let message = format!(
                "{} rad is more than 2π ({} turns): degrees? use {name}_deg = {}",
                short(x),
                short(x.abs() / MAX_ANGLE),
                ctx.value_text(node)
            );
            warn(ctx, tree, path, message)
        })
        .collect()
}

/// The density of the body, mass over the ellipsoid's volume (4/3)π a b c [kg/m³].
pub fn density_of(scene: &Scene) -> f64 {
    let s = scene.body.semi_axes();
    scene.body.mass() / (4.0 / 3.0 * std::f64::consts::PI * s.x * s.y * s.z)
}

/// Rule 2: a density outside [[`MIN_DENSITY`], [`MAX_DENSITY`]], on `body.mass`.
fn density(ctx: &Ctx<'_>, scenario: &Scenario) -> Option<Warning> {
    let rho = density_of(&scenario.scene);
    let m = scenario.scene.body.mass();
    let range = format!(
        "solids have {} to {} kg/m³, foam to osmium",
        short(MIN_DENSITY),
        short(MAX_DENSITY)
    );
    let plausible = |x: f64| (MIN_DENSITY..=MAX_DENSITY).contains(&x);
    let slip = if plausible(rho / 1000.0) {
        format!(
            "grams? {} g is mass = {} ({} kg/m³)",
            short(m),
            short(m / 1000.0),
            short(rho / 1000.0)
        )
    } else if plausible(rho * 1e6) || plausible(rho * 1e9) {
        "semi-axes a, b, c in cm or mm typed as m?".to_owned()
    } else {
        "check the units of mass (kg) and a, b, c (m)".to_owned()
    };
    if plausible(rho) {
        return None;
    }
    let message = format!(
        "the density mass / ((4/3)π a b c) is {} kg/m³, and {range}: {slip}",
        short(rho)
    );
    warn(ctx, &scenario.tree, "body.mass", message)
}

/// The initial rotational energy ½ ωᵀ I ω over m g L (L the largest semi-axis); `None`
/// without gravity.
pub fn spin_ratio(scene: &Scene) -> Option<f64> {
    let body = &scene.body;
    let omega: Vector3<f64> = scene
        .initial
        .omega_body
        .unwrap_or_else(|| scene.initial.angles.omega_body());
    let energy = 0.5 * omega.dot(&(body.inertia() * omega));
    let weight = body.mass() * scene.gravity * body.semi_axes().max();
    (weight > 0.0).then(|| energy / weight)
}

/// Rule 3: a rotational energy above [`MAX_SPIN_ENERGY`] m g L, on the rate key of the
/// largest magnitude.
fn spin(ctx: &Ctx<'_>, scenario: &Scenario) -> Option<Warning> {
    let ratio = spin_ratio(&scenario.scene)?;
    if ratio <= MAX_SPIN_ENERGY {
        return None;
    }
    let tree = &scenario.tree;
    let magnitude = |node: &Node| match &node.value {
        Value::Array(a) => a
            .iter()
            .filter_map(Node::as_f64)
            .map(f64::abs)
            .fold(0.0, f64::max),
        _ => node.as_f64().unwrap_or(0.0).abs(),
    };
    let (name, node) = RATE_KEYS
        .iter()
        .filter_map(|k| {
            let n = tree.get(&KeyPath::parse(&format!("initial.{k}")).ok()?)?;
            Some((*k, n))
        })
        .max_by(|a, b| magnitude(a.1).total_cmp(&magnitude(b.1)))?;
    // rpm typed as rad/s multiplies the energy by (2π / 60)⁻²: the hint when undoing it
    // gives a plausible spin.
    let undone = ratio * (MAX_ANGLE / 60.0).powi(2);
    let rpm = if name.ends_with("_deg") || undone > MAX_SPIN_ENERGY {
        String::new()
    } else {
        format!(
            ": rpm typed as rad/s? {} rpm is {} rad/s",
            short(magnitude(node)),
            short(magnitude(node) * MAX_ANGLE / 60.0)
        )
    };
    let message = format!(
        "the initial spin energy ½ωᵀIω is {} m g L (L the largest semi-axis), more than {} m g L{rpm}",
        short(ratio),
        short(MAX_SPIN_ENERGY)
    );
    warn(ctx, tree, &format!("initial.{name}"), message)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every scenario file under `scenarios/` and `scenarios/paper/`.
    fn bundled() -> Vec<std::path::PathBuf> {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios");
        let mut files = Vec::new();
        for dir in [root.clone(), root.join("paper")] {
            for e in std::fs::read_dir(&dir).expect("scenarios/") {
                let p = e.expect("an entry").path();
                if p.extension().is_some_and(|x| x == "toml") {
                    files.push(p);
                }
            }
        }
        files.sort();
        assert!(files.len() >= 30, "{} scenario files", files.len());
        files
    }

    #[test]
    fn no_bundled_scenario_warns() {
        for path in bundled() {
            let s = load(&path, &[] as &[&str]).unwrap_or_else(|e| panic!("{e}"));
            let w = warnings(&s);
            assert!(
                w.is_empty(),
                "{}",
                w.iter()
                    .map(ToString::to_string)
                    .collect::<Vec<_>>()
                    .join("\n")
            );
        }
    }

    /// The issue's egg (a = b = 2 cm, c = 3 cm, 60 g), laid at 80° and spun at 135 rad/s,
    /// with `initial` lines replaced by `initial`, `body` lines by `body`.
    fn egg(body: &str, initial: &str) -> String {
        format!(
            "[body]\na = 0.02\nc = 0.03\n{body}\ninertia = \"uniform\"\n\
             [initial]\n{initial}\n\
             [contact]\nmodel = \"sliding\"\nfriction = 0.3\n\
             [output]\nt_end = 0.1\ndt = 0.01\n"
        )
    }

    /// The warnings of `text` with `sets`, as lines.
    fn lines(text: &str, sets: &[&str]) -> Vec<String> {
        let s = parse(text, "egg.toml", sets).unwrap_or_else(|e| panic!("{e}"));
        warnings(&s).iter().map(ToString::to_string).collect()
    }

    const MASS: &str = "mass = 0.06";
    const START: &str = "theta_deg = 80\nphi_dot = 135";

    #[test]
    fn the_plausible_egg_does_not_warn() {
        assert_eq!(lines(&egg(MASS, START), &[]), Vec::<String>::new());
        // Exactly one turn, either way, is still an orientation.
        let turn = "theta = 0.2\nphi = -6.283185307179586\npsi = 6.283185307179586";
        assert_eq!(lines(&egg(MASS, turn), &[]), Vec::<String>::new());
    }

    #[test]
    fn an_angle_beyond_a_turn_in_a_radian_key_warns_naming_the_degree_key() {
        let w = lines(&egg(MASS, "theta = 80\nphi_dot = 1.0"), &[]);
        assert_eq!(
            w,
            [
                "egg.toml:7:1: warning: initial.theta = 80: 80 rad is more than 2π (12.7 turns): degrees? use theta_deg = 80"
            ]
        );
        let w = lines(&egg(MASS, "theta = 0.2\npsi = -90.0"), &[]);
        assert_eq!(w.len(), 1);
        assert!(w[0].contains("initial.psi = -90.0: -90 rad is more than 2π (14.3 turns): degrees? use psi_deg = -90.0"), "{}", w[0]);
        // A rotation's angle, and a value given by --set.
        let rot = "rotation = [{ axis = \"x\", angle = 0.5 }, { axis = \"z\", angle = 30 }]";
        let w = lines(&egg(MASS, rot), &[]);
        assert_eq!(w.len(), 1);
        assert!(w[0].starts_with("egg.toml:7:"), "{}", w[0]);
        assert!(w[0].contains("initial.rotation[1].angle = 30: 30 rad is more than 2π (4.77 turns): degrees? use angle_deg = 30"), "{}", w[0]);
        let w = lines(&egg(MASS, START), &["initial.phi=400"]);
        assert_eq!(w.len(), 1);
        assert!(
            w[0].starts_with("egg.toml: --set initial.phi=400: warning: initial.phi = 400: "),
            "{}",
            w[0]
        );
        // Degree keys have their own unit: 80° is no slip.
        assert_eq!(
            lines(&egg(MASS, "theta_deg = 80\npsi_deg = 720"), &[]),
            Vec::<String>::new()
        );
    }

    #[test]
    fn a_density_no_solid_has_warns_on_the_mass() {
        let w = lines(&egg("mass = 60", START), &[]);
        assert_eq!(
            w,
            [
                "egg.toml:4:1: warning: body.mass = 60: the density mass / ((4/3)π a b c) is 1.19e6 kg/m³, and solids have 10 to 30000 kg/m³, foam to osmium: grams? 60 g is mass = 0.06 (1194 kg/m³)"
            ]
        );
        // Semi-axes in cm typed as m: a = b = 2 m, c = 3 m for 60 g (not spun: a 3 m egg
        // at 135 rad/s would warn of its spin too).
        let text = egg(MASS, "theta_deg = 80").replace("a = 0.02\nc = 0.03", "a = 2\nc = 3");
        let w = lines(&text, &[]);
        assert_eq!(w.len(), 1);
        assert!(w[0].contains("body.mass = 0.06: the density mass / ((4/3)π a b c) is 0.00119 kg/m³, and solids have 10 to 30000 kg/m³, foam to osmium: semi-axes a, b, c in cm or mm typed as m?"), "{}", w[0]);
        // No hint that would not help: 1000 times the mass of a 2 × 3 cm egg in grams.
        let w = lines(&egg("mass = 60000", START), &[]);
        assert_eq!(w.len(), 1);
        assert!(w[0].ends_with("is 1.19e9 kg/m³, and solids have 10 to 30000 kg/m³, foam to osmium: check the units of mass (kg) and a, b, c (m)"), "{}", w[0]);
        // The bounds themselves are plausible: a 2 × 3 cm polystyrene egg, an osmium one.
        for rho in [MIN_DENSITY * (1.0 + 1e-9), MAX_DENSITY * (1.0 - 1e-9)] {
            let m = rho * 4.0 / 3.0 * std::f64::consts::PI * 0.02 * 0.02 * 0.03;
            let text = egg(&format!("mass = {m}"), START);
            assert_eq!(lines(&text, &[]), Vec::<String>::new(), "{rho}");
        }
    }

    #[test]
    fn a_spin_whose_energy_dwarfs_gravity_warns_on_the_largest_rate() {
        let w = lines(
            &egg(MASS, "theta_deg = 80\nphi_dot = 1600\npsi_dot = 1.0"),
            &[],
        );
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].starts_with(
                "egg.toml:8:1: warning: initial.phi_dot = 1600: the initial spin energy ½ωᵀIω is "
            ),
            "{}",
            w[0]
        );
        assert!(w[0].ends_with(" m g L (L the largest semi-axis), more than 100 m g L: rpm typed as rad/s? 1600 rpm is 168 rad/s"), "{}", w[0]);
        // The body angular velocity, and degrees per second (no rpm hint there).
        let w = lines(&egg(MASS, "omega_body = [0, 0, -2000]"), &[]);
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].contains("initial.omega_body = [0, 0, -2000]: ")
                && w[0].ends_with("2000 rpm is 209 rad/s"),
            "{}",
            w[0]
        );
        let w = lines(&egg(MASS, "psi_dot_deg = 200000"), &[]);
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(w[0].ends_with("more than 100 m g L"), "{}", w[0]);
        // No rpm hint when a spin in rpm would still be implausible.
        let w = lines(&egg(MASS, "phi_dot = 20000"), &[]);
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(w[0].ends_with("more than 100 m g L"), "{}", w[0]);
        // Without gravity there is no scale: no warning.
        let text = egg(MASS, "phi_dot = 1600") + "[effects]\ngravity = 0\n";
        assert_eq!(lines(&text, &[]), Vec::<String>::new());
        // Just below the bound: the ratio is quadratic in the rate.
        let s = parse(&egg(MASS, "phi_dot = 1600"), "egg.toml", &[] as &[&str]).expect("valid");
        let ratio = spin_ratio(&s.scene).expect("gravity");
        let below = 1600.0 * (MAX_SPIN_ENERGY / ratio).sqrt() * (1.0 - 1e-9);
        assert_eq!(
            lines(&egg(MASS, &format!("phi_dot = {below}")), &[]),
            Vec::<String>::new()
        );
    }

    #[test]
    fn the_issues_three_slips_warn_together_in_rule_order() {
        let w = lines(&egg("mass = 60", "theta = 80\nphi_dot = 1600"), &[]);
        let keys: Vec<&str> = w
            .iter()
            .map(|l| l.split(": ").nth(2).unwrap_or(""))
            .collect();
        assert_eq!(
            keys,
            [
                "initial.theta = 80",
                "body.mass = 60",
                "initial.phi_dot = 1600"
            ],
            "{w:?}"
        );
    }

    #[test]
    fn short_numbers() {
        assert_eq!(short(1.19e6), "1.19e6");
        assert_eq!(short(1.2e6), "1.2e6");
        assert_eq!(short(700.4), "700");
        assert_eq!(short(0.0628), "0.0628");
        assert_eq!(short(12.73), "12.7");
        assert_eq!(short(100.0), "100");
        assert_eq!(short(3e4), "30000");
    }
}
