//! Fracture kernels: the stress and failure criteria, the break check, the per-grain load,
//! strengths and jitter, the split, the seeded uniforms, the cohesive bonds and springs, and
//! whether a shape can break.

use super::*;
use fractum::fracture::break_plane::{self, Trigger};
use fractum::fracture::cohesion::{self, Demand};
use fractum::fracture::{
    Criterion, FractureParams, GrainLoad, PendingSplit, bond_split, criteria, grain_average_stress,
    grain_fails, split_grain,
};
use fractum::sample::{UNIFORM_COUNTERS, UNIFORMS_PER_COUNTER, uniforms};

/// The average stress of grain `b` (9 doubles out, Pa, tension positive, row-major; Eq.
/// 8-13) from the moment of its contact forces `moment` (9 doubles, row-major, N m: the sum
/// of force (x) (point - centre) over its contacts, force on b) and the torque `torque` on it
/// (3 doubles, N m), with the inertial terms of its angular acceleration and velocity.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_average_stress(
    b: *const FractumBody,
    moment: *const f64,
    torque: *const f64,
    stress: *mut f64,
) -> FractumStatus {
    kernel(|| {
        let b = body_in(get(b)?)?;
        let moment = matrix(doubles::<9>(moment)?);
        let torque = vec3_at(torque)?;
        let stress = doubles_mut::<9>(stress)?;
        *stress = matrix_out(&grain_average_stress(&b, &moment, &torque));
        Ok(())
    })
}

/// The principal compressions of a stress (9 doubles, row-major, Pa, tension positive): 3
/// doubles out (Pa, compression positive, s1 >= s2 >= s3; of the symmetric part).
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_principal_compressions(
    stress: *const f64,
    out: *mut f64,
) -> FractumStatus {
    kernel(|| {
        let s = matrix(doubles::<9>(stress)?);
        *doubles_mut::<3>(out)? = criteria::principal_compression_values(&s);
        Ok(())
    })
}

/// `*fails` = 1 when Hoek-Brown fails at the principal compressions `s1` >= `s3` (Pa,
/// compression positive) for the strength `sigma_c` (Pa) and `mi`, else 0.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_hoek_brown_fails(
    s1: f64,
    s3: f64,
    sigma_c: f64,
    mi: f64,
    fails: *mut i32,
) -> FractumStatus {
    kernel(|| {
        *get_mut(fails)? = i32::from(criteria::hoek_brown_fails(s1, s3, sigma_c, mi));
        Ok(())
    })
}

/// The largest tensile stress (Pa) of a Hertz contact of elastic (Hertz) normal force
/// `normal_force` (N: a contact's `hertz_force`, not its damped total) and contact radius
/// `contact_radius` (m) for Poisson's ratio `poisson` (Eq. 17).
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_contact_tensile_stress(
    normal_force: f64,
    contact_radius: f64,
    poisson: f64,
    stress: *mut f64,
) -> FractumStatus {
    kernel(|| {
        *get_mut(stress)? = criteria::contact_tensile_stress(normal_force, contact_radius, poisson);
        Ok(())
    })
}

/// The Weibull strength factor (dimensionless; Eq. 18) for the uniform variate `p` in (0, 1),
/// the Weibull modulus `w`, the grain's equivalent radius `x` (m) and the reference radius
/// `x_m` (m).
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_weibull_factor(
    p: f64,
    w: f64,
    x: f64,
    x_m: f64,
    factor: *mut f64,
) -> FractumStatus {
    kernel(|| {
        *get_mut(factor)? = criteria::weibull_factor(p, w, x, x_m);
        Ok(())
    })
}

