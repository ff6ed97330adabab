//! The distinct lattice spring model on Voronoi elements (dlsm paper,
//! Sections 2–5): every face shared by two elements is a cohesive contact whose force comes
//! from Hooke's law applied to a strain built from the displacement of the surroundings.
//!
//! Per step, for every element i (reference point O_i: its Voronoi seed, where its mass is
//! lumped; see [`crate::sample::voronoi::elements`]):
//!
//! ```text
//! d_j = R_iᵀ (O_j − O_i) − r⁰_ij                 displacement of neighbour j in i's frame (Eq. 5–6)
//! H_i = Σ_j d_j (A_i⁺ r⁰_ij)ᵀ, A_i = Σ_j r⁰ r⁰ᵀ  least-squares displacement gradient (Eq. 1–7)
//! ε_i = sym(H_i)                                 strain in i's frame (Eq. 8–15), then world
//! ```
//!
//! With fewer than 3 unbroken neighbours the displacement field is null (ε = 0); with 3 or
//! more the same formula solves the system exactly (3, independent) or in the least-squares
//! sense (more); when the neighbours are coplanar the pseudo-inverse keeps the directions
//! they span. Then per contact (i, j), n = (O_j − O_i)/L:
//!
//! ```text
//! ε_ij = (ε_i + ε_j)/2 with εnn replaced by (L − L0)/L0          Eq. 16–19
//! σ_ij = 2μ ε_ij + λ tr(ε_ij) I,  f_ij = S σ_ij n (force on i)    Eq. 20–25
//! m_ij = (O_ij − O_i) × f_ij + K S θ_ij,  m_ji = −(O_ij − O_j) × f_ij − K S θ_ij   Eq. 28–34
//! ```
//!
//! O_ij is the midpoint of the seeds (on the face plane of a Voronoi tessellation) and θ_ij
//! the rotation of j relative to i since the start (axis × angle, from the quaternions).
//! K = E·L0 (Eq. 30) is read as a couple modulus per unit contact area, so that K S θ is a
//! moment (N·m): the paper's product E·L0 is in N/m and needs an area to act on a rotation.
//! Expressing the strain in the element's own frame makes the model indifferent to rigid
//! rotations, large ones included.
//!
//! Brittle failure (Eq. 35–36): with a tensile strength σf a contact whose σxx = n·σn
//! exceeds σf breaks for good, carries no cohesive force from that step on and leaves the
//! least squares of both its elements.
//!
//! The passes write to separate arrays (per element, then per contact, then a gather per
//! element), so results do not depend on the number of threads.

use nalgebra::{Matrix3, Quaternion, SymmetricEigen, UnitQuaternion};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::parallel::threads_here;
use crate::sample::voronoi::{Neighbour, VoronoiCell};
use crate::state::{Bodies, Forces, Vec3};

/// A symmetric tensor as [xx, yy, zz, xy, xz, yz].
pub type Sym = [f64; 6];

/// Which strain an element's least squares give (Section 2 builds it to first order, Eq. 15;
/// the measures differ at second order in the strain).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StrainMeasure {
    /// `G E Gᵀ` with `E = ½(FᵀF − P)`: Green's strain of the neighbourhood, carried to the
    /// world by the neighbourhood's own motion (blind to the element's spin).
    #[default]
    GreenPushed,
    /// `R E Rᵀ`: the same Green strain, turned to the world by the element's rotation.
    GreenRotated,
    /// `R sym(H) Rᵀ`, `H = F − P`: Eq. 15 as printed, linear in the neighbours' displacement
    /// seen from the element's frame.
    Linear,
}

impl StrainMeasure {
    pub fn as_str(self) -> &'static str {
        match self {
            StrainMeasure::GreenPushed => "green_pushed",
            StrainMeasure::GreenRotated => "green_rotated",
            StrainMeasure::Linear => "linear",
        }
    }
}

/// One neighbour of an element in the neighbour lists.
#[derive(Debug, Clone, Copy)]
struct Entry {
    /// The neighbouring element.
    other: u32,
    /// The contact, with [`SECOND`] set when this element is the second of the pair.
    contact: u32,
    /// `A⁺ r⁰`: the least-squares weight of this neighbour (zero once the contact is broken).
    w: Vec3,
}

const SECOND: u32 = 1 << 31;

/// Forces and moments of one contact in the last evaluation.
#[derive(Debug, Clone, Copy, Default)]
struct ContactOut {
    /// Force on the first element (the second gets −f).
    f: Vec3,
    torque_first: Vec3,
    torque_second: Vec3,
}

