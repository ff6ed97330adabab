//! Fragments: connected components of bodies over the links that still hold them together
//! (intact beams in `beam2d`, intact cohesive springs between sub-particles in `granular`).

/// Disjoint sets with path halving and union by size.
#[derive(Debug, Clone)]
pub struct UnionFind {
    parent: Vec<u32>,
    size: Vec<u32>,
}

impl UnionFind {
    /// `n` singletons.
    pub fn new(n: usize) -> Self {
        assert!(n <= u32::MAX as usize, "at most 2^32 - 1 elements");
        UnionFind {
            parent: (0..n as u32).collect(),
            size: vec![1; n],
        }
    }

    pub fn len(&self) -> usize {
        self.parent.len()
    }

    pub fn is_empty(&self) -> bool {
        self.parent.is_empty()
    }

    /// The representative of `i`'s set.
    pub fn find(&mut self, mut i: usize) -> usize {
        while self.parent[i] as usize != i {
            let grand = self.parent[self.parent[i] as usize];
            self.parent[i] = grand;
            i = grand as usize;
        }
        i
    }

    /// Joins the sets of `a` and `b`; false when they were one set already.
    pub fn union(&mut self, a: usize, b: usize) -> bool {
        let (mut ra, mut rb) = (self.find(a), self.find(b));
        if ra == rb {
            return false;
        }
        if self.size[ra] < self.size[rb] {
            std::mem::swap(&mut ra, &mut rb);
        }
        self.parent[rb] = ra as u32;
        self.size[ra] += self.size[rb];
        true
    }

    /// A component label per element, numbered 0, 1, ... in the order of each component's
    /// lowest element (deterministic whatever the order of the unions), and the number of
    /// components.
    pub fn labels(&mut self) -> (Vec<u32>, usize) {
        let n = self.len();
        let mut label_of_root = vec![u32::MAX; n];
        let mut labels = vec![0; n];
        let mut count = 0;
        for (i, label) in labels.iter_mut().enumerate() {
            let r = self.find(i);
            if label_of_root[r] == u32::MAX {
                label_of_root[r] = count as u32;
                count += 1;
            }
            *label = label_of_root[r];
        }
        (labels, count)
    }
}

/// The components of `n` bodies joined by `links`: a label per body (see
/// [`UnionFind::labels`]) and the number of components.
pub fn components(n: usize, links: impl IntoIterator<Item = (usize, usize)>) -> (Vec<u32>, usize) {
    let mut uf = UnionFind::new(n);
    for (a, b) in links {
        uf.union(a, b);
    }
    uf.labels()
}

/// The total of `values` (masses, volumes) per component, in label order.
pub fn sum_by_component(labels: &[u32], count: usize, values: &[f64]) -> Vec<f64> {
    let mut sums = vec![0.0; count];
    for (&l, &v) in labels.iter().zip(values) {
        sums[l as usize] += v;
    }
    sums
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chains_and_singletons() {
        // 0-1-2 and 4-5, with 3 and 6 alone.
        let (labels, count) = components(7, [(1, 2), (5, 4), (0, 1)]);
        assert_eq!(count, 4);
        assert_eq!(labels, vec![0, 0, 0, 1, 2, 2, 3]);
        let masses = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0];
        assert_eq!(
            sum_by_component(&labels, count, &masses),
            vec![6.0, 4.0, 11.0, 7.0]
        );
    }

    #[test]
    fn union_reports_whether_it_joined() {
        let mut uf = UnionFind::new(3);
        assert!(uf.union(0, 2));
        assert!(!uf.union(2, 0));
        assert_eq!(uf.find(0), uf.find(2));
        assert_ne!(uf.find(1), uf.find(0));
    }
}
