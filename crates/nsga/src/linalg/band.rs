//! Banded LU for the large Newton matrices of chains (tall block columns): the unknowns
//! renumbered by reverse Cuthill–McKee, then Gaussian elimination with partial pivoting
//! inside the band (LAPACK's `dgbtf2`), faer's sparse LU where the band is wide.
//!
//! Ordered by interface, the Newton matrix of a chain is block-banded: the rows of an
//! interface's contacts hold the unknowns of the two bodies it joins, a body's rows the
//! multipliers of its two interfaces. Reverse Cuthill–McKee finds such an order from the
//! pattern alone (breadth-first from an end of the chain), with a half-bandwidth of about
//! one body and one interface. The factorization then costs O(n b²) for a band of b, with
//! no symbolic analysis: where each entry goes is an index computation, and a pattern
//! that changes with the index sets (an open contact's rows differ from a closed one's)
//! changes nothing as long as its entries stay in the band. They nearly always do: a row's
//! other form couples the same bodies. So the order is kept per matrix size (pruning
//! changes the size) and computed again only for a matrix that does not fit its band
//! ([`Ordering::fits`]).

use super::{LinalgError, LinearSolver, SparseLu, SYMBOLIC_CACHE};

/// Widest band, kl + ku + 1 diagonals, that [`BandLu`] factors itself; a wider matrix goes
/// to faer's sparse LU (whose supernodes and ordering beat the dense band of a matrix
/// that is not a chain). See docs/linear-algebra.md ("Banded LU").
pub const MAX_BAND: usize = 160;

/// A symmetric renumbering of the unknowns and the band it gives a matrix.
#[derive(Debug, Clone)]
struct Ordering {
    /// `new[i]`: the position of unknown i in the banded matrix.
    new: Vec<usize>,
    /// Sub- and superdiagonals of the matrix it was computed for.
    kl: usize,
    ku: usize,
}

impl Ordering {
    /// The reverse Cuthill–McKee order of the pattern of `triplets` (made symmetric).
    fn of(n: usize, triplets: &[(usize, usize, f64)]) -> Self {
        let graph = Graph::of(n, triplets);
        let old = graph.reverse_cuthill_mckee();
        let mut new = vec![0; n];
        for (p, &i) in old.iter().enumerate() {
            new[i] = p;
        }
        let (kl, ku) = band(&new, triplets);
        Self { new, kl, ku }
    }

    /// Whether a matrix whose band is (kl, ku) in this order keeps it: a band a little
    /// wider than the one the order was made for (a row's other form) is kept, a much
    /// wider one (another pruning of the same size renumbers the unknowns) is not.
    fn fits(&self, (kl, ku): (usize, usize)) -> bool {
        let room = |b: usize| b + b / 4 + 2;
        kl <= room(self.kl) && ku <= room(self.ku)
    }
}

/// Sub- and superdiagonals (kl, ku) of the matrix `triplets` renumbered by `new`.
fn band(new: &[usize], triplets: &[(usize, usize, f64)]) -> (usize, usize) {
    let (mut kl, mut ku) = (0, 0);
    for &(r, c, _) in triplets {
        let (r, c) = (new[r], new[c]);
        kl = kl.max(r.saturating_sub(c));
        ku = ku.max(c.saturating_sub(r));
    }
    (kl, ku)
}

/// The symmetric adjacency of a matrix pattern, without the diagonal, compressed by row.
struct Graph {
    ptr: Vec<usize>,
    adj: Vec<usize>,
}

impl Graph {
    fn of(n: usize, triplets: &[(usize, usize, f64)]) -> Self {
        let mut ptr = vec![0; n + 1];
        for &(r, c, _) in triplets.iter().filter(|t| t.0 != t.1) {
            ptr[r + 1] += 1;
            ptr[c + 1] += 1;
        }
        for i in 0..n {
            ptr[i + 1] += ptr[i];
        }
        let mut fill = ptr.clone();
        let mut adj = vec![0; ptr[n]];
        for &(r, c, _) in triplets.iter().filter(|t| t.0 != t.1) {
            adj[fill[r]] = c;
            fill[r] += 1;
            adj[fill[c]] = r;
            fill[c] += 1;
        }
        // Duplicates out, so that degrees count neighbours (stamp of the last row that
        // listed each one).
        let mut seen = vec![usize::MAX; n];
        let mut kept = 0;
        let mut start = 0;
        for i in 0..n {
            let end = ptr[i + 1];
            for k in start..end {
                let j = adj[k];
                if seen[j] != i {
                    seen[j] = i;
                    adj[kept] = j;
                    kept += 1;
                }
            }
            start = end;
            ptr[i + 1] = kept;
        }
        adj.truncate(kept);
        Self { ptr, adj }
    }