/// The cohesive contacts of a Voronoi sample and the scratch of their force evaluation.
#[derive(Debug, Clone)]
pub struct DlsmBonds {
    /// Lamé's λ and 2μ (Pa).
    lambda: f64,
    two_mu: f64,
    pub young: f64,
    pub poisson: f64,
    /// The inverse of each element's initial orientation: `q q0⁻¹` turns with the element
    /// from the identity.
    frame0_inv: Vec<UnitQuaternion<f64>>,
    /// Neighbour lists: element i's are `entries[start[i]..start[i + 1]]`.
    start: Vec<u32>,
    entries: Vec<Entry>,
    /// Initial seed-to-seed vector of each entry in its element's principal frame (m).
    r0: Vec<Vec3>,
    /// Projector on the directions the least squares spans (identity for most elements),
    /// in the principal frame; `full_rank` marks those whose projector is the identity.
    proj: Vec<Sym>,
    full_rank: Vec<bool>,
    /// Contacts: elements (first < second), shared face area S (m²), initial seed distance
    /// L0 (m), rotational stiffness K S = E L0 S (N·m/rad), broken for good.
    pub pair: Vec<[u32; 2]>,
    pub area: Vec<f64>,
    pub length0: Vec<f64>,
    rot_stiffness: Vec<f64>,
    pub broken: Vec<bool>,
    /// The elements' strain measure.
    pub strain_measure: StrainMeasure,
    // Scratch of the last evaluation.
    frame: Vec<UnitQuaternion<f64>>,
    strain: Vec<Sym>,
    out: Vec<ContactOut>,
}

/// Elements per parallel task (below this, one thread does the pass).
const CHUNK: usize = 1024;

