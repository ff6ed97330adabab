//! Contact kernels: the contact law, the Hertz–Mindlin force, the convex narrow phase, the
//! pair and wall contacts with their memories, placements, the neighbour-list row with the
//! separated pairs' skip, and the poly-ellipsoid grains' construction and volume.

use super::*;
use fractum::contact::convex::{self, ContactGeometry, Placed};
use fractum::contact::hertz_mindlin::{
    ContactForce, Hertz, KernelConsts, Mindlin, ViscousDamping, hertz_mindlin,
};
use fractum::contact::pair::{
    BodyView, ContactBody, PairMemory, PairOut, Placement, bound_off_wall, bounds_apart, forget,
    pair_contact_or_gap, pair_reach, skips, travel_step, wall_contact,
};

fn consts(law: &FractumContactLaw) -> KernelConsts {
    KernelConsts {
        four_thirds_e: law.four_thirds_e,
        two_e: law.two_e,
        damping: law.damping,
        eight_g: law.eight_g,
        mu: law.mu,
    }
}

/// A candidate the library's bounding test rejects: it forgets what the library's kernel
/// would forget ([`forget`]) and touches nothing.
fn no_contact(
    law: &FractumContactLaw,
    shapes: i32,
    memory: &mut FractumPairMemory,
    out: &mut FractumContact,
) {
    let mut hist = Vec3::from(memory.hist);
    forget(
        &mut hist,
        &mut memory.radius,
        law.friction != 0,
        shapes != 0,
    );
    memory.hist = hist.into();
    *out = contact_out(None);
}

fn contact_out(p: Option<PairOut>) -> FractumContact {
    match p {
        None => FractumContact::default(),
        Some(p) => FractumContact {
            force: p.force.into(),
            torque_a: p.torque_i.into(),
            torque_b: p.torque_j.into(),
            point: p.point.into(),
            normal: p.normal.into(),
            normal_force: p.c.normal_force,
            hertz_force: p.c.hertz_force,
            radius: p.c.radius,
            stiffness: p.c.stiffness,
            energy: p.c.energy,
            dissipated: p.c.dissipated,
            touching: 1,
        },
    }
}

fn geometry_out(g: Option<ContactGeometry>) -> FractumGeometry {
    match g {
        None => FractumGeometry::default(),
        Some(g) => FractumGeometry {
            normal: g.normal.into(),
            depth: g.depth,
            point: g.point.into(),
            point_a: g.point_a.into(),
            point_b: g.point_b.into(),
            r_eff: g.r_eff,
            touching: 1,
        },
    }
}

/// The contact law of grains of Young's modulus `young` (Pa) and Poisson's ratio `poisson`,
/// with viscous damping for the restitution coefficient `restitution` (in (0, 1]; read only
/// when `damping` is nonzero) and Mindlin friction of coefficient `mu` (read only when
/// `friction` is nonzero), as Fractum's `contact`, `damping` and `friction` effects fold it.
/// Against walls of another friction coefficient, make a second law with that `mu`.
/// Finding the damping coefficient integrates collisions: a few tens of milliseconds; make
/// the law once.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_contact_law(
    young: f64,
    poisson: f64,
    restitution: f64,
    mu: f64,
    damping: i32,
    friction: i32,
    out: *mut FractumContactLaw,
) -> FractumStatus {
    kernel(|| {
        let out = get_mut(out)?;
        let (damp, fric) = (damping != 0, friction != 0);
        input_if(damp && !(restitution > 0.0 && restitution <= 1.0))?;
        let hertz = Hertz::new(young, poisson);
        let d = damp.then(|| ViscousDamping::from_restitution(restitution));
        let m = fric.then(|| Mindlin::new(young, poisson, mu));
        let k = KernelConsts::new(&hertz, d.as_ref(), m.as_ref());
        *out = FractumContactLaw {
            four_thirds_e: k.four_thirds_e,
            two_e: k.two_e,
            damping: k.damping,
            eight_g: k.eight_g,
            mu: k.mu,
            damp: i32::from(damp),
            friction: i32::from(fric),
        };
        Ok(())
    })
}

