//! The measured constants of the stepper, in one structure ([`Options::tuning`]).
//!
//! Each field is a value that a measurement can change: an iteration budget, a
//! contraction factor, a cycle or stall limit, a threshold. Its doc comment gives the
//! measurement or the argument behind its default. Round-off bounds and algorithmic
//! invariants are not tuning and stay constants where they are used.
//!
//! Any field can be set at run time by name ([`Options::set`], the hidden `--tuning
//! NAME=VALUE` flag of the block and cylinder commands), so that
//! `scripts/reference_workload.py BIN --variant tuning.NAME=VALUE` re-measures its
//! effect on the reference workload with one binary.
//!
//! [`Options::tuning`]: crate::Options::tuning
//! [`Options::set`]: crate::Options::set

/// The measured constants of the stepper (docs/tuning.md, "The constants").
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Tuning {
    /// Residual reduction a simplified Newton update must reach; below it the next
    /// update is exact (see [`crate::LinearOptions::reuse_factorization`]). With the
    /// harness at commit 2eadf80 (`scripts/reference_workload.py
    /// target/release/rollstack --repeat 2 --variant tuning.reuse_contraction=0.15
    /// --variant tuning.reuse_contraction=0.3`, and 0.1 against 0.2), 0.2 takes the
    /// 135-run matrix 267 140 linear solves against 277 555 with 0.1 (−3.8 %, time
    /// 0.961), the Lire collapse 51 against 69, its landing on a floor 668 against 997
    /// and the kicked 30-block column 47 both; 0.15 leaves 2 last-resort steps, 0.3 the
    /// matrix 264 450 (time 0.973) but the landing 727. Over the landing's 100
    /// neighbours (`cargo run --release -p blockstack --example lire_nearby 100 --floor
    /// --tuning tuning.reuse_contraction=V`) 0.1, 0.2, 0.3 take 1069, 1008 and 1015
    /// linear solves per run, and the collapse's neighbours 62, 48 and 42. (Measured
    /// against 367 717 linear solves on the matrix, 0.2 had lost on the landing, 1147
    /// against 567, and 0.1 was kept.)
    pub reuse_contraction: f64,
    /// Simplified Newton updates in a row before an exact one (see
    /// [`crate::LinearOptions::reuse_factorization`]). 4 or 8 on the Lire collapse: none
    /// 3 % better. With the harness (`scripts/reference_workload.py target/release/rollstack --repeat 1 --variant tuning.max_reuses=8`): the 135-run matrix takes
    /// 362 370 linear solves against 367 717 (−1.5 %), the Lire collapse on a floor 1352
    /// against 567.
    pub max_reuses: usize,
    /// Longest period (in Newton iterations) of the set cycles that
    /// [`crate::newton::settled_cycle`] recognizes (from period 2). The landings of the
    /// Lire collapse cycle with periods of 7 to 9 iterations, which with periods only up
    /// to 4 ran on to the iteration limit, and its fork with a period of 12.
    pub longest_cycle: usize,
    /// Periods from which [`crate::newton::settled_cycle`] takes two repetitions as
    /// evidence instead of three: two periods of 6 iterations or more span as many
    /// iterates as three of 4. The fork of the Lire collapse (t = 5.04) cycles with a
    /// period of 12, whose third period ended just at the 40 iterations of blockstack's
    /// first attempts: 8 exact updates and 29 evaluations that repeated the first two
    /// periods (80 linear solves instead of 88). With the harness
    /// (`scripts/reference_workload.py target/release/rollstack --repeat 1 --variant tuning.long_cycle=12`): the matrix 363 135 linear solves against 367 717
    /// (−1.2 %), the floor landing 571 against 567.
    pub long_cycle: usize,
    /// Iterations without progress after which a fixed-set solve is given up
    /// ([`crate::newton::stalled`]). Measured with the harness
    /// (`scripts/reference_workload.py target/release/rollstack --repeat 1 --variant tuning.stall_iterations=2`, then `=6`): the 135-run matrix takes 377 242 and 377 532
    /// linear solves against 369 344 with 3, the Lire collapse 70 and 75 against 71, on a
    /// floor 563 and 574 against 567.
    pub stall_iterations: usize,
    /// The progress the give-up rules ask for: a cycle's last period, or a fixed-set
    /// solve's last [`Tuning::stall_iterations`] residuals, must reach this fraction of
    /// the smallest residual before them, or the attempt is given up. With the harness
    /// (`scripts/reference_workload.py target/release/rollstack --repeat 1 --variant tuning.progress=0.25`): the matrix 362 321 linear solves against 367 717
    /// (−1.5 %), the Lire collapse 69 against 71, on a floor 565 against 567.
    pub progress: f64,
    /// The held-sets attempt releases the held sets when an update reduces their
    /// residual by less than this factor. With the harness
    /// (`scripts/reference_workload.py target/release/rollstack --repeat 1 --variant tuning.held_contraction=0.25`): the matrix 365 193 linear solves against 367 717
    /// (−0.7 %), the other workloads the same.
    pub held_contraction: f64,
    /// Newton iterations allowed when the flip probe checks that a fixed-set solution
    /// also solves the free step (it converges at once when it does; `Stepper::quick_check`).
    /// The probe is off in the reference workload, so the harness cannot measure it: the
    /// check only has to see convergence that starts at once.
    pub quick_check_iterations: usize,
    /// Newton updates allowed from a predicted start before the step is solved again
    /// from the last solution with its full budget. A good prediction converges in one
    /// update; one that needs more is mostly a step where a contact changes state, for
    /// which the extrapolation says nothing. An attempt still converging goes on: while
    /// its updates keep the index sets and contract the residual by
    /// [`Tuning::reuse_contraction`], it may use the step's whole budget
    /// (`NewtonSettings::contracting_extra`). Without that, a prediction followed by
    /// simplified updates on aging factors (contraction 0.02–0.06 per update in the Lire
    /// collapse at t ≈ 5.6) missed the tolerance after two updates by a factor of 1.3
    /// and started again from the last solution, 10⁵ times farther off (docs/method.md
    /// §4). On the at-rest columns of 10 and 30 blocks (`rollstack blocks shake --blocks
    /// 10 --omega 2 --amplitude 0.001 --mu 0.2 --steps-per-period 314 --t-end 1 --json
    /// --force`), whose corners rock, 6 updates cost 113 linear solves against 77
    /// without prediction, 2 updates cost 91; with 1, 95 586 evaluations over 40 Lire
    /// collapses against 78 929. With the harness
    /// (`scripts/reference_workload.py target/release/rollstack --repeat 1 --variant tuning.predicted_start_iterations=4`): the matrix 359 137 linear solves against
    /// 367 717 (−2.3 %), but the floor landing 1269 against 567.
    pub predicted_start_iterations: usize,
    /// The predicted attempt ([`crate::NewtonOptions::predict_start`]) is given up at its
    /// start, without an update, where ‖R‖∞ at the prediction exceeds this: the step
    /// then starts from the last solution, as after any failed prediction. A smooth
    /// step's prediction is off by the extrapolation's truncation error (10⁻¹⁰ to 10⁻⁸
    /// in the matrix's sliding rows); one that exceeds 10⁻⁶ has met a contact event (an
    /// impact, a stick–slip change), which the past solutions do not foresee. There the
    /// prediction is no better a start than the last solution (in the sliding rows the
    /// two first residuals agree to 10⁻³, and the attempt from the last solution retook
    /// the predicted attempt's updates, residual for residual; docs/experiments.md §4),
    /// so its updates and factorizations were spent twice. With the harness
    /// (`scripts/reference_workload.py target/release/rollstack --repeat 3 --variant
    /// tuning.predicted_start_residual=1e300`, the rule off): the matrix 328 683 → 277 555
    /// linear solves (−15.6 %), see docs/method.md §4 for the times and the neighbours.
    pub predicted_start_residual: f64,
    /// Largest ratio of the position correction to the step's motion,
    ///
    /// ‖Q‖ / (Δt(‖u_n‖ + ‖u_{n+1}‖) + Δt²(‖ā_n‖ + ‖ā_{n+1}‖ + ‖M⁻¹h‖)),   ‖v‖ = maxᵢ √Mᵢᵢ |vᵢ|,
    ///
    /// of a solution that is taken. The steps taken in the 135-run shaken-column
    /// matrix, the Lire collapse with and without a floor, the thesis's scenes and the
    /// kicked tall columns stay at or below 1.4, and fixed-set candidates of their branch
    /// points at or below 2.1; the far solutions start at 6.95, and the one that turned
    /// block 25 of a kicked 30-block column by 0.83 rad in one step had 325
    /// (docs/method.md §8.1, "Far solutions"). With the harness
    /// (`scripts/reference_workload.py target/release/rollstack --repeat 1 --variant tuning.far_correction=8`): no count of the workload changes.
    pub far_correction: f64,
    /// Columns of Z = J₀⁻¹ E kept per factorization for the low-rank updates. Measured
    /// with the harness (`scripts/reference_workload.py target/release/rollstack --repeat 1 --variant tuning.kept_columns=16`): no count of the workload changes;
    /// the kept columns save triangular solves. When an update needs more room, the
    /// least recently used make it, and 32 could not hold the rows of the held-sets
    /// attempt's updates ([`Tuning::held_low_rank_rows`]; measured when a full set was
    /// dropped whole):
    /// the kicked 100-block column to t = 1 (`rollstack blocks shake --blocks 100 --omega
    /// 2 --amplitude 0.001 --mu 0.2 --steps-per-period 314 --t-end 1 --json --tuning
    /// tuning.kept_columns=32`) spent 2.9 s in simplified updates against 0.87 s with 128
    /// (3.6 against 1.8 s of solver time, the same 201 linear solves).
    pub kept_columns: usize,
    /// Most rows of the Newton matrix a low-rank update replaces
    /// ([`crate::LinearOptions::low_rank_updates`]); where the sets differ from the kept
    /// factors' in more, the matrix is factorized anew. 5 rows: 506 182 linear solves
    /// over the matrix against 448 027 with 8 (at commit f654c32). With the harness
    /// (`scripts/reference_workload.py target/release/rollstack --repeat 1 --variant
    /// tuning.low_rank_rows=16 --variant tuning.low_rank_rows=32`): 16 rows take the
    /// matrix 303 902 linear solves against 330 444 (−8.0 %, solver time −1.6 %) and the
    /// Lire collapse 45 against 71, but its landing on a floor 715 against 567 and the
    /// kicked 30-block column 114 against 78 (+48 % time); 32 rows the matrix 293 137
    /// (−11 %, time −3.6 %), the floor landing 1271, kicked30 120. The kicked 100-block
    /// column to t = 1 gains (1294, 937, 852 linear solves at 8, 16, 32 rows; 2.5, 2.1,
    /// 2.1 s), but no value pays on the whole workload. A held-sets attempt takes
    /// [`Tuning::held_low_rank_rows`] instead.
    pub low_rank_rows: usize,
    /// Most rows a low-rank update replaces in a held-sets attempt, whose kept factors
    /// follow its sets (docs/method.md §8.2, "The held-sets attempt"). With the harness
    /// (`scripts/reference_workload.py target/release/rollstack --repeat 1 --variant
    /// tuning.held_low_rank_rows=K` for K = 8, 16, 32, 128): the kicked 30-block column 77,
    /// 55, 44 and 35 linear solves against 45 (128 rows: 6 % more time), the matrix
    /// 331 332, 326 702, 328 653 and 328 683 against 328 683. The kicked 100- and 200-block
    /// columns to t = 1 (`rollstack blocks shake --blocks N --omega 2 --amplitude 0.001
    /// --mu 0.2 --steps-per-period 314 --t-end 1 --json --tuning tuning.held_low_rank_rows=K`):
    /// 630 and 1289 linear solves with 16 rows, 312 and 535 with 32, 201 and 394 with 64.
    pub held_low_rank_rows: usize,
    /// Normal sets of the last plain Newton matrices found singular that are
    /// remembered, to go straight to the regularized matrix. When a collapsing column
    /// lands on a floor, Newton moves among a handful of normal sets and dozens of
    /// stick–slip combinations; remembering only the last singular set made it
    /// rediscover each at the cost of a failed plain factorization and a dense LU. Over
    /// the Lire collapse on a floor and 99 neighbours (`cargo run --release -p blockstack
    /// --example lire_nearby 100 --floor`) that took 938 linear solves per run, against
    /// 810 remembering the normal sets of the last 16; 64 and 1024 cost more. With the
    /// harness (`scripts/reference_workload.py target/release/rollstack --repeat 1 --variant tuning.singular_sets_kept=8`): the matrix 366 523 linear solves against
    /// 367 717, the other workloads the same.
    pub singular_sets_kept: usize,
    /// Open contacts are pruned when their gap exceeds this many Δt times their gap
    /// rate (plus Δt² times their gap acceleration): they cannot close within the step,
    /// with a margin of one more step for the rate. With the harness
    /// (`scripts/reference_workload.py target/release/rollstack --repeat 1 --variant tuning.prune_margin=1`): the matrix takes 340 474 linear solves against 367 717
    /// (−7.4 %), but the Lire collapse on a floor 905 against 567 and the kicked 30-block
    /// column 171 against 143.
    pub prune_margin: f64,
}

