//! The rigid body: an ellipsoid with semi-axes (a, b, c) along its principal body axes,
//! centre of mass G offset from the geometric centre C0, central inertia about G — and up
//! to [`MAX_SPHERES`] contact spheres and [`MAX_RIMS`] rims fixed in the body (a tippe
//! top's stem, a top's peg; a coin's or a disc's edge: docs/physics.md, "Contact spheres"
//! and "Rims"), which touch the plane but carry no mass of their own (the inertia is the
//! whole body's). A body whose ellipsoid does not touch ([`Body::without_ellipsoid_contact`])
//! touches with its spheres and rims only: a coin is its rim.
//!
//! docs/physics.md, "Body, frames, conventions". The paper's body is a = b, c, with
//! `com_offset = (0, 0, −D2)` (paper eq. 7) and `I_b = diag(I, I, I3)`.

use nalgebra::{Matrix3, Vector3};

use crate::error::{Digits, ModelError, Value};

/// Most contact spheres a body may have.
pub const MAX_SPHERES: usize = 8;

/// The longest contact sphere name \[bytes\]: a name is a word that names output columns
/// (`normal_force_stem`) and, with another, a mode (`two_contacts@ellipsoid+stem`).
pub const MAX_NAME: usize = 24;

/// Largest contact sphere, and farthest sphere centre from the ellipsoid's centre C0, in
/// units of the body's largest semi-axis L (docs/scenarios.md, "Contact spheres"): a
/// stem or peg is a fraction of L to a few L long; beyond 10³ L the scales of the motion
/// (step sizes, the gap's tolerance of 10⁻⁹ of the body's extent) are those of the
/// sphere, not of the body, and the run grinds.
pub const MAX_SPHERE_SPAN: f64 = 1e3;

/// Smallest contact sphere radius, in units of L: the gap is resolved to 10⁻⁹ of the
/// body's extent (the guard of docs/physics.md, "The hybrid machine"), so a radius of
/// 10⁻⁶ L is a thousand times the smallest gap the run tells apart.
pub const MIN_SPHERE_RADIUS: f64 = 1e-6;

/// A contact sphere fixed in the body.
#[derive(Debug, Clone, PartialEq)]
pub struct Sphere {
    /// Its name (output columns and events name the surface by it).
    pub name: String,
    /// Its centre in body axes, from the ellipsoid's centre C0 \[m\].
    pub center: Vector3<f64>,
    /// Its radius \[m\].
    pub radius: f64,
}

/// Most rims a body may have.
pub const MAX_RIMS: usize = 4;

/// A rim fixed in the body: the torus swept by a sphere of radius `edge` whose centre runs
/// round the circle of radius `radius` about the body's z axis, centred at `center` on
/// that axis (docs/physics.md, "Rims"). `edge` = 0 is a sharp edge (a thin disc's rim).
#[derive(Debug, Clone, PartialEq)]
pub struct Rim {
    /// Its name (output columns and events name the surface by it).
    pub name: String,
    /// The centre of its circle in body axes, from the ellipsoid's centre C0, on the body
    /// z axis: (0, 0, z) \[m\].
    pub center: Vector3<f64>,
    /// R > 0: the radius of the circle through the centres of the edge's cross-section \[m\].
    pub radius: f64,
    /// r ≥ 0: the radius of the rounded edge; 0 a sharp edge \[m\].
    pub edge: f64,
}

/// A surface of the body that can touch the plane.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Surface {
    /// The ellipsoid.
    Ellipsoid,
    /// Contact sphere number k ([`Body::spheres`]).
    Sphere(usize),
    /// Rim number k ([`Body::rims`]).
    Rim(usize),
}

/// A validated rigid ellipsoid, with its contact spheres. Construct with [`Body::new`]
/// (and [`Body::with_spheres`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// Semi-axes (a, b, c) along body x, y, z \[m\].
    semi_axes: Vector3<f64>,
    /// Mass \[kg\].
    mass: f64,
    /// Central inertia tensor about G in body axes [kg·m²].
    inertia: Matrix3<f64>,
    /// Its inverse [1/(kg·m²)].
    inertia_inv: Matrix3<f64>,
    /// G − C0 in body axes \[m\].
    com_offset: Vector3<f64>,
    /// Its contact spheres.
    spheres: Vec<Sphere>,
    /// Its rims.
    rims: Vec<Rim>,
    /// Whether the ellipsoid itself touches the plane (false: only its spheres and rims
    /// do, the ellipsoid carrying the mass only).
    ellipsoid_contact: bool,
    /// The surface whose contact the geometry describes (`geometry::Contact::new`): the
    /// one touching the plane; the ellipsoid unless set ([`Body::touching`]).
    surface: Surface,
}

