//! Contact kernels: the contact law, the Hertz–Mindlin force, the convex narrow phase, the
//! pair and wall contacts with their memories, placements, the neighbour-list row with the
//! separated pairs' skip, and the poly-ellipsoid grains' construction and volume.

use super::*;
use fractum::contact::convex::{self, ContactGeometry, Placed};
use fractum::contact::hertz_mindlin::{
    ContactForce, Hertz, KernelConsts, Mindlin, ViscousDamping, hertz_mindlin,
};
use fractum::contact::pair::{
    BodyView, ContactBody, PairMemory, PairOut, Placement, bound_off_sleeve, bound_off_wall,
    bounds_apart, forget, pair_contact_or_gap, pair_reach, skips, sleeve_contact, travel_step,
    wall_contact,
};
use fractum::state::{SLEEVE_SLICES, Sleeve};

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
        let k = consts(law);
        let row = Row::of(
            law,
            &k,
            (bodies, places, keys, travel),
            nb,
            index_mask,
            stride,
            dt,
            update,
            shapes,
        )?;
        let partners = slice_in(partners, n)?;
        let memory = slice_mut(memory, n * stride)?;
        let out = slice_mut(out, n)?;
        let at = slice_mut(at, n)?;
        let kept = if kept.is_null() {
            None
        } else {
            Some(slice_mut(kept, n)?)
        };
        let mut count = 0;
        row.contacts(i as usize, partners, memory, kept, |jj, p| {
            out[count] = contact_out(Some(p));
            at[count] = jj as i32;
            count += 1;
        })?;
        *n_out = count as i32;
        Ok(())
    })
}

