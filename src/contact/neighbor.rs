//! Broad phase: a cell list builds a Verlet half list of body pairs that may touch, rebuilt
//! only when some body has moved more than half the skin since the last build.
//!
//! The list is stored row by row (CSR): row i holds the partners j > i whose bounding spheres
//! come within `skin` of each other, in increasing j. The transposed index (for each body,
//! the pair slots where it is the partner) lets the force loop run in parallel and still sum
//! every body's forces in one fixed order, whatever the thread count.

use rayon::prelude::*;

use crate::parallel::{on_team, split_ranges, team_blocks, threads_here};
use crate::state::{Vec3, Walls};

/// Verlet half list of body pairs.
#[derive(Debug, Clone, Default)]
pub struct PairList {
    pub skin: f64,
    /// Row starts: pairs of body i are `offsets[i]..offsets[i + 1]`.
    pub offsets: Vec<u32>,
    /// Partner j of each pair slot.
    pub partners: Vec<u32>,
    /// Transposed index: the pair slots with partner j are
    /// `t_slots[t_offsets[j]..t_offsets[j + 1]]`, in increasing slot order.
    pub t_offsets: Vec<u32>,
    pub t_slots: Vec<u32>,
    /// Positions at the last build.
    ref_pos: Vec<Vec3>,
    /// Number of builds so far (diagnostics).
    pub builds: u64,
}

impl PairList {
    pub fn new(skin: f64) -> Self {
        PairList {
            skin,
            ..Default::default()
        }
    }

    pub fn len(&self) -> usize {
        self.partners.len()
    }

    pub fn is_empty(&self) -> bool {
        self.partners.is_empty()
    }

    /// Largest displacement of a body since the last build (m); infinite before the first.
    pub fn max_displacement(&self, pos: &[Vec3]) -> f64 {
        if self.ref_pos.len() != pos.len() {
            return f64::INFINITY;
        }
        let max2 = if let Some(parts) = team_blocks(pos.len()) {
            on_team(parts, |_, r| {
                pos[r.clone()]
                    .iter()
                    .zip(&self.ref_pos[r])
                    .map(|(p, r)| (p - r).norm_squared())
                    .fold(0.0, f64::max)
            })
            .into_iter()
            .fold(0.0, f64::max)
        } else if pos.len() >= 8192 && threads_here() > 1 {
            pos.par_iter()
                .zip(self.ref_pos.par_iter())
                .with_min_len(4096)
                .map(|(p, r)| (p - r).norm_squared())
                .reduce(|| 0.0, f64::max)
        } else {
            pos.iter()
                .zip(&self.ref_pos)
                .map(|(p, r)| (p - r).norm_squared())
                .fold(0.0, f64::max)
        };
        max2.sqrt()
    }

    /// True when the list may miss a pair: some body has moved more than skin / 2.
    pub fn needs_rebuild(&self, pos: &[Vec3]) -> bool {
        self.max_displacement(pos) > 0.5 * self.skin
    }

    /// Rebuilds the list for bodies at `pos` with bounding radii `radius`.
    pub fn build(&mut self, pos: &[Vec3], radius: &[f64]) {
        let n = pos.len();
        let rmax = radius.iter().copied().fold(0.0, f64::max);
        let grid = CellGrid::new(pos, 2.0 * rmax + self.skin);
        let skin = self.skin;
        // The rows of `range`: each row's partner count and the partners, row after row (no
        // list per row: one build of 8600 bodies allocated 8600 of them).
        let rows_of = |range: std::ops::Range<usize>| {
            let mut counts = Vec::with_capacity(range.len());
            let mut partners = Vec::new();
            for i in range {
                let start = partners.len();
                let xi = pos[i];
                let ri = radius[i];
                grid.for_each_near(&xi, |j| {
                    if j > i {
                        let cut = ri + radius[j] + skin;
                        if (xi - pos[j]).norm_squared() < cut * cut {
                            partners.push(j as u32);
                        }
                    }
                });
                partners[start..].sort_unstable();
                counts.push((partners.len() - start) as u32);
            }
            (counts, partners)
        };
        let parts: Vec<(Vec<u32>, Vec<u32>)> = if let Some(parts) = team_blocks(n) {
            on_team(parts, |_, r| rows_of(r))
        } else if threads_here() > 1 {
            let ranges: Vec<_> = (0..n).step_by(256).map(|a| a..(a + 256).min(n)).collect();
            ranges.into_par_iter().map(rows_of).collect()
        } else {
            vec![rows_of(0..n)]
        };
        self.offsets.clear();
        self.offsets.reserve(n + 1);
        self.offsets.push(0);
        let total: usize = parts.iter().map(|(_, p)| p.len()).sum();
        self.partners.clear();
        self.partners.reserve(total);
        let mut end = 0u32;
        for (counts, partners) in &parts {
            self.partners.extend_from_slice(partners);
            for &c in counts {
                end += c;
                self.offsets.push(end);
            }
        }
        self.build_transpose(n);
        self.ref_pos.clear();
        self.ref_pos.extend_from_slice(pos);
        self.builds += 1;
    }

