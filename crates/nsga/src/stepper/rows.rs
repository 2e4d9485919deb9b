//! Sparse rows over the unknowns x, and the chain rule through q_{n+1}(x) and
//! u_{n+1}(x) that turns the system's derivatives into rows of the Newton matrix.

use crate::system::Triplets;

/// Rows of a sparse matrix over the columns of x, compressed by row.
#[derive(Debug, Clone, Default)]
pub(crate) struct RowMat {
    ptr: Vec<usize>,
    idx: Vec<usize>,
    val: Vec<f64>,
    fill: Vec<usize>,
    pub tmp: Vec<(usize, usize, f64)>,
}

impl RowMat {
    /// Compresses `tmp` (row, col, value) into rows 0..nrows.
    pub(crate) fn build(&mut self, nrows: usize) {
        self.ptr.clear();
        self.ptr.resize(nrows + 1, 0);
        for &(r, _, _) in &self.tmp {
            self.ptr[r + 1] += 1;
        }
        for i in 0..nrows {
            self.ptr[i + 1] += self.ptr[i];
        }
        self.idx.resize(self.tmp.len(), 0);
        self.val.resize(self.tmp.len(), 0.0);
        self.fill.clone_from(&self.ptr);
        for &(r, c, v) in &self.tmp {
            self.idx[self.fill[r]] = c;
            self.val[self.fill[r]] = v;
            self.fill[r] += 1;
        }
        self.tmp.clear();
    }
    pub(crate) fn row(&self, r: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        (self.ptr[r]..self.ptr[r + 1]).map(move |i| (self.idx[i], self.val[i]))
    }
}

/// Pushes `scale · D · B` into `out` rows, with `D` given in q-columns, placing the
/// result in the a-block (× c_qa) and the Q-block (× 1): ∂q_{n+1}/∂a = Δt²βα_r B,
/// ∂q_{n+1}/∂Q = B (docs/method.md §4).
pub(crate) fn push_q_derivative(
    out: &mut Vec<(usize, usize, f64)>,
    d: &Triplets<f64>,
    b: &RowMat,
    row_off: usize,
    scale: f64,
    cols: &[(usize, f64)],
) {
    for &(r, j, v) in &d.entries {
        for (i, bij) in b.row(j) {
            for &(off, c) in cols {
                out.push((row_off + r, off + i, scale * c * v * bij));
            }
        }
    }
}

/// Pushes `scale · D` (D in u-columns, or transposed W when `transpose`) into the
/// column blocks `cols` (offset, factor).
pub(crate) fn push_u_derivative(
    out: &mut Vec<(usize, usize, f64)>,
    d: &Triplets<f64>,
    transpose: bool,
    row_off: usize,
    scale: f64,
    cols: &[(usize, f64)],
) {
    for &(r0, c0, v) in &d.entries {
        let (r, c) = if transpose { (c0, r0) } else { (r0, c0) };
        for &(off, f) in cols {
            out.push((row_off + r, off + c, scale * f * v));
        }
    }
}