impl Body {
    /// Validates and builds a body.
    ///
    /// Rejects non-positive or non-finite semi-axes and mass, an inertia tensor that is
    /// not symmetric, whose principal moments are not positive or violate the triangle
    /// inequality (I_i ≤ I_j + I_k), and a centre of mass outside the ellipsoid
    /// (gᵀ A⁻² g ≥ 1).
    pub fn new(
        semi_axes: Vector3<f64>,
        mass: f64,
        inertia: Matrix3<f64>,
        com_offset: Vector3<f64>,
    ) -> Result<Self, ModelError> {
        // The contact geometry squares the semi-axes (the support function, Aₖ²nₖ): a
        // square that underflows to a subnormal or zero, or overflows, is refused.
        let (min, max) = (f64::MIN_POSITIVE.sqrt(), f64::MAX.sqrt());
        for (name, v) in ["a", "b", "c"].iter().zip(semi_axes.iter()) {
            if !(v.is_finite() && *v > 0.0) {
                return Err(ModelError::invalid(
                    format!("body.{name}"),
                    *v,
                    "a semi-axis must be a positive, finite length in metres",
                ));
            }
            if !(min..=max).contains(v) {
                return Err(ModelError::invalid(
                    format!("body.{name}"),
                    *v,
                    format!(
                        "a semi-axis must be from {min:.1e} to {max:.1e} m, so that its square is a normal float"
                    ),
                ));
            }
        }
        if !(mass.is_finite() && mass > 0.0) {
            return Err(ModelError::invalid(
                "body.mass",
                mass,
                "the mass must be positive and finite (kg)",
            ));
        }
        if inertia.iter().any(|v| !v.is_finite()) {
            return Err(ModelError::invalid(
                "body.inertia",
                Value::Matrix(Box::new(inertia), Digits::Short),
                "every entry must be finite (kg m^2)",
            ));
        }
        let scale = inertia.abs().max();
        if (inertia - inertia.transpose()).abs().max() > 1e-12 * scale {
            return Err(ModelError::invalid(
                "body.inertia",
                Value::Matrix(Box::new(inertia), Digits::Short),
                "the inertia tensor must be symmetric",
            ));
        }
        let moments = inertia.symmetric_eigenvalues();
        if moments.iter().any(|&m| m <= 0.0) {
            return Err(ModelError::invalid(
                "body.inertia",
                Value::vector(&moments),
                "principal moments of inertia must be positive",
            ));
        }
        let (i0, i1, i2) = (moments[0], moments[1], moments[2]);
        let slack = 1e-12 * (i0 + i1 + i2);
        if i0 > i1 + i2 + slack || i1 > i0 + i2 + slack || i2 > i0 + i1 + slack {
            return Err(ModelError::invalid(
                "body.inertia",
                Value::vector(&moments),
                "principal moments must satisfy the triangle inequality (each at most the sum of the other two)",
            ));
        }
        if com_offset.iter().any(|v| !v.is_finite()) {
            return Err(ModelError::invalid(
                "body.com_offset",
                Value::vector(&com_offset),
                "the centre-of-mass offset must be finite (m)",
            ));
        }
        let radial = com_offset.component_div(&semi_axes).norm_squared();
        if radial >= 1.0 {
            return Err(ModelError::invalid(
                "body.com_offset",
                Value::vector(&com_offset),
                format!(
                    "the centre of mass must lie inside the ellipsoid (g^T A^-2 g = {radial:.6} must be < 1)"
                ),
            ));
        }
        let inertia_inv = inertia.try_inverse().ok_or_else(|| {
            ModelError::invalid(
                "body.inertia",
                Value::Matrix(Box::new(inertia), Digits::Short),
                "the inertia tensor must be invertible",
            )
        })?;
        Ok(Body {
            semi_axes,
            mass,
            inertia,
            inertia_inv,
            com_offset,
            spheres: Vec::new(),
            rims: Vec::new(),
            ellipsoid_contact: true,
            surface: Surface::Ellipsoid,
        })
    }