    fn n(&self) -> usize {
        self.ptr.len() - 1
    }

    fn degree(&self, i: usize) -> usize {
        self.ptr[i + 1] - self.ptr[i]
    }

    fn neighbours(&self, i: usize) -> &[usize] {
        &self.adj[self.ptr[i]..self.ptr[i + 1]]
    }

    /// Cuthill–McKee from a pseudo-peripheral vertex of each connected component
    /// (neighbours by increasing degree), reversed.
    fn reverse_cuthill_mckee(&self) -> Vec<usize> {
        let n = self.n();
        let mut order = Vec::with_capacity(n);
        let mut placed = vec![false; n];
        let mut bfs = Bfs {
            queue: Vec::new(),
            level: vec![usize::MAX; n],
        };
        for v in 0..n {
            if placed[v] {
                continue;
            }
            let start = self.peripheral(v, &mut bfs);
            let first = order.len();
            order.push(start);
            placed[start] = true;
            let mut head = first;
            while head < order.len() {
                let u = order[head];
                head += 1;
                let from = order.len();
                for &w in self.neighbours(u) {
                    if !placed[w] {
                        placed[w] = true;
                        order.push(w);
                    }
                }
                order[from..].sort_by_key(|&w| self.degree(w));
            }
        }
        order.reverse();
        order
    }

    /// A vertex of `v`'s component far from the others (George & Liu): breadth-first
    /// from `v`, then from a least-degree vertex of the last level, while that deepens.
    fn peripheral(&self, v: usize, bfs: &mut Bfs) -> usize {
        let (mut root, mut depth) = (v, self.levels(v, bfs));
        loop {
            let last = &bfs.queue[depth.1..];
            let far = *last
                .iter()
                .min_by_key(|&&w| self.degree(w))
                .expect("the last level holds a vertex");
            let next = self.levels(far, bfs);
            if next.0 <= depth.0 {
                return root;
            }
            (root, depth) = (far, next);
        }
    }

    /// Breadth-first from `root` into `bfs.queue`: (number of levels, start of the last).
    fn levels(&self, root: usize, bfs: &mut Bfs) -> (usize, usize) {
        let Bfs { queue, level } = bfs;
        // Only the last search's vertices are marked: unmarking them keeps the cost of
        // a search that of its component (a matrix of many small components would
        // otherwise cost n per component).
        for &w in queue.iter() {
            level[w] = usize::MAX;
        }
        queue.clear();
        queue.push(root);
        level[root] = 0;
        let (mut head, mut last_start, mut depth) = (0, 0, 0);
        while head < queue.len() {
            let u = queue[head];
            head += 1;
            for &w in self.neighbours(u) {
                if level[w] == usize::MAX {
                    level[w] = level[u] + 1;
                    if level[w] > depth {
                        depth = level[w];
                        last_start = queue.len();
                    }
                    queue.push(w);
                }
            }
        }
        (depth + 1, last_start)
    }
}

/// A breadth-first search's queue (the vertices it reached, level by level) and their
/// levels (`usize::MAX`: not reached).
struct Bfs {
    queue: Vec<usize>,
    level: Vec<usize>,
}

