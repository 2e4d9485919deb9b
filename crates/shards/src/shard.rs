//! Which rows of a sweep one run computes.

use crate::ShardError;
use std::fmt;
use std::ops::Range;
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

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl FromStr for Shard {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let not_k_n = || format!("shard '{s}' is not K/N");
        let (k, n) = s.split_once('/').ok_or_else(not_k_n)?;
        let index: usize = k.trim().parse().map_err(|_| not_k_n())?;
        let count: usize = n.trim().parse().map_err(|_| not_k_n())?;
        if count == 0 || index == 0 || index > count {
            return Err(format!("shard '{s}' needs 1 <= K <= N"));
        }
        Ok(Self { index, count })
    }
}

impl Shard {
    /// The indices of the rows this shard owns among `n`: a contiguous block, so that
    /// the shards' outputs concatenate in input order, and the blocks of shards 1..=N
    /// cover 0..n exactly once.
    #[must_use]
    pub fn range(&self, n: usize) -> Range<usize> {
        // u128: n × count overflows usize only for absurd sweeps, but must not panic.
        let cut = |k: usize| (n as u128 * k as u128 / self.count as u128) as usize;
        cut(self.index - 1)..cut(self.index)
    }

    /// The (global index, value) pairs of `values` this shard owns ([`Self::range`]).
    #[must_use]
    pub fn select<T: Clone>(&self, values: &[T]) -> Vec<(usize, T)> {
        self.range(values.len())
            .map(|i| (i, values[i].clone()))
            .collect()
    }
}

/// The shard a run was asked for: `K/N`, or `auto`, which reads it from the environment
/// of a Slurm job array. An explicit `K/N` always wins over the environment, so that a
/// shard can be rerun by hand inside an allocation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShardChoice {
    /// `--shard K/N`.
    Given(Shard),
    /// `--shard auto`.
    Auto,
}

impl Default for ShardChoice {
    fn default() -> Self {
        Self::Given(Shard::default())
    }
}

impl fmt::Display for ShardChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Given(s) => s.fmt(f),
            Self::Auto => f.write_str("auto"),
        }
    }
}

impl FromStr for ShardChoice {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        if s.trim() == "auto" {
            return Ok(Self::Auto);
        }
        s.parse()
            .map(Self::Given)
            .map_err(|e| format!("{e} (or auto, inside a Slurm job array)"))
    }
}

impl ShardChoice {
    /// The shard to run; `var` looks up an environment variable. `auto` takes task
    /// `SLURM_ARRAY_TASK_ID` of `SLURM_ARRAY_TASK_COUNT`, counted from
    /// `SLURM_ARRAY_TASK_MIN` in steps of `SLURM_ARRAY_TASK_STEP` (so `--array=0-3` and
    /// `--array=1-4` both give shards 1/4..4/4).
    ///
    /// ```
    /// use shards::{Shard, ShardChoice};
    /// let env = |name: &str| match name {
    ///     "SLURM_ARRAY_TASK_ID" => Some("2".to_owned()),
    ///     "SLURM_ARRAY_TASK_COUNT" => Some("4".to_owned()),
    ///     _ => None,
    /// };
    /// assert_eq!(ShardChoice::Auto.resolve(env)?, Shard { index: 3, count: 4 });
    /// # Ok::<(), shards::ShardError>(())
    /// ```
    ///
    /// # Errors
    /// `auto` outside a job array, or a job array whose variables do not name a task.
    pub fn resolve(&self, var: impl Fn(&str) -> Option<String>) -> Result<Shard, ShardError> {
        if let Self::Given(shard) = self {
            return Ok(*shard);
        }
        let number = |name: &str, default: Option<usize>| -> Result<usize, ShardError> {
            match var(name) {
                Some(text) => text.trim().parse().map_err(|_| {
                    ShardError::Shard(format!("--shard auto: {name}='{text}' is not a number"))
                }),
                None => default.ok_or_else(|| {
                    ShardError::Shard(format!(
                        "--shard auto: {name} is not set; auto works inside a Slurm job array \
                         (sbatch --array), otherwise give --shard K/N"
                    ))
                }),
            }
        };
        let id = number("SLURM_ARRAY_TASK_ID", None)?;
        let count = number("SLURM_ARRAY_TASK_COUNT", None)?;
        let min = number("SLURM_ARRAY_TASK_MIN", Some(0))?;
        let step = number("SLURM_ARRAY_TASK_STEP", Some(1))?.max(1);
        let bad = || {
            ShardError::Shard(format!(
                "--shard auto: task {id} is not one of the {count} tasks from {min} in steps \
                 of {step}"
            ))
        };
        let offset = id.checked_sub(min).ok_or_else(bad)?;
        if offset % step != 0 || offset / step >= count {
            return Err(bad());
        }
        Ok(Shard {
            index: offset / step + 1,
            count,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_cover_in_order_exactly_once() {
        for n in [0, 1, 7, 10, 101] {
            for count in 1..=12 {
                let mut all = Vec::new();
                for index in 1..=count {
                    all.extend(Shard { index, count }.range(n));
                }
                assert_eq!(all, (0..n).collect::<Vec<_>>());
            }
        }
        assert!("0/3".parse::<Shard>().is_err());
        assert!("4/3".parse::<Shard>().is_err());
        assert!("x".parse::<Shard>().is_err());
    }

    #[test]
    fn auto_reads_the_job_array_and_given_wins() {
        let env = |id: &'static str, min: Option<&'static str>| {
            move |name: &str| match name {
                "SLURM_ARRAY_TASK_ID" => Some(id.to_owned()),
                "SLURM_ARRAY_TASK_COUNT" => Some("4".to_owned()),
                "SLURM_ARRAY_TASK_MIN" => min.map(str::to_owned),
                _ => None,
            }
        };
        let auto: ShardChoice = "auto".parse().unwrap();
        assert_eq!(auto.resolve(env("0", None)).unwrap().to_string(), "1/4");
        assert_eq!(
            auto.resolve(env("4", Some("1"))).unwrap().to_string(),
            "4/4"
        );
        assert!(auto.resolve(env("4", None)).is_err());
        assert!(auto
            .resolve(|_| None)
            .unwrap_err()
            .to_string()
            .contains("not set"));
        let given: ShardChoice = "2/3".parse().unwrap();
        assert_eq!(given.resolve(env("0", None)).unwrap().to_string(), "2/3");
    }
}