/// The Hertz-Mindlin force on A for the overlap `delta` (m, > 0) along the unit normal `n`
/// (3 doubles, from B to A), Hertz radius `r_eff` (m), effective mass `m_eff` (kg; read with
/// damping), velocity `v` (3 doubles, m/s) of A's contact point relative to B's, and the
/// tangential displacement `hist` (3 doubles, m; read and updated with friction) over the
/// step `dt` (s); `update` = 0 only for a force evaluation that must not advance `hist`.
/// Fills force, normal_force, hertz_force, radius, stiffness, energy, dissipated and
/// touching = 1 of
/// `*out` (the rest 0).
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn fractum_kernel_hertz_mindlin(
    law: *const FractumContactLaw,
    n: *const f64,
    delta: f64,
    r_eff: f64,
    m_eff: f64,
    v: *const f64,
    hist: *mut f64,
    dt: f64,
    update: i32,
    out: *mut FractumContact,
) -> FractumStatus {
    kernel(|| {
        let law = get(law)?;
        let (n, v) = (vec3_at(n)?, vec3_at(v)?);
        let hist = doubles_mut::<3>(hist)?;
        let out = get_mut(out)?;
        let k = consts(law);
        let mut h = Vec3::from(*hist);
        let update = update != 0;
        let c: ContactForce = match (law.damp != 0, law.friction != 0) {
            (false, false) => {
                hertz_mindlin::<false, false>(&k, &n, delta, r_eff, m_eff, &v, &mut h, dt, update)
            }
            (true, false) => {
                hertz_mindlin::<true, false>(&k, &n, delta, r_eff, m_eff, &v, &mut h, dt, update)
            }
            (false, true) => {
                hertz_mindlin::<false, true>(&k, &n, delta, r_eff, m_eff, &v, &mut h, dt, update)
            }
            (true, true) => {
                hertz_mindlin::<true, true>(&k, &n, delta, r_eff, m_eff, &v, &mut h, dt, update)
            }
        };
        *hist = h.into();
        *out = FractumContact {
            force: c.force.into(),
            normal_force: c.normal_force,
            hertz_force: c.hertz_force,
            radius: c.radius,
            stiffness: c.stiffness,
            energy: c.elastic_energy,
            dissipated: c.dissipated,
            touching: 1,
            ..FractumContact::default()
        };
        Ok(())
    })
}

/// The contact geometry of bodies `a` and `b` placed as Fractum places them (a sphere by its
/// radius about its centre), the search started from `guess` (3 doubles: a direction from B
/// to A of any length, e.g. the last normal or a's centre minus b's; 0 0 0: centroid to
/// centroid). `out->touching` = 0 when they are separated.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_convex_contact(
    a: *const FractumBody,
    b: *const FractumBody,
    guess: *const f64,
    out: *mut FractumGeometry,
) -> FractumStatus {
    kernel(|| {
        let (a, b) = (body_in(get(a)?)?, body_in(get(b)?)?);
        let guess = vec3_at(guess)?;
        let out = get_mut(out)?;
        let (va, vb) = (BodyView::new(&a), BodyView::new(&b));
        *out = geometry_out(convex::contact(&va.placed(), &vb.placed(), &guess));
        Ok(())
    })
}

/// The contact geometry of body `a` with the wall through `wall_point` (3 doubles, m) of unit
/// normal `wall_normal` (3 doubles, pointing out of the wall into the free side).
/// `out->touching` = 0 when `a` is clear of it.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_wall_geometry(
    a: *const FractumBody,
    wall_normal: *const f64,
    wall_point: *const f64,
    out: *mut FractumGeometry,
) -> FractumStatus {
    kernel(|| {
        let a = body_in(get(a)?)?;
        let (n, p) = (vec3_at(wall_normal)?, vec3_at(wall_point)?);
        let out = get_mut(out)?;
        *out = geometry_out(convex::wall_contact(&BodyView::new(&a).placed(), &n, &p));
        Ok(())
    })
}