/// Every row of a host's neighbour list `list` in one call: each row's contacts as
/// `fractum_kernel_pair_row` computes them (the same bodies, placements, keys, travels and
/// records), gathered for `fractum_kernel_sum_contacts`.
///
/// - `touching` (room for `capacity`, the list's candidates suffice) receives each touching
///   contact in the rows' order, as its row's atom `i` sees it (force and torques swapped
///   back where the partner was body A), with both atoms' shares of the frequency bound
///   when `shares` is nonzero; `*n_touching` their count.
/// - `sides` (room for `2 capacity`) receives the codes `fractum_kernel_sum_contacts`
///   takes, ordered for its sums: the owned atoms (below `n_local`) in index order, each
///   one's contacts in the order of its partners' keys (the same bits on any rank count);
///   `*n_sides` their count.
/// - `energy[0]` and `energy[1]` grow by the contacts' elastic energy and dissipation, each
///   contact counted where its body A is owned.
/// - Records: with `keep` nonzero each row's stored records are updated in place (and its
///   kept flags set); with `keep` 0 they are computed on copies and left as they were, the
///   kept flags set from the stored records. A record whose pair involves a key of
///   `reshaped` (`n_reshaped` keys, sorted) starts afresh: its held Hertz radius and its
///   reach (doubles 6 and 7) are cleared first.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn fractum_kernel_pair_list(
    law: *const FractumContactLaw,
    bodies: *const FractumBody,
    places: *const FractumPlacement,
    keys: *const i64,
    travel: *const f64,
    n_bodies: i32,
    n_local: i32,
    list: *const FractumNeighbours,
    keep: i32,
    reshaped: *const i64,
    n_reshaped: usize,
    dt: f64,
    update: i32,
    shapes: i32,
    shares: i32,
    touching: *mut FractumTouching,
    capacity: usize,
    n_touching: *mut usize,
    sides: *mut i32,
    n_sides: *mut usize,
    energy: *mut f64,
) -> FractumStatus {
    kernel(|| {
        let law = get(law)?;
        let list = get(list)?;
        let (n_touching, n_sides) = (get_mut(n_touching)?, get_mut(n_sides)?);
        let energy = slice_mut(energy, 2)?;
        *n_touching = 0;
        *n_sides = 0;
        input_if(n_bodies < 0 || n_local < 0 || n_local > n_bodies || list.inum < 0)?;
        let (nb, nl) = (n_bodies as usize, n_local as usize);
        input_if(list.stride < 8)?;
        let stride = list.stride as usize;
        let k = consts(law);
        let row = Row::of(
            law,
            &k,
            (bodies, places, keys, travel),
            nb,
            list.index_mask,
            stride,
            dt,
            update,
            shapes,
        )?;
        let (bodies, keys) = (row.bodies, row.keys);
        let reshaped = slice_in(reshaped, n_reshaped)?;
        let out = slice_mut(touching, capacity)?;
        let codes = slice_mut(sides, 2 * capacity)?;
        let inum = list.inum as usize;
        let ilist = slice_in(list.ilist, inum)?;
        // Rows are owned atoms: the tables are read below `n_local` only.
        let numneigh = slice_in(list.numneigh, nl)?;
        let firstneigh = slice_in(list.firstneigh, nl)?;
        let history = !list.firstvalue.is_null();
        let (firstvalue, firsttouch) = if history {
            (
                slice_in(list.firstvalue, nl)?,
                slice_in(list.firsttouch, nl)?,
            )
        } else {
            (&[][..], &[][..])
        };
        let was_reshaped = |key: i64| !reshaped.is_empty() && reshaped.binary_search(&key).is_ok();
        // Each side: its atom, its partner's key and its code, in the rows' order.
        let mut found: Vec<(u32, i64, i32)> = Vec::new();
        let mut scratch: Vec<f64> = Vec::new();
        let (mut elastic, mut dissipated) = (0.0, 0.0);
        let mut count = 0usize;
        for &i in ilist {
            input_if(i < 0 || i as usize >= nl)?;
            let i = i as usize;
            let jnum = numneigh[i];
            input_if(jnum < 0)?;
            if jnum == 0 {
                continue;
            }
            let n = jnum as usize;
            let partners = slice_in(firstneigh[i], n)?;
            let stored = if history {
                Some(slice_mut(firstvalue[i], n * stride)?)
            } else {
                None
            };
            let touch = if history {
                Some(slice_mut(firsttouch[i], n)?)
            } else {
                None
            };
            // The row's records: the stored ones when they are kept, else a copy (zeros
            // without records) thrown away after the row.
            let (records, kept) = match stored {
                Some(st) if keep != 0 => (st, touch),
                other => {
                    scratch.clear();
                    match &other {
                        Some(st) => scratch.extend_from_slice(st),
                        None => scratch.resize(n * stride, 0.0),
                    }
                    if let (Some(touch), Some(st)) = (touch, &other) {
                        for (jj, t) in touch.iter_mut().enumerate() {
                            *t = i32::from(
                                st[jj * stride..(jj + 1) * stride].iter().any(|v| *v != 0.0),
                            );
                        }
                    }
                    (&mut scratch[..], None)
                }
            };
            if !reshaped.is_empty() {
                let all = was_reshaped(keys[i]);
                for (jj, &p) in partners.iter().enumerate() {
                    let j = (p & list.index_mask) as usize;
                    input_if(j >= nb)?;
                    if all || was_reshaped(keys[j]) {
                        records[jj * stride + 6] = 0.0;
                        records[jj * stride + 7] = 0.0;
                    }
                }
            }
            let mut failed = Ok(());
            row.contacts(i, partners, records, kept, |jj, p| {
                if failed.is_err() {
                    return;
                }
                let j = (partners[jj] & list.index_mask) as usize;
                let swap = keys[i] > keys[j];
                let a = if swap { j } else { i };
                if a < nl {
                    elastic += p.c.energy;
                    dissipated += p.c.dissipated;
                }
                if count >= out.len() {
                    failed = Err(FRACTUM_ERR_INPUT);
                    return;
                }
                let c = contact_out(Some(p));
                let neg = |v: [f64; 3]| v.map(|x| -x);
                let mut t = FractumTouching {
                    i: i as i32,
                    j: j as i32,
                    force: if swap { neg(c.force) } else { c.force },
                    torque_i: if swap { c.torque_b } else { c.torque_a },
                    torque_j: if swap { c.torque_a } else { c.torque_b },
                    point: c.point,
                    hertz_force: c.hertz_force,
                    radius: c.radius,
                    share_i: 0.0,
                    share_j: 0.0,
                };
                if shares != 0 {
                    // Both bodies' loads once per contact, as fractum_kernel_frequency_shares.
                    match (
                        body_load(law, &c, &bodies[i]),
                        body_load(law, &c, &bodies[j]),
                    ) {
                        (Ok(li), Ok(lj)) => {
                            t.share_i = fractum::contact::records::frequency_share(li, Some(lj));
                            t.share_j = fractum::contact::records::frequency_share(lj, Some(li));
                        }
                        (Err(e), _) | (_, Err(e)) => {
                            failed = Err(e);
                            return;
                        }
                    }
                }
                out[count] = t;
                found.push((i as u32, keys[j], 2 * count as i32));
                if j < nl {
                    found.push((j as u32, keys[i], 2 * count as i32 + 1));
                }
                count += 1;
            })?;
            failed?;
        }
        // Each atom's sides in the order of its partners' keys: atoms by a counting sort
        // (stable) into `codes` with their keys beside them, then a stable insertion sort
        // within each atom (a few contacts each).
        let mut first = vec![0usize; nl + 1];
        for s in &found {
            first[s.0 as usize + 1] += 1;
        }
        for a in 0..nl {
            first[a + 1] += first[a];
        }
        let mut cursor = first[..nl].to_vec();
        let codes = &mut codes[..found.len()];
        let mut key = vec![0i64; found.len()];
        for s in &found {
            let at = &mut cursor[s.0 as usize];
            codes[*at] = s.2;
            key[*at] = s.1;
            *at += 1;
        }
        for a in 0..nl {
            for k in first[a] + 1..first[a + 1] {
                let (moving, moving_key) = (codes[k], key[k]);
                let mut m = k;
                while m > first[a] && key[m - 1] > moving_key {
                    codes[m] = codes[m - 1];
                    key[m] = key[m - 1];
                    m -= 1;
                }
                codes[m] = moving;
                key[m] = moving_key;
            }
        }
        energy[0] += elastic;
        energy[1] += dissipated;
        *n_touching = count;
        *n_sides = found.len();
        Ok(())
    })
}

