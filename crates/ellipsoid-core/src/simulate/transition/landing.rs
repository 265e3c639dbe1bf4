//! Touchdowns and their impacts (docs/physics.md, "Impact at touchdown", "Settling",
//! "Simultaneous touchdowns", "Impact at several contacts"): a surface touching down from
//! flight ([`touchdown`]), taken back to its zero gap ([`back_to_contact`]) and struck
//! ([`Strike`]), the surfaces that touch at the same instant ([`coinciding`]), the impact
//! at several contacts at once ([`contacts_touchdown`]), and the settling speeds that
//! decide whether a surface stays on the plane ([`settling_speed`],
//! [`second_settling_speed`]). Where the body goes after an impact is
//! [`settle`]'s (`contacts`).

use nalgebra::Vector3;

use crate::body::{Body, Surface};
use crate::effects::Effect;
use crate::geometry::{self, Contact};
use crate::impact::{self, Approach, Tangential};
use crate::integrate::rk4_step;
use crate::kinematics::Kinematics;
use crate::model::MOST_CONTACTS;
use crate::state::{self, State};

use crate::simulate::context::{ContactSet, Context};
use crate::simulate::flat;
use crate::simulate::numerics::{BACK_STEPS, SECOND_GAP_RISE};
use crate::simulate::outcome::{EventKind, EventRecord, ImpactReport, Mode, Status};
use crate::simulate::phase::{FlightPhase, FrictionlessPhase, Next, phase};
use crate::simulate::scene::ContactModel;

use super::contacts::settle;
use super::{clear_flight_slots, renew_reference, touch};

/// Touchdown of `surface` from flight, located at its gap = −δz on the flight's dense
/// output at (t, y): the impact is taken where the gap is zero ([`back_to_contact`], which
/// moves `t` back), its loss booked in W, with the scene's restitution unless the rebound
/// is within the settling speed after it (then plastic, the surface staying in contact);
/// the outcome goes on the plane by [`settle`]. Other surfaces that touch the plane at the
/// same instant ([`coinciding`]) and that the impact would leave approaching it take the
/// impact with it, at once ([`contacts_touchdown`], docs/physics.md "Simultaneous
/// touchdowns"): taken in turn, each impact drives the other surface into the plane
/// within the time resolution of the located touchdown, where no event can be seen, and
/// the body fell through the plane. An impact at them with no solution stops the run with
/// `several_contacts` at the located state.
pub(in crate::simulate) fn touchdown<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &mut ContactSet,
    surface: Surface,
    t: &mut f64,
    y: &mut State,
    events: &mut Vec<EventRecord>,
) -> Next {
    let body = &ctx.scene.body;
    let (t0, y0) = (*t, *y);
    let strike = Strike::new(ctx, contacts, surface, t, y);
    if matches!(surface, Surface::Rim(_))
        && geometry::ring_direction(strike.kin.contact.zeta).1 <= ctx.scene.landing.flat_tilt
    {
        // A rim touching down flat lands on its face (`flat::land_flat`).
        touch(contacts, surface, *t, events);
        events.push(EventRecord {
            kind: EventKind::Touchdown {
                speed: -normal_velocity(body, surface, &strike.pre),
                surface,
            },
            t: *t,
        });
        *y = strike.pre;
        return flat::land_flat(ctx, contacts, Mode::Flight, *t, y, events);
    }
    let law = tangential(ctx.scene.contact);
    let single = strike.impact(law, ctx.scene.landing.restitution);
    let coincide = coinciding(ctx, contacts, &strike, &[], &single.1);
    let (staying, after, reports, speed) = if coincide.is_empty() {
        // The settling speed after the impact: its rates decide what presses the body down.
        let settles = |y: &State| free_settling_speed(ctx, contacts, surface, y);
        let (hit, after, settles) = strike.settled(law, single, settles);
        let staying = if settles {
            Staying::One(surface)
        } else {
            Staying::Neither
        };
        let speed = -hit.normal_velocity.0;
        (staying, after, vec![strike.report(&hit)], speed)
    } else {
        let settles = |s: Surface, y: &State| free_settling_speed(ctx, contacts, s, y);
        let with = &coincide[..coincide.len().min(MOST_CONTACTS - 1)];
        let Some(outcome) = contacts_touchdown(ctx, contacts, &strike, with, law, settles) else {
            (*t, *y) = (t0, y0);
            return Next::Stop(
                Status::SeveralContacts {
                    touching: surface,
                    pressed: coincide[0],
                    approach: normal_velocity(body, coincide[0], &single.1),
                },
                Mode::Flight,
            );
        };
        let (staying, after, reports) = outcome;
        let speed = -normal_velocity(body, surface, &strike.pre);
        (staying, after, reports, speed)
    };
    touch(contacts, surface, *t, events);
    events.push(EventRecord {
        kind: EventKind::Touchdown { speed, surface },
        t: *t,
    });
    *y = after;
    settle(
        ctx,
        contacts,
        Mode::Flight,
        surface,
        staying,
        *t,
        y,
        &reports,
        events,
    )
}