/// The whole contact of the pair (a, b) as Fractum's contact effect computes it: the
/// bounding-sphere rejection; for two spheres (or with `shapes` = 0) the sphere formula, else
/// the convex contact warm-started from `memory->normal` with the Hertz radius held in
/// `memory->radius`; Hertz-Mindlin with the tangential displacement `memory->hist` (m) over
/// the step `dt` (s; `update` = 0 only for a force evaluation that must not advance it);
/// the torques, point and normal. The effective mass is m_a m_b / (m_a + m_b). `shapes` is
/// Fractum's poly-ellipsoid variant, nonzero when any grain of the run may be a
/// poly-ellipsoid: then a pair that is not two spheres takes the convex contact (two spheres
/// take the sphere formula either way).
/// `out->touching` = 0 when they do not touch (memory updated as Fractum does: hist and
/// radius reset).
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn fractum_kernel_pair(
    law: *const FractumContactLaw,
    a: *const FractumBody,
    b: *const FractumBody,
    memory: *mut FractumPairMemory,
    dt: f64,
    update: i32,
    shapes: i32,
    out: *mut FractumContact,
) -> FractumStatus {
    kernel(|| pair_in(law, a, None, b, None, memory, dt, update, shapes, out))
}

/// `fractum_kernel_pair` with the bodies' placements given (`pa`, `pb`, as
/// `fractum_kernel_placement` computes them for `a` and `b` now), as the run places every body
/// once per force evaluation instead of once per pair: a caller with many pairs per body
/// places each body once. The same bits as `fractum_kernel_pair` with those placements; a
/// placement that is not the body's gives the contact of the body so placed.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn fractum_kernel_pair_placed(
    law: *const FractumContactLaw,
    a: *const FractumBody,
    pa: *const FractumPlacement,
    b: *const FractumBody,
    pb: *const FractumPlacement,
    memory: *mut FractumPairMemory,
    dt: f64,
    update: i32,
    shapes: i32,
    out: *mut FractumContact,
) -> FractumStatus {
    kernel(|| {
        let (pa, pb) = (get(pa)?, get(pb)?);
        pair_in(
            law,
            a,
            Some(pa),
            b,
            Some(pb),
            memory,
            dt,
            update,
            shapes,
            out,
        )
    })
}

/// Where Fractum places body `b`'s shape in the world for a force evaluation
/// (`Placement::of`): for `fractum_kernel_pair_placed`.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_placement(
    b: *const FractumBody,
    out: *mut FractumPlacement,
) -> FractumStatus {
    kernel(|| {
        let b = body_in(get(b)?)?;
        let out = get_mut(out)?;
        let p = Placement::of(&b.pos, &b.orientation, &b.shape);
        *out = FractumPlacement {
            origin: p.origin.into(),
            rot: matrix_out(&p.rot),
        };
        Ok(())
    })
}

fn placement_in(p: &FractumPlacement) -> Placement {
    Placement {
        origin: Vec3::from(p.origin),
        rot: matrix(&p.rot),
    }
}

/// The C ABI's body as the contact kernels read it, without building a library `Body`: its
/// kinematics straight from the caller's struct, a poly-ellipsoid by its checked semi-axes and
/// the placement given, or else its own (the same bits as [`BodyView`] over `body_in` of it
/// with that placement).
struct RawBody<'a> {
    b: &'a FractumBody,
    pe: PolyEllipsoid,
    place: Option<&'a FractumPlacement>,
}

impl<'a> RawBody<'a> {
    /// `place` is read only for a poly-ellipsoid (`None`: placed as `Placement::of` places it).
    /// Refuses a poly-ellipsoid whose semi-axes are not finite and positive.
    #[inline(always)]
    fn new(b: &'a FractumBody, place: Option<&'a FractumPlacement>) -> Result<Self, FractumStatus> {
        let pe = if b.sphere != 0 {
            PolyEllipsoid::sphere(b.radius)
        } else {
            PolyEllipsoid::new(b.semi).map_err(|_| FRACTUM_ERR_INPUT)?
        };
        Ok(RawBody { b, pe, place })
    }
}

