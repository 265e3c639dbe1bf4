//! The format: walking the tree into a `Scene` (body, initial state, contact, effects,
//! solver, output) and the `[check]` table.

use super::*;

/// An empty table standing in for an optional table that is absent.
pub(super) static EMPTY: Node = Node {
    value: Value::Table(Vec::new()),
    origin: Origin::File(0..0),
};

pub(super) fn build(ctx: &Ctx<'_>, tree: &Node) -> Result<(Scene, Check)> {
    let root = ctx.table_of("", tree, &tree.origin, &keys(""), "the scenario")?;
    let body = read_body(ctx, tree, &root)?;
    let contact = read_contact(ctx, &root)?;
    let disc = read_disc(ctx, &root, contact)?;
    let landing = read_landing(ctx, &root)?;
    let initial = read_initial(ctx, &root, contact)?;
    let (gravity, effects) = read_effects(ctx, &root)?;
    let solver = read_solver(ctx, &root)?;
    let (t_end, sample_times) = read_output(ctx, &root)?;
    let check = read_check(ctx, &root)?;
    let observe = read_observe(ctx, &root, &Layout::of(&body))?;
    let sections = read_sections(ctx, &root, &Layout::of(&body))?;
    let scene = Scene {
        body,
        gravity,
        contact,
        disc,
        landing,
        effects,
        initial,
        solver,
        t_end,
        sample_times,
        observe,
        sections,
    };
    scene.validate().map_err(|e| ctx.model(tree, &e))?;
    Ok((scene, check))
}

pub(super) fn read_body(ctx: &Ctx<'_>, tree: &Node, root: &Sec<'_>) -> Result<Body> {
    let sec = ctx
        .section(
            root,
            "body",
            &keys("body"),
            "semi-axes, mass, centre of mass, inertia",
        )?
        .ok_or_else(|| {
            ctx.missing(
                root,
                "body",
                "a scenario needs a [body] table (semi-axes a and c, mass, inertia)",
            )
        })?;
    let a = ctx.required(&sec, "a", "the semi-axis along body x (m)")?;
    let b = ctx
        .number(&sec, "b", "the semi-axis along body y (m)")?
        .map_or(a, |(v, _)| v);
    let c = ctx.required(
        &sec,
        "c",
        "the semi-axis along the symmetry axis, body z (m)",
    )?;
    let mass = ctx.required(&sec, "mass", "the mass (kg)")?;
    ctx.exclusive(
        &sec,
        "com_offset",
        "com_offset_vector",
        "the distance D2 of G below the centre on the axis, or the general vector G − C0",
    )?;
    let com = if let Some((d2, _)) = ctx.number(
        &sec,
        "com_offset",
        "D2, the distance of G below the geometric centre along body z (m)",
    )? {
        Vector3::new(0.0, 0.0, -d2)
    } else if let Some(v) =
        ctx.numbers::<3>(&sec, "com_offset_vector", "G − C0 in body axes (m)")?
    {
        Vector3::from(v)
    } else {
        Vector3::zeros()
    };
    let axes = Vector3::new(a, b, c);
    let inertia = read_inertia(ctx, &sec, axes, mass, com)?;
    let (spheres, rims) = read_parts(ctx, &sec)?;
    let touches = match sec.get("ellipsoid_contact") {
        None => true,
        Some(g) => match g.node().value {
            Value::Bool(b) => b,
            _ => {
                return Err(ctx.wrong_type(
                    &sec,
                    g,
                    "true or false: whether the ellipsoid itself touches the plane",
                ));
            }
        },
    };
    Body::new(axes, mass, inertia, com)
        .and_then(|body| body.with_spheres(spheres))
        .and_then(|body| body.with_rims(rims))
        .and_then(|body| {
            if touches {
                Ok(body)
            } else {
                body.without_ellipsoid_contact()
            }
        })
        .map_err(|e| ctx.model(tree, &e))
}

