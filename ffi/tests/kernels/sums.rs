//! The bulk contact sum against the per-contact path it replaces in a host (the plugin's
//! pair summed each side into its atom's force, torque and row, and called
//! `fractum_kernel_grain_load_add` for each grain load).

use super::*;

/// `fractum_kernel_sum_contacts` gives, bit for bit, the per-side sums: forces, torques,
/// frequency rows and grain loads (with critical contacts above a threshold that some
/// contacts pass), grains held by springs left out of the loads, sides in a host's order;
/// and refuses a side naming an atom out of range before adding anything.
#[test]
fn bulk_contact_sum_gives_the_per_side_bits() {
    let mut d = Draw::new(33);
    let (atoms, contacts) = (12usize, 40usize);
    let touching: Vec<FractumTouching> = (0..contacts)
        .map(|_| {
            let i = (d.u() * atoms as f64) as i32;
            let j = (i + 1 + (d.u() * (atoms - 1) as f64) as i32) % atoms as i32;
            FractumTouching {
                i,
                j,
                force: c_vec(&d.vec(10.0)),
                torque_i: c_vec(&d.vec(1e-3)),
                torque_j: c_vec(&d.vec(1e-3)),
                point: c_vec(&d.vec(1e-3)),
                hertz_force: d.range(0.0, 20.0),
                radius: d.range(1e-5, 1e-4),
                share_i: d.range(0.0, 1e12),
                share_j: d.range(0.0, 1e12),
            }
        })
        .collect();
    // Each atom's sides together, in an order of the host's choosing (here: by contact).
    let mut sides: Vec<i32> = Vec::new();
    for atom in 0..atoms as i32 {
        for (k, t) in touching.iter().enumerate() {
            if t.i == atom {
                sides.push(2 * k as i32);
            }
            if t.j == atom {
                sides.push(2 * k as i32 + 1);
            }
        }
    }
    let centre: Vec<[f64; 3]> = (0..atoms).map(|_| c_vec(&d.vec(1e-3))).collect();
    // Weibull factor, sample grain, splits, intact springs: every third grain held.
    let grain: Vec<[f64; 5]> = (0..atoms)
        .map(|k| {
            [
                d.range(0.5, 2.0),
                0.0,
                0.0,
                if k % 3 == 1 { 2.0 } else { 0.0 },
                0.0,
            ]
        })
        .collect();
    let (poisson, sigma_f) = (0.2, 3e8);
    let start_f: Vec<[f64; 3]> = (0..atoms).map(|_| c_vec(&d.vec(1.0))).collect();
    let start_t: Vec<[f64; 3]> = (0..atoms).map(|_| c_vec(&d.vec(1e-4))).collect();

    // The per-side path, as the plugin's pair took it.
    let (mut f1, mut t1) = (start_f.clone(), start_t.clone());
    let mut shares1 = vec![0.0; atoms];
    let mut loads1 = vec![FractumGrainLoad::default(); atoms];
    for &code in &sides {
        let t = &touching[code as usize >> 1];
        let as_j = code & 1 == 1;
        let a = if as_j { t.j } else { t.i } as usize;
        let force = if as_j { t.force.map(|v| -v) } else { t.force };
        let turn = if as_j { t.torque_j } else { t.torque_i };
        for k in 0..3 {
            f1[a][k] += force[k];
            t1[a][k] += turn[k];
        }
        shares1[a] += if as_j { t.share_j } else { t.share_i };
        if grain[a][3] == 0.0 {
            let s = fractum_kernel_grain_load_add(
                &mut loads1[a],
                centre[a].as_ptr(),
                force.as_ptr(),
                t.point.as_ptr(),
                t.hertz_force,
                t.radius,
                poisson,
                sigma_f * grain[a][0],
            );
            assert_eq!(s, FRACTUM_OK);
        }
    }
    assert!(
        loads1.iter().any(|l| l.count > 0),
        "some contacts are critical"
    );
    assert!(
        loads1.iter().any(|l| l.count == 0 && l.moment != [0.0; 9]),
        "some are not"
    );

    // The bulk path.
    let (mut f2, mut t2) = (start_f.clone(), start_t.clone());
    let mut shares2 = vec![0.0; atoms];
    let mut loads2 = vec![FractumGrainLoad::default(); atoms];
    let fp: Vec<*mut f64> = f2.iter_mut().map(|r| r.as_mut_ptr()).collect();
    let tp: Vec<*mut f64> = t2.iter_mut().map(|r| r.as_mut_ptr()).collect();
    let cp: Vec<*const f64> = centre.iter().map(|r| r.as_ptr()).collect();
    let gp: Vec<*const f64> = grain.iter().map(|r| r.as_ptr()).collect();
    let sum = |shares: *mut f64, loads: *mut FractumGrainLoad, sides: &[i32]| {
        fractum_kernel_sum_contacts(
            touching.as_ptr(),
            touching.len(),
            sides.as_ptr(),
            sides.len(),
            atoms,
            fp.as_ptr(),
            tp.as_ptr(),
            cp.as_ptr(),
            gp.as_ptr(),
            poisson,
            sigma_f,
            0,
            shares,
            loads,
        )
    };
    assert_eq!(
        sum(shares2.as_mut_ptr(), loads2.as_mut_ptr(), &sides),
        FRACTUM_OK
    );
    assert_eq!(f2, f1);
    assert_eq!(t2, t1);
    assert_eq!(shares2, shares1);
    assert_eq!(loads2, loads1);

    // The particle-strength reading: critical above sigma_f times the factor's cube root.
    let mut loads3 = vec![FractumGrainLoad::default(); atoms];
    for &code in &sides {
        let t = &touching[code as usize >> 1];
        let as_j = code & 1 == 1;
        let a = if as_j { t.j } else { t.i } as usize;
        let force = if as_j { t.force.map(|v| -v) } else { t.force };
        if grain[a][3] == 0.0 {
            let s = fractum_kernel_grain_load_add(
                &mut loads3[a],
                centre[a].as_ptr(),
                force.as_ptr(),
                t.point.as_ptr(),
                t.hertz_force,
                t.radius,
                poisson,
                sigma_f * grain[a][0].cbrt(),
            );
            assert_eq!(s, FRACTUM_OK);
        }
    }
    assert_ne!(
        loads3, loads1,
        "the cube root moves some contact across the threshold"
    );
    let mut loads4 = vec![FractumGrainLoad::default(); atoms];
    let s = fractum_kernel_sum_contacts(
        touching.as_ptr(),
        touching.len(),
        sides.as_ptr(),
        sides.len(),
        atoms,
        fp.as_ptr(),
        tp.as_ptr(),
        cp.as_ptr(),
        gp.as_ptr(),
        poisson,
        sigma_f,
        1,
        null_mut(),
        loads4.as_mut_ptr(),
    );
    assert_eq!(s, FRACTUM_OK);
    assert_eq!(loads4, loads3);

    // Without shares and loads: the forces alone.
    let f_before = f2.clone();
    assert_eq!(sum(null_mut(), null_mut(), &sides[..1]), FRACTUM_OK);
    assert_ne!(f2, f_before);

    // A side of a contact that does not exist, or of an atom out of range: nothing added.
    let (f_before, t_before) = (f2.clone(), t2.clone());
    let bad = [0, 2 * contacts as i32];
    assert_eq!(sum(null_mut(), null_mut(), &bad), FRACTUM_ERR_INPUT);
    assert_eq!((f2.clone(), t2.clone()), (f_before, t_before));
}