/// The unit normal (3 doubles out) of the plane through the `n` points (m; the
/// least-squares plane for more than 3); `*found` = 0 (normal 0 0 0) for fewer than 3 or
/// collinear points.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_contacts_plane_normal(
    points: *const [f64; 3],
    n: usize,
    normal: *mut f64,
    found: *mut i32,
) -> FractumStatus {
    kernel(|| {
        let pts = self::points(points, n)?;
        let normal = doubles_mut::<3>(normal)?;
        let found = get_mut(found)?;
        let nrm = break_plane::contacts_plane_normal(pts);
        *normal = nrm.unwrap_or_else(Vec3::zeros).into();
        *found = i32::from(nrm.is_some());
        Ok(())
    })
}

fn fracture_params(l: &FractumFractureLaw) -> Result<FractureParams, FractumStatus> {
    let within = |v: i32, (lo, hi): (usize, usize)| v >= 0 && (lo..=hi).contains(&(v as usize));
    let springs_ok = l.springs == 0 || within(l.springs, fractum::fracture::SPRINGS);
    input_if(!within(l.critical_contacts, fractum::fracture::CRITICAL_CONTACTS) || !springs_ok)?;
    input_if(!(l.comminution_limit >= 0.0 && l.comminution_limit.is_finite()))?;
    Ok(fracture_params_in(l))
}

fn trigger_out(t: Option<(Trigger, Criterion, f64)>) -> FractumTrigger {
    match t {
        None => FractumTrigger::default(),
        Some((Trigger::HoekBrown { stress }, _, value)) => FractumTrigger {
            kind: 1,
            stress: matrix_out(&stress),
            value,
            ..FractumTrigger::default()
        },
        Some((Trigger::Contacts { normal }, _, value)) => FractumTrigger {
            kind: 2,
            normal: normal.into(),
            value,
            ..FractumTrigger::default()
        },
    }
}

fn trigger_in(t: &FractumTrigger) -> Result<Trigger, FractumStatus> {
    match t.kind {
        1 => Ok(Trigger::HoekBrown {
            stress: matrix(&t.stress),
        }),
        2 => Ok(Trigger::Contacts {
            normal: Vec3::from(t.normal),
        }),
        _ => Err(FRACTUM_ERR_INPUT),
    }
}

/// Whether free grain `b` breaks, as Fractum checks it after a step: Hoek-Brown on its
/// average stress (of the contact moment `moment`, 9 doubles row-major, N m, and the torque
/// `torque`, 3 doubles, N m; see fractum_kernel_average_stress) with sigma_c, times its
/// Weibull factor `strength` (1 without Weibull statistics) where `law->weibull_sigma_c`;
/// else, when `n_critical` >=
/// `law->critical_contacts`, the critical contacts (those with a contact tensile stress above
/// `law->sigma_f * strength`) with `critical_points` their first min(n_critical, 3) points
/// (m, largest stress first; may be null when n_critical is 0) spanning a plane and
/// `top_stress` (Pa) the largest of their stresses. The caller sums the moment over a grain's
/// contacts (force on it (x) (point - centre)) and collects its critical contacts; Fractum
/// checks only grains with a nonzero moment that no spring holds. `out->kind` = 0: no break,
/// and so for a piece below `law->comminution_limit`, which Fractum does not check. With
/// `law->particle_strength` the critical contacts are those above `law->sigma_f *
/// cbrt(strength)`.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn fractum_kernel_check(
    law: *const FractumFractureLaw,
    b: *const FractumBody,
    strength: f64,
    moment: *const f64,
    torque: *const f64,
    n_critical: usize,
    critical_points: *const [f64; 3],
    top_stress: f64,
    out: *mut FractumTrigger,
) -> FractumStatus {
    kernel(|| {
        let p = fracture_params(get(law)?)?;
        let b = body_in(get(b)?)?;
        let moment = matrix(doubles::<9>(moment)?);
        let torque = vec3_at(torque)?;
        let pts = points(critical_points, n_critical.min(3))?;
        let out = get_mut(out)?;
        if p.below_comminution_limit(b.volume()) {
            *out = trigger_out(None);
            return Ok(());
        }
        *out = trigger_out(grain_fails(
            &p, &b, strength, &moment, &torque, n_critical, pts, top_stress,
        ));
        Ok(())
    })
}

