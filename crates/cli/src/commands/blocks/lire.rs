//! `rollstack blocks lire`: the Leaning Tower of Lire (§4.3, Figure 4.4), run like a
//! scene with [`simulate_with_output`].

use super::simulate::{finish_command, print_warnings, simulate_with_output};
use super::{OutputArgs, SolverArgs};
use anyhow::Result;
use blockstack::scenarios::{lire, lire_on_floor, Perturbation};
use clap::{Args, ValueEnum};
use input::text::parse_finite;

/// Which block of the Lire tower is pushed outward by 1 % of its width.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum PerturbArg {
    /// The exact maximum-overhang configuration (an unstable equilibrium).
    None,
    /// The lowest free block: the whole column collapses (Figure 4.4).
    Bottom,
    /// The top block: it topples alone.
    Top,
}

impl From<PerturbArg> for Perturbation {
    fn from(p: PerturbArg) -> Self {
        match p {
            PerturbArg::None => Self::None,
            PerturbArg::Bottom => Self::Bottom,
            PerturbArg::Top => Self::Top,
        }
    }
}

/// Arguments of `rollstack blocks lire`.
#[derive(Debug, Args)]
pub struct LireArgs {
    /// Number of free blocks on the table (the thesis: 4).
    #[arg(long, default_value_t = 4, allow_hyphen_values = true)]
    pub blocks: usize,
    /// Which block is shifted outward by 1 % of its width.
    #[arg(long, value_enum, default_value_t = PerturbArg::None, allow_hyphen_values = true)]
    pub perturb: PerturbArg,
    /// Put a floor at the bottom of the table so that the blocks that fall land (beyond
    /// the thesis, whose blocks fall freely).
    #[arg(long)]
    pub floor: bool,
    /// End time (model time units, g = 1; the thesis: 10).
    #[arg(long, default_value_t = 10.0, value_parser = parse_finite, allow_hyphen_values = true)]
    pub t_end: f64,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub solver: SolverArgs,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub output: OutputArgs,
}

/// Snapshot times of Figure 4.4.
pub const LIRE_SNAPSHOTS: [f64; 3] = [0.0, 5.0, 6.4];

/// Runs `rollstack blocks lire`.
///
/// # Errors
/// Bad options, a run that stopped early, or unwritable output.
pub fn run_lire(args: &LireArgs) -> Result<()> {
    blockstack::scene::check_block_count("--blocks", args.blocks)?;
    let scene = if args.floor {
        lire_on_floor(args.blocks, args.perturb.into())?
    } else {
        lire(args.blocks, args.perturb.into())?
    };
    let options = args.solver.run_options(Some(args.t_end), false)?;
    args.solver.check_run(&scene, &options)?;
    let perturb = args
        .perturb
        .to_possible_value()
        .map_or_else(String::new, |v| v.get_name().to_owned());
    let plan = args.output.plan(
        LIRE_SNAPSHOTS.to_vec(),
        format!("Lire tower, perturbation {perturb}"),
        args.solver.force,
    );
    let inputs = serde_json::json!({
        "blocks": args.blocks,
        "perturb": perturb,
        "floor": args.floor,
        "t_end": args.t_end,
        "prox_constant": args.solver.prox_constant,
        "explore_branches": args.solver.explore_branches,
        "last_resort": args.solver.last_resort,
        "low_rank_updates": args.solver.low_rank_updates,
        "snapshots": plan.snapshots,
    });
    print_warnings(&scene);
    let out = simulate_with_output(&scene, &options, &plan, "blocks lire", &inputs)?;
    finish_command(&out, args.output.json, plan.dir.as_deref())
}