/// Whether `s` is a contact sphere's or rim's name: 1 to [`MAX_NAME`] ASCII letters,
/// digits or underscores (`Body::with_spheres`' rule, checked here to point at the TOML
/// value).
fn is_part_name(s: &str) -> bool {
    (1..=MAX_NAME).contains(&s.len()) && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// A contact sphere or rim read from its table: its name, its centre and its radius, and a
/// rim's edge.
struct Part {
    name: String,
    center: Vector3<f64>,
    radius: f64,
    edge: f64,
}

/// The `[[body.sphere]]` and `[[body.rim]]` arrays of tables: contact spheres and rims
/// fixed in the body (docs/scenarios.md, "Contact spheres" and "Rims"); names unique
/// among both.
fn read_parts(ctx: &Ctx<'_>, body: &Sec<'_>) -> Result<(Vec<Sphere>, Vec<Rim>)> {
    let spheres = read_part_tables(ctx, body, "sphere", MAX_SPHERES, &[])?;
    let taken: Vec<&str> = spheres.iter().map(|p| p.name.as_str()).collect();
    let rims = read_part_tables(ctx, body, "rim", MAX_RIMS, &taken)?;
    let spheres = (spheres.into_iter())
        .map(|p| Sphere {
            name: p.name,
            center: p.center,
            radius: p.radius,
        })
        .collect();
    let rims = (rims.into_iter())
        .map(|p| Rim {
            name: p.name,
            center: p.center,
            radius: p.radius,
            edge: p.edge,
        })
        .collect();
    Ok((spheres, rims))
}

/// The `[[body.{kind}]]` array of tables (`kind` "sphere" or "rim"), at most `most`, no
/// name one of `taken`.
fn read_part_tables(
    ctx: &Ctx<'_>,
    body: &Sec<'_>,
    kind: &str,
    most: usize,
    taken: &[&str],
) -> Result<Vec<Part>> {
    let rim = kind == "rim";
    let Some(got) = body.get(kind) else {
        return Ok(Vec::new());
    };
    let Value::Array(items) = &got.node().value else {
        return Err(ctx.wrong_type(
            body,
            got,
            &format!("an array of tables ([[body.{kind}]] entries)"),
        ));
    };
    if items.len() > most {
        let what = if rim { "rims" } else { "contact spheres" };
        return Err(ctx.bad(
            ErrorKind::Invalid,
            body,
            got,
            format!("{} entries; a body has at most {most} {what}", items.len()),
        ));
    }
    let mut out: Vec<Part> = Vec::with_capacity(items.len());
    for (k, item) in items.iter().enumerate() {
        let what = if rim {
            "a rim: name, center, radius, edge"
        } else {
            "a contact sphere: name, center, radius"
        };
        let sec = ctx.table_of(
            &format!("body.{kind}[{k}]"),
            item,
            &item.origin,
            &keys(&format!("body.{kind}")),
            what,
        )?;
        let name = match sec.get("name") {
            None => {
                let example = if rim { "edge" } else { "stem" };
                return Err(ctx.missing(
                    &sec,
                    "name",
                    format!("give the {kind} a name (a string, e.g. \"{example}\")"),
                ));
            }
            Some(g) => match &g.node().value {
                Value::Str(s) if is_part_name(s) => {
                    let dup = out.iter().any(|o| &o.name == s) || taken.contains(&s.as_str());
                    if s == "ellipsoid" || dup {
                        return Err(ctx.bad(
                            ErrorKind::Invalid,
                            &sec,
                            g,
                            format!("{kind} names must be unique among spheres and rims and not \"ellipsoid\" (the body's own surface)"),
                        ));
                    }
                    s.clone()
                }
                Value::Str(_) => {
                    return Err(ctx.bad(
                        ErrorKind::Invalid,
                        &sec,
                        g,
                        format!(
                            "a {kind}'s name is 1 to {MAX_NAME} ASCII letters, digits or \
                             underscores (it names output columns, e.g. normal_force_stem)"
                        ),
                    ));
                }
                _ => return Err(ctx.wrong_type(&sec, g, &format!("a string: the {kind}'s name"))),
            },
        };
        let centre = if rim {
            "the centre of the rim's circle in body axes, from the ellipsoid's centre, on the symmetry axis: [0.0, 0.0, z] (m)"
        } else {
            "the sphere's centre in body axes, from the ellipsoid's centre (m)"
        };
        let center = ctx
            .numbers::<3>(&sec, "center", centre)?
            .ok_or_else(|| ctx.missing(&sec, "center", format!("give {centre}")))?;
        if rim && (center[0] != 0.0 || center[1] != 0.0) {
            return Err(ctx.bad(
                ErrorKind::Invalid,
                &sec,
                sec.get("center").expect("just read"),
                "a rim's centre lies on the body's symmetry axis: [0.0, 0.0, z]",
            ));
        }
        let radius_what = if rim {
            "the radius R of the rim's circle through the centres of its edge's cross-section (m)"
        } else {
            "the sphere's radius (m)"
        };
        let radius = ctx
            .checked(
                &sec,
                "radius",
                radius_what,
                |v| v > 0.0,
                "a radius must be positive and finite (m)",
            )?
            .ok_or_else(|| ctx.missing(&sec, "radius", format!("give {radius_what}")))?;
        let edge = if rim {
            let edge_what = "the radius r of the rim's rounded edge, 0 for a sharp edge (m)";
            ctx.checked(
                &sec,
                "edge",
                edge_what,
                |v| v >= 0.0,
                "an edge radius must be finite and at least 0 (m)",
            )?
            .ok_or_else(|| ctx.missing(&sec, "edge", format!("give {edge_what}")))?
        } else {
            0.0
        };
        out.push(Part {
            name,
            center: Vector3::from(center),
            radius,
            edge,
        });
    }
    Ok(out)
}

pub(super) fn read_inertia(
    ctx: &Ctx<'_>,
    sec: &Sec<'_>,
    axes: Vector3<f64>,
    mass: f64,
    com: Vector3<f64>,
) -> Result<Matrix3<f64>> {
    const FORMS: &str = "[I1, I2, I3] (principal moments about G, kg m^2), a symmetric 3x3 array [[..], [..], [..]], or \"uniform\"";
    let got = sec.get("inertia").ok_or_else(|| {
        ctx.missing(
            sec,
            "inertia",
            format!("give the central inertia in body axes: {FORMS}"),
        )
    })?;
    let numbers = |items: &[Node]| items.iter().map(Node::as_f64).collect::<Option<Vec<f64>>>();
    match &got.node().value {
        Value::Str(s) if s == "uniform" => {
            if com != Vector3::zeros() {
                return Err(ctx.bad(
                    ErrorKind::Invalid,
                    sec,
                    got,
                    "\"uniform\" is a homogeneous body, whose centre of mass is the geometric centre; with a centre-of-mass offset give the moments about G",
                ));
            }
            Ok(uniform_inertia(axes, mass))
        }
        Value::Array(items) if items.len() == 3 => {
            if let Some(d) = numbers(items) {
                return Ok(Matrix3::from_diagonal(&Vector3::new(d[0], d[1], d[2])));
            }
            let rows: Option<Vec<Vec<f64>>> = items
                .iter()
                .map(|row| match &row.value {
                    Value::Array(r) if r.len() == 3 => numbers(r),
                    _ => None,
                })
                .collect();
            match rows {
                Some(r) => Ok(Matrix3::from_fn(|i, j| r[i][j])),
                None => Err(ctx.bad(ErrorKind::Type, sec, got, format!("expected {FORMS}"))),
            }
        }
        _ => Err(ctx.bad(ErrorKind::Type, sec, got, format!("expected {FORMS}"))),
    }
}

pub(super) fn read_contact(ctx: &Ctx<'_>, root: &Sec<'_>) -> Result<ContactModel> {
    let models = quoted(&ContactModel::NAMES);
    let sec = ctx
        .section(root, "contact", &keys("contact"), "model and friction")?
        .ok_or_else(|| {
            ctx.missing(
                root,
                "contact",
                format!("a scenario needs a [contact] table with model = {models}"),
            )
        })?;
    let (model, _) = ctx
        .choice(&sec, "model", &ContactModel::NAMES)?
        .ok_or_else(|| {
            ctx.missing(
                &sec,
                "model",
                format!("give the contact model, one of {models}"),
            )
        })?;
    let friction = ctx.checked(
        &sec,
        "friction",
        "μ, the Coulomb coefficient",
        |v| v >= 0.0,
        "the Coulomb coefficient must be finite and non-negative",
    )?;
    let need = || {
        ctx.missing(
            &sec,
            "friction",
            format!(
                "the {model} model needs μ, the Coulomb friction coefficient (e.g. friction = 0.3)"
            ),
        )
    };
    let no_friction = |why: &str| {
        match sec.get("friction") {
        Some(got) => Err(ctx.bad(ErrorKind::Invalid, &sec, got, format!("the {model} model takes no friction coefficient ({why}); remove it, or use model = \"coulomb\""))),
        None => Ok(()),
    }
    };
    let viscous = ctx.checked(
        &sec,
        "viscous_friction",
        "μ_v, the viscous coefficient (s/m)",
        |v| (0.0..=MAX_VISCOUS_FRICTION).contains(&v),
        &format!(
            "the viscous coefficient must be finite and within [0, {}] s/m",
            number(MAX_VISCOUS_FRICTION)
        ),
    )?;
    if let (Some(got), false) = (sec.get("viscous_friction"), model == "viscous") {
        return Err(ctx.bad(
            ErrorKind::Invalid,
            &sec,
            got,
            format!("the {model} model takes no viscous coefficient; remove it, or use model = \"viscous\""),
        ));
    }
    Ok(match ContactModel::named(model) {
        Some(ContactModel::Viscous { .. }) => {
            no_friction("its friction is viscous: give viscous_friction")?;
            ContactModel::Viscous {
                viscous_friction: viscous.ok_or_else(|| {
                    ctx.missing(
                        &sec,
                        "viscous_friction",
                        "the viscous model needs μ_v, the viscous coefficient in s/m (e.g. viscous_friction = 0.5)",
                    )
                })?,
            }
        }
        Some(ContactModel::Frictionless) => {
            no_friction("the plane exerts no friction")?;
            ContactModel::Frictionless
        }
        Some(ContactModel::Rolling) => {
            no_friction("rolling assumes unlimited friction")?;
            ContactModel::Rolling
        }
        Some(ContactModel::Sliding { .. }) => ContactModel::Sliding {
            friction: friction.ok_or_else(need)?,
        },
        Some(ContactModel::Coulomb { .. }) => ContactModel::Coulomb {
            friction: friction.ok_or_else(need)?,
        },
        None => return Err(unknown_name(ctx, &sec, "model", &ContactModel::NAMES)),
    })
}

/// The error of a name that `choice` accepted but no dispatch arm reads (a name list
/// longer than its enum): names the key, the value and the names allowed.
fn unknown_name(ctx: &Ctx<'_>, sec: &Sec<'_>, key: &str, names: &[&str]) -> ScenarioError {
    let got = sec.get(key).expect("a name was read");
    ctx.bad(
        ErrorKind::Invalid,
        sec,
        got,
        format!("expected one of {}", quoted(names)),
    )
}

/// `contact_radius` and `contact_law` of `[contact]`: a contact disc (R > 0), or `None`
/// for a point contact. The rules combining them with the body and the model are
/// `Scene::validate`'s.
pub(super) fn read_disc(
    ctx: &Ctx<'_>,
    root: &Sec<'_>,
    contact: ContactModel,
) -> Result<Option<ContactDisc>> {
    let Some(sec) = ctx.section(root, "contact", &keys("contact"), "model and friction")? else {
        return Ok(None);
    };
    let radius = ctx.checked(
        &sec,
        "contact_radius",
        "R, the radius of the contact disc (m)",
        |v| v >= 0.0,
        "the contact radius must be finite and non-negative (m); 0 is a point contact",
    )?;
    let law = ctx
        .choice(&sec, "contact_law", &contensou::Law::NAMES)?
        .map(|(name, got)| (contensou::Law::from_name(name).expect("one of NAMES"), got));
    if let (Some((_, got)), None) = (law, contact.friction()) {
        return Err(ctx.bad(
            ErrorKind::Invalid,
            &sec,
            got,
            "the contact law is the friction law of a contact disc: it needs model = \"sliding\" or \"coulomb\" and contact_radius > 0",
        ));
    }
    Ok(radius.filter(|r| *r > 0.0).map(|radius| ContactDisc {
        radius,
        law: law.map_or_else(contensou::Law::default, |(l, _)| l),
    }))
}

/// `[contact] restitution` and `on_lift_off` (docs/physics.md, "Flight"), `flat_tilt`
/// (docs/physics.md, "Rims": "The flat landing").
pub(super) fn read_landing(ctx: &Ctx<'_>, root: &Sec<'_>) -> Result<Landing> {
    let Some(sec) = ctx.section(root, "contact", &keys("contact"), "model and friction")? else {
        return Ok(Landing::default());
    };
    let restitution = ctx
        .checked(
            &sec,
            "restitution",
            "e, the energetic coefficient of restitution",
            |v| (0.0..=1.0).contains(&v),
            "the coefficient of restitution must lie in [0, 1] (0: plastic, 1: elastic)",
        )?
        .unwrap_or(Landing::default().restitution);
    let lift_off = match ctx.choice(&sec, "on_lift_off", &LiftOff::NAMES)? {
        Some(("stop", _)) => LiftOff::Stop,
        _ => LiftOff::Fly,
    };
    let flat_tilt = ctx
        .checked(
            &sec,
            "flat_tilt",
            "sin α, the tilt at which a rim lands on its face",
            |v| (geometry::FLAT_TILT..=Landing::MAX_FLAT_TILT).contains(&v),
            &format!(
                "the flat tilt must lie in [{:e}, {:e}] (sin α; the rim's far side within 2R sin α of the plane)",
                geometry::FLAT_TILT,
                Landing::MAX_FLAT_TILT
            ),
        )?
        .unwrap_or(geometry::FLAT_TILT);
    Ok(Landing {
        restitution,
        lift_off,
        flat_tilt,
    })
}

pub(super) fn read_initial(
    ctx: &Ctx<'_>,
    root: &Sec<'_>,
    contact: ContactModel,
) -> Result<InitialState> {
    let sec = ctx
        .section(
            root,
            "initial",
            &keys("initial"),
            "initial angles, rates, position and velocity",
        )?
        .unwrap_or(Sec {
            path: "initial".into(),
            node: &EMPTY,
        });
    let orientation = if let Some(got) = sec.get("rotation") {
        for key in ["theta", "phi", "psi"] {
            for k in [key.to_owned(), format!("{key}_deg")] {
                if sec.get(&k).is_some() {
                    return Err(ctx.bad(
                        ErrorKind::Conflict,
                        &sec,
                        got,
                        format!(
                            "give either {} or the Euler angles (here {}), not both",
                            sec.full("rotation"),
                            sec.full(&k)
                        ),
                    ));
                }
            }
        }
        let r = read_rotation(ctx, &sec, got)?;
        let e =
            EulerAngles::from_rotation(r.to_rotation_matrix().matrix(), &Vector3::zeros(), None);
        (e.theta, e.phi, e.psi)
    } else {
        (
            ctx.angle(
                &sec,
                "theta",
                "θ, the tilt of the symmetry axis from the vertical (rad)",
            )?
            .unwrap_or(0.0),
            ctx.angle(&sec, "phi", "φ, the precession angle (rad)")?
                .unwrap_or(0.0),
            ctx.angle(&sec, "psi", "ψ, the spin angle (rad)")?
                .unwrap_or(0.0),
        )
    };
    ctx.exclusive(
        &sec,
        "omega_body",
        "omega_body_deg",
        "radians or degrees per second",
    )?;
    let omega = match ctx.numbers::<3>(&sec, "omega_body", "the body angular velocity (rad/s)")? {
        Some(w) => Some(Vector3::from(w)),
        None => ctx
            .numbers::<3>(&sec, "omega_body_deg", "the body angular velocity (deg/s)")?
            .map(|w| Vector3::from(w).map(f64::to_radians)),
    };
    let mut rates = [0.0; 3];
    for (rate, key) in rates.iter_mut().zip(["theta_dot", "phi_dot", "psi_dot"]) {
        if let Some(got) = [key.to_owned(), format!("{key}_deg")]
            .iter()
            .find_map(|k| sec.get(k))
            .filter(|_| omega.is_some())
        {
            let body_key = if sec.get("omega_body").is_some() {
                "omega_body"
            } else {
                "omega_body_deg"
            };
            return Err(ctx.bad(
                ErrorKind::Conflict,
                &sec,
                got,
                format!(
                    "give either {} or the Euler-angle rates, not both",
                    sec.full(body_key)
                ),
            ));
        }
        *rate = ctx
            .angle(&sec, key, "an Euler-angle rate (rad/s)")?
            .unwrap_or(0.0);
    }
    let (theta, phi, psi) = orientation;
    let angles = EulerAngles {
        theta,
        phi,
        psi,
        theta_dot: rates[0],
        phi_dot: rates[1],
        psi_dot: rates[2],
    };
    let position = ctx
        .numbers::<2>(&sec, "position", "x, y of G (m)")?
        .map_or_else(Vector2::zeros, Vector2::from);
    let height = ctx
        .checked(
            &sec,
            "height",
            "the gap of the lowest point above the plane (m)",
            |v| v >= 0.0,
            "the gap above the plane must be finite and non-negative (m)",
        )?
        .unwrap_or(0.0);
    let three = sec
        .get("velocity")
        .is_some_and(|got| matches!(&got.node().value, Value::Array(a) if a.len() == 3));
    let (velocity, velocity_z) = if three {
        let v = ctx.numbers::<3>(&sec, "velocity", "the velocity of G (m/s)")?;
        (v.map(|v| Vector2::new(v[0], v[1])), v.map(|v| v[2]))
    } else {
        let v = ctx.numbers::<2>(
            &sec,
            "velocity",
            "the horizontal velocity of G, [vx, vy] (or [vx, vy, vz] in flight) (m/s)",
        )?;
        (v.map(Vector2::from), None)
    };
    if let Some(got) = sec.get("velocity") {
        if velocity_z.is_some() && height == 0.0 {
            return Err(ctx.bad(ErrorKind::Invalid, &sec, got, "a vertical velocity (third component) needs a body that starts in flight (initial.height > 0); touching the plane, v_Gz follows from the contact"));
        }
        if contact == ContactModel::Rolling && height == 0.0 {
            return Err(ctx.bad(ErrorKind::Invalid, &sec, got, "not allowed for the rolling model on the plane, where the velocity of G is implied by ω (v_G = −ω × r); remove it (or start in flight, initial.height > 0)"));
        }
    }
    for (name, v) in [
        ("position", position.as_slice()),
        (
            "velocity",
            velocity.as_ref().map_or(&[][..], |v| v.as_slice()),
        ),
        (
            "omega_body",
            omega.as_ref().map_or(&[][..], |v| v.as_slice()),
        ),
    ] {
        if v.iter().any(|x| !x.is_finite()) {
            let got = sec
                .get(name)
                .or_else(|| sec.get(&format!("{name}_deg")))
                .expect("a value was read");
            return Err(ctx.bad(
                ErrorKind::Invalid,
                &sec,
                got,
                "every component must be finite",
            ));
        }
    }
    Ok(InitialState {
        angles,
        omega_body: omega,
        position,
        velocity,
        height,
        velocity_z,
    })
}

/// `rotation = [{ axis = "x", angle = … }, …]`: R = R1 R2 … (body → world).
pub(super) fn read_rotation(
    ctx: &Ctx<'_>,
    sec: &Sec<'_>,
    got: Got<'_>,
) -> Result<UnitQuaternion<f64>> {
    const FORM: &str = "an array of { axis = \"x\" | \"y\" | \"z\", angle = rad (or angle_deg) } tables, composed as R = R1 R2 …";
    let Value::Array(items) = &got.node().value else {
        return Err(ctx.wrong_type(sec, got, FORM));
    };
    let mut q = UnitQuaternion::identity();
    for (i, item) in items.iter().enumerate() {
        let path = format!("{}[{i}]", sec.full("rotation"));
        let rot = ctx.table_of(&path, item, &item.origin, &keys("initial.rotation"), FORM)?;
        let (axis, _) = ctx.choice(&rot, "axis", &ROTATION_AXES)?.ok_or_else(|| ctx.missing(&rot, "axis", "give the axis, \"x\", \"y\" or \"z\" (world and body axes coincide before the rotation)"))?;
        let angle = ctx
            .angle(&rot, "angle", "the rotation angle (rad)")?
            .ok_or_else(|| {
                ctx.missing(
                    &rot,
                    "angle",
                    "give the angle in radians (angle) or degrees (angle_deg)",
                )
            })?;
        if !angle.is_finite() {
            return Err(ctx.bad(
                ErrorKind::Invalid,
                &rot,
                rot.get("angle")
                    .or_else(|| rot.get("angle_deg"))
                    .expect("just read"),
                "the angle must be finite",
            ));
        }
        let axis = match axis {
            "x" => Vector3::x_axis(),
            "y" => Vector3::y_axis(),
            _ => Vector3::z_axis(),
        };
        q *= UnitQuaternion::from_axis_angle(&axis, angle);
    }
    Ok(q)
}

/// `[effects]`: g, then each optional effect of [`EffectSet`] from its key (the struct
/// literal names every field, so an effect added to `crate::effects` without a reader here
/// does not compile).
pub(super) fn read_effects(ctx: &Ctx<'_>, root: &Sec<'_>) -> Result<(f64, EffectSet)> {
    let Some(sec) = ctx.section(
        root,
        "effects",
        &keys("effects"),
        "gravity and optional dissipation",
    )?
    else {
        return Ok((DEFAULT_GRAVITY, EffectSet::default()));
    };
    let gravity = ctx
        .checked(
            &sec,
            "gravity",
            "g (m/s^2)",
            |v| v >= 0.0,
            "g must be finite and non-negative (m/s^2)",
        )?
        .unwrap_or(DEFAULT_GRAVITY);
    let effects = EffectSet {
        rolling_resistance: resistance(
            ctx,
            &sec,
            "rolling_resistance",
            "c_r, the rolling-resistance length (m)",
            "m",
        )?
        .map(|(coefficient, regularisation)| RollingResistance {
            coefficient,
            regularisation,
        }),
        spin_friction: resistance(
            ctx,
            &sec,
            "spin_friction",
            "c_s, the spin-friction length (m)",
            "m",
        )?
        .map(|(coefficient, regularisation)| SpinFriction {
            coefficient,
            regularisation,
        }),
        air_drag: read_air_drag(ctx, &sec)?,
        rolling_friction: resistance(
            ctx,
            &sec,
            "rolling_friction",
            "mu_r, the rolling-friction coefficient (1)",
            "1",
        )?
        .map(|(coefficient, regularisation)| RollingFriction {
            coefficient,
            regularisation,
        }),
        air_film: air_table(ctx, &sec, "air_film", "{ viscosity = mu (Pa s) }")?
            .map(|sub| {
                Ok(AirFilm {
                    viscosity: air_property(ctx, &sub, VISCOSITY)?,
                })
            })
            .transpose()?,
        air_boundary_layer: air_table(
            ctx,
            &sec,
            "air_boundary_layer",
            "{ viscosity = mu (Pa s), density = rho (kg/m^3) }",
        )?
        .map(|sub| {
            Ok(AirBoundaryLayer {
                viscosity: air_property(ctx, &sub, VISCOSITY)?,
                density: air_property(ctx, &sub, DENSITY)?,
            })
        })
        .transpose()?,
    };
    Ok((gravity, effects))
}

/// `air_drag = { linear = k (kg/s), angular = k_ω (kg m²/s) }`, each coefficient
/// finite and ≥ 0, absent = 0.
fn read_air_drag(ctx: &Ctx<'_>, effects: &Sec<'_>) -> Result<Option<AirDrag>> {
    let path = effects.full("air_drag");
    let Some(sec) = ctx.section(
        effects,
        "air_drag",
        &keys(&path),
        "{ linear = k (kg/s), angular = k_ω (kg m^2/s) }",
    )?
    else {
        return Ok(None);
    };
    let linear = ctx.checked(
        &sec,
        "linear",
        "k, the linear drag coefficient (kg/s)",
        |v| v >= 0.0,
        "the drag coefficient must be finite and non-negative (kg/s)",
    )?;
    let angular = ctx.checked(
        &sec,
        "angular",
        "k_ω, the angular drag coefficient (kg m^2/s)",
        |v| v >= 0.0,
        "the drag coefficient must be finite and non-negative (kg m^2/s)",
    )?;
    Ok(Some(AirDrag {
        linear: linear.unwrap_or(0.0),
        angular: angular.unwrap_or(0.0),
    }))
}

/// An air law's property: its key, what it is, and the rule (finite, positive, at most
/// the bound, with its reason).
type Property = (&'static str, &'static str, fn(f64) -> bool, &'static str);

/// μ: a gas's or a thin liquid's; beyond 10 Pa s the film no longer is a lubricating gap.
const VISCOSITY: Property = (
    "viscosity",
    "mu, the air's dynamic viscosity (Pa s)",
    |v| v > 0.0 && v <= 10.0,
    "the viscosity must be positive and at most 10 Pa s (air: 1.8e-5 Pa s)",
);

/// ρ: a fluid's, at most 1e4 kg/m³.
const DENSITY: Property = (
    "density",
    "rho, the air's density (kg/m^3)",
    |v| v > 0.0 && v <= 1e4,
    "the density must be positive and at most 1e4 kg/m^3 (air: 1.2 kg/m^3)",
);

/// The table `[effects.key]` of an air law, if present.
fn air_table<'t>(
    ctx: &Ctx<'t>,
    effects: &Sec<'t>,
    key: &str,
    form: &str,
) -> Result<Option<Sec<'t>>> {
    ctx.section(effects, key, &keys(&effects.full(key)), form)
}