fn pending_out(s: &PendingSplit) -> FractumPending {
    FractumPending {
        centroid: s.centroid.into(),
        accel: s.accel.into(),
        alpha: s.alpha.into(),
        omega: s.omega.into(),
        points: s.points.map(Into::into),
        count: s.count as i32,
        area: s.area,
    }
}

fn pending_in(s: &FractumPending) -> Result<PendingSplit, FractumStatus> {
    input_if(!(0..=16).contains(&s.count))?;
    Ok(PendingSplit {
        a: 0,
        b: 0,
        centroid: Vec3::from(s.centroid),
        accel: Vec3::from(s.accel),
        alpha: Vec3::from(s.alpha),
        omega: Vec3::from(s.omega),
        points: s.points.map(Vec3::from),
        count: s.count as usize,
        area: s.area,
    })
}

/// The allowed range (inclusive) of the counting fracture key named `key` (a NUL-terminated
/// string: "critical_contacts" or "springs"), the one Fractum's scene checks and kernels use
/// (`fractum::fracture::key_range`): written to `*lo`, `*hi`. FRACTUM_ERR_INPUT for another
/// name.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_fracture_range(
    key: *const std::ffi::c_char,
    lo: *mut f64,
    hi: *mut f64,
) -> FractumStatus {
    kernel(|| {
        let name = c_str(key)?;
        let (a, b) = fractum::fracture::key_range(name).ok_or(FRACTUM_ERR_INPUT)?;
        let (lo, hi) = (get_mut(lo)?, get_mut(hi)?);
        *lo = a as f64;
        *hi = b as f64;
        Ok(())
    })
}

/// Adds one contact to grain load `load`, as Fractum's check adds it
/// (`fractum::fracture::GrainLoad::add`): the force `force` on the grain (3 doubles, N) at
/// `point` (m) to the moment about the grain's centre `centre` (m), and, when the contact
/// tensile stress of its Hertz force `hertz_force` (N) and radius `radius` (m) at Poisson's
/// ratio `poisson` is above `threshold` (Pa: sigma_f times the grain's Weibull factor), to
/// its critical contacts. A host adds a grain's contacts in the order Fractum would (the
/// moment is a sum: its last bits follow the order).
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn fractum_kernel_grain_load_add(
    load: *mut FractumGrainLoad,
    centre: *const f64,
    force: *const f64,
    point: *const f64,
    hertz_force: f64,
    radius: f64,
    poisson: f64,
    threshold: f64,
) -> FractumStatus {
    kernel(|| {
        let l = get_mut(load)?;
        input_if(l.count < 0)?;
        let (centre, force, point) = (vec3_at(centre)?, vec3_at(force)?, vec3_at(point)?);
        let mut g = GrainLoad {
            moment: matrix(&l.moment),
            count: l.count as usize,
            stress: l.stress,
            point: l.point.map(Vec3::from),
        };
        g.add(
            &centre,
            &force,
            &point,
            hertz_force,
            radius,
            poisson,
            threshold,
        );
        *l = grain_load_out(&g);
        Ok(())
    })
}

/// The Weibull factor of grain `grain` (its identity: 1 + its index in Fractum's bodies, the
/// atom ID of `fractum export lammps --plugin`) after `generation` splits, as Fractum's run
/// draws it (`fractum::fracture::grain_strength`, keyed by `seed`, grain and generation): of
/// the body `b`'s volume, with Weibull modulus `w` and reference size `x_m` (m).
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_grain_strength(
    seed: u64,
    grain: u64,
    generation: u32,
    b: *const FractumBody,
    w: f64,
    x_m: f64,
    factor: *mut f64,
) -> FractumStatus {
    kernel(|| {
        input_if(!(w > 0.0 && x_m > 0.0))?;
        let volume = body_in(get(b)?)?.volume();
        *get_mut(factor)? =
            fractum::fracture::grain_strength(seed, grain, generation, volume, w, x_m);
        Ok(())
    })
}