    fn build_transpose(&mut self, n: usize) {
        let mut counts = vec![0u32; n + 1];
        for &j in &self.partners {
            counts[j as usize + 1] += 1;
        }
        for j in 0..n {
            counts[j + 1] += counts[j];
        }
        self.t_offsets = counts.clone();
        let mut fill = counts;
        self.t_slots = vec![0; self.partners.len()];
        for (slot, &j) in self.partners.iter().enumerate() {
            let at = &mut fill[j as usize];
            self.t_slots[*at as usize] = slot as u32;
            *at += 1;
        }
    }

    /// The pair slots of row i.
    #[inline]
    pub fn row(&self, i: usize) -> std::ops::Range<usize> {
        self.offsets[i] as usize..self.offsets[i + 1] as usize
    }

    /// Splits the rows into about `parts` ranges of similar pair counts, at row boundaries.
    pub fn row_chunks(&self, parts: usize) -> Vec<std::ops::Range<usize>> {
        let n = self.offsets.len().saturating_sub(1);
        let total = self.partners.len().max(1);
        let per = total.div_ceil(parts.max(1)).max(1);
        let mut chunks = Vec::with_capacity(parts);
        let mut start = 0;
        while start < n {
            let target = self.offsets[start] as usize + per;
            let mut end = start + 1;
            while end < n && (self.offsets[end] as usize) < target {
                end += 1;
            }
            chunks.push(start..end);
            start = end;
        }
        chunks
    }
}

/// Carries per-pair data (contact history) from an old list to a new one: pairs present in
/// both keep their value, new pairs start at `T::default()`.
pub fn transfer_pair_data<T: Copy + Default + Send + Sync>(
    old_offsets: &[u32],
    old_partners: &[u32],
    old: &[T],
    new: &PairList,
) -> Vec<T> {
    let mut out = vec![T::default(); new.partners.len()];
    if old.is_empty() {
        return out;
    }
    let rows = (new.offsets.len() - 1).min(old_offsets.len().saturating_sub(1));
    // Rows `range` into `out`, the slots from row `range.start`'s first on.
    let fill = |range: std::ops::Range<usize>, out: &mut [T]| {
        let base = new.offsets[range.start] as usize;
        for i in range {
            let (mut a, a_end) = (old_offsets[i] as usize, old_offsets[i + 1] as usize);
            for b in new.row(i) {
                let j = new.partners[b];
                while a < a_end && old_partners[a] < j {
                    a += 1;
                }
                if a < a_end && old_partners[a] == j {
                    out[b - base] = old[a];
                }
            }
        }
    };
    // With a team, in blocks of rows across it (each row's slots are its own).
    match team_blocks(rows) {
        Some(blocks) => {
            let slots: Vec<_> = blocks
                .iter()
                .map(|r| new.offsets[r.start] as usize..new.offsets[r.end] as usize)
                .collect();
            let work: Vec<_> = split_ranges(&mut out, &slots)
                .into_iter()
                .zip(blocks)
                .collect();
            on_team(work, |_, (out, rows)| fill(rows, out));
        }
        None => fill(0..rows, &mut out),
    }
    out
}