impl ContactBody for RawBody<'_> {
    #[inline(always)]
    fn pos(&self) -> Vec3 {
        Vec3::from(self.b.pos)
    }
    #[inline(always)]
    fn vel(&self) -> Vec3 {
        Vec3::from(self.b.vel)
    }
    #[inline(always)]
    fn omega(&self) -> Vec3 {
        Vec3::from(self.b.omega)
    }
    #[inline(always)]
    fn mass(&self) -> f64 {
        self.b.mass
    }
    #[inline(always)]
    fn radius(&self) -> f64 {
        self.b.radius
    }
    #[inline(always)]
    fn is_sphere(&self) -> bool {
        self.b.sphere != 0
    }
    #[inline(always)]
    fn placed(&self) -> Placed<'_> {
        if self.b.sphere != 0 {
            return Placed::sphere(self.b.radius, Vec3::from(self.b.pos));
        }
        let p = match self.place {
            Some(p) => placement_in(p),
            None => Placement::of(
                &Vec3::from(self.b.pos),
                &quat(&self.b.quat),
                &Shape::PolyEllipsoid {
                    pe: self.pe,
                    origin: Vec3::from(self.b.origin),
                    to_body: quat(&self.b.to_body),
                },
            ),
        };
        Placed::poly_ellipsoid(&self.pe, p.origin, p.rot)
    }
}

/// The contact of the pair (a, b), placed by `pa`, `pb` when given, as the run computes it:
/// the library's bounding test first (most candidates of a neighbour list do not touch: then
/// only what the library would forget, and the bounding spheres' gap), else the whole kernel
/// (`pair_contact_or_gap`: the contact, or the gap of a separated pair). `hist` and `m` are
/// the pair's memory.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn pair_of(
    law: &FractumContactLaw,
    k: &KernelConsts,
    a: &FractumBody,
    pa: Option<&FractumPlacement>,
    b: &FractumBody,
    pb: Option<&FractumPlacement>,
    hist: &mut Vec3,
    m: &mut PairMemory,
    dt: f64,
    update: bool,
    shapes: bool,
) -> Result<Result<PairOut, f64>, FractumStatus> {
    let (xa, xb) = (Vec3::from(a.pos), Vec3::from(b.pos));
    if bounds_apart(&xa, a.radius, &xb, b.radius) {
        forget(hist, &mut m.radius, law.friction != 0, shapes);
        return Ok(Err((xa - xb).norm() - (a.radius + b.radius)));
    }
    let (va, vb) = (RawBody::new(a, pa)?, RawBody::new(b, pb)?);
    Ok(variants!(
        law.damp != 0,
        law.friction != 0,
        shapes,
        pair_contact_or_gap(k, &va, &vb, hist, m, dt, update)
    ))
}

/// How far body `after` may have moved since it was `before` (the same body one drift
/// later; m), added to `*travel`: the centroid's path plus the bounding radius times a bound
/// on the angle turned, as Fractum's contact effect sums each body's motion for the
/// separated pairs' skip (`fractum::contact::pair::travel_step`). `fractum_kernel_pair_row`
/// reads the sums.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_travel(
    before: *const FractumBody,
    after: *const FractumBody,
    travel: *mut f64,
) -> FractumStatus {
    kernel(|| {
        let (from, to) = (get(before)?, get(after)?);
        let travel = get_mut(travel)?;
        *travel += travel_step(
            &Vec3::from(from.pos),
            &quat(&from.quat),
            &Vec3::from(to.pos),
            &quat(&to.quat),
            to.radius,
        );
        Ok(())
    })
}