    /// The body with contact spheres `spheres` (at most [`MAX_SPHERES`], names unique
    /// words of at most [`MAX_NAME`] bytes, centres finite, radii positive lengths whose squares are normal floats,
    /// as the semi-axes are). With L the largest semi-axis, each radius is from
    /// [`MIN_SPHERE_RADIUS`] L to [`MAX_SPHERE_SPAN`] L and each centre at most
    /// [`MAX_SPHERE_SPAN`] L from C0 (docs/scenarios.md, "Contact spheres").
    pub fn with_spheres(mut self, spheres: Vec<Sphere>) -> Result<Self, ModelError> {
        if spheres.len() > MAX_SPHERES {
            return Err(ModelError::invalid(
                "body.sphere",
                Value::Count(spheres.len() as u64, "entries"),
                format!("a body has at most {MAX_SPHERES} contact spheres"),
            ));
        }
        for (k, sp) in spheres.iter().enumerate() {
            let part = Part::new("sphere", k, &sp.name, self.semi_axes.max());
            part.name(
                spheres[..k].iter().any(|o| o.name == sp.name)
                    || self.rims.iter().any(|o| o.name == sp.name),
            )?;
            part.length("radius", sp.radius, false)?;
            part.center(sp.center)?;
        }
        self.spheres = spheres;
        Ok(self)
    }

    /// The body with rims `rims` (at most [`MAX_RIMS`]; names unique among its spheres and
    /// rims, as a sphere's are; centres on the body z axis, as far from C0 as a sphere's;
    /// radius R and edge r bounded as a sphere's radius is, the edge also 0:
    /// docs/scenarios.md, "Rims").
    pub fn with_rims(mut self, rims: Vec<Rim>) -> Result<Self, ModelError> {
        if rims.len() > MAX_RIMS {
            return Err(ModelError::invalid(
                "body.rim",
                Value::Count(rims.len() as u64, "entries"),
                format!("a body has at most {MAX_RIMS} rims"),
            ));
        }
        for (k, rim) in rims.iter().enumerate() {
            let part = Part::new("rim", k, &rim.name, self.semi_axes.max());
            part.name(
                rims[..k].iter().any(|o| o.name == rim.name)
                    || self.spheres.iter().any(|o| o.name == rim.name),
            )?;
            part.length("radius", rim.radius, false)?;
            part.length("edge", rim.edge, true)?;
            part.center(rim.center)?;
            if rim.center.x != 0.0 || rim.center.y != 0.0 {
                return Err(ModelError::invalid(
                    part.field("center"),
                    Value::vector(&rim.center),
                    "a rim's centre lies on the body's symmetry axis: [0.0, 0.0, z]",
                ));
            }
        }
        self.rims = rims;
        Ok(self)
    }

    /// The body with its ellipsoid not touching the plane: only its spheres and rims touch
    /// (a coin: its rim), the ellipsoid giving the body its size and, unless the inertia
    /// is given, its mass distribution. Refused for a body with neither.
    pub fn without_ellipsoid_contact(mut self) -> Result<Self, ModelError> {
        if self.spheres.is_empty() && self.rims.is_empty() {
            return Err(ModelError::invalid(
                "body.ellipsoid_contact",
                Value::Choice("false".into()),
                "a body whose ellipsoid does not touch needs a contact sphere or a rim ([[body.sphere]], [[body.rim]])",
            ));
        }
        self.ellipsoid_contact = false;
        let first = self.surfaces().next().unwrap_or(Surface::Ellipsoid);
        self.surface = first;
        Ok(self)
    }

    /// The same body, its geometry describing the contact of `surface`.
    pub fn touching(&self, surface: Surface) -> Body {
        Body {
            surface,
            ..self.clone()
        }
    }

    /// The paper's body: a = b, c, CM a distance `d2` below C0 on the axis, principal
    /// moments `i` (transverse, about G) and `i3` (axial).
    pub fn of_revolution(
        a: f64,
        c: f64,
        mass: f64,
        i: f64,
        i3: f64,
        d2: f64,
    ) -> Result<Self, ModelError> {
        Body::new(
            Vector3::new(a, a, c),
            mass,
            Matrix3::from_diagonal(&Vector3::new(i, i, i3)),
            Vector3::new(0.0, 0.0, -d2),
        )
    }

