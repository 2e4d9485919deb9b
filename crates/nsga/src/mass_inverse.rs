//! M⁻¹ by the diagonal blocks of the mass matrix, for the dense contact problems of the
//! last resort and of the consistent start's Lemke stage ([`crate::coulomb_lcp`]).
//!
//! A system of free bodies has a block-diagonal M: one block per body (3 × 3 for a
//! planar block, diagonal even), coupled only where the system's coordinates couple
//! them. Inverting M as one dense matrix costs O(n³) in its n coordinates and applying
//! it O(n²), which at 1000 blocks (n = 3000) took about half of a last-resort step. Here
//! the coordinates are grouped into the connected components of M's sparsity pattern,
//! each component's block is inverted on its own, and M⁻¹v costs the blocks' entries.
//! A system whose M couples every coordinate gets one block: the dense inverse as before.

use nalgebra::{DMatrix, DVector};

/// M⁻¹ as the inverses of M's diagonal blocks (see the module docs).
#[derive(Debug, Clone)]
pub(crate) struct MassInverse {
    /// Per block: its coordinates, ascending, and the inverse of M restricted to them.
    blocks: Vec<(Vec<usize>, DMatrix<f64>)>,
    /// The number of coordinates.
    n: usize,
}

impl MassInverse {
    /// The inverse of the n × n matrix M given by its (row, column, value) entries
    /// (duplicates summed); None when a block of M is singular.
    pub(crate) fn of(n: usize, entries: &[(usize, usize, f64)]) -> Option<Self> {
        let mut component = Components::new(n);
        for &(i, j, _) in entries {
            component.join(i, j);
        }
        // Coordinates by component, in order of their least coordinate.
        let mut block_of = vec![usize::MAX; n];
        let mut members: Vec<Vec<usize>> = Vec::new();
        for i in 0..n {
            let root = component.root(i);
            if block_of[root] == usize::MAX {
                block_of[root] = members.len();
                members.push(Vec::new());
            }
            block_of[i] = block_of[root];
            members[block_of[i]].push(i);
        }
        // Each coordinate's place within its block.
        let mut local = vec![0; n];
        for coordinates in &members {
            for (p, &i) in coordinates.iter().enumerate() {
                local[i] = p;
            }
        }
        let mut matrices: Vec<DMatrix<f64>> = members
            .iter()
            .map(|c| DMatrix::zeros(c.len(), c.len()))
            .collect();
        for &(i, j, v) in entries {
            matrices[block_of[i]][(local[i], local[j])] += v;
        }
        let blocks = members
            .into_iter()
            .zip(matrices)
            .map(|(c, m)| Some((c, m.try_inverse()?)))
            .collect::<Option<Vec<_>>>()?;
        Some(Self { blocks, n })
    }

    /// The number of coordinates.
    pub(crate) fn dim(&self) -> usize {
        self.n
    }

    /// M⁻¹v.
    pub(crate) fn apply(&self, v: &[f64]) -> DVector<f64> {
        let mut out = DVector::zeros(self.n);
        for (coordinates, inverse) in &self.blocks {
            for (r, &i) in coordinates.iter().enumerate() {
                out[i] = coordinates
                    .iter()
                    .enumerate()
                    .map(|(c, &j)| inverse[(r, c)] * v[j])
                    .sum();
            }
        }
        out
    }
}

/// Union–find over the coordinates: two are in one component when an entry of M joins
/// them, directly or through others.
struct Components {
    parent: Vec<usize>,
}

impl Components {
    fn new(n: usize) -> Self {
        Self {
            parent: (0..n).collect(),
        }
    }

    fn root(&mut self, mut i: usize) -> usize {
        while self.parent[i] != i {
            // Path halving keeps the trees flat.
            self.parent[i] = self.parent[self.parent[i]];
            i = self.parent[i];
        }
        i
    }

    fn join(&mut self, i: usize, j: usize) {
        let (a, b) = (self.root(i), self.root(j));
        // The lesser root stays, so a component's root is its least coordinate.
        if a != b {
            self.parent[a.max(b)] = a.min(b);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::MassInverse;
    use nalgebra::{DMatrix, DVector};

    /// A mass matrix with a coupled 2 × 2 block (coordinates 0 and 3), a diagonal entry
    /// given twice (coordinate 1, summed) and one alone (coordinate 2).
    fn entries() -> Vec<(usize, usize, f64)> {
        vec![
            (0, 0, 2.0),
            (0, 3, 0.5),
            (3, 0, 0.5),
            (3, 3, 1.0),
            (1, 1, 1.5),
            (1, 1, 1.5),
            (2, 2, 4.0),
        ]
    }

    #[test]
    fn applies_the_inverse_of_the_whole_matrix() {
        let e = entries();
        let mut m = DMatrix::<f64>::zeros(4, 4);
        for &(i, j, v) in &e {
            m[(i, j)] += v;
        }
        let dense = m.try_inverse().expect("regular");
        let inverse = MassInverse::of(4, &e).expect("regular");
        assert_eq!(inverse.blocks.len(), 3);
        let v = [1.0, -2.0, 0.5, 3.0];
        let expected: DVector<f64> = &dense * DVector::from_column_slice(&v);
        let applied: DVector<f64> = inverse.apply(&v);
        assert!((applied - expected).amax() < 1e-15);
        assert_eq!(inverse.dim(), 4);
    }

    #[test]
    fn a_singular_block_is_reported() {
        let mut e = entries();
        e.push((2, 2, -4.0));
        assert!(MassInverse::of(4, &e).is_none());
    }
}