/// For each wall, the bodies close enough to touch it before the next rebuild.
#[derive(Debug, Clone, Default)]
pub struct WallLists {
    pub candidates: Vec<Vec<u32>>,
    /// Wall points at the last build.
    ref_points: Vec<Vec3>,
    pub builds: u64,
}

impl WallLists {
    /// True when some wall has moved more than skin / 2 along its normal since the last build.
    pub fn needs_rebuild(&self, walls: &Walls, skin: f64) -> bool {
        if self.ref_points.len() != walls.len()
            || self.candidates.len() != walls.len() + usize::from(walls.sleeve.is_some())
        {
            return true;
        }
        walls
            .walls
            .iter()
            .zip(&self.ref_points)
            .any(|(w, p)| (w.point - p).dot(&w.normal).abs() > 0.5 * skin)
    }

    /// Rebuilds the candidate lists: one per wall (empty for a wall that touches nothing,
    /// [`Walls::touches`]), then one for the sleeve if there is one (it never moves). Valid
    /// while bodies move less than skin / 2 and walls less than skin / 2 along their normals.
    pub fn build(&mut self, walls: &Walls, pos: &[Vec3], radius: &[f64], skin: f64) {
        let near = |distance: &dyn Fn(&Vec3) -> f64| -> Vec<u32> {
            (0..pos.len())
                .filter(|&i| distance(&pos[i]) < radius[i] + skin)
                .map(|i| i as u32)
                .collect()
        };
        self.candidates = walls
            .walls
            .iter()
            .enumerate()
            .map(|(k, w)| {
                if walls.touches(k) {
                    near(&|x| w.distance(x))
                } else {
                    Vec::new()
                }
            })
            .chain(walls.sleeve.iter().map(|s| near(&|x| s.distance(x))))
            .collect();
        self.ref_points = walls.walls.iter().map(|w| w.point).collect();
        self.builds += 1;
    }
}

/// Carries per-candidate data from old wall lists to new ones (both sorted by body).
pub fn transfer_wall_data<T: Copy + Default>(
    old_lists: &[Vec<u32>],
    old: &[Vec<T>],
    new_lists: &[Vec<u32>],
) -> Vec<Vec<T>> {
    new_lists
        .iter()
        .enumerate()
        .map(|(w, list)| {
            let mut out = vec![T::default(); list.len()];
            if let (Some(ol), Some(od)) = (old_lists.get(w), old.get(w)) {
                let mut a = 0;
                for (b, &i) in list.iter().enumerate() {
                    while a < ol.len() && ol[a] < i {
                        a += 1;
                    }
                    if a < ol.len() && ol[a] == i && a < od.len() {
                        out[b] = od[a];
                    }
                }
            }
            out
        })
        .collect()
}

/// A uniform grid of cubic cells over the bodies' bounding box, filled by counting sort.
pub struct CellGrid {
    origin: Vec3,
    inv_size: f64,
    dims: [usize; 3],
    starts: Vec<u32>,
    items: Vec<u32>,
}