impl DlsmBonds {
    /// The contacts of `cells` (each shared face once, area averaged over its two sides)
    /// for elements `bodies` built from them in the same order (at the seeds, in principal
    /// frames).
    pub fn from_cells(cells: &[VoronoiCell], bodies: &Bodies, young: f64, poisson: f64) -> Self {
        let n = cells.len();
        let mut pair = Vec::new();
        let mut area = Vec::new();
        let mut length0 = Vec::new();
        for (i, c) in cells.iter().enumerate() {
            for f in &c.faces {
                let Neighbour::Cell(j) = f.neighbour else {
                    continue;
                };
                if j <= i {
                    continue;
                }
                // A face that only one side has (cells cut by their own tangent planes on a
                // curved wall) carries a few millionths of the area: left out.
                let Some(g) = cells[j]
                    .faces
                    .iter()
                    .find(|g| g.neighbour == Neighbour::Cell(i))
                else {
                    continue;
                };
                pair.push([i as u32, j as u32]);
                area.push(0.5 * (f.area + g.area));
                length0.push((cells[j].seed - c.seed).norm());
            }
        }
        let mut count = vec![0u32; n + 1];
        for p in &pair {
            count[p[0] as usize + 1] += 1;
            count[p[1] as usize + 1] += 1;
        }
        for k in 0..n {
            count[k + 1] += count[k];
        }
        let start = count.clone();
        let mut fill = count;
        let mut entries = vec![
            Entry {
                other: 0,
                contact: 0,
                w: Vec3::zeros()
            };
            start[n] as usize
        ];
        let mut r0 = vec![Vec3::zeros(); start[n] as usize];
        let frame0_inv: Vec<UnitQuaternion<f64>> =
            bodies.orientation.iter().map(|q| q.inverse()).collect();
        // Contacts are numbered in (first, second) order, so each element's entries come out
        // sorted by contact.
        for (c, p) in pair.iter().enumerate() {
            for (me, other, flag) in [(p[0], p[1], 0), (p[1], p[0], SECOND)] {
                let k = fill[me as usize] as usize;
                fill[me as usize] += 1;
                entries[k] = Entry {
                    other,
                    contact: c as u32 | flag,
                    w: Vec3::zeros(),
                };
                r0[k] = frame0_inv[me as usize]
                    * (cells[other as usize].seed - cells[me as usize].seed);
            }
        }
        let lambda = young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson));
        let two_mu = young / (1.0 + poisson);
        let rot_stiffness = length0
            .iter()
            .zip(&area)
            .map(|(l, s)| young * l * s)
            .collect();
        let contacts = pair.len();
        let mut bonds = DlsmBonds {
            lambda,
            two_mu,
            young,
            poisson,
            frame0_inv,
            start,
            entries,
            r0,
            proj: vec![[0.0; 6]; n],
            full_rank: vec![false; n],
            pair,
            area,
            length0,
            rot_stiffness,
            broken: vec![false; contacts],
            strain_measure: StrainMeasure::default(),
            frame: vec![UnitQuaternion::identity(); n],
            strain: vec![[0.0; 6]; n],
            out: vec![ContactOut::default(); contacts],
        };
        for i in 0..n {
            bonds.update_least_squares(i);
        }
        bonds
    }

    pub fn elements(&self) -> usize {
        self.start.len() - 1
    }

    pub fn contacts(&self) -> usize {
        self.pair.len()
    }

    /// Unbroken contacts.
    pub fn intact(&self) -> usize {
        self.broken.iter().filter(|b| !**b).count()
    }

    /// Unbroken neighbours of element i.
    pub fn active_neighbours(&self, i: usize) -> usize {
        self.range(i)
            .filter(|&k| !self.broken[(self.entries[k].contact & !SECOND) as usize])
            .count()
    }

    /// Smallest over largest eigenvalue of element i's least-squares matrix A (0 when it has
    /// fewer than 3 unbroken neighbours).
    pub fn conditioning(&self, i: usize) -> f64 {
        let mut a = Matrix3::zeros();
        for k in self.range(i) {
            if !self.broken[(self.entries[k].contact & !SECOND) as usize] {
                a += self.r0[k] * self.r0[k].transpose();
            }
        }
        let e = SymmetricEigen::new(a).eigenvalues;
        if e.max() > 0.0 {
            e.min() / e.max()
        } else {
            0.0
        }
    }

    fn range(&self, i: usize) -> std::ops::Range<usize> {
        self.start[i] as usize..self.start[i + 1] as usize
    }

    /// The elements and contacts of element i's neighbour list: (other, contact).
    pub fn neighbours(&self, i: usize) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.range(i).map(|k| {
            let e = &self.entries[k];
            (e.other as usize, (e.contact & !SECOND) as usize)
        })
    }

    /// Marks contacts broken and takes them out of the least squares of their elements.
    pub fn break_contacts(&mut self, contacts: &[usize]) {
        let mut touched = Vec::with_capacity(2 * contacts.len());
        for &c in contacts {
            self.broken[c] = true;
            touched.extend(self.pair[c].iter().map(|&e| e as usize));
        }
        touched.sort_unstable();
        touched.dedup();
        for i in touched {
            self.update_least_squares(i);
        }
    }

    /// Recomputes element i's least-squares weights over its unbroken neighbours.
    fn update_least_squares(&mut self, i: usize) {
        let range = self.range(i);
        let active: Vec<usize> = range
            .clone()
            .filter(|&k| !self.broken[(self.entries[k].contact & !SECOND) as usize])
            .collect();
        for k in range {
            self.entries[k].w = Vec3::zeros();
        }
        self.proj[i] = [0.0; 6];
        self.full_rank[i] = false;
        if active.len() < 3 {
            return;
        }
        let mut a = Matrix3::zeros();
        for &k in &active {
            a += self.r0[k] * self.r0[k].transpose();
        }
        let eig = SymmetricEigen::new(a);
        let top = eig.eigenvalues.max();
        let mut pinv = Matrix3::zeros();
        let mut proj = Matrix3::zeros();
        let mut rank = 0;
        for m in 0..3 {
            let l = eig.eigenvalues[m];
            if l > 1e-9 * top {
                let v = eig.eigenvectors.column(m);
                pinv += v * v.transpose() / l;
                proj += v * v.transpose();
                rank += 1;
            }
        }
        if rank == 3 {
            // Exact inverse for the usual case: the least squares then reproduce any
            // linear field to round-off.
            pinv = a.try_inverse().unwrap_or(pinv);
            self.full_rank[i] = true;
        }
        for &k in &active {
            self.entries[k].w = pinv * self.r0[k];
        }
        self.proj[i] = sym_of(&proj);
    }

    /// Evaluates the cohesive forces and moments into `forces` (overwriting them) and
    /// returns the contacts that broke in this evaluation (σxx > `strength`), in contact
    /// order; they are broken already when this returns.
    pub fn evaluate(
        &mut self,
        bodies: &Bodies,
        forces: &mut Forces,
        strength: Option<f64>,
    ) -> Vec<usize> {
        self.frames(bodies);
        self.strains(&bodies.pos, &bodies.orientation);
        let broke = match strength {
            Some(s) => self.contact_pass::<true>(bodies, s),
            None => self.contact_pass::<false>(bodies, f64::INFINITY),
        };
        self.gather(forces);
        if !broke.is_empty() {
            self.break_contacts(&broke);
        }
        broke
    }

    /// Pass 1: every element's rotation since the start.
    fn frames(&mut self, bodies: &Bodies) {
        let orientation = &bodies.orientation;
        let frame0_inv = &self.frame0_inv;
        let work = |i0: usize, frame: &mut [UnitQuaternion<f64>]| {
            for (k, f) in frame.iter_mut().enumerate() {
                *f = orientation[i0 + k] * frame0_inv[i0 + k];
            }
        };
        if parallel(self.frame.len()) {
            self.frame
                .par_chunks_mut(CHUNK)
                .enumerate()
                .for_each(|(c, f)| work(c * CHUNK, f));
        } else {
            work(0, &mut self.frame);
        }
    }

    /// Pass 2: every element's strain (world frame), Eq. 1–15.
    fn strains(&mut self, seed: &[Vec3], orientation: &[UnitQuaternion<f64>]) {
        let (start, entries) = (&self.start, &self.entries);
        let (proj, full) = (&self.proj, &self.full_rank);
        let measure = self.strain_measure;
        let work = |i0: usize, out: &mut [Sym]| {
            for (k, e) in out.iter_mut().enumerate() {
                let i = i0 + k;
                let oi = seed[i];
                // G = Σ (O_j − O_i) wᵀ: world displacement against principal-frame weights.
                let mut g = Matrix3::zeros();
                for en in &entries[start[i] as usize..start[i + 1] as usize] {
                    let d = seed[en.other as usize] - oi;
                    g += d * en.w.transpose();
                }
                // In i's frame the neighbourhood has moved by F = Rᵀ G = P + H (H: the
                // least-squares gradient, Eq. 7). Its strain, E = ½(FᵀF − P) = sym(H) + ½HᵀH,
                // is Eq. 15 to first order; unlike sym(H) alone it does not depend on R (FᵀF
                // = GᵀG), so an element turning relative to its neighbours strains nothing.
                // It is carried to the world by the neighbourhood's own motion, R F E Fᵀ Rᵀ =
                // G E Gᵀ (R E Rᵀ to first order in the strain), so that forces follow the
                // material even where the element's rotation lags behind it.
                let p = if full[i] {
                    Matrix3::identity()
                } else {
                    mat_of(&proj[i])
                };
                *e = match measure {
                    StrainMeasure::GreenPushed => {
                        let green = g.tr_mul(&g) - p;
                        sym_of(&(g * (green * 0.5) * g.transpose()))
                    }
                    StrainMeasure::GreenRotated => {
                        let r = orientation[i].to_rotation_matrix().into_inner();
                        let green = g.tr_mul(&g) - p;
                        sym_of(&(r * (green * 0.5) * r.transpose()))
                    }
                    StrainMeasure::Linear => {
                        let r = orientation[i].to_rotation_matrix().into_inner();
                        let h = r.tr_mul(&g) - p;
                        sym_of(&(r * mat_of(&sym_of(&h)) * r.transpose()))
                    }
                };
            }
        };
        if parallel(self.strain.len()) {
            self.strain
                .par_chunks_mut(CHUNK)
                .enumerate()
                .for_each(|(c, out)| work(c * CHUNK, out));
        } else {
            work(0, &mut self.strain);
        }
    }

    /// Pass 3: force and moments of every contact, Eq. 16–36. Returns the contacts that
    /// broke (when `FRACTURE`).
    fn contact_pass<const FRACTURE: bool>(&mut self, bodies: &Bodies, strength: f64) -> Vec<usize> {
        let seed = &bodies.pos;
        let (pair, area, length0, rot_k) =
            (&self.pair, &self.area, &self.length0, &self.rot_stiffness);
        let (frame, strain) = (&self.frame, &self.strain);
        let (lambda, two_mu) = (self.lambda, self.two_mu);
        let work =
            |c0: usize, out: &mut [ContactOut], broken: &mut [bool], broke: &mut Vec<usize>| {
                for k in 0..out.len() {
                    let c = c0 + k;
                    if broken[k] {
                        out[k] = ContactOut::default();
                        continue;
                    }
                    let [i, j] = pair[c];
                    let (i, j) = (i as usize, j as usize);
                    let (oi, oj) = (seed[i], seed[j]);
                    let d = oj - oi;
                    let l = d.norm();
                    let n = d / l;
                    let (a, b) = (&strain[i], &strain[j]);
                    let e = [
                        0.5 * (a[0] + b[0]),
                        0.5 * (a[1] + b[1]),
                        0.5 * (a[2] + b[2]),
                        0.5 * (a[3] + b[3]),
                        0.5 * (a[4] + b[4]),
                        0.5 * (a[5] + b[5]),
                    ];
                    let en = Vec3::new(
                        e[0] * n.x + e[3] * n.y + e[4] * n.z,
                        e[3] * n.x + e[1] * n.y + e[5] * n.z,
                        e[4] * n.x + e[5] * n.y + e[2] * n.z,
                    );
                    let enn = n.dot(&en);
                    let engineering = l / length0[c] - 1.0;
                    let delta = engineering - enn;
                    let trace = e[0] + e[1] + e[2] + delta;
                    let sigma_xx = two_mu * engineering + lambda * trace;
                    if FRACTURE && sigma_xx > strength {
                        broken[k] = true;
                        broke.push(c);
                        out[k] = ContactOut::default();
                        continue;
                    }
                    let f = (two_mu * (en + n * delta) + n * (lambda * trace)) * area[c];
                    // O_ij is halfway: O_ij − O_i = d/2 and O_ij − O_j = −d/2.
                    let arm = (0.5 * d).cross(&f);
                    let theta = rotation_vector(&(frame[j] * frame[i].inverse()).into_inner());
                    let couple = theta * rot_k[c];
                    out[k] = ContactOut {
                        f,
                        torque_first: arm + couple,
                        torque_second: arm - couple,
                    };
                }
            };
        let mut broke = Vec::new();
        if parallel(self.out.len()) {
            let parts: Vec<Vec<usize>> = self
                .out
                .par_chunks_mut(4 * CHUNK)
                .zip(self.broken.par_chunks_mut(4 * CHUNK))
                .enumerate()
                .map(|(c, (o, b))| {
                    let mut v = Vec::new();
                    work(c * 4 * CHUNK, o, b, &mut v);
                    v
                })
                .collect();
            for p in parts {
                broke.extend(p);
            }
        } else {
            work(0, &mut self.out, &mut self.broken, &mut broke);
        }
        broke
    }

    /// Pass 4: each element sums its contacts' forces and moments.
    fn gather(&self, forces: &mut Forces) {
        let (start, entries, out) = (&self.start, &self.entries, &self.out);
        let work = |i0: usize, force: &mut [Vec3], torque: &mut [Vec3]| {
            for k in 0..force.len() {
                let i = i0 + k;
                let (mut f, mut t) = (Vec3::zeros(), Vec3::zeros());
                for en in &entries[start[i] as usize..start[i + 1] as usize] {
                    let o = &out[(en.contact & !SECOND) as usize];
                    if en.contact & SECOND == 0 {
                        f += o.f;
                        t += o.torque_first;
                    } else {
                        f -= o.f;
                        t += o.torque_second;
                    }
                }
                force[k] = f;
                torque[k] = t;
            }
        };
        if parallel(forces.force.len()) {
            forces
                .force
                .par_chunks_mut(CHUNK)
                .zip(forces.torque.par_chunks_mut(CHUNK))
                .enumerate()
                .for_each(|(c, (f, t))| work(c * CHUNK, f, t));
        } else {
            work(0, &mut forces.force, &mut forces.torque);
        }
    }

    /// The strain of element i in the last evaluation (world frame).
    pub fn element_strain(&self, i: usize) -> Sym {
        self.strain[i]
    }

    /// The contact strain (Eq. 16–18) and stress (Eq. 20) of contact c in the last
    /// evaluation, world frame.
    pub fn contact_state(&self, bodies: &Bodies, c: usize) -> (Sym, Sym) {
        let [i, j] = self.pair[c];
        let (a, b) = (&self.strain[i as usize], &self.strain[j as usize]);
        let mut e = [0.0; 6];
        for m in 0..6 {
            e[m] = 0.5 * (a[m] + b[m]);
        }
        let d = bodies.pos[j as usize] - bodies.pos[i as usize];
        let l = d.norm();
        let n = d / l;
        let em = mat_of(&e);
        let delta = l / self.length0[c] - 1.0 - n.dot(&(em * n));
        let em = em + n * n.transpose() * delta;
        let e = sym_of(&em);
        let tr = e[0] + e[1] + e[2];
        let mut s = [0.0; 6];
        for m in 0..6 {
            s[m] = self.two_mu * e[m] + if m < 3 { self.lambda * tr } else { 0.0 };
        }
        (e, s)
    }

    /// Strain energy of the intact contacts in the last evaluation (J): each contact stands
    /// for the double pyramid from the two seeds to its face (volume S L0 / 3) at energy
    /// density σ:ε/2, plus the rotational springs K S θ²/2. The model's forces do not derive
    /// from a potential, so this is an estimate (exact for uniform strain).
    pub fn strain_energy(&self, bodies: &Bodies) -> f64 {
        let mut total = 0.0;
        for c in 0..self.pair.len() {
            if self.broken[c] {
                continue;
            }
            let (e, s) = self.contact_state(bodies, c);
            let density = 0.5
                * (e[0] * s[0]
                    + e[1] * s[1]
                    + e[2] * s[2]
                    + 2.0 * (e[3] * s[3] + e[4] * s[4] + e[5] * s[5]));
            let [i, j] = self.pair[c];
            let theta = rotation_vector(
                &(self.frame[j as usize] * self.frame[i as usize].inverse()).into_inner(),
            );
            total += density * self.area[c] * self.length0[c] / 3.0
                + 0.5 * self.rot_stiffness[c] * theta.norm_squared();
        }
        total
    }

    /// σxx = n·σn of contact c in the last evaluation (Pa), Eq. 35.
    pub fn normal_stress(&self, bodies: &Bodies, c: usize) -> f64 {
        let (_, s) = self.contact_state(bodies, c);
        let [i, j] = self.pair[c];
        let n = (bodies.pos[j as usize] - bodies.pos[i as usize]).normalize();
        n.dot(&(mat_of(&s) * n))
    }

    /// Eq. 39 without its factor, with the stiffness a contact has in this model: the
    /// smallest `sqrt(m_ij L0 / (M S))` over the contacts, `m_ij = m_i m_j / (m_i + m_j)`
    /// (Eq. 40). The paper writes E; a contact's normal spring is `(λ + 2μ) S / L0` and its
    /// shear spring about `μ S / L0`, and M = λ + 2μ, the larger of the two, is E at ν = 0,
    /// 1.11 E at 0.2, 2.14 E at 0.4, 17 E at 0.49, 13 E at −0.95 and 67 E at −0.99.
    pub fn critical_time_step(&self, mass: &[f64]) -> f64 {
        let modulus = self.lambda + self.two_mu;
        let mut dt = f64::INFINITY;
        for (c, p) in self.pair.iter().enumerate() {
            let (mi, mj) = (mass[p[0] as usize], mass[p[1] as usize]);
            let m = mi * mj / (mi + mj);
            dt = dt.min((m * self.length0[c] / (modulus * self.area[c])).sqrt());
        }
        dt
    }
}