/// LU factors of a banded matrix with partial pivoting, in LAPACK's band storage: column
/// j holds rows j − kl − ku ..= j + kl (U gains kl superdiagonals from the row
/// interchanges).
///
/// The elimination and the substitutions use each column only within its envelope: a
/// chain's band is mostly zeros, even after fill. On the 1000-block column moving with its
/// base (17 000 unknowns, kl = ku = 30) the envelopes hold 297 k of L's 510 k band entries
/// and 315 k of U's 1.02 M. Factors that serve more than one substitution (simplified
/// updates) are read from their envelopes packed one column after the other (`packed`,
/// 4.9 MB against the band's 12 MB there), since the substitutions stream the factors
/// from memory: over the whole band they took 38 % of that run's time. The entries left
/// out are exact zeros, whose updates `x −= 0 · y` change nothing: the factors and
/// solutions are the same to the bit.
#[derive(Debug, Clone, Default)]
struct BandFactors {
    n: usize,
    kl: usize,
    ku: usize,
    ab: Vec<f64>,
    /// Row interchanged with row j at step j.
    pivot: Vec<usize>,
    /// Scratch of the elimination, which `spans` are made from: per column j, the
    /// multipliers of L in rows j + 1 ..= j + lower[j] and the entries of U above the
    /// diagonal in rows j − upper[j] .. j; outside, the band is zero.
    lower: Vec<usize>,
    upper: Vec<usize>,
    /// The columns within their envelopes (`BandFactors::pack`); empty until packed.
    packed: Vec<f64>,
    /// Per column j, `[first, pivot, end]`: its entries of U above the pivot are at
    /// `first..pivot` of `ab` (of `packed` once packed), its multipliers at `pivot + 1..end`.
    spans: Vec<[usize; 3]>,
}

impl BandFactors {
    fn ld(&self) -> usize {
        2 * self.kl + self.ku + 1
    }

    /// Position of entry (i, j) in `ab`, for j − kl − ku ≤ i ≤ j + kl.
    fn at(&self, i: usize, j: usize) -> usize {
        j * self.ld() + self.kl + self.ku + i - j
    }

    /// The matrix `triplets` renumbered by `new`, in a band (kl, ku) that holds it.
    fn assemble(
        &mut self,
        n: usize,
        (kl, ku): (usize, usize),
        new: &[usize],
        t: &[(usize, usize, f64)],
    ) {
        (self.n, self.kl, self.ku) = (n, kl, ku);
        self.ab.clear();
        self.ab.resize(n * self.ld(), 0.0);
        for &(r, c, v) in t {
            let k = self.at(new[r], new[c]);
            self.ab[k] += v;
        }
    }

    /// Gaussian elimination with partial pivoting (`dgbtf2`); an error at a zero or
    /// non-finite pivot.
    fn factor(&mut self) -> Result<(), LinalgError> {
        let (n, kl, ku, ld) = (self.n, self.kl, self.ku, self.ld());
        self.pivot.clear();
        self.lower.clear();
        // Column c's first nonzero entry of U above the pivot is in row c − upper[c]: 0
        // until the elimination meets one. Rows of U are made in order, so the first
        // met is the highest.
        self.upper.clear();
        self.upper.resize(n, 0);
        // The last column that the interchanges so far reach.
        let mut ju = 0;
        for j in 0..n {
            let km = kl.min(n - 1 - j);
            let d = self.at(j, j);
            let jp = argmax_abs(&self.ab[d..=d + km]);
            let p = self.ab[d + jp];
            if p == 0.0 || !p.is_finite() {
                return Err(LinalgError("singular matrix (band LU)".into()));
            }
            self.pivot.push(j + jp);
            ju = ju.max((j + ku + jp).min(n - 1));
            if jp != 0 {
                for c in j..=ju {
                    let k = self.at(j, c);
                    self.ab.swap(k, k + jp);
                }
            }
            let (l, rest) = self.ab[d + 1..].split_at_mut(km);
            let inverse = 1.0 / p;
            l.iter_mut().for_each(|x| *x *= inverse);
            // The multipliers up to the last nonzero one (later steps leave them as
            // they are): the rows below it are not updated.
            let len = l.iter().rposition(|&x| x != 0.0).map_or(0, |last| last + 1);
            self.lower.push(len);
            // Row j of U, whose entry in column j + c is at at(j, j + c) = d + c(ld − 1),
            // updates the rows j + 1 ..= j + len below it.
            for c in 1..=ju - j {
                let u0 = c * (ld - 1) - 1;
                let u = rest[u0 - km];
                if u != 0.0 {
                    let upper = &mut self.upper[j + c];
                    if *upper == 0 {
                        *upper = c;
                    }
                    let below = &mut rest[u0 - km + 1..=u0 - km + len];
                    below
                        .iter_mut()
                        .zip(&l[..len])
                        .for_each(|(x, li)| *x -= li * u);
                }
            }
        }
        self.spans.clear();
        for j in 0..n {
            let d = self.at(j, j);
            let span = [d - self.upper[j], d, d + 1 + self.lower[j]];
            self.spans.push(span);
        }
        self.packed.clear();
        Ok(())
    }