/// A required property of an air law's table.
fn air_property(ctx: &Ctx<'_>, sub: &Sec<'_>, (key, what, ok, rule): Property) -> Result<f64> {
    ctx.checked(sub, key, what, ok, rule)?
        .ok_or_else(|| ctx.missing(sub, key, format!("give {what}")))
}

/// `key = c` or `key = { coefficient = c, regularisation = ε }` → (c, ε), c in `unit`.
fn resistance(
    ctx: &Ctx<'_>,
    sec: &Sec<'_>,
    key: &str,
    what: &str,
    unit: &str,
) -> Result<Option<(f64, f64)>> {
    let rule = format!("the coefficient must be finite and non-negative ({unit})");
    let Some(got) = sec.get(key) else {
        return Ok(None);
    };
    if let Some(c) = got.node().as_f64() {
        if !(c.is_finite() && c >= 0.0) {
            return Err(ctx.bad(ErrorKind::Invalid, sec, got, rule));
        }
        return Ok(Some((c, DEFAULT_REGULARISATION)));
    }
    let form =
        format!("a number {what}, or {{ coefficient = c ({unit}), regularisation = ε (rad/s) }}");
    let sub = ctx.table_of(
        &sec.full(key),
        got.node(),
        &got.entry.key_origin,
        &keys(&sec.full(key)),
        &form,
    )?;
    let c = ctx
        .checked(&sub, "coefficient", what, |v| v >= 0.0, &rule)?
        .ok_or_else(|| ctx.missing(&sub, "coefficient", format!("give {what}")))?;
    let eps = ctx
        .checked(
            &sub,
            "regularisation",
            "ε, the regularisation rate (rad/s)",
            |v| v > 0.0,
            "the regularisation must be positive and finite (rad/s)",
        )?
        .unwrap_or(DEFAULT_REGULARISATION);
    Ok(Some((c, eps)))
}

