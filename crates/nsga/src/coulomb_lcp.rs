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

use crate::constrained_mass::InverseMass;
use crate::friction_polygon;
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

/// Whether a layout has planar friction laws only and no bilateral constraints: what the
/// consistent start's Lemke stage takes ([`crate::start`]). The last resort's step takes
/// every layout ([`crate::fallback`]).
///
/// # Errors
/// What the layout has beyond that.
pub(crate) fn planar_without_bilateral(l: &Layout) -> Result<(), String> {
    if l.n_bilateral_position + l.n_bilateral_velocity > 0
        || l.friction.iter().any(|f| f.components != 1)
    {
        return Err("the start's LCP covers planar friction without bilateral constraints".into());
    }
    Ok(())
}

/// The bound of one friction law in a [`CoulombLcp`].
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct FrictionBound {
    /// μ.
    pub mu: f64,
    /// The normal unknowns whose sum it bounds (positions among the normal unknowns).
    pub normals: Vec<usize>,
    /// The directions its percussion is spanned by ([`crate::friction_polygon`]).
    pub directions: Vec<Vec<f64>>,
}

impl FrictionBound {
    /// The law's number of tangential components.
    fn components(&self) -> usize {
        self.directions[0].len()
    }
}

/// One Coulomb problem: its rows, the force directions of its unknowns, and the
/// friction bounds. The normal unknowns come first, then the components of each
/// sticking friction law in turn.
#[derive(Debug, Clone, Default)]
pub(crate) struct CoulombLcp {
    /// Per row, its constraint's W column (w_N, then each law's w_F components).
    pub rows: Vec<DVector<f64>>,
    /// Per row, the generalized force direction its percussion acts along (f_i, then
    /// w_F).
    pub forces: Vec<DVector<f64>>,
    /// How many of the rows are normal ones.
    pub normals: usize,
    /// Per sticking law, its bound.
    pub bounds: Vec<FrictionBound>,
    /// The rows at the free motion, wᵀv_free + c, in the order of the rows.
    pub free: Vec<f64>,
}

/// A solution of a [`CoulombLcp`].
#[derive(Debug, Clone)]
pub(crate) struct CoulombSolution {
    /// The normal unknowns z_i.
    pub normal: Vec<f64>,
    /// Per sticking law, its percussion's components (β⁺ − β⁻ for a planar law).
    pub friction: Vec<f64>,
    /// M⁻¹(Σ f_i z_i + Σ w_F P_F): what the unknowns add to v_free.
    pub change: DVector<f64>,
    /// Lemke's pivots.
    pub pivots: usize,
    /// The complementarity residual of Lemke's solution.
    pub residual: f64,
}

/// Σ_m d_m x_m over a direction's components d: ±x for a planar law, exactly.
fn along(d: &[f64], x: impl Fn(usize) -> f64) -> f64 {
    d.iter()
        .enumerate()
        .map(|(m, dm)| dm * x(m))
        .reduce(|a, b| a + b)
        .unwrap_or(0.0)
}

impl CoulombLcp {
    /// The rows of the contacts `normals` and of the components of the friction laws
    /// `laws`, in that order: their W columns (normal k is position constraint ng + k,
    /// law j's components follow nγ and the laws before it).
    pub fn rows_of(
        layout: &Layout,
        d: &ContactMatrices,
        normals: &[usize],
        laws: &[usize],
    ) -> Vec<DVector<f64>> {
        let (ng, nga) = (layout.n_bilateral_position, layout.n_bilateral_velocity);
        let offsets = layout.friction_offsets();
        normals
            .iter()
            .map(|&k| d.w_p.dense(ng + k))
            .chain(laws.iter().flat_map(|&j| {
                let first = nga + offsets[j];
                (0..layout.friction[j].components).map(move |m| d.w_v.dense(first + m))
            }))
            .collect()
    }

    /// The bounds of the friction laws `laws`: per law, μ, the positions in `normals`
    /// (sorted) of its normal contacts among them, and its directions.
    pub fn bounds_of(layout: &Layout, normals: &[usize], laws: &[usize]) -> Vec<FrictionBound> {
        laws.iter()
            .map(|&j| {
                let law = &layout.friction[j];
                let among = |k: &usize| normals.binary_search(k).ok();
                FrictionBound {
                    mu: law.mu,
                    normals: law.normals.iter().filter_map(among).collect(),
                    directions: friction_polygon::directions(law.components),
                }
            })
            .collect()
    }

