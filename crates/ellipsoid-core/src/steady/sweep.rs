//! A family against a parameter: the spectrum at each value of one scenario key, and the
//! critical values where the stability changes, located by bisection (docs/physics.md,
//! "Steady motions and their stability", "Families against a parameter").
//!
//! A value the scenario refuses (an unknown or non-numeric key, a value out of its range)
//! refuses the sweep; a value the scenario takes but where the family has no steady motion
//! is a row of its own, with the reason.

use std::sync::atomic::{AtomicBool, Ordering};

use nalgebra::Complex;

use super::{Analysis, Family, Solve, analyse_solving};
use crate::error::{ModelError, Value};
use crate::scenario::{self, Scenario};
use crate::simulate::Scene;

/// Most values a sweep accepts.
pub const MAX_VALUES: usize = 100_000;

/// The keys a tilted family replaces by the unknown it solves for: varying them changes
/// nothing.
fn solved_keys(solve: Solve) -> &'static [&'static str] {
    match solve {
        Solve::Spin => &["initial.psi_dot", "initial.psi_dot_deg"],
        Solve::PhiDot => &["initial.phi_dot", "initial.phi_dot_deg"],
        Solve::Theta => &["initial.theta", "initial.theta_deg"],
    }
}

/// Relative width to which a critical value's bracket is narrowed.
const CRITICAL_TOLERANCE: f64 = 1e-13;

/// Where the stability changes between two values of the parameter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Critical {
    /// The parameter's value (the bracket's midpoint; its half-width ≤ 1e-13 relative).
    pub value: f64,
    pub kind: CriticalKind,
    /// Whether the motion is stable on the side of larger values.
    pub stable_above: bool,
    /// The eigenvalue that leaves the stable half-plane, just on the unstable side [1/s].
    pub eigenvalue: Complex<f64>,
}

/// How the stability changes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CriticalKind {
    /// Two imaginary pairs meet and leave the axis as a quartet ±α ± iβ (the spectrum
    /// is symmetric about the imaginary axis: the frictionless and rolling laws).
    Collision,
    /// A complex pair crosses the imaginary axis alone.
    Hopf,
    /// A real eigenvalue crosses zero.
    Real,
}

impl CriticalKind {
    /// Its name in tables and Python (`kind`).
    pub fn name(self) -> &'static str {
        match self {
            CriticalKind::Collision => "collision",
            CriticalKind::Hopf => "hopf",
            CriticalKind::Real => "real",
        }
    }
}

