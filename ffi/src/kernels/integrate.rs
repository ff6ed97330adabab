//! Integration kernels: velocity Verlet's kick and drift of one grain, the contacts'
//! frequency shares, the adapted step and the step check.

use super::*;
use nalgebra::UnitQuaternion;

/// Velocity Verlet's first half kick and drift of one grain over `dt` (s), as Fractum's
/// integrator moves each body (`velocity_verlet::kick_drift_body`, orientations tracked):
/// `b`'s velocity, position, angular velocity and orientation advance under `force` (3
/// doubles, N) and `torque` (3 doubles, N m, world).
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_kick_drift(
    b: *mut FractumBody,
    force: *const f64,
    torque: *const f64,
    dt: f64,
) -> FractumStatus {
    kernel(|| {
        let (force, torque) = (vec3_at(force)?, vec3_at(torque)?);
        let b = get_mut(b)?;
        let mut body = body_in(b)?;
        fractum::integrate::velocity_verlet::kick_drift_body(
            &mut body.pos,
            &mut body.vel,
            &mut body.omega,
            &mut body.orientation,
            &force,
            &torque,
            body.inv_mass,
            &body.inv_inertia,
            dt,
            true,
        );
        b.pos = body.pos.into();
        b.vel = body.vel.into();
        b.omega = body.omega.into();
        b.quat = quat_out(&body.orientation);
        Ok(())
    })
}

/// One contact's share of body `a`'s row in Fractum's frequency bound (rad²/s²), as its step
/// adaptation sums it (`contact::records::frequency_share` of the `contact_load`s): the
/// contact `c` (its point, normal and stiffness) under `law` (friction adds the tangential
/// spring) loads `a` (its centre, orientation, mass and principal moments are read) and its
/// partner `b` (NULL for a wall). A body's row sums the shares of its contacts, walls
/// included; the bound is sqrt of the largest row: see `fractum_kernel_adapted_step`.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_frequency_share(
    law: *const FractumContactLaw,
    c: *const FractumContact,
    a: *const FractumBody,
    b: *const FractumBody,
    share: *mut f64,
) -> FractumStatus {
    kernel(|| {
        let (law, c, a) = (get(law)?, get(c)?, get(a)?);
        let b = if b.is_null() { None } else { Some(get(b)?) };
        let share = get_mut(share)?;
        let own = body_load(law, c, a)?;
        let other = b.map(|b| body_load(law, c, b)).transpose()?;
        *share = fractum::contact::records::frequency_share(own, other);
        Ok(())
    })
}

/// `fractum_kernel_frequency_share` for both bodies of a pair contact `c` at once, each
/// body's load computed once (as Fractum's own estimate does per contact): `share_a` the
/// contact's share of `a`'s row, `share_b` of `b`'s; the same bits as two calls.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_frequency_shares(
    law: *const FractumContactLaw,
    c: *const FractumContact,
    a: *const FractumBody,
    b: *const FractumBody,
    share_a: *mut f64,
    share_b: *mut f64,
) -> FractumStatus {
    kernel(|| {
        let (law, c, a, b) = (get(law)?, get(c)?, get(a)?, get(b)?);
        let (share_a, share_b) = (get_mut(share_a)?, get_mut(share_b)?);
        let (la, lb) = (body_load(law, c, a)?, body_load(law, c, b)?);
        *share_a = fractum::contact::records::frequency_share(la, Some(lb));
        *share_b = fractum::contact::records::frequency_share(lb, Some(la));
        Ok(())
    })
}

/// Contact `c`'s load on `body` (`fractum::contact::records::contact_load`), its mass and
/// moments checked positive.
pub(super) fn body_load(
    law: &FractumContactLaw,
    c: &FractumContact,
    body: &FractumBody,
) -> Result<f64, FractumStatus> {
    let tangential = if law.friction != 0 {
        fractum::contact::records::tangential_ratio(law.eight_g, law.two_e)
    } else {
        0.0
    };
    let inertia = Vec3::from(body.inertia);
    // NaN fails every comparison: refused with the non-positive values.
    let positive = |v: f64| v > 0.0;
    input_if(!positive(body.mass) || !inertia.iter().all(|&m| positive(m)))?;
    Ok(fractum::contact::records::contact_load(
        &Vec3::from(c.point),
        &Vec3::from(c.normal),
        c.stiffness,
        &Vec3::from(body.pos),
        &quat(&body.quat),
        1.0 / body.mass,
        &inertia.map(|m| 1.0 / m),
        tangential,
    ))
}