/// The contacts of one row of a neighbour list: body `i` of `bodies` (`n_bodies` of them) with
/// each of its `n` candidates `partners[k] & index_mask`, as `fractum_kernel_pair_placed` gives
/// them one by one, in one call. Each pair is computed with the body of the lower `keys` value
/// (a tag) as A, so a pair gives the same bits in whichever row it is found. `places` holds
/// every body's placement (`fractum_kernel_placement`; read with `shapes` on, may be null
/// without). `memory` holds the candidates' records, `stride` doubles apart: a
/// `FractumPairMemory` (7 doubles), then, with `travel` given, the pair's reach (1 double, 0
/// for a new pair; stride >= 8).
///
/// With `travel` (the bodies' summed motions, `fractum_kernel_travel`; null: off) and `shapes`
/// on, a pair found apart keeps the sum of the travels its bodies must reach before they can
/// touch, and is not searched until they do: Fractum's separated pairs' skip, which changes no
/// result (the search would find the pair apart again).
///
/// Writes the touching pairs to `out[0..*n_out]` with their candidate's index in `at` (both
/// with room for `n`), and, when `kept` is not null, `kept[k]` = 1 where candidate k's record
/// is not all zeros after the call (what a host keeps between neighbour builds).
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn fractum_kernel_pair_row(
    law: *const FractumContactLaw,
    bodies: *const FractumBody,
    places: *const FractumPlacement,
    keys: *const i64,
    travel: *const f64,
    n_bodies: i32,
    i: i32,
    partners: *const i32,
    n: i32,
    index_mask: i32,
    memory: *mut f64,
    stride: i32,
    dt: f64,
    update: i32,
    shapes: i32,
    kept: *mut i32,
    out: *mut FractumContact,
    at: *mut i32,
    n_out: *mut i32,
) -> FractumStatus {
    kernel(|| {
        let law = get(law)?;
        let n_out = get_mut(n_out)?;
        *n_out = 0;
        input_if(n_bodies < 0 || n < 0 || i < 0 || i >= n_bodies)?;
        let (nb, n) = (n_bodies as usize, n as usize);
        let skip = !travel.is_null() && shapes != 0;
        input_if(stride < 7 || (skip && stride < 8))?;
        let stride = stride as usize;
        let bodies = slice_in(bodies, nb)?;
        let keys = slice_in(keys, nb)?;
        let places = if shapes != 0 {
            Some(slice_in(places, nb)?)
        } else {
            None
        };
        let travel = if skip {
            Some(slice_in(travel, nb)?)
        } else {
            None
        };
        let partners = slice_in(partners, n)?;
        let memory = slice_mut(memory, n * stride)?;
        let out = slice_mut(out, n)?;
        let at = slice_mut(at, n)?;
        let mut kept = if kept.is_null() {
            None
        } else {
            Some(slice_mut(kept, n)?)
        };
        let k = consts(law);
        let i = i as usize;
        let mut count = 0;
        for (jj, &p) in partners.iter().enumerate() {
            let j = (p & index_mask) as usize;
            input_if(j >= nb)?;
            let (a, b) = if keys[i] > keys[j] { (j, i) } else { (i, j) };
            let record = &mut memory[jj * stride..(jj + 1) * stride];
            let (ba, bb) = (&bodies[a], &bodies[b]);
            let touched = match travel {
                Some(t) if skips(record[7], t[a], t[b]) => None,
                _ => {
                    let mut hist = Vec3::new(record[0], record[1], record[2]);
                    let mut m = PairMemory {
                        normal: Vec3::new(record[3], record[4], record[5]),
                        radius: record[6],
                    };
                    let place = |x: usize| places.map(|ps| &ps[x]);
                    let result = pair_of(
                        law,
                        &k,
                        ba,
                        place(a),
                        bb,
                        place(b),
                        &mut hist,
                        &mut m,
                        dt,
                        update != 0,
                        shapes != 0,
                    )?;
                    record[..3].copy_from_slice(hist.as_slice());
                    record[3..6].copy_from_slice(m.normal.as_slice());
                    record[6] = m.radius;
                    if let Some(t) = travel {
                        record[7] = match result {
                            Ok(_) => 0.0,
                            Err(gap) => pair_reach(t[a], t[b], gap, ba.radius, bb.radius),
                        };
                    }
                    result.ok()
                }
            };
            if let Some(kept) = kept.as_deref_mut() {
                kept[jj] = i32::from(record.iter().any(|v| *v != 0.0));
            }
            if let Some(p) = touched {
                out[count] = contact_out(Some(p));
                at[count] = jj as i32;
                count += 1;
            }
        }
        *n_out = count as i32;
        Ok(())
    })
}

