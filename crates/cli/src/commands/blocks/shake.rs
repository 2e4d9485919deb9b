//! `rollstack blocks shake`: a column shaken at its base (§4.4), built by
//! `blockstack::scenarios::shaking_column` from the flags and run like a scene, with the
//! outputs of `blocks run`.

use super::converge::ConvergenceArgs;
use super::simulate::{finish_command, print_warnings, simulate_with_output, with_convergence};
use super::units::{omega_of_hz, UnitArgs};
use super::{OutputArgs, SolverArgs};
use anyhow::Result;
use blockstack::scenarios::{shaking_column_in, Shaking};
use clap::Args;
use input::text::{parse_finite, parse_value};

/// Arguments of `rollstack blocks shake`.
#[derive(Debug, Args)]
pub struct ShakeArgs {
    /// Number of free blocks (--width × --height, m = 1) in the column (≥ 1).
    #[arg(long, default_value_t = 4, allow_hyphen_values = true)]
    pub blocks: usize,
    /// Angular frequency ω of the base, x = A sin(ωt) (rad per time unit, > 0; `2pi`
    /// accepted).
    #[arg(long, default_value_t = 4.0, value_parser = parse_value, allow_hyphen_values = true)]
    pub omega: f64,
    /// Frequency f of the base in cycles per time unit (Hz with lengths in metres and
    /// --gravity 9.81), instead of --omega: ω = 2πf.
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true, conflicts_with = "omega")]
    pub hz: Option<f64>,
    /// Amplitude A of the base motion (length units).
    #[arg(long, default_value_t = 0.2, value_parser = parse_finite, allow_hyphen_values = true)]
    pub amplitude: f64,
    /// Friction coefficient μ at every contact (dimensionless, ≥ 0).
    #[arg(long, default_value_t = 0.2, value_parser = parse_finite, allow_hyphen_values = true)]
    pub mu: f64,
    /// Steps per base period N: Δt = 2π/(Nω) (Figure 4.6: 100).
    #[arg(long, default_value_t = 100.0, value_parser = parse_finite, allow_hyphen_values = true)]
    pub steps_per_period: f64,
    /// Base periods simulated: t_end = P·2π/ω.
    #[arg(long, default_value_t = 10.0, value_parser = parse_finite, allow_hyphen_values = true)]
    pub periods: f64,
    /// The blocks start moving with the base (velocity Aω), not at rest: no sliding
    /// at t = 0, so the column is loaded only by the base's acceleration.
    #[arg(long)]
    pub start_with_base: bool,
    /// End time (model time units), instead of --periods.
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true, conflicts_with = "periods")]
    pub t_end: Option<f64>,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub units: UnitArgs,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub solver: SolverArgs,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub output: OutputArgs,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub convergence: ConvergenceArgs,
}

/// Refuses a base frequency whose time step 2π/(Nω) or span cannot be stepped (infinite,
/// or zero), naming the flags that make them in the units typed: the scenario names only
/// its "dt". `frequency` is the frequency as typed (`--omega 4`); `span` is the flag and
/// value of a span given in time units (`--t-end`, `--t-max`), else the span is
/// P·2π/ω. Each message names only the flags its quantity is made of: the step
/// `--steps-per-period`, the span `--periods` or the span's own flag.
///
/// # Errors
/// A time step or span that is not a positive finite number.
pub(super) fn check_stepping(
    p: &Shaking,
    frequency: &str,
    span: Option<(&str, f64)>,
) -> Result<()> {
    if let Some((flag, t)) = span {
        anyhow::ensure!(
            t.is_finite() && t > 0.0,
            "{flag} {} cannot be stepped: it must be a positive finite time",
            input::Short(t)
        );
    }
    let dt = p.period() / p.steps_per_period;
    anyhow::ensure!(
        dt.is_finite() && dt > 0.0,
        "{frequency} with --steps-per-period {} gives a time step 2π/(Nω) of {}, which \
         cannot be stepped",
        input::Short(p.steps_per_period),
        input::Short(dt)
    );
    // A span given in time units was checked above; P is then derived from it, and a
    // message naming --periods would name a value the user did not type.
    if span.is_none() {
        let span = p.duration();
        anyhow::ensure!(
            span.is_finite() && span > 0.0,
            "{frequency} with --periods {} gives a span P·2π/ω of {}, which cannot be \
             stepped",
            input::Short(p.periods),
            input::Short(span)
        );
    }
    Ok(())
}

/// Runs `rollstack blocks shake`.
///
/// # Errors
/// Bad parameters, a run that could not start or stopped early, or unwritable output.
pub fn run_shake(args: &ShakeArgs) -> Result<()> {
    blockstack::scene::check_block_count("--blocks", args.blocks)?;
    let omega = match args.hz {
        Some(hz) => omega_of_hz(input::positive("--hz", hz)?),
        None => input::positive("--omega", args.omega)?,
    };
    input::non_negative("--mu", args.mu)?;
    // Checked here so that the errors name the flags, not the scenario's "periods".
    input::positive("--periods", args.periods)?;
    input::positive("--steps-per-period", args.steps_per_period)?;
    let units = args.units.units()?;
    let p = Shaking {
        blocks: args.blocks,
        amplitude: args.amplitude,
        omega,
        periods: args.periods,
        steps_per_period: args.steps_per_period,
        mu: args.mu,
        start_with_base: args.start_with_base,
    };
    let frequency = match args.hz {
        Some(hz) => format!("--hz {}", input::Short(hz)),
        None => format!("--omega {}", input::Short(p.omega)),
    };
    check_stepping(&p, &frequency, args.t_end.map(|t| ("--t-end", t)))?;
    let scene = shaking_column_in(&p, &units)?;
    let options = args.solver.run_options(args.t_end, false)?;
    args.solver.check_run(&scene, &options)?;
    let t_end = options.t_end.unwrap_or(scene.solver.t_end);
    let plan = args.output.plan(
        vec![0.0, 0.5 * t_end, t_end],
        format!(
            "shaken column, x = {} sin({} t)",
            args.amplitude,
            input::Short(omega)
        ),
        args.solver.force,
    );
    let inputs = serde_json::json!({
        "blocks": p.blocks, "omega": p.omega, "hz": args.hz, "amplitude": p.amplitude,
        "mu": p.mu, "width": units.width, "height": units.height, "gravity": units.gravity,
        "steps_per_period": p.steps_per_period, "start_with_base": p.start_with_base,
        "periods": args.t_end.is_none().then_some(p.periods), "t_end": t_end,
        "prox_constant": args.solver.prox_constant,
        "explore_branches": args.solver.explore_branches,
        "last_resort": args.solver.last_resort,
        "low_rank_updates": args.solver.low_rank_updates, "snapshots": plan.snapshots,
    });
    print_warnings(&scene);
    let out = simulate_with_output(&scene, &options, &plan, "blocks shake", &inputs)?;
    let out = with_convergence(out, &args.convergence, &scene, &options, args.solver.force)?;
    finish_command(&out, args.output.json, plan.dir.as_deref())
}
