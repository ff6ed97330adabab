//! Bulk sums over a host's contacts: one call adds every touching contact of an evaluation
//! to its atoms' forces, torques, frequency rows and grain loads, in the order the host
//! chose (the order of a sum sets its last bits).

use super::*;
use fractum::fracture::GrainLoad;

/// Adds the contacts `touching` (`n_touching`) to their atoms in the order of `sides`
/// (`n_sides` codes: `2 k` is contact `k` as its atom `i` sees it, `2 k + 1` as its atom `j`
/// does; a host lists each atom's sides together, in the order its sum must take): the force
/// (`force[i]`, opposite on `j`) and torque rows (3 doubles each) grow by the contact's;
/// `shares` (null: not summed) by its share of the atom's row; and, with `loads` given, the
/// grain load of an atom that no cohesive spring holds (`grain` row: column 0 its Weibull
/// factor, column 3 its intact springs) by the contact, as `fractum_kernel_grain_load_add`
/// adds it about the atom's centre (`centre` row) with the threshold `sigma_f` times the
/// factor (times its cube root with `particle` nonzero: the factor is the grain's particle
/// strength, as `fracture.weibull_on = "particle"` reads it). `shares` and `loads` hold `n_atoms` entries; every atom a side names must be below
/// `n_atoms` (`FRACTUM_ERR_INPUT` otherwise, before anything is added).
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn fractum_kernel_sum_contacts(
    touching: *const FractumTouching,
    n_touching: usize,
    sides: *const i32,
    n_sides: usize,
    n_atoms: usize,
    force: *const *mut f64,
    torque: *const *mut f64,
    centre: *const *const f64,
    grain: *const *const f64,
    poisson: f64,
    sigma_f: f64,
    particle: i32,
    shares: *mut f64,
    loads: *mut FractumGrainLoad,
) -> FractumStatus {
    kernel(|| {
        let touching = slice_in(touching, n_touching)?;
        let sides = slice_in(sides, n_sides)?;
        let shares = slice_mut(shares, if shares.is_null() { 0 } else { n_atoms })?;
        let loads = slice_mut(loads, if loads.is_null() { 0 } else { n_atoms })?;
        let with_loads = !loads.is_empty();
        // The row tables: one row pointer per atom.
        let rows = if n_sides > 0 { n_atoms } else { 0 };
        let (force, torque) = (slice_in(force, rows)?, slice_in(torque, rows)?);
        let with_rows = if with_loads { n_atoms } else { 0 };
        let (centre, grain) = (slice_in(centre, with_rows)?, slice_in(grain, with_rows)?);
        // Every side checked before any sum changes.
        let side_of = |code: i32| -> Result<(&FractumTouching, bool, usize), FractumStatus> {
            input_if(code < 0)?;
            let t = touching.get(code as usize >> 1).ok_or(FRACTUM_ERR_INPUT)?;
            let as_j = code & 1 == 1;
            let atom = if as_j { t.j } else { t.i };
            input_if(atom < 0 || atom as usize >= n_atoms)?;
            Ok((t, as_j, atom as usize))
        };
        for &code in sides {
            side_of(code)?;
        }
        // The grain load of the atom whose sides are being added, in the library's form.
        let mut open: Option<(usize, GrainLoad)> = None;
        let close = |open: &mut Option<(usize, GrainLoad)>, loads: &mut [FractumGrainLoad]| {
            if let Some((atom, g)) = open.take() {
                loads[atom] = convert::grain_load_out(&g);
            }
        };
        for &code in sides {
            let (t, as_j, atom) = side_of(code)?;
            let f = if as_j { t.force.map(|v| -v) } else { t.force };
            let turn = if as_j { &t.torque_j } else { &t.torque_i };
            // SAFETY: the host's row tables hold a row of 3 doubles for every atom below
            // n_atoms (documented), not aliased during the call.
            let (fr, tr) = unsafe { (row_mut::<3>(force[atom]), row_mut::<3>(torque[atom])) };
            for d in 0..3 {
                fr[d] += f[d];
                tr[d] += turn[d];
            }
            if !shares.is_empty() {
                shares[atom] += if as_j { t.share_j } else { t.share_i };
            }
            if !with_loads {
                continue;
            }
            // SAFETY: as above; a grain row has at least 4 doubles, a centre 3.
            let (g, c) = unsafe { (row::<4>(grain[atom]), row::<3>(centre[atom])) };
            if g[3] != 0.0 {
                continue;
            }
            if open.as_ref().is_none_or(|(at, _)| *at != atom) {
                close(&mut open, loads);
                let l = &loads[atom];
                input_if(l.count < 0)?;
                open = Some((
                    atom,
                    GrainLoad {
                        moment: matrix(&l.moment),
                        count: l.count as usize,
                        stress: l.stress,
                        point: l.point.map(Vec3::from),
                    },
                ));
            }
            let (_, load) = open.as_mut().expect("opened above");
            load.add(
                &Vec3::from(*c),
                &Vec3::from(f),
                &Vec3::from(t.point),
                t.hertz_force,
                t.radius,
                poisson,
                if particle != 0 {
                    sigma_f * g[0].cbrt()
                } else {
                    sigma_f * g[0]
                },
            );
        }
        close(&mut open, loads);
        Ok(())
    })
}