/// What every row of an evaluation shares: the law, the bodies with their placements,
/// keys and travels, and how a row's records are laid out.
struct Row<'a> {
    law: &'a FractumContactLaw,
    k: &'a KernelConsts,
    bodies: &'a [FractumBody],
    places: Option<&'a [FractumPlacement]>,
    keys: &'a [i64],
    travel: Option<&'a [f64]>,
    index_mask: i32,
    stride: usize,
    dt: f64,
    update: bool,
    shapes: bool,
}

impl<'a> Row<'a> {
    /// A host's tables of `n` bodies, their placements (read with `shapes`), keys and travels
    /// (read with `shapes`, where given: the separated pairs' skip).
    #[allow(clippy::too_many_arguments, clippy::type_complexity)]
    fn of(
        law: &'a FractumContactLaw,
        k: &'a KernelConsts,
        (bodies, places, keys, travel): (
            *const FractumBody,
            *const FractumPlacement,
            *const i64,
            *const f64,
        ),
        n: usize,
        index_mask: i32,
        stride: usize,
        dt: f64,
        update: i32,
        shapes: i32,
    ) -> Result<Self, FractumStatus> {
        let skip = !travel.is_null() && shapes != 0;
        Ok(Row {
            law,
            k,
            bodies: slice_in(bodies, n)?,
            places: if shapes != 0 {
                Some(slice_in(places, n)?)
            } else {
                None
            },
            keys: slice_in(keys, n)?,
            travel: if skip {
                Some(slice_in(travel, n)?)
            } else {
                None
            },
            index_mask,
            stride,
            dt,
            update: update != 0,
            shapes: shapes != 0,
        })
    }

