//! The exploration's tree, strategies and caps, on a walker whose forks are known: a
//! "motion" x that forks into x + 1 and x + 2 every `period` steps.

use nsga::explore::{explore, BranchEnd, ExploreOptions, Strategy, Walker};
use nsga::{BranchPoint, IndexSets, State, StepError};

#[derive(Debug, Clone)]
struct Doubling {
    state: State,
    period: u64,
    horizon: u64,
    observed: Vec<(usize, u64)>,
    id: usize,
}

impl Doubling {
    fn new(period: u64, horizon: u64) -> Self {
        Self {
            state: State {
                q: vec![0.0],
                ..State::default()
            },
            period,
            horizon,
            observed: Vec::new(),
            id: 0,
        }
    }
}

impl Walker for Doubling {
    type Outcome = (f64, Vec<(usize, u64)>);
    fn begin(&mut self, id: usize) {
        self.id = id;
        self.observed.clear();
    }
    fn step(&mut self) -> Result<Option<BranchPoint>, StepError> {
        let t = self.state.t;
        self.state.k += 1;
        self.state.t = self.state.k as f64;
        if !self.state.k.is_multiple_of(self.period) {
            return Ok(None);
        }
        let at = |dx: f64| {
            let mut s = self.state.clone();
            s.q[0] += dx;
            (IndexSets::empty(0, 0), s)
        };
        let candidates = vec![at(1.0), at(2.0)];
        self.state.q[0] += 1.0; // the chosen candidate
        Ok(Some(BranchPoint {
            t,
            candidates,
            consistent: vec![true; 2],
            tried: 2,
            chosen: 0,
        }))
    }
    fn observe(&mut self) {
        self.observed.push((self.id, self.state.k));
    }
    fn state(&self) -> &State {
        &self.state
    }
    fn done(&self) -> bool {
        self.state.k >= self.horizon
    }
    fn fork(&self, candidate: State) -> Self {
        Self {
            state: candidate,
            ..self.clone()
        }
    }
    fn finish(&mut self, _end: &BranchEnd) -> Self::Outcome {
        (self.state.q[0], std::mem::take(&mut self.observed))
    }
}

fn leaves(options: &ExploreOptions) -> Vec<f64> {
    let tree = explore(Doubling::new(3, 10), options);
    let mut x: Vec<f64> = tree.leaves().map(|b| b.outcome.0).collect();
    x.sort_by(f64::total_cmp);
    x
}

#[test]
fn every_continuation_is_followed_once_and_the_past_is_shared() {
    // Forks at k = 3, 6, 9: 1 + 2 + 4 + 8 = 15 branches, 8 leaves.
    for strategy in [Strategy::Breadth, Strategy::Depth] {
        let options = ExploreOptions {
            strategy,
            ..ExploreOptions::default()
        };
        let tree = explore(Doubling::new(3, 10), &options);
        assert_eq!(tree.branches.len(), 15, "{strategy:?}");
        assert_eq!(tree.leaves().count(), 8);
        // Each leaf holds x = sum of three increments of 1 or 2, all 8 paths distinct.
        let mut x: Vec<f64> = tree.leaves().map(|b| b.outcome.0).collect();
        x.sort_by(f64::total_cmp);
        assert_eq!(x, [3.0, 4.0, 4.0, 4.0, 5.0, 5.0, 5.0, 6.0]);
        for b in &tree.branches {
            // Steps are never taken twice: a branch's states are its own.
            let ks: Vec<u64> = b.outcome.1.iter().map(|&(_, k)| k).collect();
            assert_eq!(ks.first().copied(), Some(b.start.1), "branch {}", b.id);
            assert!(b.outcome.1.iter().all(|&(id, _)| id == b.id));
            match b.end {
                BranchEnd::Forked => {
                    let f = b.followed_fork().expect("a forked branch has its fork");
                    assert_eq!(f.children.len(), 2);
                    assert_eq!(b.end_at.1 + 1, tree.branches[f.children[0]].start.1);
                    assert_eq!(*ks.last().unwrap(), b.end_at.1);
                }
                _ => assert_eq!(b.end_at.1, 10),
            }
        }
    }
}

#[test]
fn breadth_numbers_branches_generation_by_generation() {
    let tree = explore(Doubling::new(3, 10), &ExploreOptions::default());
    let depths: Vec<usize> = tree.branches.iter().map(|b| b.depth).collect();
    assert_eq!(depths, [0, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 3, 3, 3, 3]);
    let depth = explore(
        Doubling::new(3, 10),
        &ExploreOptions {
            strategy: Strategy::Depth,
            ..ExploreOptions::default()
        },
    );
    // Depth first: the first candidate's subtree gets the next ids.
    let depths: Vec<usize> = depth.branches.iter().map(|b| b.depth).collect();
    assert_eq!(depths, [0, 1, 1, 2, 2, 3, 3, 3, 3, 2, 2, 3, 3, 3, 3]);
}

#[test]
fn caps_end_the_run_cleanly_with_what_was_found() {
    // Five branches: the root's fork (3), one more fork (5); then forks are passed.
    let capped = ExploreOptions {
        max_branches: 6,
        ..ExploreOptions::default()
    };
    let tree = explore(Doubling::new(3, 10), &capped);
    assert_eq!(tree.branches.len(), 5);
    assert!(tree.branch_cap_reached && !tree.depth_cap_reached);
    assert!(tree
        .leaves()
        .all(|b| b.end == BranchEnd::Horizon && b.end_at.1 == 10));
    let unfollowed = tree.forks().filter(|(_, f)| !f.followed).count();
    assert!(unfollowed > 0);
    // Depth 1: only the root forks; its two children pass their forks.
    let shallow = ExploreOptions {
        max_depth: 1,
        ..ExploreOptions::default()
    };
    let tree = explore(Doubling::new(3, 10), &shallow);
    assert_eq!(tree.branches.len(), 3);
    assert!(tree.depth_cap_reached);
    assert_eq!(leaves(&shallow), vec![3.0, 4.0]);
    // A wall time of zero stops the root at once.
    let instant = ExploreOptions {
        max_wall: Some(std::time::Duration::ZERO),
        ..ExploreOptions::default()
    };
    let tree = explore(Doubling::new(3, 10), &instant);
    assert_eq!(tree.branches.len(), 1);
    assert_eq!(tree.branches[0].end, BranchEnd::WallTime);
    assert!(tree.wall_cap_reached);
}

#[test]
fn the_tree_does_not_depend_on_the_thread_count() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let tree = explore(Doubling::new(2, 12), &ExploreOptions::default());
            tree.branches
                .iter()
                .map(|b| (b.id, b.parent, b.start, b.end_at, b.outcome.0))
                .collect::<Vec<_>>()
        })
    };
    let one = run(1);
    assert_eq!(one.len(), 127);
    assert_eq!(one, run(2));
    assert_eq!(one, run(4));
}
