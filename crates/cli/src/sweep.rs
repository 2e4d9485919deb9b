//! Parameter sweeps: the shard a run computes (the `shards` crate) and an
//! order-preserving parallel map on rayon with a progress bar (docs/architecture.md,
//! Conventions).

use rayon::prelude::*;
pub use shards::{Shard, ShardChoice};

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
    fn ordered() {
        let v: Vec<u64> = (0..100).collect();
        assert_eq!(
            par_map_ordered(&v, "t", |x| x * 2),
            v.iter().map(|x| x * 2).collect::<Vec<_>>()
        );
    }
}