#[allow(clippy::too_many_arguments)]
fn pair_in(
    law: *const FractumContactLaw,
    a: *const FractumBody,
    pa: Option<&FractumPlacement>,
    b: *const FractumBody,
    pb: Option<&FractumPlacement>,
    memory: *mut FractumPairMemory,
    dt: f64,
    update: i32,
    shapes: i32,
    out: *mut FractumContact,
) -> KResult {
    let law = get(law)?;
    let (a, b) = (get(a)?, get(b)?);
    let memory = get_mut(memory)?;
    let out = get_mut(out)?;
    let mut hist = Vec3::from(memory.hist);
    let mut m = PairMemory {
        normal: Vec3::from(memory.normal),
        radius: memory.radius,
    };
    let p = pair_of(
        law,
        &consts(law),
        a,
        pa,
        b,
        pb,
        &mut hist,
        &mut m,
        dt,
        update != 0,
        shapes != 0,
    )?
    .ok();
    *memory = FractumPairMemory {
        hist: hist.into(),
        normal: m.normal.into(),
        radius: m.radius,
    };
    *out = contact_out(p);
    Ok(())
}

/// The contact of body `a` with the wall through `wall_point` (3 doubles, m) of unit normal
/// `wall_normal` (3 doubles, into the bodies' side) moving at `wall_velocity` (3 doubles,
/// m/s), as Fractum's contact effect computes it (with `shapes` nonzero a poly-ellipsoid's
/// wall contact, else the sphere's), with the candidate's tangential displacement
/// `memory->hist` (m) and held Hertz radius `memory->radius` (m; `memory->normal` is not
/// used) over the step `dt` (s). The wall gets the opposite force; `out->torque_b` is 0.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn fractum_kernel_wall(
    law: *const FractumContactLaw,
    a: *const FractumBody,
    wall_normal: *const f64,
    wall_point: *const f64,
    wall_velocity: *const f64,
    memory: *mut FractumPairMemory,
    dt: f64,
    update: i32,
    shapes: i32,
    out: *mut FractumContact,
) -> FractumStatus {
    kernel(|| {
        let law = get(law)?;
        let a = get(a)?;
        let (n, p, w) = (
            vec3_at(wall_normal)?,
            vec3_at(wall_point)?,
            vec3_at(wall_velocity)?,
        );
        let memory = get_mut(memory)?;
        let out = get_mut(out)?;
        if bound_off_wall(&Vec3::from(a.pos), a.radius, &n, &p) {
            no_contact(law, shapes, memory, out);
            return Ok(());
        }
        let a = body_in(a)?;
        let k = consts(law);
        let va = BodyView::new(&a);
        let mut hist = Vec3::from(memory.hist);
        let mut held = memory.radius;
        let c = variants!(
            law.damp != 0,
            law.friction != 0,
            shapes != 0,
            wall_contact(&k, &va, &n, &p, &w, &mut hist, &mut held, dt, update != 0)
        );
        memory.hist = hist.into();
        memory.radius = held;
        *out = contact_out(c);
        Ok(())
    })
}

/// A poly-ellipsoid of semi-axes `semi` (6 doubles, a+ a- b+ b- c+ c-, m; finite and > 0,
/// else FRACTUM_ERR_INPUT) and mass `mass` (kg) at rest, its centroid at `centroid` (3
/// doubles, m) and its shape frame turned by `shape_quat` (4 doubles, shape to world, w x y z),
/// as Fractum adds one: its body frame is its principal frame of inertia.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_poly_ellipsoid_body(
    semi: *const f64,
    mass: f64,
    centroid: *const f64,
    shape_quat: *const f64,
    out: *mut FractumBody,
) -> FractumStatus {
    kernel(|| {
        let semi = *doubles::<6>(semi)?;
        let centroid = vec3_at(centroid)?;
        let q = quat(doubles::<4>(shape_quat)?);
        let out = get_mut(out)?;
        let pe = PolyEllipsoid::new(semi).map_err(|_| FRACTUM_ERR_INPUT)?;
        *out = body_out(&Body::poly_ellipsoid(pe, mass, centroid, q));
        Ok(())
    })
}

/// The volume (m^3) of body `b`.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_body_volume(
    b: *const FractumBody,
    volume: *mut f64,
) -> FractumStatus {
    kernel(|| {
        let b = body_in(get(b)?)?;
        *get_mut(volume)? = b.volume();
        Ok(())
    })
}