/// Fractum's step adaptation for fracture runs (`integrate::adapted_step`): with `sum` the
/// largest row of the frequency bound (`fractum_kernel_frequency_share` summed over a body's
/// contacts) over all bodies, `*next` = the step to take after `dt` (s): `dt` shortened so
/// that `omega dt` is `target` when it is above that (omega = sqrt(sum)), else `dt` unchanged.
/// Fractum's target is 3 x `time.safety` (`granular::ADAPT_PER_SAFETY`: 0.6 at the default
/// 0.2); it checks every output step and after every split.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_adapted_step(
    sum: f64,
    dt: f64,
    target: f64,
    next: *mut f64,
) -> FractumStatus {
    kernel(|| {
        let valid = sum >= 0.0 && dt > 0.0 && target > 0.0; // false for NaN too
        input_if(!valid)?;
        let omega = fractum::contact::records::frequency_bound(sum);
        *get_mut(next)? = fractum::integrate::adapted_step(omega, dt, target).unwrap_or(dt);
        Ok(())
    })
}

/// Fractum's check of a step against its contacts, as its granular run makes it: with `sum`
/// the largest row of the frequency bound over all bodies (as for
/// `fractum_kernel_adapted_step`), `*omega_dt` = omega dt and `*verdict` = 2 when the step is
/// unstable (`integrate::step_verdict`: omega dt above 2, the run stops), 1 when contacts are
/// resolved by few steps (above 1.6: a warning), else 0.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_step_check(
    sum: f64,
    dt: f64,
    omega_dt: *mut f64,
    verdict: *mut i32,
) -> FractumStatus {
    kernel(|| {
        input_if(!(sum >= 0.0 && dt > 0.0 && dt.is_finite()))?;
        let (omega_dt, verdict) = (get_mut(omega_dt)?, get_mut(verdict)?);
        *omega_dt = fractum::contact::records::frequency_bound(sum) * dt;
        use fractum::integrate::{StepVerdict, step_verdict};
        *verdict = match step_verdict(*omega_dt) {
            StepVerdict::Fine => 0,
            StepVerdict::Coarse => 1,
            StepVerdict::Unstable => 2,
        };
        Ok(())
    })
}

/// Velocity Verlet's second half kick of one grain (`velocity_verlet::kick_body`): `b`'s
/// velocity and angular velocity advance over `dt`/2 under `force` and `torque`.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_kick(
    b: *mut FractumBody,
    force: *const f64,
    torque: *const f64,
    dt: f64,
) -> FractumStatus {
    kernel(|| {
        let (force, torque) = (vec3_at(force)?, vec3_at(torque)?);
        let b = get_mut(b)?;
        let mut body = body_in(b)?;
        fractum::integrate::velocity_verlet::kick_body(
            &mut body.vel,
            &mut body.omega,
            &body.orientation,
            &force,
            &torque,
            body.inv_mass,
            &body.inv_inertia,
            dt,
            true,
        );
        b.vel = body.vel.into();
        b.omega = body.omega.into();
        Ok(())
    })
}

/// One atom of `FractumAtomRows` as the integrator needs it: position, velocity, angular
/// velocity, orientation and inverse mass and moments, with the inverses as the library
/// makes them (1/m), so that the bits are those of `fractum_kernel_kick_drift` on the
/// atom's `FractumBody`.
struct AtomState {
    pos: Vec3,
    vel: Vec3,
    omega: Vec3,
    orientation: UnitQuaternion<f64>,
    inv_mass: f64,
    inv_inertia: Vec3,
}