pub(super) fn read_solver(ctx: &Ctx<'_>, root: &Sec<'_>) -> Result<SolverSettings> {
    let sec = ctx
        .section(
            root,
            "solver",
            &keys("solver"),
            "method, tolerances and step",
        )?
        .unwrap_or(Sec {
            path: "solver".into(),
            node: &EMPTY,
        });
    let method = ctx
        .choice(&sec, "method", &Method::NAMES)?
        .map_or(DEFAULT_METHOD, |(m, _)| m);
    let rtol = ctx
        .checked(&sec, "rtol", "the relative tolerance", |v| (10.0 * f64::EPSILON..=1e-2).contains(&v), "the relative tolerance must lie between 10·EPS ≈ 2.2e-15 and 1e-2 (looser tolerances leave no correct digit)")?
        .unwrap_or(DEFAULT_RTOL);
    let atol = ctx
        .checked(
            &sec,
            "atol",
            "the absolute tolerance",
            |v| v > 0.0,
            "the absolute tolerance must be positive and finite",
        )?
        .unwrap_or(DEFAULT_ATOL);
    let step = ctx.checked(
        &sec,
        "step",
        "the step (s)",
        |v| v > 0.0,
        "the step must be positive and finite (s)",
    )?;
    let max_steps = ctx
        .checked(
            &sec,
            "max_steps",
            "the most steps per run segment",
            |v| v >= 1.0 && v.fract() == 0.0 && v < u64::MAX as f64,
            "must be a whole number, at least 1 and below 2^64",
        )?
        .map_or(DEFAULT_MAX_STEPS, |v| v as u64);
    let kind = Method::ALL.into_iter().find(|m| m.name() == method);
    let (method, initial_step) = match kind {
        Some(Method::Rk4 { .. }) => {
            let h = step.ok_or_else(|| {
                ctx.missing(
                    &sec,
                    "step",
                    "the rk4 method needs its fixed step (s), e.g. step = 1e-4",
                )
            })?;
            (Method::Rk4 { h }, None)
        }
        Some(m @ (Method::Dopri5 | Method::Dop853)) => (m, step),
        None => return Err(unknown_name(ctx, &sec, "method", &Method::NAMES)),
    };
    Ok(SolverSettings {
        method,
        rtol,
        atol,
        initial_step,
        max_steps,
    })
}

