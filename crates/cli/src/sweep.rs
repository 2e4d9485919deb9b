//! Parameter sweeps: `A:B:STEP` ranges, `--shard K/N`, and an order-preserving
//! parallel map on rayon with a progress bar (docs/architecture.md, Conventions).

use anyhow::{bail, Result};
use rayon::prelude::*;
use std::str::FromStr;

/// Parses `A:B:STEP` into the values A, A+STEP, … up to B inclusive (within 1e-9 of a
/// step), or a single number into one value.
///
/// # Errors
/// Non-finite values, a step of the wrong sign or zero, or more than ten million points.
pub fn parse_range(text: &str) -> Result<Vec<f64>> {
    let parts: Vec<&str> = text.split(':').collect();
    let num = |s: &str| -> Result<f64> {
        let v: f64 = s.trim().parse().map_err(|_| {
            anyhow::anyhow!("cannot read '{s}' in range '{text}' (expected A:B:STEP)")
        })?;
        if !v.is_finite() {
            bail!("range '{text}' has a non-finite value");
        }
        Ok(v)
    };
    match parts.as_slice() {
        [a] => Ok(vec![num(a)?]),
        [a, b, step] => {
            let (a, b, step) = (num(a)?, num(b)?, num(step)?);
            if step == 0.0 || (b - a) * step < 0.0 {
                bail!("range '{text}': STEP must be non-zero and point from A to B");
            }
            let n = ((b - a) / step + 1e-9).floor();
            if n > 1e7 {
                bail!("range '{text}' has more than ten million points");
            }
            // n is a checked non-negative count below 1e7, so the cast is exact.
            #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
            let n = n as usize;
            Ok((0..=n).map(|i| a + step * i as f64).collect())
        }
        _ => bail!("cannot read range '{text}' (expected A:B:STEP)"),
    }
}

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
    fn ranges() {
        assert_eq!(parse_range("1:2:0.5").unwrap(), vec![1.0, 1.5, 2.0]);
        assert_eq!(parse_range("3").unwrap(), vec![3.0]);
        assert_eq!(parse_range("0:1:0.1").unwrap().len(), 11);
        assert_eq!(parse_range("2:1:-0.5").unwrap(), vec![2.0, 1.5, 1.0]);
        for bad in ["1:2:0", "1:2:-1", "a:b:c", "1:2", "1:nan:1"] {
            assert!(parse_range(bad).is_err(), "{bad}");
        }
    }

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