    /// The friction unknowns β, as (law, direction): direction 0 of every law, then
    /// direction 1, and so on (for planar laws: every β⁺, then every β⁻).
    fn directional_unknowns(&self) -> Vec<(usize, usize)> {
        let most = self.bounds.iter().map(|b| b.directions.len()).max();
        (0..most.unwrap_or(0))
            .flat_map(|i| {
                (0..self.bounds.len())
                    .filter(move |&l| i < self.bounds[l].directions.len())
                    .map(move |l| (l, i))
            })
            .collect()
    }

    /// Solves the problem by Lemke's method (regularized where the tableau is rank
    /// deficient), accepting a complementarity residual up to `accept`.
    ///
    /// The unknowns are the normal ones z, the β of [`Self::directional_unknowns`] and
    /// one λ per law; a β row is λ + dᵀ(W_Fᵀv + c), a λ row μ Σ z − Σ β.
    ///
    /// # Errors
    /// Lemke's failure: a ray (no solution) or bad data.
    pub fn solve(
        &self,
        m_inv: &impl InverseMass,
        accept: f64,
    ) -> Result<CoulombSolution, LcpFailure> {
        let a = self.normals;
        let b = self.bounds.len();
        let betas = self.directional_unknowns();
        let n = a + betas.len() + b;
        // Each law's first row among the rows (normals first).
        let mut first = Vec::with_capacity(b);
        let mut next = a;
        for bound in &self.bounds {
            first.push(next);
            next += bound.components();
        }
        let g_cols = self.force_columns(m_inv);
        let v = self.row_products(&g_cols);
        // Row or column i of the LCP as a combination of the problem's rows: a normal
        // row itself, a β the law's rows along its direction.
        let along_row = |i: usize, x: &dyn Fn(usize) -> f64| -> f64 {
            if i < a {
                x(i)
            } else {
                let (l, dir) = betas[i - a];
                along(&self.bounds[l].directions[dir], |m| x(first[l] + m))
            }
        };
        let mut m = vec![0.0; n * n];
        let mut rhs = vec![0.0; n];
        let unknowns = a + betas.len();
        for r in 0..unknowns {
            for c in 0..unknowns {
                m[r * n + c] = along_row(r, &|row| along_row(c, &|col| v[row][col]));
            }
            rhs[r] = along_row(r, &|row| self.free[row]);
        }
        for (i, &(l, _)) in betas.iter().enumerate() {
            // λ enters every direction's row of its law; the law's bound row closes
            // the system.
            m[(a + i) * n + unknowns + l] = 1.0;
            m[(unknowns + l) * n + a + i] = -1.0;
        }
        for (l, bound) in self.bounds.iter().enumerate() {
            for &p in &bound.normals {
                m[(unknowns + l) * n + p] = bound.mu;
            }
        }
        let (sol, _) = lemke_regularized(&m, &rhs, 50 * n + 50, accept)?;
        let friction: Vec<f64> = self
            .bounds
            .iter()
            .enumerate()
            .flat_map(|(l, bound)| {
                let z = &sol.z;
                let of_law: Vec<(usize, &Vec<f64>)> = (0..betas.len())
                    .filter(|&i| betas[i].0 == l)
                    .map(|i| (a + i, &bound.directions[betas[i].1]))
                    .collect();
                (0..bound.components()).map(move |m| {
                    of_law
                        .iter()
                        .map(|&(i, d)| z[i] * d[m])
                        .reduce(|x, y| x + y)
                        .unwrap_or(0.0)
                })
            })
            .collect();
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

    /// M⁻¹ times each row's force direction.
    fn force_columns(&self, m_inv: &impl InverseMass) -> Vec<DVector<f64>> {
        self.forces
            .iter()
            .map(|f| m_inv.apply(f.as_slice()))
            .collect()
    }

    /// The products w_rᵀ g_c of every row r with every column `g_cols` (M⁻¹f_c).
    fn row_products(&self, g_cols: &[DVector<f64>]) -> Vec<Vec<f64>> {
        // A row has the few entries of the bodies its contact touches: the products run
        // over those only.
        self.rows
            .iter()
            .map(|row| {
                let support: Vec<(usize, f64)> = row
                    .iter()
                    .copied()
                    .enumerate()
                    .filter(|e| e.1 != 0.0)
                    .collect();
                g_cols
                    .iter()
                    .map(|g_c| support.iter().map(|&(i, w)| w * g_c[i]).sum())
                    .collect()
            })
            .collect()
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