pub(super) fn read_output(ctx: &Ctx<'_>, root: &Sec<'_>) -> Result<(f64, Vec<f64>)> {
    let sec = ctx
        .section(root, "output", &keys("output"), "end time and sampling")?
        .ok_or_else(|| {
            ctx.missing(
                root,
                "output",
                "a scenario needs an [output] table with t_end and dt (or times)",
            )
        })?;
    let t_end = ctx
        .checked(
            &sec,
            "t_end",
            "the end time (s)",
            |v| v > 0.0,
            "the end time must be positive and finite (s)",
        )?
        .ok_or_else(|| ctx.missing(&sec, "t_end", "give the end time of the run (s)"))?;
    ctx.exclusive(
        &sec,
        "dt",
        "times",
        "a sampling interval or explicit output times",
    )?;
    if let Some(dt) = ctx.checked(
        &sec,
        "dt",
        "the sampling interval (s)",
        |v| v > 0.0,
        "the sampling interval must be positive and finite (s)",
    )? {
        let times = grid(t_end, dt).map_err(|n| {
            ctx.bad(
                ErrorKind::Invalid,
                &sec,
                sec.get("dt").expect("just read"),
                format!(
                    "t_end / dt asks for {} samples; at most {MAX_SAMPLES} are allowed (raise dt)",
                    number(n)
                ),
            )
        })?;
        return Ok((t_end, times));
    }
    let got = sec.get("times").ok_or_else(|| {
        ctx.missing(
            &sec,
            "dt",
            "give the sampling interval dt (s), or explicit output times = [t1, t2, …]",
        )
    })?;
    const FORM: &str = "an array of output times (s)";
    let Value::Array(items) = &got.node().value else {
        return Err(ctx.wrong_type(&sec, got, FORM));
    };
    let times = items
        .iter()
        .map(Node::as_f64)
        .collect::<Option<Vec<f64>>>()
        .ok_or_else(|| {
            ctx.bad(
                ErrorKind::Type,
                &sec,
                got,
                "every output time must be a number (s)",
            )
        })?;
    if times.is_empty() {
        return Err(ctx.bad(
            ErrorKind::Invalid,
            &sec,
            got,
            "give at least one output time",
        ));
    }
    if times.len() > MAX_SAMPLES {
        return Err(ctx.bad(
            ErrorKind::Invalid,
            &sec,
            got,
            format!("at most {MAX_SAMPLES} output times are allowed"),
        ));
    }
    Ok((t_end, times))
}