/// Runs `step` on every advanced atom of `a`, then writes the state back; `drifts`: the step
/// moves the atoms (their orientations are written, and their travels grow).
fn advance_rows(
    a: *const FractumAtomRows,
    drifts: bool,
    mut step: impl FnMut(&mut AtomState, &Vec3, &Vec3),
) -> KResult {
    let a = get(a)?;
    input_if(a.n < 0)?;
    let n = a.n as usize;
    if n == 0 {
        return Ok(());
    }
    let mask = slice_in(a.mask, if a.mask.is_null() { 0 } else { n })?;
    let mass = slice_in(a.mass, n)?;
    let radius = slice_in(a.radius, n)?;
    let tracked = !a.quat.is_null();
    let travels = drifts && tracked && !a.travel.is_null();
    // The row tables (one row pointer per atom; the optional ones empty when not given).
    let (x, v, w) = (slice_in(a.x, n)?, slice_in(a.v, n)?, slice_in(a.omega, n)?);
    let (force, torque) = (slice_in(a.force, n)?, slice_in(a.torque, n)?);
    let q_rows = slice_in(a.quat, if tracked { n } else { 0 })?;
    let moments = slice_in(a.inertia, if tracked { n } else { 0 })?;
    let travel = slice_in(a.travel, if travels { n } else { 0 })?;
    for i in 0..n {
        if !mask.is_empty() && mask[i] & a.groupbit == 0 {
            continue;
        }
        // SAFETY: the caller passes row tables of at least n rows of the documented widths,
        // not aliased during the call (documented).
        unsafe {
            let (x, v, w) = (row_mut::<3>(x[i]), row_mut::<3>(v[i]), row_mut::<3>(w[i]));
            let (orientation, inv_inertia) = if tracked {
                let moments = Vec3::from(*row::<3>(moments[i]));
                (quat(row::<4>(q_rows[i])), moments.map(|m| 1.0 / m))
            } else {
                // fractum_body's sphere without shape arrays, then body_in's inverse.
                let moment = 0.4 * mass[i] * radius[i] * radius[i];
                (UnitQuaternion::identity(), Vec3::repeat(1.0 / moment))
            };
            let mut s = AtomState {
                pos: Vec3::from(*x),
                vel: Vec3::from(*v),
                omega: Vec3::from(*w),
                orientation,
                inv_mass: 1.0 / mass[i],
                inv_inertia,
            };
            let (before_pos, before_q) = (s.pos, s.orientation);
            step(
                &mut s,
                &Vec3::from(*row::<3>(force[i])),
                &Vec3::from(*row::<3>(torque[i])),
            );
            *v = s.vel.into();
            *w = s.omega.into();
            if drifts {
                *x = s.pos.into();
                if tracked {
                    *row_mut::<4>(q_rows[i]) = quat_out(&s.orientation);
                }
            }
            if travels {
                row_mut::<1>(travel[i])[0] += fractum::contact::pair::travel_step(
                    &before_pos,
                    &before_q,
                    &s.pos,
                    &s.orientation,
                    radius[i],
                );
            }
        }
    }
    Ok(())
}

/// `fractum_kernel_kick_drift` over a host's atoms in one call, with each moving atom's
/// travel summed as `fractum_kernel_travel` sums it: the same bits as those calls atom by
/// atom on each atom's `FractumBody`, without building one. Positions, velocities, angular
/// velocities and (with `quat`) orientations are advanced over `dt` (s) under the rows'
/// forces and torques.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_kick_drift_atoms(
    atoms: *const FractumAtomRows,
    dt: f64,
) -> FractumStatus {
    kernel(|| {
        advance_rows(atoms, true, |s, force, torque| {
            fractum::integrate::velocity_verlet::kick_drift_body(
                &mut s.pos,
                &mut s.vel,
                &mut s.omega,
                &mut s.orientation,
                force,
                torque,
                s.inv_mass,
                &s.inv_inertia,
                dt,
                true,
            )
        })
    })
}

/// `fractum_kernel_kick` over a host's atoms in one call (velocities and angular velocities
/// advanced over `dt`/2): the same bits as the calls atom by atom.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_kick_atoms(
    atoms: *const FractumAtomRows,
    dt: f64,
) -> FractumStatus {
    kernel(|| {
        advance_rows(atoms, false, |s, force, torque| {
            fractum::integrate::velocity_verlet::kick_body(
                &mut s.vel,
                &mut s.omega,
                &s.orientation,
                force,
                torque,
                s.inv_mass,
                &s.inv_inertia,
                dt,
                true,
            )
        })
    })
}