/// `fractum_kernel_grain_strength` with the size exponent `beta` (>= 0) given: the factor
/// scales as (x/x_m)^(-beta) instead of Eq. 18's (x/x_m)^(-2/w) (a scene's
/// `fracture.size_exponent`; `fractum::fracture::grain_strength_sized`), the same draw.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn fractum_kernel_grain_strength_sized(
    seed: u64,
    grain: u64,
    generation: u32,
    b: *const FractumBody,
    w: f64,
    beta: f64,
    x_m: f64,
    factor: *mut f64,
) -> FractumStatus {
    kernel(|| {
        input_if(!(w > 0.0 && x_m > 0.0 && beta >= 0.0 && beta.is_finite()))?;
        let volume = body_in(get(b)?)?.volume();
        *get_mut(factor)? =
            fractum::fracture::grain_strength_sized(seed, grain, generation, volume, w, beta, x_m);
        Ok(())
    })
}

/// The angles (3 doubles, rad) of the slight random rotation of sphere `grain`'s ideal break
/// plane at its split after `generation` splits, as Fractum's run draws them
/// (`fractum::fracture::grain_jitter`), for fractum_kernel_split's `jitter`.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_grain_jitter(
    seed: u64,
    grain: u64,
    generation: u32,
    angles: *mut f64,
) -> FractumStatus {
    kernel(|| {
        *doubles_mut::<3>(angles)? = fractum::fracture::grain_jitter(seed, grain, generation);
        Ok(())
    })
}

/// Splits grain `parent`, which carries the force `force` (3 doubles, N) and torque `torque`
/// (3 doubles, N m), for the reason `trigger` (kind 1 or 2, from fractum_kernel_check), as
/// Fractum splits it: the break plane (a sphere first turns to the ideal plane with
/// `law->ideal_plane`, and with `law->plane_jitter` by the slight rotation of the angles
/// `jitter`, 3 doubles in rad from fractum_kernel_jitter_angles; NULL: no rotation), the two
/// halves moving as the parent did, and the pending bond (the parent's acceleration force x
/// (1 / mass), angular acceleration, centroid and angular velocity, and with cohesion
/// (`law->springs` > 0) the spring points on the break plane and the area each stands for). `out->axis` = -1
/// when the grain's shape forbids breaking. FRACTUM_ERR_INPUT when the parent's radius or mass
/// is not finite and positive.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_split(
    law: *const FractumFractureLaw,
    parent: *const FractumBody,
    force: *const f64,
    torque: *const f64,
    trigger: *const FractumTrigger,
    jitter: *const f64,
    out: *mut FractumSplit,
) -> FractumStatus {
    kernel(|| {
        let p = fracture_params(get(law)?)?;
        let parent = grain_in(get(parent)?)?;
        let (force, torque) = (vec3_at(force)?, vec3_at(torque)?);
        let trigger = trigger_in(get(trigger)?)?;
        let jitter = if jitter.is_null() {
            None
        } else {
            Some(*doubles::<3>(jitter)?)
        };
        let out = get_mut(out)?;
        *out = match split_grain(&p, &parent, &force, &torque, &trigger, jitter) {
            None => FractumSplit {
                axis: -1,
                ..FractumSplit::default()
            },
            Some(s) => FractumSplit {
                axis: s.axis as i32,
                plus: body_out(&s.plus),
                minus: body_out(&s.minus),
                pending: pending_out(&s.pending),
            },
        };
        Ok(())
    })
}

/// The angles (3 doubles out, rad) of a sphere's random slight break-plane rotation from 6
/// uniform variates `u` in [0, 1]: per angle k the magnitude `theta_max (0.5 + 0.5 u[2k])`
/// (theta_max = atan(1/5)), positive when `u[2k+1] >= 0.5`, else negative. Fractum draws the
/// six from its fracture stream (per angle: a 53-bit uniform, then a 32-bit word / 2^32); a
/// host may take them from fractum_kernel_uniforms.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_jitter_angles(u: *const f64, angles: *mut f64) -> FractumStatus {
    kernel(|| {
        let u = doubles::<6>(u)?;
        *doubles_mut::<3>(angles)? = break_plane::jitter_angles(u);
        Ok(())
    })
}