impl Default for Tuning {
    fn default() -> Self {
        Self {
            reuse_contraction: 0.2,
            max_reuses: 4,
            longest_cycle: 12,
            long_cycle: 6,
            stall_iterations: 3,
            progress: 0.5,
            held_contraction: 0.5,
            quick_check_iterations: 8,
            predicted_start_iterations: 2,
            predicted_start_residual: 1e-6,
            far_correction: 4.0,
            kept_columns: 128,
            low_rank_rows: crate::stepper::LOW_RANK_ROWS,
            held_low_rank_rows: 64,
            singular_sets_kept: 16,
            prune_margin: 2.0,
        }
    }
}

impl Tuning {
    /// The first of the factors and thresholds that is negative or not finite, as a
    /// message naming it; the counts may be any whole number (0 switches a rule off or
    /// makes it give up at once).
    pub(crate) fn check(&self) -> Result<(), String> {
        let factors = [
            ("reuse_contraction", self.reuse_contraction),
            ("progress", self.progress),
            ("held_contraction", self.held_contraction),
            ("far_correction", self.far_correction),
            ("prune_margin", self.prune_margin),
            ("predicted_start_residual", self.predicted_start_residual),
        ];
        match factors.iter().find(|(_, v)| !(v.is_finite() && *v >= 0.0)) {
            Some((name, v)) => Err(format!("tuning.{name} = {v} must be finite and >= 0")),
            None => Ok(()),
        }
    }
}