/// The surfaces other than `strike`'s and `joined` that touch the plane at the instant of
/// its touchdown and approach it at `after` (a flight-form state at that instant) faster
/// than their settling speed: at the located touchdown their gap g_k is within its
/// round-off δz, or within what their approach v_k covers in the time resolution τ of
/// the located event (`Numerics::time_resolution`),
/// ```text
///   g_k ≤ δz + τ max(0, −v_k),    v_k < −v_settle,k,
/// ```
/// where the integrator, which takes no zero within round-off of the start of a
/// segment, would never see them touch down. Most approaching first.
pub(super) fn coinciding<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    strike: &Strike,
    joined: &[Surface],
    after: &State,
) -> Vec<Surface> {
    let body = &ctx.scene.body;
    let tau = ctx.numerics.time_resolution(strike.t);
    let mut near: Vec<(f64, Surface)> = body
        .surfaces()
        .filter(|s| *s != strike.surface && !joined.contains(s))
        .filter_map(|s| {
            let at = Kinematics::flying_at(body, s, &strike.pre);
            let v = normal_velocity(body, s, after);
            let settle = free_settling_speed(ctx, contacts, s, after);
            let reach = ctx.numerics.gap_resolution(&at) + tau * (-v).max(0.0);
            (at.gap <= reach && v < -settle).then_some((v, s))
        })
        .collect();
    near.sort_by(|a, b| a.0.total_cmp(&b.0));
    near.into_iter().map(|(_, s)| s).collect()
}

/// A surface at its touchdown: the flight-form state taken back to the surface's zero gap
/// ([`back_to_contact`]) and the body there as the impact law sees it.
pub(super) struct Strike {
    pub(super) surface: Surface,
    /// The instant of the touchdown \[s\].
    pub(super) t: f64,
    /// The state at zero gap, before the impact (flight form).
    pub(super) pre: State,
    pub(super) kin: Kinematics,
    pub(super) approach: Approach,
}

impl Strike {
    /// `surface` touching down at (t, y), `t` moved back to its zero gap.
    pub(super) fn new<E: Effect + Copy + 'static>(
        ctx: &Context<'_, E>,
        contacts: &ContactSet,
        surface: Surface,
        t: &mut f64,
        y: &State,
    ) -> Self {
        let body = &ctx.scene.body;
        let pre;
        (*t, pre) = back_to_contact(ctx, contacts, surface, *t, y);
        let kin = Kinematics::flying_at(body, surface, &pre);
        let rot = kin.rot;
        let approach = Approach {
            mass: body.mass(),
            inertia_inv: rot * body.inertia_inv() * rot.transpose(),
            r: rot * kin.contact.r,
            v_g: kin.v_g,
            omega: rot * kin.omega,
        };
        Strike {
            surface,
            t: *t,
            pre,
            kin,
            approach,
        }
    }

    /// The state after an impact that leaves G at `v_g` and the body turning at `omega`
    /// (world), its kinetic-energy `loss` booked in W, and no gap (it is zero to round-off
    /// at the located contact).
    pub(super) fn after(&self, v_g: Vector3<f64>, omega: Vector3<f64>, loss: f64) -> State {
        let mut y = self.pre;
        y[state::VEL] = v_g.x;
        y[state::VEL + 1] = v_g.y;
        y[state::VEL_Z] = v_g.z;
        y.fixed_rows_mut::<3>(state::OMEGA)
            .copy_from(&self.kin.rot.tr_mul(&omega));
        y[state::WORK] += loss;
        y[state::HEIGHT] = self.kin.contact.height;
        y
    }

    /// The impact at the surface alone with restitution `e`, and the state after it.
    pub(super) fn impact(&self, law: Tangential, e: f64) -> (impact::Impact, State) {
        let hit = impact::resolve(&self.approach, law, e);
        let after = self.after(hit.v_g, hit.omega, hit.energy_loss);
        (hit, after)
    }

    /// The impact `hit` (with the state after it) kept where its rebound exceeds the
    /// settling speed `settles` gives at the state after it, else taken again plastic;
    /// with whether the surface stays on the plane.
    pub(super) fn settled(
        &self,
        law: Tangential,
        (hit, after): (impact::Impact, State),
        settles: impl Fn(&State) -> f64,
    ) -> (impact::Impact, State, bool) {
        let rebound = hit.normal_velocity.1;
        if rebound > settles(&after) {
            return (hit, after, false);
        }
        if rebound > 0.0 {
            let (hit, after) = self.impact(law, 0.0);
            return (hit, after, true);
        }
        (hit, after, true)
    }

    /// The report of the impact `hit` at the surface (its outcome, `persistent`, is filled
    /// in by [`settle`]).
    pub(super) fn report(&self, hit: &impact::Impact) -> ImpactReport {
        ImpactReport {
            impulse: hit.impulse,
            energy_loss: hit.energy_loss,
            stuck: hit.stuck,
            rebound: hit.normal_velocity.1,
            persistent: false,
            surface: self.surface,
        }
    }
}