/// Whether a pass over `n` items should use the pool.
fn parallel(n: usize) -> bool {
    n >= 2 * CHUNK && threads_here() > 1
}

/// The rotation vector (axis × angle, angle in [0, π]) of a unit quaternion.
#[inline]
pub fn rotation_vector(q: &Quaternion<f64>) -> Vec3 {
    let v = q.imag();
    let s2 = v.norm_squared();
    let sign = if q.w < 0.0 { -2.0 } else { 2.0 };
    if s2 < 1e-4 {
        // asin(s)/s = 1 + s²/6 + 3s⁴/40 + O(s⁶): exact to 1e-13 here.
        v * (sign * (1.0 + s2 * (1.0 / 6.0 + s2 * (3.0 / 40.0))))
    } else {
        let s = s2.sqrt();
        v * (sign * s.min(1.0).asin() / s)
    }
}

/// The symmetric part of a matrix as [xx, yy, zz, xy, xz, yz].
#[inline]
pub fn sym_of(m: &Matrix3<f64>) -> Sym {
    [
        m[(0, 0)],
        m[(1, 1)],
        m[(2, 2)],
        0.5 * (m[(0, 1)] + m[(1, 0)]),
        0.5 * (m[(0, 2)] + m[(2, 0)]),
        0.5 * (m[(1, 2)] + m[(2, 1)]),
    ]
}

#[inline]
pub fn mat_of(s: &Sym) -> Matrix3<f64> {
    Matrix3::new(s[0], s[3], s[4], s[3], s[1], s[5], s[4], s[5], s[2])
}

#[cfg(test)]
mod tests;