/// t = k·dt for k = 0, 1, … while ≤ t_end, plus t_end itself if it is not on the grid
/// (a time within 1e-9·k·dt of t_end counts as t_end). Err(number of samples) when
/// there would be more than [`MAX_SAMPLES`].
pub(super) fn grid(t_end: f64, dt: f64) -> std::result::Result<Vec<f64>, f64> {
    let ratio = t_end / dt;
    let nearest = ratio.round();
    let on_grid = nearest >= 1.0 && (ratio - nearest).abs() <= 1e-9 * nearest;
    // n grid points before t_end, then t_end
    let n = if on_grid {
        nearest
    } else {
        ratio.floor() + 1.0
    };
    if n + 1.0 > MAX_SAMPLES as f64 {
        return Err(n + 1.0);
    }
    let n = n as usize;
    let mut times: Vec<f64> = (0..n).map(|k| k as f64 * dt).collect();
    times.push(t_end);
    Ok(times)
}

pub(super) fn read_check(ctx: &Ctx<'_>, root: &Sec<'_>) -> Result<Check> {
    let Some(sec) = ctx.section(
        root,
        "check",
        &keys("check"),
        "expected status and invariant tolerances",
    )?
    else {
        return Ok(Check::default());
    };
    let status = ctx
        .choice(&sec, "status", &STATUS_NAMES)?
        .map(|(s, _)| s.to_owned());
    let mut drift = BTreeMap::new();
    for name in DRIFT_NAMES {
        if let Some(tol) = ctx.checked(
            &sec,
            name,
            "the largest allowed relative drift",
            |v| v >= 0.0,
            "a tolerance must be finite and non-negative",
        )? {
            drift.insert(name.to_owned(), tol);
        }
    }
    Ok(Check { status, drift })
}

