//! The planar Coulomb contact problem on one level, as a linear complementarity problem
//! solved by Lemke's method ([`crate::lcp`]), in the form of Anitescu and Potra (1997).
//!
//! On the velocity level the unknowns are percussions and the rows are speeds (the
//! Moreau–Jean step of [`crate::lcp_step`]); on the acceleration level they are forces
//! and accelerations (the consistent start's Lemke stage, [`crate::start`]). Either way,
//! with v_free the level's free motion (ũ, or M⁻¹h):
//!
//! v = v_free + M⁻¹(Σ_i f_i z_i + Σ_j w_{F,j} (β⁺_j − β⁻_j)),
//! 0 ≤ z_i ⟂ w_{N,i}ᵀ v + c_i ≥ 0,
//! 0 ≤ β⁺_j ⟂ λ_j + w_{F,j}ᵀ v + c_j ≥ 0,  0 ≤ β⁻_j ⟂ λ_j − w_{F,j}ᵀ v − c_j ≥ 0,
//! 0 ≤ λ_j ⟂ μ_j Σ_{i ∈ j} z_i − β⁺_j − β⁻_j ≥ 0,
//!
//! where f_i, the generalized force direction of normal unknown i, is its row w_{N,i}
//! except where its friction law slides in a known direction s: then the friction force
//! −μ z_i sign(s) acts with it, and f_i = w_{N,i} − μ sign(s) w_F (a sliding law has no
//! unknowns of its own). The LCP's matrix is then no longer symmetric in its normal
//! block, which Lemke's method does not need.

use crate::lcp::{lemke_regularized, LcpFailure};
use crate::mass_inverse::MassInverse;
use crate::system::{Evaluation, Layout};
use nalgebra::DVector;

/// M⁻¹ and the W columns of one evaluation, the pieces the LCPs are built from.
pub(crate) struct ContactMatrices {
    /// M⁻¹, by M's diagonal blocks.
    pub m_inv: MassInverse,
    /// The columns of W_p asked for.
    pub w_p: SparseColumns,
    /// The columns of W_v asked for.
    pub w_v: SparseColumns,
}

impl ContactMatrices {
    /// M⁻¹ and the first `np` columns of W_p and `nv` of W_v (None: M is singular).
    pub(crate) fn of(eval: &Evaluation<f64>, nu: usize, np: usize, nv: usize) -> Option<Self> {
        Some(Self {
            m_inv: MassInverse::of(nu, &eval.mass.entries)?,
            w_p: SparseColumns::of(nu, np, &eval.position_w.entries),
            w_v: SparseColumns::of(nu, nv, &eval.velocity_w.entries),
        })
    }
}

/// The first columns of a matrix given by (row, column, value) entries, each as its
/// nonzero entries by ascending row (duplicates summed).
///
/// A contact's column of W has the entries of the one or two bodies it joins. Stored
/// densely, the W of a 1000-block column on a floor (3000 coordinates, 6000 normal
/// contacts) took 144 MB, and every product with it ran over the zeros.
#[derive(Debug, Clone)]
pub(crate) struct SparseColumns {
    rows: usize,
    columns: Vec<Vec<(usize, f64)>>,
}

impl SparseColumns {
    /// Columns 0..`count` of the `rows`-row matrix with `entries`.
    pub(crate) fn of(rows: usize, count: usize, entries: &[(usize, usize, f64)]) -> Self {
        let mut columns = vec![Vec::new(); count];
        for &(i, c, v) in entries.iter().filter(|e| e.1 < count) {
            columns[c].push((i, v));
        }
        for column in &mut columns {
            column.sort_by_key(|e| e.0);
            column.dedup_by(|later, kept| {
                let same = later.0 == kept.0;
                if same {
                    kept.1 += later.1;
                }
                same
            });
        }
        Self { rows, columns }
    }

    /// The nonzero entries of column `c`, by ascending row.
    pub(crate) fn entries(&self, c: usize) -> &[(usize, f64)] {
        &self.columns[c]
    }

    /// Column `c` as a dense vector.
    pub(crate) fn dense(&self, c: usize) -> DVector<f64> {
        let mut out = DVector::zeros(self.rows);
        for &(i, v) in &self.columns[c] {
            out[i] = v;
        }
        out
    }

    /// The product of column `c` with `v`.
    pub(crate) fn dot(&self, c: usize, v: &[f64]) -> f64 {
        self.columns[c].iter().map(|&(i, w)| w * v[i]).sum()
    }
}

/// One planar Coulomb problem: its rows, the force directions of its unknowns, and the
/// friction bounds. The normal unknowns come first, then one per sticking friction law.
#[derive(Debug, Clone, Default)]
pub(crate) struct CoulombLcp {
    /// Per unknown, its constraint's W column (w_N, then w_F).
    pub rows: Vec<DVector<f64>>,
    /// Per unknown, the generalized force direction it acts along (f_i, then w_F).
    pub forces: Vec<DVector<f64>>,
    /// How many of the unknowns are normal ones.
    pub normals: usize,
    /// Per sticking law: μ and the normal unknowns whose sum it bounds.
    pub bounds: Vec<(f64, Vec<usize>)>,
    /// The rows at the free motion, wᵀv_free + c, in the order of the unknowns.
    pub free: Vec<f64>,
}