    /// Copies each column's envelope into `packed` (unless it holds them already), and
    /// points the spans there.
    fn pack(&mut self) {
        if !self.packed.is_empty() {
            return;
        }
        for span in &mut self.spans {
            let [first, pivot, end] = *span;
            let at = self.packed.len();
            self.packed.extend_from_slice(&self.ab[first..end]);
            *span = [at, at + pivot - first, at + end - first];
        }
    }

    /// Overwrites `y` with the solution of the factored system, reading the columns
    /// from `packed` when they are there.
    fn substitute(&self, y: &mut [f64]) {
        let f = if self.packed.is_empty() {
            &self.ab
        } else {
            &self.packed
        };
        for (j, &[_, pivot, end]) in self.spans.iter().enumerate() {
            y.swap(j, self.pivot[j]);
            let yj = y[j];
            if yj != 0.0 {
                let l = &f[pivot + 1..end];
                y[j + 1..=j + l.len()]
                    .iter_mut()
                    .zip(l)
                    .for_each(|(yi, li)| *yi -= li * yj);
            }
        }
        for (j, &[first, pivot, _]) in self.spans.iter().enumerate().rev() {
            y[j] /= f[pivot];
            let yj = y[j];
            if yj != 0.0 {
                let u = &f[first..pivot];
                y[j - u.len()..j]
                    .iter_mut()
                    .zip(u)
                    .for_each(|(yi, ui)| *yi -= ui * yj);
            }
        }
    }
}

/// Index of the first entry of largest magnitude (0 for NaNs only).
fn argmax_abs(v: &[f64]) -> usize {
    let mut best = 0;
    for (i, x) in v.iter().enumerate().skip(1) {
        if x.abs() > v[best].abs() {
            best = i;
        }
    }
    best
}

/// Banded LU after a reverse Cuthill–McKee ordering kept per matrix size, faer's sparse
/// LU ([`SparseLu`]) for matrices whose band is wider than [`MAX_BAND`] (see the module
/// docs).
#[derive(Debug, Clone)]
pub struct BandLu {
    /// Orderings of recent sizes (most recent last), at most `kept`.
    orderings: Vec<(usize, Ordering)>,
    kept: usize,
    /// Boxed: its buffers would make `LargeLu::Band` much larger than `LargeLu::Sparse`.
    factors: Box<BandFactors>,
    /// Whether `factors` hold the last matrix (in the last ordering).
    factored: bool,
    wide: SparseLu,
    last_wide: bool,
    /// Orderings computed since the solver was made.
    computed: usize,
    y: Vec<f64>,
}

impl BandLu {
    /// A solver that keeps the orderings of the last `sizes` matrix sizes (at least 1),
    /// and `SparseLu::keeping(sizes)` for wide matrices.
    #[must_use]
    pub fn keeping(sizes: usize) -> Self {
        Self {
            orderings: Vec::new(),
            kept: sizes.max(1),
            factors: Box::default(),
            factored: false,
            wide: SparseLu::keeping(sizes),
            last_wide: false,
            computed: 0,
            y: Vec::new(),
        }
    }

    /// How many orderings were computed (each a breadth-first pass over the pattern):
    /// one per matrix size while the patterns stay in their band.
    #[must_use]
    pub fn orderings_computed(&self) -> usize {
        self.computed
    }

    /// Moves the ordering for the matrix `triplets` of size n to the end of the kept
    /// ones and returns the matrix's band in it: the kept ordering of size n when the
    /// matrix fits it, else a new one.
    fn order(&mut self, n: usize, triplets: &[(usize, usize, f64)]) -> (usize, usize) {
        if let Some(i) = self.orderings.iter().position(|(m, _)| *m == n) {
            let kept = self.orderings.remove(i);
            let b = band(&kept.1.new, triplets);
            if kept.1.fits(b) {
                self.orderings.push(kept);
                return b;
            }
        }
        if self.orderings.len() >= self.kept {
            self.orderings.remove(0);
        }
        let fresh = Ordering::of(n, triplets);
        self.computed += 1;
        let b = (fresh.kl, fresh.ku);
        self.orderings.push((n, fresh));
        b
    }