/// The `[[observe]]` array of tables: events on output columns (docs/scenarios.md,
/// "Observables"); a column is one of `layout`'s numeric columns (a body with contact
/// spheres adds its per-surface columns).
pub(super) fn read_observe(ctx: &Ctx<'_>, root: &Sec<'_>, layout: &Layout) -> Result<Vec<Observe>> {
    read_crossings(
        ctx,
        root,
        layout,
        ("observe", "observable", MAX_OBSERVE),
        "an observable: name, column, crosses, direction, terminal",
        |sec| match sec.get("terminal") {
            None => Ok(false),
            Some(g) => match g.node().value {
                Value::Bool(b) => Ok(b),
                _ => Err(ctx.wrong_type(
                    sec,
                    g,
                    "true or false: whether the run ends at the first crossing",
                )),
            },
        },
    )
    .map(|list| {
        list.into_iter()
            .map(|(o, terminal)| Observe { terminal, ..o })
            .collect()
    })
}

/// The `[[section]]` array of tables: Poincaré sections (docs/scenarios.md, "Poincaré
/// sections"), each a crossing as an observable's and the most points it keeps. The
/// sections together keep at most [`MAX_SECTION_POINTS`] points (the sum of their
/// `max_points`; a section without `max_points` keeps an equal share,
/// [`MAX_SECTION_POINTS`] / the number of sections): memory and the sections table grow
/// with the points, so the bound holds them to what one section may keep.
pub(super) fn read_sections(
    ctx: &Ctx<'_>,
    root: &Sec<'_>,
    layout: &Layout,
) -> Result<Vec<Section>> {
    let count = match root.get("section").map(|g| &g.node().value) {
        Some(Value::Array(items)) => items.len().max(1),
        _ => 1,
    };
    let share = MAX_SECTION_POINTS / count as u64;
    let mut total: u64 = 0;
    let mut index = 0;
    let list = read_crossings(
        ctx,
        root,
        layout,
        ("section", "section", MAX_SECTIONS),
        "a Poincaré section: name, column, crosses, direction, max_points",
        |sec| {
            let given = ctx.checked(
                sec,
                "max_points",
                "the most points the section keeps",
                |v| v >= 1.0 && v.fract() == 0.0 && v <= MAX_SECTION_POINTS as f64,
                &format!("must be a whole number from 1 to {MAX_SECTION_POINTS}"),
            )?;
            let points = given.map_or(share, |v| v as u64);
            total += points;
            index += 1;
            if total > MAX_SECTION_POINTS {
                let rule = format!(
                    "the sections together keep at most {MAX_SECTION_POINTS} points (the sum of their \
                     max_points; a section without max_points keeps {MAX_SECTION_POINTS} / {count} = {share}): \
                     the first {index} sum to {total}; lower max_points"
                );
                return Err(match sec.get("max_points") {
                    Some(g) => ctx.bad(ErrorKind::Invalid, sec, g, rule),
                    None => ctx.error(
                        ErrorKind::Invalid,
                        &sec.node.origin,
                        Some(sec.full("max_points")),
                        Some(format!("{points} (the default)")),
                        rule,
                    ),
                });
            }
            Ok(points)
        },
    )?;
    Ok(list
        .into_iter()
        .map(|(crossing, max_points)| Section {
            crossing,
            max_points,
        })
        .collect())
}