impl CellGrid {
    /// Cells of edge at least `min_size`, enlarged if needed so that there are at most about
    /// four cells per body (bodies flying far apart would otherwise ask for a huge grid).
    pub fn new(pos: &[Vec3], min_size: f64) -> Self {
        let mut lo = Vec3::repeat(f64::INFINITY);
        let mut hi = Vec3::repeat(f64::NEG_INFINITY);
        for p in pos {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        if pos.is_empty() {
            lo = Vec3::zeros();
            hi = Vec3::zeros();
        }
        let mut extent = hi - lo;
        let max_cells = (4 * pos.len()).max(64) as f64;
        let mut size = min_size.max(1e-300);
        if !extent.iter().all(|e| e.is_finite()) || !size.is_finite() {
            // A non-finite position (a run blowing up): one cell holds every body, so the step
            // ends (the search below never would) and the run's finiteness check stops it.
            lo = Vec3::zeros();
            extent = Vec3::zeros();
            size = 1.0;
        }
        loop {
            let cells: f64 = extent.iter().map(|e| (e / size).floor() + 1.0).product();
            if cells <= max_cells {
                break;
            }
            size *= 1.25;
        }
        let dims = [0, 1, 2].map(|a| (extent[a] / size).floor() as usize + 1);
        let ncell = dims[0] * dims[1] * dims[2];
        let inv_size = 1.0 / size;
        let cell_of = |p: &Vec3| {
            let c = [0, 1, 2].map(|a| (((p[a] - lo[a]) * inv_size) as usize).min(dims[a] - 1));
            (c[2] * dims[1] + c[1]) * dims[0] + c[0]
        };
        let mut starts = vec![0u32; ncell + 1];
        for p in pos {
            starts[cell_of(p) + 1] += 1;
        }
        for c in 0..ncell {
            starts[c + 1] += starts[c];
        }
        let mut fill = starts.clone();
        let mut items = vec![0u32; pos.len()];
        for (i, p) in pos.iter().enumerate() {
            let c = cell_of(p);
            items[fill[c] as usize] = i as u32;
            fill[c] += 1;
        }
        CellGrid {
            origin: lo,
            inv_size,
            dims,
            starts,
            items,
        }
    }

    /// Calls `f(j)` for every body in the 27 cells around `x`, in a fixed order.
    #[inline]
    pub fn for_each_near(&self, x: &Vec3, mut f: impl FnMut(usize)) {
        let c = [0, 1, 2].map(|a| {
            let v = ((x[a] - self.origin[a]) * self.inv_size).floor();
            v.clamp(0.0, (self.dims[a] - 1) as f64) as isize
        });
        for dz in -1..=1isize {
            let z = c[2] + dz;
            if z < 0 || z >= self.dims[2] as isize {
                continue;
            }
            for dy in -1..=1isize {
                let y = c[1] + dy;
                if y < 0 || y >= self.dims[1] as isize {
                    continue;
                }
                let row = (z as usize * self.dims[1] + y as usize) * self.dims[0];
                let x0 = (c[0] - 1).max(0) as usize;
                let x1 = ((c[0] + 1) as usize).min(self.dims[0] - 1);
                let from = self.starts[row + x0] as usize;
                let to = self.starts[row + x1 + 1] as usize;
                for &j in &self.items[from..to] {
                    f(j as usize);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    #[test]
    fn list_matches_brute_force_and_transpose_is_consistent() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let n = 400;
        let pos: Vec<Vec3> = (0..n)
            .map(|_| Vec3::new(rng.random(), rng.random(), rng.random()) * 0.01)
            .collect();
        let radius: Vec<f64> = (0..n).map(|_| 2e-4 + 3e-4 * rng.random::<f64>()).collect();
        let mut list = PairList::new(1e-4);
        list.build(&pos, &radius);
        let mut brute = Vec::new();
        for i in 0..n {
            for j in i + 1..n {
                let cut = radius[i] + radius[j] + 1e-4;
                if (pos[i] - pos[j]).norm_squared() < cut * cut {
                    brute.push((i as u32, j as u32));
                }
            }
        }
        let mut got = Vec::new();
        for i in 0..n {
            for s in list.row(i) {
                got.push((i as u32, list.partners[s]));
            }
        }
        assert_eq!(got, brute);
        for j in 0..n {
            let slots = &list.t_slots[list.t_offsets[j] as usize..list.t_offsets[j + 1] as usize];
            assert!(slots.windows(2).all(|w| w[0] < w[1]));
            for &s in slots {
                assert_eq!(list.partners[s as usize] as usize, j);
            }
        }
        let chunks = list.row_chunks(7);
        assert_eq!(chunks.first().unwrap().start, 0);
        assert_eq!(chunks.last().unwrap().end, n);
        assert!(chunks.windows(2).all(|w| w[0].end == w[1].start));
    }

    #[test]
    fn pair_data_survives_a_rebuild() {
        let pos = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
        ];
        let radius = vec![0.5; 3];
        let mut list = PairList::new(0.2);
        list.build(&pos, &radius);
        assert_eq!(list.len(), 2);
        let data = vec![7.0, 9.0];
        let (oo, op) = (list.offsets.clone(), list.partners.clone());
        let mut moved = pos.clone();
        moved[2].x = 5.0;
        list.build(&moved, &radius);
        let new = transfer_pair_data(&oo, &op, &data, &list);
        assert_eq!(new, vec![7.0]);
    }
}