/// The surfaces an impact leaves on the plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Staying {
    Neither,
    One(Surface),
    /// Several, the first `count` of `surfaces`: the first the one whose geometry the
    /// several-contact phase takes.
    Several {
        surfaces: [Surface; MOST_CONTACTS],
        count: usize,
    },
}

impl Staying {
    /// `surfaces` (two or three) stay.
    pub(super) fn several(surfaces: &[Surface]) -> Staying {
        Staying::Several {
            surfaces: std::array::from_fn(|i| surfaces.get(i).copied().unwrap_or(surfaces[0])),
            count: surfaces.len(),
        }
    }
}

/// The impact of `strike` at its surface j and at the surfaces `pressed` at once
/// (`impact::resolve_contacts`, docs/physics.md "Impact at several contacts"), with the
/// scene's restitution and friction law. A contact stays where its normal velocity after
/// the impact is within its settling speed `settles(surface, y)`. Where all stay and one
/// of them rebounds, the impact is taken again with e = 0 (the plastic impact that ends a
/// bounce sequence the phase could not resolve, section "Settling"). A further surface
/// that touches the plane at the same instant and that the impact leaves approaching it
/// ([`coinciding`]) joins the impact, which is taken again, up to [`MOST_CONTACTS`]
/// surfaces. Returns who stays (the pressed surfaces first), the state after the impact
/// (flight form, its loss in W) and an impact report per surface (the loss on the struck
/// one's); `None` where the impact has no solution (the rolling model's no-slip law where
/// sticking the struck contact would pull; an iteration that does not converge).
pub(super) fn contacts_touchdown<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    strike: &Strike,
    pressed: &[Surface],
    law: Tangential,
    settles: impl Fn(Surface, &State) -> f64,
) -> Option<(Staying, State, Vec<ImpactReport>)> {
    let kin = &strike.kin;
    let mut surfaces: Vec<Surface> = std::iter::once(strike.surface)
        .chain(pressed.iter().copied())
        .collect();
    let solve = |surfaces: &[Surface], e: f64| {
        let levers: Vec<Vector3<f64>> = (surfaces[1..].iter())
            .map(|&s| kin.rot * Contact::of(&ctx.scene.body, s, kin.contact.zeta, kin.omega).r)
            .collect();
        let hit = impact::resolve_contacts(&strike.approach, &levers, law, e)?;
        let after = strike.after(hit.v_g, hit.omega, hit.energy_loss);
        let stays: Vec<bool> = (surfaces.iter().enumerate())
            .map(|(i, &s)| hit.normal_velocity[i].1 <= settles(s, &after))
            .collect();
        Some((hit, after, stays))
    };
    let (mut hit, mut after, mut stays) = loop {
        let solved = solve(&surfaces, ctx.scene.landing.restitution)?;
        match coinciding(ctx, contacts, strike, &surfaces[1..], &solved.1).first() {
            Some(&more) if surfaces.len() < MOST_CONTACTS => surfaces.push(more),
            _ => break solved,
        }
    };
    if hit.restitution > 0.0
        && stays.iter().all(|&s| s)
        && hit.normal_velocity[..surfaces.len()]
            .iter()
            .any(|v| v.1 > 0.0)
    {
        (hit, after, stays) = solve(&surfaces, 0.0)?;
    }
    // The pressed surfaces first: the several-contact phase takes the first's geometry.
    let staying: Vec<Surface> = (1..surfaces.len())
        .chain([0])
        .filter(|&i| stays[i])
        .map(|i| surfaces[i])
        .collect();
    let staying = match staying.as_slice() {
        [] => Staying::Neither,
        [one] => Staying::One(*one),
        several => Staying::several(several),
    };
    // The loss is the impact's, reported at the struck surface: split between the
    // contacts as the work of each impulse, −P_i·(v_i⁻ + v_i⁺)/2, a share can be negative
    // (with friction one impulse can speed the body up while another slows it more).
    let reports = surfaces
        .iter()
        .enumerate()
        .map(|(i, &surface)| ImpactReport {
            impulse: hit.impulse[i],
            energy_loss: if i == 0 { hit.energy_loss } else { 0.0 },
            stuck: hit.stuck[i],
            rebound: hit.normal_velocity[i].1,
            persistent: false,
            surface,
        })
        .collect();
    Some((staying, after, reports))
}

