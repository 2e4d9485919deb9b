//! Parameter sweeps: `--shard K/N` and an order-preserving
//! parallel map on rayon with a progress bar (docs/architecture.md, Conventions).

use rayon::prelude::*;
use std::str::FromStr;

/// One part K of N (1-based) of a sweep, for splitting it across machines.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// This part, 1..=count.
    pub index: usize,
    /// Number of parts.
    pub count: usize,
}

impl Default for Shard {
    fn default() -> Self {
        Self { index: 1, count: 1 }
    }
}

impl FromStr for Shard {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let (k, n) = s
            .split_once('/')
            .ok_or_else(|| format!("shard '{s}' is not K/N"))?;
        let index: usize = k
            .trim()
            .parse()
            .map_err(|_| format!("shard '{s}' is not K/N"))?;
        let count: usize = n
            .trim()
            .parse()
            .map_err(|_| format!("shard '{s}' is not K/N"))?;
        if count == 0 || index == 0 || index > count {
            return Err(format!("shard '{s}' needs 1 <= K <= N"));
        }
        Ok(Self { index, count })
    }
}

impl Shard {
    /// The (global index, value) pairs of `values` this shard owns: a contiguous block,
    /// so the shards' outputs concatenate in input order.
    #[must_use]
    pub fn select<T: Clone>(&self, values: &[T]) -> Vec<(usize, T)> {
        let n = values.len();
        let lo = n * (self.index - 1) / self.count;
        let hi = n * self.index / self.count;
        (lo..hi).map(|i| (i, values[i].clone())).collect()
    }
}

/// Runs `f` on every item in parallel and returns the results in input order, with a
/// progress bar. A failing item does not stop the others.
pub fn par_map_ordered<T, R, F>(items: &[T], message: &str, f: F) -> Vec<R>
where
    T: Sync,
    R: Send,
    F: Fn(&T) -> R + Sync + Send,
{
    let pb = crate::progress::bar(items.len() as u64, message);
    let out: Vec<R> = items
        .par_iter()
        .map(|item| {
            let r = f(item);
            pb.inc(1);
            r
        })
        .collect();
    pb.finish_and_clear();
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_cover_in_order() {
        let v: Vec<usize> = (0..10).collect();
        let mut all = Vec::new();
        for k in 1..=3 {
            let s: Shard = format!("{k}/3").parse().unwrap();
            all.extend(s.select(&v).into_iter().map(|(i, _)| i));
        }
        assert_eq!(all, v);
        assert!("0/3".parse::<Shard>().is_err());
        assert!("4/3".parse::<Shard>().is_err());
    }

    #[test]
    fn ordered() {
        let v: Vec<u64> = (0..100).collect();
        assert_eq!(
            par_map_ordered(&v, "t", |x| x * 2),
            v.iter().map(|x| x * 2).collect::<Vec<_>>()
        );
    }
}