/// What a sweep reads of one value's analysis: its eigenvalues and its verdict
/// ([`Analysis`]; under the viscous law, [`super::viscous::ViscousSpin`]).
pub trait Stability: Clone {
    /// The eigenvalues [1/s], by decreasing real part.
    fn eigenvalues(&self) -> Vec<Complex<f64>>;
    /// Linear stability: no real part above `STABLE_TOLERANCE` of [`Stability::scale`].
    fn stable(&self) -> bool;
    /// The spectrum's scale max |λ| [1/s].
    fn scale(&self) -> f64;
    /// What moves in each mode and how clearly ([`super::Mode::clarity`]), in the order of
    /// the eigenvalues.
    fn names(&self) -> Vec<(&'static str, f64)>;
    /// Renames the modes (name and clarity), in the order of the eigenvalues.
    fn rename(&mut self, names: &[(&'static str, f64)]);
    /// The eigenvectors, in the order of the eigenvalues.
    fn vectors(&self) -> Vec<Vec<Complex<f64>>>;
    /// The largest real part [1/s].
    fn max_real(&self) -> f64 {
        self.eigenvalues()
            .iter()
            .map(|z| z.re)
            .fold(f64::NEG_INFINITY, f64::max)
    }
}

impl Stability for Analysis {
    fn eigenvalues(&self) -> Vec<Complex<f64>> {
        self.spectrum.eigenvalues()
    }
    fn stable(&self) -> bool {
        self.spectrum.stable()
    }
    fn scale(&self) -> f64 {
        self.spectrum.scale()
    }
    fn names(&self) -> Vec<(&'static str, f64)> {
        self.spectrum
            .modes
            .iter()
            .map(|m| (m.name, m.clarity))
            .collect()
    }
    fn rename(&mut self, names: &[(&'static str, f64)]) {
        for (mode, &(name, clarity)) in self.spectrum.modes.iter_mut().zip(names) {
            (mode.name, mode.clarity) = (name, clarity);
        }
    }
    fn vectors(&self) -> Vec<Vec<Complex<f64>>> {
        self.spectrum
            .modes
            .iter()
            .map(|m| m.vector.as_slice().to_vec())
            .collect()
    }
}

/// One value's analysis, or why there is none (e.g. no steady motion there).
pub type Row<T = Analysis> = Result<T, ModelError>;

/// The family along the values of one key.
#[derive(Debug, Clone)]
pub struct Sweep<T = Analysis> {
    pub family: Family,
    /// What a tilted family solves for.
    pub solve: Solve,
    /// The scenario key varied.
    pub key: String,
    pub values: Vec<f64>,
    pub rows: Vec<Row<T>>,
    /// Critical values, in increasing order.
    pub critical: Vec<Critical>,
}

/// The analysis of `family` (solving for `solve`) for `base` with `key` set to `value`
/// (`key=value` applied after the scenario's own overrides).
pub fn analyse_at(base: &Scenario, (family, solve): (Family, Solve), key: &str, value: f64) -> Row {
    at(base, key, value, &|scene| {
        analyse_solving(scene, family, solve)
    })
}

/// The scene of `base` with `key` set to `value` (`key=value` applied after the
/// scenario's own overrides), or the scenario's refusal as an error naming `key`.
fn scene_at(base: &Scenario, key: &str, value: f64) -> Result<Scene, ModelError> {
    let mut overrides = base.overrides.clone();
    overrides.push(format!("{key}={value:e}"));
    scenario::parse(&base.text, &base.source, &overrides)
        .map(|s| s.scene)
        .map_err(|e| {
            // Its rule alone when the error is the key's own, else the whole message.
            let why = if e.key.as_deref() == Some(key) {
                e.rule
            } else {
                e.to_string()
            };
            ModelError::invalid(
                key,
                value,
                format!("the scenario refuses this value: {why}"),
            )
        })
}

/// `analyse` of the scene of `base` with `key` set to `value` ([`scene_at`]).
fn at<T>(base: &Scenario, key: &str, value: f64, analyse: &dyn Fn(&Scene) -> Row<T>) -> Row<T> {
    analyse(&scene_at(base, key, value)?)
}

/// Whether `cancel` is given and set.
fn cancelled(cancel: Option<&AtomicBool>) -> bool {
    cancel.is_some_and(|c| c.load(Ordering::Relaxed))
}

/// Sweeps `key` over `values` (finite, at most [`MAX_VALUES`]) and locates every change
/// of stability between consecutive values that both have a steady motion.
pub fn sweep(
    base: &Scenario,
    family: Family,
    key: &str,
    values: &[f64],
) -> Result<Sweep, ModelError> {
    sweep_solving(base, family, Solve::Spin, key, values, None)
}

/// [`sweep`], a tilted family solving for the unknown `solve` names, stopped when
/// `cancel` is set (see [`sweep_with`]).
pub fn sweep_solving(
    base: &Scenario,
    family: Family,
    solve: Solve,
    key: &str,
    values: &[f64],
    cancel: Option<&AtomicBool>,
) -> Result<Sweep, ModelError> {
    sweep_with(
        base,
        (family, solve),
        key,
        values,
        &|scene| analyse_solving(scene, family, solve),
        cancel,
    )
}

/// [`sweep_solving`] with any analysis of a scene (the viscous spins':
/// [`super::viscous::sweep`]). Refused as a whole (an error naming `key`) if the scenario
/// refuses one of the values. When `cancel` is set (read before each value and each
/// bisection step) it stops with an error saying how many values were done: the caller
/// that set it reports the interruption instead.
pub fn sweep_with<T: Stability>(
    base: &Scenario,
    (family, solve): (Family, Solve),
    key: &str,
    values: &[f64],
    analyse: &dyn Fn(&Scene) -> Row<T>,
    cancel: Option<&AtomicBool>,
) -> Result<Sweep<T>, ModelError> {
    if values.is_empty() || values.len() > MAX_VALUES {
        return Err(ModelError::invalid(
            key,
            Value::Count(values.len() as u64, "values"),
            format!("a sweep takes 1 to {MAX_VALUES} values"),
        ));
    }
    // At φ̇ = 0 the spin is not solved for but given (`tilted::from_angles`).
    let init = &base.scene.initial;
    let spin_given =
        solve == Solve::Spin && init.angles.phi_dot == 0.0 && init.omega_body.is_none();
    if family.tilted() && !spin_given && solved_keys(solve).contains(&key) {
        let given: Vec<&str> = ["initial.theta", "initial.phi_dot", "initial.psi_dot"]
            .into_iter()
            .filter(|k| !solved_keys(solve).contains(k))
            .collect();
        return Err(ModelError::invalid(
            key,
            Value::Count(values.len() as u64, "values"),
            format!(
                "the {} family solves for {} here, which replaces this key: vary one of the given quantities ({}) or a body or gravity key instead",
                family.name(),
                solve.name(),
                given.join(", ")
            ),
        ));
    }
    if let Some(v) = values.iter().find(|v| !v.is_finite()) {
        return Err(ModelError::invalid(key, *v, "every value must be finite"));
    }
    let interrupted = |done: usize| {
        ModelError::invalid(
            key,
            Value::Count(values.len() as u64, "values"),
            format!("the sweep was interrupted after {done} of them"),
        )
    };
    let mut rows: Vec<Row<T>> = Vec::with_capacity(values.len());
    for (done, &v) in values.iter().enumerate() {
        if cancelled(cancel) {
            return Err(interrupted(done));
        }
        rows.push(analyse(&scene_at(base, key, v)?));
    }
    name_branches(&mut rows);
    let mut critical = Vec::new();
    for k in 1..values.len() {
        let (Ok(a), Ok(b)) = (&rows[k - 1], &rows[k]) else {
            continue;
        };
        if a.stable() != b.stable() {
            critical.push(locate(
                base,
                key,
                analyse,
                (values[k - 1], a),
                (values[k], b),
                cancel,
            ));
            if cancelled(cancel) {
                return Err(interrupted(values.len()));
            }
        }
    }
    critical.sort_by(|x, y| x.value.total_cmp(&y.value));
    Ok(Sweep {
        family,
        solve,
        key: key.to_owned(),
        values: values.to_vec(),
        rows,
        critical,
    })
}

/// Gives each branch of modes one name along the sweep (docs/physics.md, "Steady motions
/// and their stability", "The family's zero"): a branch is a mode followed from one
/// value's row to the next by nearest match ([`nearest_match`]: eigenvalue and
/// eigenvector), broken by a row without a motion or with another number of modes; its
/// name is that of its clearest member ([`super::Mode::clarity`]; on
/// a tie, the first), so that a mode whose eigenvector turns gradually from a pitch into
/// a roll keeps the name of where it is most clearly one of them.
fn name_branches<T: Stability>(rows: &mut [Row<T>]) {
    // The branch of each mode of each row, and each branch's clearest name so far.
    let mut branch_of: Vec<Vec<usize>> = Vec::with_capacity(rows.len());
    let mut names: Vec<(&'static str, f64)> = Vec::new();
    type Modes = (Vec<Complex<f64>>, Vec<Vec<Complex<f64>>>);
    let mut previous: Option<(Modes, Vec<usize>)> = None;
    for row in rows.iter() {
        let Ok(motion) = row else {
            branch_of.push(Vec::new());
            previous = None;
            continue;
        };
        let modes = (motion.eigenvalues(), motion.vectors());
        let count = modes.0.len();
        let ids: Vec<usize> = match &previous {
            Some((before, ids)) if before.0.len() == count => {
                let matched = nearest_match(before, &modes);
                matched.iter().map(|&i| ids[i]).collect()
            }
            _ => (0..count).map(|k| names.len() + k).collect(),
        };
        for (&id, named) in ids.iter().zip(motion.names()) {
            if id == names.len() {
                names.push(named);
            } else if named.1 > names[id].1 {
                names[id] = named;
            }
        }
        branch_of.push(ids.clone());
        previous = Some((modes, ids));
    }
    for (row, ids) in rows.iter_mut().zip(&branch_of) {
        if let Ok(motion) = row {
            let renamed: Vec<(&'static str, f64)> = ids.iter().map(|&id| names[id]).collect();
            motion.rename(&renamed);
        }
    }
}

/// For each mode of `after` (eigenvalues and eigenvectors), the index of its match in
/// `before` (as many modes): the closest pair first, then the closest of the rest, the
/// distance of modes i and j being |λi − λj| / max |λ| + 1 − |vi* vj| / (|vi| |vj|), so that
/// two eigenvalues that cross are told apart by what moves.
fn nearest_match(
    (lb, vb): &(Vec<Complex<f64>>, Vec<Vec<Complex<f64>>>),
    (la, va): &(Vec<Complex<f64>>, Vec<Vec<Complex<f64>>>),
) -> Vec<usize> {
    let m = la.len();
    let scale = lb
        .iter()
        .chain(la)
        .map(|z| z.norm())
        .fold(f64::MIN_POSITIVE, f64::max);
    let overlap = |x: &[Complex<f64>], y: &[Complex<f64>]| {
        let dot: Complex<f64> = x.iter().zip(y).map(|(a, b)| a.conj() * b).sum();
        let norms = x.iter().map(|a| a.norm_sqr()).sum::<f64>().sqrt()
            * y.iter().map(|b| b.norm_sqr()).sum::<f64>().sqrt();
        if norms > 0.0 { dot.norm() / norms } else { 0.0 }
    };
    let distance =
        |i: usize, j: usize| (lb[i] - la[j]).norm() / scale + 1.0 - overlap(&vb[i], &va[j]);
    let mut pairs: Vec<(f64, usize, usize)> = (0..m)
        .flat_map(|i| (0..m).map(move |j| (i, j)))
        .map(|(i, j)| (distance(i, j), i, j))
        .collect();
    pairs.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut matched = vec![usize::MAX; m];
    let mut used = vec![false; m];
    for (_, i, j) in pairs {
        if !used[i] && matched[j] == usize::MAX {
            used[i] = true;
            matched[j] = i;
        }
    }
    matched
}

/// Bisects between a stable and an unstable value until the bracket is
/// [`CRITICAL_TOLERANCE`] relative wide, then names the change from the unstable side.
/// The predicate is [`super::Spectrum::stable`] (Re λ ≤ 1e-9 max |λ|): at a collision
/// Re λ grows like √|p − p_c|, so the predicate flips within ~1e-18 |λ|²/(dRe²/dp) of p_c
/// and the bracket is the error; at a transversal crossing (Hopf, real) it flips where
/// Re λ = 1e-9 max |λ|, a distance 1e-9 max |λ| / (dRe λ/dp) from p_c.
/// A value in between without a steady motion, or `cancel` set, ends the search at the
/// bracket so far.
fn locate<T: Stability>(
    base: &Scenario,
    key: &str,
    analyse: &dyn Fn(&Scene) -> Row<T>,
    (p, a): (f64, &T),
    (q, b): (f64, &T),
    cancel: Option<&AtomicBool>,
) -> Critical {
    let stable_above = b.stable();
    let (mut stable, mut unstable) = if stable_above { (q, p) } else { (p, q) };
    let mut at_unstable = if stable_above { a.clone() } else { b.clone() };
    while (stable - unstable).abs() > CRITICAL_TOLERANCE * stable.abs().max(unstable.abs()) {
        let mid = 0.5 * (stable + unstable);
        if mid == stable || mid == unstable || cancelled(cancel) {
            break;
        }
        let Ok(an) = at(base, key, mid, analyse) else {
            break;
        };
        if an.stable() {
            stable = mid;
        } else {
            unstable = mid;
            at_unstable = an;
        }
    }
    let top = at_unstable.eigenvalues()[0];
    let scale = at_unstable.scale();
    // Classified on the unstable value of the sweep, where the eigenvalues are well
    // separated (at the bracket a collision's pair is split by only ~√ of the bracket).
    let kind = if top.im.abs() <= 1e-9 * scale {
        CriticalKind::Real
    } else if symmetric(if stable_above { a } else { b }) {
        CriticalKind::Collision
    } else {
        CriticalKind::Hopf
    };
    Critical {
        value: 0.5 * (stable + unstable),
        kind,
        stable_above,
        eigenvalue: top,
    }
}

/// Whether the spectrum is symmetric about the imaginary axis (every λ has a partner −λ̄
/// within 1e-6 of the scale), as for a Hamiltonian or reversible system: its stability
/// can change only where eigenvalues collide (or at zero).
fn symmetric<T: Stability>(an: &T) -> bool {
    let scale = an.scale();
    let eig = an.eigenvalues();
    eig.iter()
        .all(|z| eig.iter().any(|w| (w + z.conj()).norm() <= 1e-6 * scale))
}