/// A solution of a [`CoulombLcp`].
#[derive(Debug, Clone)]
pub(crate) struct CoulombSolution {
    /// The normal unknowns z_i.
    pub normal: Vec<f64>,
    /// Per sticking law, β⁺ − β⁻.
    pub friction: Vec<f64>,
    /// M⁻¹(Σ f_i z_i + Σ w_F (β⁺ − β⁻)): what the unknowns add to v_free.
    pub change: DVector<f64>,
    /// Lemke's pivots.
    pub pivots: usize,
    /// The complementarity residual of Lemke's solution.
    pub residual: f64,
}

impl CoulombLcp {
    /// The rows of the contacts `normals` and of the friction laws `laws`, in that
    /// order: their W columns.
    pub fn rows_of(d: &ContactMatrices, normals: &[usize], laws: &[usize]) -> Vec<DVector<f64>> {
        normals
            .iter()
            .map(|&k| d.w_p.dense(k))
            .chain(laws.iter().map(|&j| d.w_v.dense(j)))
            .collect()
    }

    /// The bounds of the friction laws `laws`: per law, μ and the positions in
    /// `normals` (sorted) of its normal contacts among them.
    pub fn bounds_of(layout: &Layout, normals: &[usize], laws: &[usize]) -> Vec<(f64, Vec<usize>)> {
        laws.iter()
            .map(|&j| {
                let law = &layout.friction[j];
                let among = |k: &usize| normals.binary_search(k).ok();
                (law.mu, law.normals.iter().filter_map(among).collect())
            })
            .collect()
    }

    /// Solves the problem by Lemke's method (regularized where the tableau is rank
    /// deficient), accepting a complementarity residual up to `accept`.
    ///
    /// # Errors
    /// Lemke's failure: a ray (no solution) or bad data.
    pub fn solve(&self, m_inv: &MassInverse, accept: f64) -> Result<CoulombSolution, LcpFailure> {
        let (a, b) = (self.normals, self.bounds.len());
        let n = a + 3 * b;
        // A row has the few entries of the bodies its contact touches: the products below
        // run over those only.
        let support: Vec<Vec<(usize, f64)>> = self
            .rows
            .iter()
            .map(|c| {
                c.iter()
                    .copied()
                    .enumerate()
                    .filter(|e| e.1 != 0.0)
                    .collect()
            })
            .collect();
        let g_cols: Vec<DVector<f64>> = self
            .forces
            .iter()
            .map(|f| m_inv.apply(f.as_slice()))
            .collect();
        let mut m = vec![0.0; n * n];
        let mut rhs = vec![0.0; n];
        // The level's rows: ±(row r)ᵀ M⁻¹ times the unknowns, β⁺ − β⁻ for friction.
        for (r, row_r) in support.iter().enumerate() {
            let rows: &[(usize, f64)] = if r < a {
                &[(r, 1.0)]
            } else {
                &[(r, 1.0), (r + b, -1.0)]
            };
            for (c, g_c) in g_cols.iter().enumerate() {
                let v: f64 = row_r.iter().map(|&(i, w)| w * g_c[i]).sum();
                for &(row, sign) in rows {
                    m[row * n + c] = sign * v;
                    if c >= a {
                        m[row * n + c + b] = -sign * v;
                    }
                }
            }
        }
        rhs[..a].copy_from_slice(&self.free[..a]);
        for (i, (mu, normals)) in self.bounds.iter().enumerate() {
            let c = self.free[a + i];
            rhs[a + i] = c;
            rhs[a + b + i] = -c;
            // λ enters both slip rows; the friction bound row closes the system.
            m[(a + i) * n + a + 2 * b + i] = 1.0;
            m[(a + b + i) * n + a + 2 * b + i] = 1.0;
            let row = a + 2 * b + i;
            for &p in normals {
                m[row * n + p] = *mu;
            }
            m[row * n + a + i] = -1.0;
            m[row * n + a + b + i] = -1.0;
        }
        let (sol, _) = lemke_regularized(&m, &rhs, 50 * n + 50, accept)?;
        let friction: Vec<f64> = (0..b).map(|i| sol.z[a + i] - sol.z[a + b + i]).collect();
        let mut change = DVector::zeros(m_inv.dim());
        for (g_c, &z) in g_cols.iter().zip(sol.z[..a].iter().chain(&friction)) {
            change += g_c * z;
        }
        Ok(CoulombSolution {
            normal: sol.z[..a].to_vec(),
            friction,
            change,
            pivots: sol.pivots,
            residual: sol.residual,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::SparseColumns;

    #[test]
    fn sparse_columns_sum_duplicates_and_keep_the_columns_asked_for() {
        // Column 0: rows 2 and 0 (row 2 given twice); column 1: row 1; column 2 is
        // beyond the two asked for.
        let entries = [
            (2, 0, 1.0),
            (0, 0, -2.0),
            (1, 1, 3.0),
            (2, 0, 0.5),
            (0, 2, 7.0),
        ];
        let w = SparseColumns::of(3, 2, &entries);
        assert_eq!(w.entries(0), &[(0, -2.0), (2, 1.5)]);
        assert_eq!(w.dense(1).as_slice(), &[0.0, 3.0, 0.0]);
        assert_eq!(w.dot(0, &[1.0, 10.0, 2.0]), 1.0);
    }
}