    /// Overwrites `rhs` with the solution from the factors, in the original numbering.
    fn substitute(&mut self, rhs: &mut [f64]) -> Result<(), LinalgError> {
        let new = &self.orderings.last().expect("an ordering per solve").1.new;
        self.y.clear();
        self.y.resize(rhs.len(), 0.0);
        for (&p, &b) in new.iter().zip(rhs.iter()) {
            self.y[p] = b;
        }
        self.factors.substitute(&mut self.y);
        for (x, &p) in rhs.iter_mut().zip(new) {
            *x = self.y[p];
        }
        super::finite(rhs, "band LU")
    }
}

impl Default for BandLu {
    fn default() -> Self {
        Self::keeping(SYMBOLIC_CACHE)
    }
}

impl LinearSolver for BandLu {
    fn solve(
        &mut self,
        n: usize,
        triplets: &[(usize, usize, f64)],
        rhs: &mut [f64],
    ) -> Result<(), LinalgError> {
        self.factored = false;
        self.last_wide = false;
        super::inside(n, triplets)?;
        let (kl, ku) = self.order(n, triplets);
        if kl + ku + 1 > MAX_BAND {
            self.last_wide = true;
            return self.wide.solve(n, triplets, rhs);
        }
        let new = &self.orderings.last().expect("ordered above").1.new;
        self.factors.assemble(n, (kl, ku), new, triplets);
        self.factors.factor()?;
        self.factored = true;
        self.substitute(rhs)
    }

    /// Packs the factors' envelopes on their second use (`BandFactors`): factors that
    /// serve one solve, as most of a kicked column's do, are not copied.
    fn solve_again(&mut self, rhs: &mut [f64]) -> Result<(), LinalgError> {
        if self.last_wide {
            return self.wide.solve_again(rhs);
        }
        if !self.factored {
            return Err(LinalgError("no factorization kept (band LU)".into()));
        }
        self.factors.pack();
        self.substitute(rhs)
    }

