//! The pair loop: each pair's force into both bodies, on one thread slot by slot or on the
//! worker team into private accumulators summed in a fixed order.

use super::*;

impl<const DAMP: bool, const FRIC: bool, const POLY: bool> HertzContact<DAMP, FRIC, POLY> {
    /// The force of the pair (i, j) in slot `s`, or None when the bodies do not overlap.
    /// `memory` is what the pair remembers (POLY): its last normal warm-starts the contact
    /// search. POLY: a pair whose bodies have not travelled far enough since it was last found
    /// apart is not searched (`reach`, the slot's [`HertzContact::pair_reach`], is updated).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(super) fn pair_force(
        &self,
        bodies: &Bodies,
        i: usize,
        j: usize,
        hist: &mut Vec3,
        memory: &mut PairMemory,
        reach: &mut f64,
        ctx: &StepContext,
    ) -> Option<PairOut> {
        if POLY && skips(*reach, self.travel[i], self.travel[j]) {
            return None;
        }
        let at = |i| BodyAt {
            bodies,
            placements: &self.placements,
            i,
        };
        match pair_contact_or_gap::<DAMP, FRIC, POLY>(
            &self.k,
            &at(i),
            &at(j),
            hist,
            memory,
            ctx.dt,
            ctx.update_history,
        ) {
            Ok(p) => {
                *reach = 0.0;
                Some(p)
            }
            Err(gap) => {
                if POLY {
                    *reach = self.reach(i, j, gap, bodies);
                }
                None
            }
        }
    }

    pub(super) fn pairs_serial(&mut self, bodies: &Bodies, forces: &mut Forces, ctx: &StepContext) {
        let mut count = 0;
        let mut dummy = Vec3::zeros();
        let mut dummy_n = PairMemory::default();
        let mut dummy_reach = 0.0;
        let mut hist = std::mem::take(&mut self.pair_hist);
        let mut normals = std::mem::take(&mut self.pair_memory);
        let mut reach = std::mem::take(&mut self.pair_reach);
        let mut records = std::mem::take(&mut self.records);
        let mut stiffness = std::mem::take(&mut self.body_stiffness);
        for i in 0..bodies.len() {
            for s in self.pairs.row(i) {
                let j = self.pairs.partners[s] as usize;
                let h = if FRIC { &mut hist[s] } else { &mut dummy };
                let nrm = if POLY { &mut normals[s] } else { &mut dummy_n };
                let r = if POLY {
                    &mut reach[s]
                } else {
                    &mut dummy_reach
                };
                if let Some(p) = self.pair_force(bodies, i, j, h, nrm, r, ctx) {
                    forces.force[i] += p.force;
                    forces.force[j] -= p.force;
                    if FRIC || POLY {
                        forces.torque[i] += p.torque_i;
                        forces.torque[j] += p.torque_j;
                    }
                    if POLY {
                        records.list.push(p.record(i, j as u32));
                        records.dissipated += p.c.dissipated;
                    } else {
                        stiffness[i] += p.c.stiffness;
                        stiffness[j] += p.c.stiffness;
                    }
                    count += 1;
                }
            }
        }
        self.pair_hist = hist;
        self.pair_memory = normals;
        self.pair_reach = reach;
        self.records = records;
        self.body_stiffness = stiffness;
        self.contacts = count;
    }

    /// In `parts` parts ([`PairParts`]): each a fixed range of rows (balanced by pair count)
    /// summing its pairs into its own accumulator over the bodies those rows touch, on the
    /// team when there is one (here in order otherwise); the accumulators are then added per
    /// body in range order. For a given number of parts the order of every sum is fixed, so
    /// runs repeat bit for bit whoever computes which part.
    pub(super) fn pairs_parallel(
        &mut self,
        parts: usize,
        bodies: &Bodies,
        forces: &mut Forces,
        ctx: &StepContext,
    ) {
        if self.chunk_parts != parts || self.chunks.len() != self.accumulators.len() {
            self.chunks = self.pairs.row_chunks(parts);
            self.accumulators = self
                .chunks
                .iter()
                .map(|rows| {
                    let mut hi = rows.end;
                    for i in rows.clone() {
                        if let Some(&j) = self.pairs.partners[self.pairs.row(i)].last() {
                            hi = hi.max(j as usize + 1);
                        }
                    }
                    Accumulator::new(rows.start..hi)
                })
                .collect();
            self.chunk_parts = parts;
        }
        let slot_ranges: Vec<Range<usize>> = self
            .chunks
            .iter()
            .map(|rows| {
                self.pairs.offsets[rows.start] as usize..self.pairs.offsets[rows.end] as usize
            })
            .collect();
        let mut hist = std::mem::take(&mut self.pair_hist);
        let mut normals = std::mem::take(&mut self.pair_memory);
        let mut reach = std::mem::take(&mut self.pair_reach);
        let mut accs = std::mem::take(&mut self.accumulators);
        {
            fn parts<'a, T>(
                data: &'a mut [T],
                on: bool,
                ranges: &[Range<usize>],
            ) -> Vec<&'a mut [T]> {
                if on {
                    split_ranges(data, ranges)
                } else {
                    ranges.iter().map(|_| &mut [][..]).collect()
                }
            }
            let work: Vec<_> = self
                .chunks
                .iter()
                .zip(accs.iter_mut())
                .zip(parts(&mut hist, FRIC, &slot_ranges))
                .zip(parts(&mut normals, POLY, &slot_ranges))
                .zip(parts(&mut reach, POLY, &slot_ranges))
                .collect();
            let this = &*self;
            let counts = on_team(work, |_, ((((rows, acc), hist), normals), reach)| {
                acc.clear();
                let base = this.pairs.offsets[rows.start] as usize;
                let lo = acc.range.start;
                let mut dummy = Vec3::zeros();
                let mut dummy_n = PairMemory::default();
                let mut dummy_reach = 0.0;
                let mut count = 0;
                for i in rows.clone() {
                    for s in this.pairs.row(i) {
                        let j = this.pairs.partners[s] as usize;
                        let h = if FRIC {
                            &mut hist[s - base]
                        } else {
                            &mut dummy
                        };
                        let nrm = if POLY {
                            &mut normals[s - base]
                        } else {
                            &mut dummy_n
                        };
                        let r = if POLY {
                            &mut reach[s - base]
                        } else {
                            &mut dummy_reach
                        };
                        if let Some(p) = this.pair_force(bodies, i, j, h, nrm, r, ctx) {
                            acc.force[i - lo] += p.force;
                            acc.force[j - lo] -= p.force;
                            if FRIC || POLY {
                                acc.torque[i - lo] += p.torque_i;
                                acc.torque[j - lo] += p.torque_j;
                            }
                            if POLY {
                                acc.records.push(p.record(i, j as u32));
                                acc.dissipated += p.c.dissipated;
                            } else {
                                acc.stiffness[i - lo] += p.c.stiffness;
                                acc.stiffness[j - lo] += p.c.stiffness;
                            }
                            count += 1;
                        }
                    }
                }
                count
            });
            self.contacts = counts.iter().sum();
        }
        // Chunk order is row order: the same records as one thread, in the same order. The
        // first chunk's list is taken over rather than copied (the list is emptied before the
        // pair loop; its buffer goes to the chunk for the next step); the others' are copied
        // as one part of the merge below, beside the bodies' sums.
        let mut taken = false;
        if POLY
            && let Some(first) = accs.first_mut()
            && self.records.list.is_empty()
        {
            std::mem::swap(&mut self.records.list, &mut first.records);
            taken = true;
        }
        // Each body adds the accumulators that hold it, in chunk order.
        let n = forces.force.len();
        #[allow(clippy::single_range_in_vec_init)] // one part: every body
        let ranges = team_blocks(n).unwrap_or_else(|| vec![0..n]);
        let mut stiffness = std::mem::take(&mut self.body_stiffness);
        let stiffness_parts = if POLY {
            ranges.iter().map(|_| &mut [][..]).collect()
        } else {
            split_ranges(&mut stiffness, &ranges)
        };
        enum Merge<'a> {
            Bodies(Range<usize>, &'a mut [Vec3], &'a mut [Vec3], &'a mut [f64]),
            Records(&'a mut ContactRecords),
        }
        let mut merge: Vec<Merge> = Vec::with_capacity(ranges.len() + 1);
        if POLY {
            merge.push(Merge::Records(&mut self.records));
        }
        merge.extend(
            ranges
                .iter()
                .zip(split_ranges(&mut forces.force, &ranges))
                .zip(split_ranges(&mut forces.torque, &ranges))
                .zip(stiffness_parts)
                .map(|(((range, f), t), k)| Merge::Bodies(range.clone(), f, t, k)),
        );
        let accs_ref = &accs;
        on_team(merge, |_, part| match part {
            Merge::Records(records) => {
                for (k, acc) in accs_ref.iter().enumerate() {
                    if k > 0 || !taken {
                        records.list.extend_from_slice(&acc.records);
                    }
                    records.dissipated += acc.dissipated;
                }
            }
            Merge::Bodies(range, f, t, k_sum) => {
                for (k, i) in range.enumerate() {
                    for acc in accs_ref {
                        if acc.range.contains(&i) {
                            f[k] += acc.force[i - acc.range.start];
                            if FRIC || POLY {
                                t[k] += acc.torque[i - acc.range.start];
                            }
                            if !POLY {
                                k_sum[k] += acc.stiffness[i - acc.range.start];
                            }
                        }
                    }
                }
            }
        });
        self.body_stiffness = stiffness;
        self.pair_hist = hist;
        self.pair_memory = normals;
        self.pair_reach = reach;
        self.accumulators = accs;
    }
}
