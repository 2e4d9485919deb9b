//! `rollstack cylinder support`: the steady support at one inclination
//! ([`cylinders::studies::support`]).

use crate::output::print_json;
use anyhow::Result;
use clap::Args;
use cylinders::studies::support::support_report;
use input::text::Angle;

/// Arguments of `rollstack cylinder support`.
#[derive(Debug, Args)]
pub struct SupportArgs {
    /// Inclination ϑ of the axis to the vertical, in (0, π/2), rad (`30deg` accepted).
    #[arg(long, allow_hyphen_values = true)]
    pub theta: Angle,
    /// Aspect ratio r/h (radius over height, dimensionless, ≥ 0).
    #[arg(long, default_value_t = 0.1, allow_hyphen_values = true)]
    pub r_over_h: f64,
    /// Static friction coefficient μ between cylinder and plane (dimensionless, ≥ 0).
    #[arg(long, default_value_t = 0.2, allow_hyphen_values = true)]
    pub mu: f64,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

pub(super) fn run(a: &SupportArgs) -> Result<()> {
    let rep = support_report(a.theta.0, a.r_over_h, a.mu)?;
    if a.json {
        return print_json(&rep);
    }
    let show = |v: Option<f64>| v.map_or_else(|| "none".to_owned(), |v| format!("{v:.6}"));
    println!(
        "Steady support at ϑ = {:.4}° (r/h = {}, μ = {})",
        a.theta.0.to_degrees(),
        a.r_over_h,
        a.mu
    );
    println!(
        "  N/mg  F_f = +μN e′2 (3.3.8)+: {}",
        show(rep.n_over_mg_plus)
    );
    println!(
        "  N/mg  smooth plane (3.3.10):  {}",
        show(rep.n_over_mg_smooth)
    );
    println!(
        "  N/mg  F_f = −μN e′2 (3.3.8)−: {}",
        show(rep.n_over_mg_minus)
    );
    println!(
        "  feasible inclinations (3.3.9)+: ({:.4}°, {:.4}°)",
        rep.theta_range[0].to_degrees(),
        rep.theta_range[1].to_degrees()
    );
    match &rep.min_force {
        Some(m) => println!(
            "  minimum force {}: F3/mg = {:.6}, F/mg = {:.6}, ‖F_a‖/mg = {:.6}",
            m.equation, m.f3_over_mg, m.f_over_mg, m.norm_over_mg
        ),
        None => println!("  no admissible applied force at this inclination"),
    }
    println!(
        "  closed forms vs balance laws (3.3.3): {:.1e}",
        rep.balance_law_error
    );
    Ok(())
}