/// The state on the flight's trajectory through (t, y) where the gap of `surface` is
/// zero: touchdown is located at gap = −δz (`phase::flight`), and an impact taken there,
/// with the penetration then removed, would add 2 a δz to v_n² at every bounce (a: the
/// gap's free deceleration) — enough to stall a Zeno sequence above the settling speed
/// whenever a e²/(1 − e²) > g (docs/physics.md, "Settling"). Newton's iteration on s,
/// gap(t + s) = 0 with d gap/dt = v_n, that surface's lowest point's normal velocity,
/// each y(t + s) one RK4 step of the flight system from (t, y); s is kept in
/// [−4√(2δz/g), 0]: the touchdown is never moved past the located event (from a grazing
/// one, v_n ≈ −1e-18 m/s, a Newton step from the lower bound went 0.07 s forward, over
/// samples already due), and never back further than a fall from rest takes through a
/// few δz, |s| ≈ δz/|v_n| being a few ns otherwise: a grazing touchdown
/// (v_n → 0, as when a body rocks between two surfaces) would otherwise send one RK4 step
/// seconds back along the flight. Without gravity the fall is at the gap's free
/// deceleration |a| ([`settling_speed`]'s), and where that is zero too there is no going
/// back: a bound from g alone was none at g = 0, and a surface leaving two contacts at
/// N ↓ 0 with its gap and normal velocity at round-off below zero (−1e-16 m, −2e-11 m/s)
/// was taken back 5 µs along a flight that never happened, to a state in which the body
/// had been touching with both.
fn back_to_contact<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    surface: Surface,
    t: f64,
    y: &State,
) -> (f64, State) {
    let body = &ctx.scene.body;
    let dz = ctx
        .numerics
        .gap_resolution(&Kinematics::flying_at(body, surface, y));
    let fall = if ctx.scene.gravity > 0.0 {
        ctx.scene.gravity
    } else {
        free_deceleration(ctx, &contacts.on(surface), y).abs()
    };
    let most = if fall > 0.0 {
        4.0 * (2.0 * dz / fall).sqrt()
    } else {
        0.0
    };
    let gap_and_rate = |y: &State| {
        let kin = Kinematics::flying_at(body, surface, y);
        let v_n = kin.v_g.z + (kin.rot * kin.omega.cross(&kin.contact.r)).z;
        (kin.gap, v_n)
    };
    let fly = ctx.system::<FlightPhase>(contacts);
    let mut k = [State::zeros(); 4];
    let (mut s, mut ys) = (0.0, *y);
    for _ in 0..BACK_STEPS {
        let (gap, v_n) = gap_and_rate(&ys);
        if gap == 0.0 || !(v_n < 0.0) {
            break;
        }
        s = (s - gap / v_n).clamp(-most, 0.0);
        ys = rk4_step(&fly, t, y, s, &mut k);
    }
    (t + s, ys)
}