/// The entries of the array of tables `table` (`[[observe]]` or `[[section]]`, at most
/// `max`, each a `what` with a unique name), each a column of `layout` crossing a value
/// in a direction (`terminal` false), with what `extra` reads of the entry's other keys.
fn read_crossings<T>(
    ctx: &Ctx<'_>,
    root: &Sec<'_>,
    layout: &Layout,
    (table, what, max): (&str, &str, usize),
    keys_hint: &str,
    mut extra: impl FnMut(&Sec<'_>) -> Result<T>,
) -> Result<Vec<(Observe, T)>> {
    let Some(got) = root.get(table) else {
        return Ok(Vec::new());
    };
    let Value::Array(items) = &got.node().value else {
        return Err(ctx.wrong_type(
            root,
            got,
            &format!("an array of tables ([[{table}]] entries)"),
        ));
    };
    if items.len() > max {
        return Err(ctx.bad(
            ErrorKind::Invalid,
            root,
            got,
            format!("{} entries; at most {max} {what}s", items.len()),
        ));
    }
    let numeric = layout.numeric_columns();
    let columns: Vec<&str> = numeric.iter().map(|c| &*c.0).collect();
    let mut out: Vec<(Observe, T)> = Vec::with_capacity(items.len());
    for (k, item) in items.iter().enumerate() {
        let sec = ctx.table_of(
            &format!("{table}[{k}]"),
            item,
            &item.origin,
            &keys(table),
            keys_hint,
        )?;
        let name = match sec.get("name") {
            None => {
                return Err(ctx.missing(
                    &sec,
                    "name",
                    format!("give the {what} a name (a string)"),
                ));
            }
            Some(g) => match &g.node().value {
                Value::Str(s) if !s.is_empty() && s.len() <= 100 => {
                    if out.iter().any(|(o, _)| &o.name == s) {
                        return Err(ctx.bad(
                            ErrorKind::Invalid,
                            &sec,
                            g,
                            format!("{what} names must be unique"),
                        ));
                    }
                    s.clone()
                }
                Value::Str(_) => {
                    return Err(ctx.bad(ErrorKind::Invalid, &sec, g, "a name of 1 to 100 bytes"));
                }
                _ => {
                    return Err(ctx.wrong_type(&sec, g, &format!("a string: the {what}'s name")));
                }
            },
        };
        let (column, _) = ctx.choice(&sec, "column", &columns)?.ok_or_else(|| {
            ctx.missing(
                &sec,
                "column",
                "give the output column to watch (e.g. \"theta\")",
            )
        })?;
        let crosses = ctx.required(&sec, "crosses", "the value the column crosses, in its unit")?;
        if !crosses.is_finite() {
            let g = sec.get("crosses").expect("just read");
            return Err(ctx.bad(
                ErrorKind::Invalid,
                &sec,
                g,
                "the value crossed must be finite",
            ));
        }
        let direction = match ctx.choice(&sec, "direction", &DIRECTIONS)?.map(|(d, _)| d) {
            Some("up") => Direction::Rising,
            Some("down") => Direction::Falling,
            _ => Direction::Either,
        };
        let more = extra(&sec)?;
        let column = layout.index(column).expect("a column name from the list");
        out.push((
            Observe {
                name,
                column,
                crosses,
                direction,
                terminal: false,
            },
            more,
        ));
    }
    Ok(out)
}