/// `n` uniform variates in (0, 1] (53 bits each) into `out` from the ChaCha8 stream `key` of
/// `seed` (seeded as Fractum's scene streams), starting at word `counter` * 2^32: the same
/// (seed, key, counter) always gives the same numbers, on any rank. `counter` < 2^36 and
/// `n` <= 2^31, else FRACTUM_ERR_INPUT; `out` may be null when `n` is 0.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_uniforms(
    seed: u64,
    key: u64,
    counter: u64,
    n: usize,
    out: *mut f64,
) -> FractumStatus {
    kernel(|| {
        input_if(counter >= UNIFORM_COUNTERS || n > UNIFORMS_PER_COUNTER)?;
        uniforms(seed, key, counter, slice_mut(out, n)?);
        Ok(())
    })
}

/// The cohesive springs of one split (Eq. 39-43), as Fractum makes them once the halves'
/// forces are known: `a` is the + half (the parent's body), `b` the - half, `force_a`,
/// `torque_a`, `force_b`, `torque_b` (3 doubles each, N and N m) the forces and torques on
/// them after the split, `pending` the split's pending bond. Their initial forces make each
/// half accelerate and turn as the parent did; a spring with no force is not made. Writes
/// the `*made` springs to `springs` (room for 16; the rest zeroed); none without cohesion
/// (`law->springs` = 0). Springs come in the order of `pending->points`, skipping any that
/// would carry no force (|f| <= 1e-12 (|demand on a| + |demand on b|)): when `*made` equals
/// `pending->count`, spring k sits at `pending->points[k]`. The caller applies each spring's
/// initial force at once, as Fractum does: `last_force` on a at the spring's point (torque
/// (point - a's centre) x force) and its opposite on b (torque -(point - b's centre) x
/// force); Fractum takes the point as `pending->points[k] - a's centre` (then + a's centre
/// for b's lever), a's centre + q_a on_a agrees with it to round-off.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn fractum_kernel_bond(
    law: *const FractumFractureLaw,
    a: *const FractumBody,
    b: *const FractumBody,
    force_a: *const f64,
    torque_a: *const f64,
    force_b: *const f64,
    torque_b: *const f64,
    pending: *const FractumPending,
    springs: *mut FractumSpring,
    made: *mut i32,
) -> FractumStatus {
    kernel(|| {
        let law = get(law)?;
        let p = fracture_params(law)?;
        let (a, b) = (body_in(get(a)?)?, body_in(get(b)?)?);
        let loads = [
            vec3_at(force_a)?,
            vec3_at(torque_a)?,
            vec3_at(force_b)?,
            vec3_at(torque_b)?,
        ];
        let pending = pending_in(get(pending)?)?;
        let springs = get_mut(springs.cast::<[FractumSpring; 16]>())?;
        let made = get_mut(made)?;
        *springs = [FractumSpring::default(); 16];
        let mut count = 0;
        if let Some((gc, _)) = p.cohesion {
            let [fa, ta, fb, tb] = &loads;
            bond_split(gc, &a, &b, [fa, ta, fb, tb], &pending, |m| {
                springs[count] = spring_out(&m.spring);
                count += 1;
            });
        }
        *made = count as i32;
        Ok(())
    })
}