    fn name(&self) -> &'static str {
        if self.last_wide {
            self.wide.name()
        } else {
            "band"
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::DenseLu;

    /// A saddle-point chain numbered by kind, as the Newton matrix is: bodies' first
    /// unknowns 0..b, their second b..2b, then the multipliers of the b − 1 joints. A
    /// closed joint's row holds the two bodies' unknowns and a zero diagonal (pivoting
    /// needed); an open joint's row only its own diagonal. `scale` varies the values.
    fn joints(b: usize, open: &[usize], scale: f64) -> (usize, Vec<(usize, usize, f64)>) {
        let n = 3 * b - 1;
        let (y, m) = (b, 2 * b);
        let mut t = Vec::new();
        for i in 0..b {
            t.push((i, i, 4.0 * scale));
            t.push((i, y + i, 1.0));
            t.push((y + i, y + i, 2.0 + 0.1 * i as f64));
            t.push((y + i, i, -scale));
            for (j, s) in [(i.wrapping_sub(1), -1.0), (i, 1.0)] {
                if j < b - 1 {
                    t.push((i, m + j, s));
                }
            }
        }
        for j in 0..b - 1 {
            if open.contains(&j) {
                t.push((m + j, m + j, 1.0));
            } else {
                t.push((m + j, j + 1, scale));
                t.push((m + j, j, -1.0));
                t.push((m + j, y + j, 0.5));
                t.push((m + j, m + j, 0.0));
            }
        }
        (n, t)
    }

    fn agrees_with_dense(solver: &mut BandLu, n: usize, t: &[(usize, usize, f64)]) {
        let b: Vec<f64> = (0..n).map(|i| (i as f64 + 0.5).sin()).collect();
        let (mut x, mut y) = (b.clone(), b.clone());
        solver.solve(n, t, &mut x).unwrap();
        DenseLu::default().solve(n, t, &mut y).unwrap();
        for (xi, yi) in x.iter().zip(&y) {
            assert!((xi - yi).abs() < 1e-12 * (1.0 + yi.abs()), "{xi} vs {yi}");
        }
        let mut again = b.clone();
        solver.solve_again(&mut again).unwrap();
        assert_eq!(again, x);
    }

    #[test]
    fn patterns_of_one_structure_share_an_ordering_and_solve_like_dense_lu() {
        let mut band = BandLu::default();
        // Ordered first for a pattern with open joints: the closed rows that come later
        // bring entries that pattern lacks.
        let cases: [(&[usize], f64); 5] = [
            (&[3, 17], 0.9),
            (&[3], 1.1),
            (&[], 1.0),
            (&[0, 28], 1.3),
            (&[], 0.7),
        ];
        for (open, scale) in cases {
            let (n, t) = joints(30, open, scale);
            agrees_with_dense(&mut band, n, &t);
            assert_eq!(band.name(), "band");
            // A fresh solver, ordered for this pattern alone, gives the same solution.
            let b: Vec<f64> = (0..n).map(|i| (i as f64 + 0.5).sin()).collect();
            let (mut kept, mut fresh) = (b.clone(), b);
            band.solve(n, &t, &mut kept).unwrap();
            BandLu::default().solve(n, &t, &mut fresh).unwrap();
            for (k, f) in kept.iter().zip(&fresh) {
                assert!((k - f).abs() < 1e-13 * (1.0 + f.abs()), "{k} vs {f}");
            }
        }
        // One ordering served every set of the structure, and its band is about one
        // body and one joint, not the kind-by-kind numbering's n/3.
        assert_eq!(band.orderings_computed(), 1);
        let ordering = &band.orderings[0].1;
        assert!(ordering.kl + ordering.ku <= 8, "{ordering:?}");
    }

    /// The factors are zero outside each column's envelope, packed they hold the band's
    /// entries within it, and the substitutions over the envelopes, read from the band or
    /// packed, give the solution of the whole band's to the bit (`BandFactors`). The
    /// oracle substitutes over every band entry, as LAPACK's `dgbtrs` does.
    #[test]
    fn the_envelopes_solve_as_the_whole_band_does() {
        let mut band = BandLu::default();
        // Ordered with every joint closed; the open joints' rows then leave holes.
        let (n, t) = joints(40, &[], 1.0);
        agrees_with_dense(&mut band, n, &t);
        let (n, t) = joints(40, &[5, 6, 20, 38], 1.2);
        let b: Vec<f64> = (0..n).map(|i| (0.3 * i as f64).cos()).collect();
        let mut from_band = b.clone();
        band.solve(n, &t, &mut from_band).unwrap();
        assert!(band.factors.packed.is_empty());
        let mut packed = b.clone();
        band.solve_again(&mut packed).unwrap();
        assert!(!band.factors.packed.is_empty());
        assert_eq!(from_band, packed);
        let f = &band.factors;
        let (kl, kv) = (f.kl, f.kl + f.ku);
        let (mut inside, mut whole) = (0, 0);
        for j in 0..n {
            let d = f.at(j, j);
            let (below, above, lower, upper) =
                (kl.min(n - 1 - j), j.min(kv), f.lower[j], f.upper[j]);
            let [first, pivot, end] = f.spans[j];
            assert_eq!(&f.packed[first..end], &f.ab[d - upper..=d + lower]);
            assert_eq!(pivot, first + upper);
            assert!(f.ab[d + 1 + lower..=d + below].iter().all(|&v| v == 0.0));
            assert!(f.ab[d - above..d - upper].iter().all(|&v| v == 0.0));
            inside += lower + upper;
            whole += below + above;
        }
        assert!(inside < whole, "{inside} of {whole}: no entry left out");
        let new = &band.orderings.last().unwrap().1.new;
        let mut oracle = vec![0.0; n];
        for (&p, &v) in new.iter().zip(&b) {
            oracle[p] = v;
        }
        for j in 0..n {
            oracle.swap(j, f.pivot[j]);
            let d = f.at(j, j);
            for i in 1..=kl.min(n - 1 - j) {
                oracle[j + i] -= f.ab[d + i] * oracle[j];
            }
        }
        for j in (0..n).rev() {
            let d = f.at(j, j);
            oracle[j] /= f.ab[d];
            for i in 1..=j.min(kv) {
                oracle[j - i] -= f.ab[d - i] * oracle[j];
            }
        }
        let oracle: Vec<f64> = new.iter().map(|&p| oracle[p]).collect();
        assert_eq!(packed, oracle);
    }

    #[test]
    fn a_renumbered_matrix_of_a_kept_size_is_ordered_again() {
        let mut band = BandLu::keeping(2);
        let (n, t) = joints(20, &[], 1.0);
        agrees_with_dense(&mut band, n, &t);
        // The same matrix with its unknowns reversed (another pruning of the same size
        // renumbers them): out of the kept band, so it gets its own ordering.
        let reversed: Vec<_> = t
            .iter()
            .map(|&(r, c, v)| (n - 1 - r, n - 1 - c, v))
            .collect();
        agrees_with_dense(&mut band, n, &reversed);
        assert_eq!(band.orderings_computed(), 2);
        // Sizes beyond the two kept evict the oldest.
        for b in [10, 12, 20] {
            let (n, t) = joints(b, &[1], 1.0);
            agrees_with_dense(&mut band, n, &t);
        }
        assert_eq!(band.orderings.len(), 2);
        assert_eq!(band.orderings_computed(), 5);
    }

    #[test]
    fn a_wide_band_goes_to_sparse_lu() {
        // A star: unknown 0 coupled to all others, whatever the order a band of n.
        let n = MAX_BAND + 10;
        let mut t = Vec::new();
        for i in 0..n {
            t.push((i, i, 3.0 + i as f64 * 1e-2));
            if i > 0 {
                t.push((0, i, 0.5));
                t.push((i, 0, -0.25));
            }
        }
        let mut band = BandLu::default();
        agrees_with_dense(&mut band, n, &t);
        assert_eq!(band.name(), "sparse");
        let (n, t) = joints(10, &[], 1.0);
        agrees_with_dense(&mut band, n, &t);
        assert_eq!(band.name(), "band");
    }

    #[test]
    fn singular_and_malformed_matrices_are_errors() {
        let mut band = BandLu::default();
        // Two equal rows.
        let t = vec![
            (0, 0, 1.0),
            (0, 1, 2.0),
            (1, 0, 1.0),
            (1, 1, 2.0),
            (2, 2, 1.0),
        ];
        assert!(band.solve(3, &t, &mut [1.0, 1.0, 1.0]).is_err());
        assert!(band.solve_again(&mut [1.0, 1.0, 1.0]).is_err());
        let err = band.solve(2, &[(0, 0, 1.0), (2, 1, 1.0)], &mut [1.0, 1.0]);
        assert!(err.unwrap_err().0.contains("outside a 2 × 2 matrix"));
    }

    /// Many components (pairs of coupled unknowns and lone ones): each search starts
    /// unmarked, and the order is a permutation with a band of one pair.
    #[test]
    fn components_are_ordered_one_by_one() {
        let n = 1201;
        let mut t = Vec::new();
        for i in 0..n {
            t.push((i, i, 2.0 + (i % 7) as f64));
            if i % 3 == 0 && i + 1 < n {
                t.push((i, i + 1, 1.0));
                t.push((i + 1, i, -1.0));
            }
        }
        let ordering = Ordering::of(n, &t);
        assert!(
            ordering.kl <= 1 && ordering.ku <= 1,
            "{} {}",
            ordering.kl,
            ordering.ku
        );
        let mut seen = ordering.new.clone();
        seen.sort_unstable();
        assert!(seen.iter().enumerate().all(|(i, &p)| i == p));
        agrees_with_dense(&mut BandLu::default(), n, &t);
    }

    #[test]
    fn reverse_cuthill_mckee_orders_a_path_from_one_end() {
        // The path 0 – 4 – 1 – 3 – 2, numbered out of order, and an isolated vertex 5.
        let edges = [(0, 4), (4, 1), (1, 3), (3, 2)];
        let mut t: Vec<_> = edges
            .iter()
            .flat_map(|&(a, b)| [(a, b, 1.0), (b, a, 1.0)])
            .collect();
        t.push((5, 5, 1.0));
        let ordering = Ordering::of(6, &t);
        assert_eq!((ordering.kl, ordering.ku), (1, 1));
        let mut seen = ordering.new.clone();
        seen.sort_unstable();
        assert_eq!(seen, [0, 1, 2, 3, 4, 5]);
    }
}

#[cfg(test)]
mod doc_tests {
    use super::MAX_BAND;

    /// docs/linear-algebra.md and docs/tuning.md give the band limit the solver uses.
    #[test]
    fn the_docs_give_the_band_limit() {
        let docs = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/");
        let algebra = std::fs::read_to_string(format!("{docs}linear-algebra.md")).unwrap();
        assert!(algebra.contains(&format!("`nsga::linalg::MAX_BAND` = {MAX_BAND} diagonals")));
        let tuning = std::fs::read_to_string(format!("{docs}tuning.md")).unwrap();
        assert!(tuning.contains(&format!(
            "| `nsga::linalg::MAX_BAND` | {MAX_BAND} diagonals |"
        )));
    }
}