    /// Semi-axes (a, b, c) \[m\].
    pub fn semi_axes(&self) -> Vector3<f64> {
        self.semi_axes
    }
    /// Mass \[kg\].
    pub fn mass(&self) -> f64 {
        self.mass
    }
    /// Central inertia about G, body axes [kg·m²].
    pub fn inertia(&self) -> &Matrix3<f64> {
        &self.inertia
    }
    /// Inverse of the central inertia [1/(kg·m²)].
    pub fn inertia_inv(&self) -> &Matrix3<f64> {
        &self.inertia_inv
    }
    /// G − C0 in body axes \[m\].
    pub fn com_offset(&self) -> Vector3<f64> {
        self.com_offset
    }
    /// Its contact spheres.
    pub fn spheres(&self) -> &[Sphere] {
        &self.spheres
    }
    /// The surface whose contact the geometry describes.
    pub fn surface(&self) -> Surface {
        self.surface
    }
    /// Its rims.
    pub fn rims(&self) -> &[Rim] {
        &self.rims
    }
    /// Whether the ellipsoid itself touches the plane.
    pub fn ellipsoid_contact(&self) -> bool {
        self.ellipsoid_contact
    }
    /// Whether the body's only surface is its ellipsoid (no spheres, no rims): the
    /// paper's body, whose outputs name no surface.
    pub fn plain(&self) -> bool {
        self.spheres.is_empty() && self.rims.is_empty()
    }
    /// Every surface that touches: the ellipsoid (unless it does not touch), then the
    /// spheres, then the rims.
    pub fn surfaces(&self) -> impl Iterator<Item = Surface> + '_ {
        (self
            .ellipsoid_contact
            .then_some(Surface::Ellipsoid)
            .into_iter())
        .chain((0..self.spheres.len()).map(Surface::Sphere))
        .chain((0..self.rims.len()).map(Surface::Rim))
    }
    /// The name of `surface`: "ellipsoid", or its sphere's or rim's name.
    pub fn surface_name(&self, surface: Surface) -> &str {
        match surface {
            Surface::Ellipsoid => "ellipsoid",
            Surface::Sphere(k) => &self.spheres[k].name,
            Surface::Rim(k) => &self.rims[k].name,
        }
    }
    /// The body's extent from C0: its largest semi-axis, or the reach of a sphere or a
    /// rim, |c| + ρ or |c| + R + r, if farther \[m\].
    pub fn reach(&self) -> f64 {
        let spheres = self.spheres.iter().map(|s| s.center.norm() + s.radius);
        let rims = self
            .rims
            .iter()
            .map(|r| r.center.norm() + r.radius + r.edge);
        spheres.chain(rims).fold(self.semi_axes.max(), f64::max)
    }
}

/// A sphere or rim being validated: its kind, index, name and the body's size L.
struct Part<'a> {
    kind: &'static str,
    k: usize,
    name_: &'a str,
    size: f64,
}

impl<'a> Part<'a> {
    fn new(kind: &'static str, k: usize, name: &'a str, size: f64) -> Self {
        Part {
            kind,
            k,
            name_: name,
            size,
        }
    }

    /// Its key `body.{kind}[k].{key}`.
    fn field(&self, key: &str) -> String {
        format!("body.{}[{}].{key}", self.kind, self.k)
    }

    /// A word of at most [`MAX_NAME`] bytes, not `taken` and not "ellipsoid".
    fn name(&self, taken: bool) -> Result<(), ModelError> {
        let (kind, name) = (self.kind, self.name_);
        let word = |c: char| c.is_ascii_alphanumeric() || c == '_';
        if name.is_empty() || name.len() > MAX_NAME || !name.chars().all(word) {
            return Err(ModelError::invalid(
                self.field("name"),
                Value::Name(name.to_owned()),
                format!(
                    "a {kind}'s name is 1 to {MAX_NAME} ASCII letters, digits or underscores \
                     (it names output columns, e.g. normal_force_stem)"
                ),
            ));
        }
        if taken || name == "ellipsoid" {
            return Err(ModelError::invalid(
                self.field("name"),
                Value::Name(name.to_owned()),
                format!(
                    "{kind} names must be unique among spheres and rims and not \"ellipsoid\" (the body's own surface)"
                ),
            ));
        }
        Ok(())
    }