/// The initial spring forces (`n` x 3 doubles out, N, on A; B gets the opposite) that meet
/// a split's demand with the least squares, for springs at `points` (`n` x 3 doubles, m,
/// relative to A's centre of mass): `demand` is 15 doubles, force_a torque_a force_b
/// torque_b b_offset (N, N m, N, N m, m; what A needs from B, what B needs from A about its
/// own centre, and B's centre relative to A's).
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_spring_initial_forces(
    points: *const [f64; 3],
    n: usize,
    demand: *const f64,
    forces: *mut [f64; 3],
) -> FractumStatus {
    kernel(|| {
        let pts = self::points(points, n)?;
        let d = doubles::<15>(demand)?;
        let v = |k: usize| Vec3::new(d[3 * k], d[3 * k + 1], d[3 * k + 2]);
        let demand = Demand {
            force_a: v(0),
            torque_a: v(1),
            force_b: v(2),
            torque_b: v(3),
            b_offset: v(4),
        };
        let out = slice_mut(forces, n)?;
        let f = cohesion::initial_forces(pts, &demand);
        for (o, x) in out.iter_mut().zip(&f) {
            *o = (*x).into();
        }
        Ok(())
    })
}

/// One evaluation of spring `s` between bodies `a` and `b` (of which it uses the positions and
/// orientations), as Fractum evaluates it each step: its largest elongation, its
/// force on a (`force_a`, 3 doubles, N; b gets the opposite), the torques on a and b about
/// their centres (`torque_a`, `torque_b`, 3 doubles each, N m), and the work it did on the
/// pair since the last evaluation (`*work`, J). When its force has fallen to zero the spring
/// breaks for good: `s->broken` = 1, `*broke` = 1, forces and torques 0. A spring already
/// broken does nothing (all 0, `*broke` = 0).
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn fractum_kernel_spring(
    s: *mut FractumSpring,
    a: *const FractumBody,
    b: *const FractumBody,
    force_a: *mut f64,
    torque_a: *mut f64,
    torque_b: *mut f64,
    work: *mut f64,
    broke: *mut i32,
) -> FractumStatus {
    kernel(|| {
        let s = get_mut(s)?;
        let (a, b) = (body_in(get(a)?)?, body_in(get(b)?)?);
        let force_a = doubles_mut::<3>(force_a)?;
        let torque_a = doubles_mut::<3>(torque_a)?;
        let torque_b = doubles_mut::<3>(torque_b)?;
        let (work, broke) = (get_mut(work)?, get_mut(broke)?);
        let mut spring = spring_in(s);
        let act = if spring.broken {
            Default::default()
        } else {
            spring.act(&a.pos, &a.orientation, &b.pos, &b.orientation)
        };
        *s = spring_out(&spring);
        *force_a = act.force.into();
        *torque_a = act.torque_a.into();
        *torque_b = act.torque_b.into();
        *work = act.work;
        *broke = i32::from(act.broke);
        Ok(())
    })
}

/// `*can` = 1 when grain `b` can break along some plane, 0 when its shape forbids breaking
/// whatever triggers it (`fracture::break_plane::shape_forbids_breaking`: two or three bad
/// semi-axis ratios, Section 3.3.3), so that `fractum_kernel_split` would return axis -1: a
/// host that must prepare a split (LAMMPS: a reneighbouring) asks first. A sphere can.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_can_break(b: *const FractumBody, can: *mut i32) -> FractumStatus {
    kernel(|| {
        let b = body_in(get(b)?)?;
        let can = get_mut(can)?;
        *can = i32::from(!fractum::fracture::break_plane::shape_forbids_breaking(
            &b.shape.semi_axes(b.radius),
        ));
        Ok(())
    })
}

/// The cohesive energy G_c = K_Ic² (1 − ν²) / E (J/m², Eq. 38) of a material of toughness
/// `toughness` (Pa m^0.5), Young's modulus `young` (Pa) and Poisson's ratio `poisson`.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_cohesive_energy(
    toughness: f64,
    young: f64,
    poisson: f64,
    gc: *mut f64,
) -> FractumStatus {
    kernel(|| {
        input_if(!(toughness > 0.0 && young > 0.0 && poisson.is_finite()))?;
        *get_mut(gc)? = cohesion::cohesive_energy(toughness, young, poisson);
        Ok(())
    })
}
