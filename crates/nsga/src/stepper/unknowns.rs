//! The unknowns of one step (paper eq. 126) and where each block sits in x.

use crate::system::Layout;

/// Sizes and offsets of the unknown vector x (eq. 126).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Offsets {
    pub nu: usize,
    pub nq: usize,
    pub ng: usize,
    pub nga: usize,
    pub nn: usize,
    pub nf: usize,
    pub a: usize,
    pub uu: usize,
    pub qq: usize,
    pub kg: usize,
    pub cg: usize,
    pub lg: usize,
    pub cga: usize,
    pub lga: usize,
    pub kn: usize,
    pub cn: usize,
    pub ln: usize,
    pub cf: usize,
    pub lf: usize,
    pub n: usize,
}

impl Offsets {
    pub(crate) fn new(l: &Layout) -> Self {
        let (nu, ng, nga, nn, nf) = (
            l.nu,
            l.n_bilateral_position,
            l.n_bilateral_velocity,
            l.n_normal(),
            l.n_friction(),
        );
        let a = 0;
        let uu = nu;
        let qq = 2 * nu;
        let kg = 3 * nu;
        let cg = kg + ng;
        let lg = cg + ng;
        let cga = lg + ng;
        let lga = cga + nga;
        let kn = lga + nga;
        let cn = kn + nn;
        let ln = cn + nn;
        let cf = ln + nn;
        let lf = cf + nf;
        let n = lf + nf;
        Self {
            nu,
            nq: l.nq,
            ng,
            nga,
            nn,
            nf,
            a,
            uu,
            qq,
            kg,
            cg,
            lg,
            cga,
            lga,
            kn,
            cn,
            ln,
            cf,
            lf,
            n,
        }
    }

    /// The blocks of x that hold the smooth forces λ (eq. 126): bilateral on position
    /// and velocity level, normal, friction. With a, the smooth unknowns; the rest
    /// (U, Q, κ, Λ) answer impacts and drift.
    pub(crate) fn forces(&self) -> [std::ops::Range<usize>; 4] {
        [
            self.lg..self.lg + self.ng,
            self.lga..self.lga + self.nga,
            self.ln..self.ln + self.nn,
            self.lf..self.lf + self.nf,
        ]
    }
}