    /// Body `i`'s contacts with each of `partners` (`& index_mask`), their records in
    /// `memory` (`stride` doubles each, updated), `kept[jj]` set where a record holds
    /// anything; `touching(jj, contact)` for each pair that touches, in the partners' order.
    /// Each pair is computed with the body of the lower key as A.
    fn contacts(
        &self,
        i: usize,
        partners: &[i32],
        memory: &mut [f64],
        mut kept: Option<&mut [i32]>,
        mut touching: impl FnMut(usize, PairOut),
    ) -> KResult {
        let (bodies, keys, stride) = (self.bodies, self.keys, self.stride);
        for (jj, &p) in partners.iter().enumerate() {
            let j = (p & self.index_mask) as usize;
            input_if(j >= bodies.len())?;
            let (a, b) = if keys[i] > keys[j] { (j, i) } else { (i, j) };
            let record = &mut memory[jj * stride..(jj + 1) * stride];
            let (ba, bb) = (&bodies[a], &bodies[b]);
            let touched = match self.travel {
                Some(t) if skips(record[7], t[a], t[b]) => None,
                _ => {
                    let mut hist = Vec3::new(record[0], record[1], record[2]);
                    let mut m = PairMemory {
                        normal: Vec3::new(record[3], record[4], record[5]),
                        radius: record[6],
                    };
                    let place = |x: usize| self.places.map(|ps| &ps[x]);
                    let result = pair_of(
                        self.law,
                        self.k,
                        ba,
                        place(a),
                        bb,
                        place(b),
                        &mut hist,
                        &mut m,
                        self.dt,
                        self.update,
                        self.shapes,
                    )?;
                    record[..3].copy_from_slice(hist.as_slice());
                    record[3..6].copy_from_slice(m.normal.as_slice());
                    record[6] = m.radius;
                    if let Some(t) = self.travel {
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
                touching(jj, p);
            }
        }
        Ok(())
    }
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

/// The contact of body `a` with a sleeve: the fixed, rigid circular cylinder of inner radius
/// `radius` (m, > 0) whose axis runs along z through `centre` (3 doubles, m; its z is not
/// read), as Fractum's contact effect computes it (`fractum::contact::pair::sleeve_contact`:
/// with `shapes` nonzero a poly-ellipsoid's farthest point from the axis, else the sphere's
/// closed form; the Hertz radius of a convex body in a concave cylinder), with the candidate's
/// tangential displacement `memory->hist` (m) and held Hertz radius `memory->radius` (m;
/// `memory->normal` is not used) over the step `dt` (s). `out->normal` points towards the
/// axis; the sleeve gets the opposite force; `out->torque_b` is 0.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn fractum_kernel_sleeve(
    law: *const FractumContactLaw,
    a: *const FractumBody,
    centre: *const f64,
    radius: f64,
    memory: *mut FractumPairMemory,
    dt: f64,
    update: i32,
    shapes: i32,
    out: *mut FractumContact,
) -> FractumStatus {
    kernel(|| {
        let law = get(law)?;
        let a = get(a)?;
        let centre = vec3_at(centre)?;
        let memory = get_mut(memory)?;
        let out = get_mut(out)?;
        input_if(!(radius > 0.0 && radius.is_finite()))?;
        let sleeve = Sleeve {
            centre,
            radius,
            force: Vec3::zeros(),
            load: 0.0,
            slices: [0.0; SLEEVE_SLICES],
            stiffness: 0.0,
            contacts: 0,
        };
        if bound_off_sleeve(&Vec3::from(a.pos), a.radius, &sleeve) {
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
            sleeve_contact(&k, &va, &sleeve, &mut hist, &mut held, dt, update != 0)
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
