//! The columns of Z = J₀⁻¹E that low-rank updates on one factorization share
//! (docs/method.md §7, docs/linear-algebra.md "Low-rank updates for changed index
//! sets"): kept by row, the least recently used making room.

/// The columns J₀⁻¹ e_r of Z kept with the factors, for the reduced rows r they were
/// computed for: they depend on nothing else, so a row that changes again on the same
/// factors costs its substitution once. At most `capacity` are kept; when an update's
/// rows need more room, the columns least recently used by an update go, never one the
/// update uses (docs/method.md §7: dropping them all cost tall columns a tenth of
/// their time).
#[derive(Debug, Clone, Default)]
pub(super) struct ZColumns {
    /// The row of each kept column, and the update that last used it.
    rows: Vec<usize>,
    last_use: Vec<u64>,
    /// The columns, `rows.len()` of them and spare buffers after them.
    cols: Vec<Vec<f64>>,
    /// Updates made since the factors were made.
    updates: u64,
    /// Scratch: the kept columns by last use.
    by_use: Vec<usize>,
}

impl ZColumns {
    /// Forgets the columns (new factors).
    pub(super) fn clear(&mut self) {
        self.rows.clear();
        self.last_use.clear();
    }

    /// Where the column of row `r` is kept.
    pub(super) fn place(&self, r: usize) -> Option<usize> {
        self.rows.iter().position(|&kept| kept == r)
    }

    /// How many columns are kept.
    #[cfg(test)]
    pub(super) fn kept(&self) -> usize {
        self.rows.len()
    }

    /// The column kept at `at`.
    pub(super) fn column(&self, at: usize) -> &[f64] {
        &self.cols[at]
    }

    /// Marks the kept columns of `rows` (one update's) as used now, and drops the least
    /// recently used others until the columns `rows` lacks fit within `capacity`
    /// (at least `rows.len()`).
    pub(super) fn make_room(&mut self, rows: &[usize], capacity: usize) {
        self.updates += 1;
        let mut missing = 0;
        for &r in rows {
            match self.place(r) {
                Some(at) => self.last_use[at] = self.updates,
                None => missing += 1,
            }
        }
        let excess = (self.rows.len() + missing).saturating_sub(capacity);
        if excess == 0 {
            return;
        }
        self.by_use.clear();
        self.by_use.extend(0..self.rows.len());
        self.by_use.sort_by_key(|&at| self.last_use[at]);
        // The oldest `excess` are not this update's: its kept columns were marked now,
        // and there are at most capacity − missing of them. They go from the highest
        // place down, so that the places still to go stay where they are.
        self.by_use.truncate(excess);
        self.by_use.sort_unstable_by(|a, b| b.cmp(a));
        for &at in &self.by_use {
            let last = self.rows.len() - 1;
            self.rows.swap_remove(at);
            self.last_use.swap_remove(at);
            self.cols.swap(at, last);
        }
    }

    /// A buffer for the next column to be kept.
    pub(super) fn spare(&mut self) -> &mut Vec<f64> {
        let at = self.rows.len();
        if self.cols.len() == at {
            self.cols.push(Vec::new());
        }
        &mut self.cols[at]
    }

    /// Keeps the column just computed in [`ZColumns::spare`] as row `r`'s, and returns
    /// its place.
    pub(super) fn push(&mut self, r: usize) -> usize {
        self.rows.push(r);
        self.last_use.push(self.updates);
        self.rows.len() - 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The kept columns go least recently used first, never one the update needs, and
    /// each column stays with its row.
    #[test]
    fn kept_columns_make_room_least_recently_used_first() {
        let mut z = ZColumns::default();
        let update = |z: &mut ZColumns, rows: &[usize]| {
            z.make_room(rows, 3);
            for &r in rows {
                if z.place(r).is_none() {
                    *z.spare() = vec![r as f64];
                    z.push(r);
                }
            }
        };
        update(&mut z, &[1, 2]);
        update(&mut z, &[3]);
        // 1 is used again, so 2 (used before 3) makes room for 4.
        update(&mut z, &[1, 4]);
        assert_eq!(z.place(2), None);
        for r in [1, 3, 4] {
            assert_eq!(z.column(z.place(r).unwrap()), [r as f64], "row {r}");
        }
        // Three new rows: all the others go.
        update(&mut z, &[5, 6, 7]);
        assert_eq!(z.rows.len(), 3);
        for r in [5, 6, 7] {
            assert_eq!(z.column(z.place(r).unwrap()), [r as f64], "row {r}");
        }
        z.clear();
        assert_eq!(z.place(5), None);
    }
}