    /// A length whose square is a normal float, from [`MIN_SPHERE_RADIUS`] L to
    /// [`MAX_SPHERE_SPAN`] L; also 0 where `zero` allows it.
    fn length(&self, key: &str, v: f64, zero: bool) -> Result<(), ModelError> {
        if zero && v == 0.0 {
            return Ok(());
        }
        let kind = self.kind;
        let (min, max) = (f64::MIN_POSITIVE.sqrt(), f64::MAX.sqrt());
        let or_zero = if zero { " (or 0)" } else { "" };
        if !(v.is_finite() && (min..=max).contains(&v)) {
            return Err(ModelError::invalid(
                self.field(key),
                v,
                format!("a {kind}'s {key} must be a length{or_zero} from {min:.1e} to {max:.1e} m"),
            ));
        }
        let (small, large) = (MIN_SPHERE_RADIUS * self.size, MAX_SPHERE_SPAN * self.size);
        if !(small..=large).contains(&v) {
            return Err(ModelError::invalid(
                self.field(key),
                v,
                format!(
                    "a {kind}'s {key} must be{or_zero} from {MIN_SPHERE_RADIUS:.0e} to {MAX_SPHERE_SPAN:.0e} times the body's largest semi-axis ({} m): {small:.3e} to {large:.3e} m",
                    crate::error::number(self.size)
                ),
            ));
        }
        Ok(())
    }

    /// A finite centre at most [`MAX_SPHERE_SPAN`] L from C0.
    fn center(&self, c: Vector3<f64>) -> Result<(), ModelError> {
        let kind = self.kind;
        let max = f64::MAX.sqrt();
        if c.iter().any(|v| !(v.is_finite() && v.abs() <= max)) {
            return Err(ModelError::invalid(
                self.field("center"),
                Value::vector(&c),
                format!("a {kind}'s centre must be finite, each coordinate at most {max:.1e} m"),
            ));
        }
        let large = MAX_SPHERE_SPAN * self.size;
        if !(c.norm() <= large) {
            return Err(ModelError::invalid(
                self.field("center"),
                Value::vector(&c),
                format!(
                    "a {kind}'s centre must be at most {MAX_SPHERE_SPAN:.0e} times the body's largest semi-axis ({} m) from the ellipsoid's centre: {large:.3e} m; it is {:.3e} m",
                    crate::error::number(self.size),
                    c.norm()
                ),
            ));
        }
        Ok(())
    }
}

/// Central inertia of a homogeneous solid ellipsoid with semi-axes (a, b, c):
/// diag(b² + c², a² + c², a² + b²) · m / 5 [kg·m²].
pub fn uniform_inertia(semi_axes: Vector3<f64>, mass: f64) -> Matrix3<f64> {
    let sq = semi_axes.component_mul(&semi_axes);
    Matrix3::from_diagonal(&Vector3::new(sq.y + sq.z, sq.x + sq.z, sq.x + sq.y)) * (mass / 5.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ok_body() -> Result<Body, ModelError> {
        Body::of_revolution(0.025, 0.0175, 0.05, 3.8e-6, 6.25e-6, 0.003)
    }

    #[test]
    fn accepts_the_paper_body() {
        assert!(ok_body().is_ok());
    }

    #[test]
    fn rejects_each_rule_with_its_name() {
        let cases: [(Result<Body, ModelError>, &str, &str); 5] = [
            (
                Body::of_revolution(-0.025, 0.0175, 0.05, 3.8e-6, 6.25e-6, 0.003),
                "body.a = -0.025",
                "positive",
            ),
            (
                Body::of_revolution(0.025, 0.0175, 0.0, 3.8e-6, 6.25e-6, 0.003),
                "body.mass = 0",
                "positive",
            ),
            (
                Body::of_revolution(0.025, 0.0175, 0.05, 1e-6, 6.25e-6, 0.003),
                "body.inertia",
                "triangle inequality",
            ),
            (
                Body::of_revolution(0.025, 0.0175, 0.05, 3.8e-6, 6.25e-6, 0.02),
                "body.com_offset",
                "inside the ellipsoid",
            ),
            (
                Body::of_revolution(0.025, 0.0175, 0.05, -3.8e-6, 6.25e-6, 0.0),
                "body.inertia",
                "positive",
            ),
        ];
        for (result, name, rule) in cases {
            let msg = result.unwrap_err().to_string();
            assert!(msg.starts_with(name) && msg.contains(rule), "{msg}");
        }
    }

    #[test]
    fn uniform_sphere_inertia_is_two_fifths_m_r_squared() {
        let i = uniform_inertia(Vector3::new(0.1, 0.1, 0.1), 2.0);
        assert!((i[(0, 0)] - 0.4 * 2.0 * 0.01).abs() < 1e-15);
    }
}