/// The settling speed at the touchdown state `y` (`Numerics::settling_speed`), with the
/// gap's deceleration with no contact force ([`free_deceleration`]).
pub(super) fn settling_speed<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    y: &State,
    kin: &Kinematics,
) -> f64 {
    ctx.numerics
        .settling_speed(free_deceleration(ctx, contacts, y), kin)
}

/// The settling speed of `surface` at the flight-form state `y` ([`settling_speed`] with
/// `surface` as the one in contact).
pub(super) fn free_settling_speed<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    surface: Surface,
    y: &State,
) -> f64 {
    let kin = Kinematics::flying_at(&ctx.scene.body, surface, y);
    settling_speed(ctx, &contacts.on(surface), y, &kin)
}

/// The deceleration of the gap of the surface in contact with no contact force at `y`,
/// a = (m g − f_z − m u·I⁻¹T − m κ)/m \[m/s²\] (see [`super::flight_is_consistent`]).
fn free_deceleration<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    y: &State,
) -> f64 {
    let free = ctx.system::<FrictionlessPhase>(contacts).evaluate(y);
    free.response.normal * free.response.painleve / ctx.scene.body.mass()
}

/// The settling speed of surface `surface`'s gap while the body touches the plane with
/// `pressed` in mode `mode` (docs/physics.md, "Settling at a second surface"), at the
/// flight-form state `y`: √(2 a k δz), a the deceleration of that gap under the phase's
/// dynamics ([`gap_deceleration`]) and k = `SECOND_GAP_RISE`. A rebound of `surface`
/// below it rises less than k δz before that dynamics brings it back, which the located
/// gap does not resolve.
pub(super) fn second_settling_speed<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    mode: Mode,
    pressed: Surface,
    surface: Surface,
    y: &State,
) -> f64 {
    let contacts = &contacts.on(pressed);
    let mut on = *y;
    clear_flight_slots(ctx, contacts, &mut on);
    renew_reference(ctx, contacts, &mut on);
    let decel = gap_deceleration(ctx, contacts, mode, surface, &on);
    let kin = Kinematics::new(&ctx.body(contacts), &on, false);
    ctx.numerics.settling_speed(SECOND_GAP_RISE * decel, &kin)
}

/// The deceleration of surface `surface`'s gap g = h_1 − h_2 (z_G = h_1 on
/// `ContactSet::surface`, the pressed one) under the dynamics of mode `mode` at the
/// contact-form state `on` \[m/s²\],
/// ```text
///   a = −g̈ = (u_1 − u_2)·ω̇ + κ_1 − κ_2,
/// ```
/// ω̇ the phase's (u_i = r_i × ζ, κ_i as in z̈_G = −u·ω̇ − κ): a > 0 drives `surface`
/// into the plane.
pub(super) fn gap_deceleration<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    mode: Mode,
    surface: Surface,
    on: &State,
) -> f64 {
    let kin = Kinematics::new(&ctx.body(contacts), on, false);
    let omega_dot = phase::<E>(mode).response(ctx, contacts, on).omega_dot;
    let other = Contact::of(&ctx.scene.body, surface, kin.contact.zeta, kin.omega);
    (kin.contact.u - other.u).dot(&omega_dot) + kin.contact.kappa - other.kappa
}

/// The normal velocity of `surface`'s lowest point at the flight-form state `y`,
/// v_n = v_Gz + e3·(R (ω × r)) \[m/s\].
pub(super) fn normal_velocity(body: &Body, surface: Surface, y: &State) -> f64 {
    let kin = Kinematics::flying_at(body, surface, y);
    kin.v_g.z + (kin.rot * kin.omega.cross(&kin.contact.r)).z
}

/// The impact law of the scene's contact model: frictionless, Coulomb (sliding and
/// Coulomb models) or its no-slip limit (rolling). The viscous model's impact is taken
/// frictionless: its tangential impulse −μ_v ∫ v_C dp is neglected (docs/physics.md,
/// "Viscous sliding").
pub(super) fn tangential(contact: ContactModel) -> Tangential {
    match contact {
        ContactModel::Frictionless | ContactModel::Viscous { .. } => Tangential::Frictionless,
        ContactModel::Sliding { friction } | ContactModel::Coulomb { friction } => {
            Tangential::Coulomb { friction }
        }
        ContactModel::Rolling => Tangential::NoSlip,
    }
}
