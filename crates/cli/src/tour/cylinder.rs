//! Tour section: the inclined rolling cylinder of Ch. 3 — support forces (§3.3), the
//! holonomies of Figures 3.10 and 3.12 (§3.4) and the Frobenius ranks (App. D, F).

use super::{Block, Section};
use crate::commands::cylinder::{write_statics, write_trace};
use anyhow::Result;
use cylinders::holonomy::{figure_3_12, CirclePath, Direction, Figure310, PathCase};
use cylinders::studies::frobenius::{
    integrability_report, ConstraintSystem, FrobeniusCase, IntegrabilityReport, PairConfiguration,
};
use cylinders::studies::holonomy::{circle_report, rectangle_report, RollSettings};
use cylinders::studies::support::support_report;
use std::path::Path;

/// The rolled checks of the tour: coarser than the command line's.
const ROLL: RollSettings = RollSettings {
    max_step: 2e-3,
    record_every: 10,
};

fn opt(v: Option<f64>) -> String {
    v.map_or_else(|| "none".to_owned(), |v| format!("{v:.6}"))
}

/// Builds the section.
///
/// # Errors
/// When a computation fails or a file cannot be written.
pub fn section(dir: &Path) -> Result<Section> {
    let mut summary = Vec::new();
    let mut blocks = Vec::new();

    // §3.3 at ϑ = 30°, r/h = 0.1, μ = 0.2 (the parameters of Figures 3.3, 3.7, 3.8).
    let (theta, rho, mu) = (30f64.to_radians(), 0.1, 0.2);
    let s = support_report(theta, rho, mu)?;
    let min = s.min_force.as_ref();
    summary.push(format!(
        "support at ϑ = 30°, r/h = 0.1, μ = 0.2: N/mg = {} (+μN), {} (smooth), {} (−μN); min ‖F_a‖/mg = {} {}; closed forms vs balance laws {:.1e}",
        opt(s.n_over_mg_plus),
        opt(s.n_over_mg_smooth),
        opt(s.n_over_mg_minus),
        opt(min.map(|m| m.norm_over_mg)),
        min.map_or("", |m| m.equation.as_str()),
        s.balance_law_error
    ));
    blocks.push(Block::Text(
        "Steady support (§3.3, corrected per ERRATA 9–11): normal force N/mg = 1 − F3/mg at the two \
         friction limits (3.3.8) and on a smooth plane (3.3.10), and the smallest applied force \
         (3.3.15)–(3.3.19). The closed forms agree with a numerical (QR) solution of the balance laws \
         (3.3.3) to the error shown."
            .into(),
    ));
    blocks.push(Block::Table {
        header: ["quantity", "value"].map(str::to_owned).to_vec(),
        rows: vec![
            vec!["N/mg, F_f = +μN e′2 (3.3.8)+".into(), opt(s.n_over_mg_plus)],
            vec!["N/mg, smooth (3.3.10)".into(), opt(s.n_over_mg_smooth)],
            vec![
                "N/mg, F_f = −μN e′2 (3.3.8)−".into(),
                opt(s.n_over_mg_minus),
            ],
            vec!["min F3/mg".into(), opt(min.map(|m| m.f3_over_mg))],
            vec!["min F/mg".into(), opt(min.map(|m| m.f_over_mg))],
            vec!["min ‖F_a‖/mg".into(), opt(min.map(|m| m.norm_over_mg))],
            vec![
                "case".into(),
                min.map_or("none".into(), |m| m.equation.clone()),
            ],
            vec![
                "ϑ of point D = arctan(2r/h) [deg]".into(),
                format!("{:.4}", s.self_balancing_theta.to_degrees()),
            ],
            vec![
                "common point (3.3.11) (ϑ deg, N/mg)".into(),
                s.common_point.map_or("none".into(), |c| {
                    format!("({:.4}, {:.6})", c[0].to_degrees(), c[1])
                }),
            ],
            vec![
                "closed form vs balance laws".into(),
                format!("{:.1e}", s.balance_law_error),
            ],
        ],
    });
    write_statics(dir, rho, mu, 361)?;
    for (file, caption) in [
        (
            "fig3_3.png",
            "Figure 3.3: feasible (ϑ, N/mg) between the friction limits, r/h = 0.1, μ = 0.2",
        ),
        (
            "fig3_4.png",
            "Figure 3.4: μ = 0.2, r/h = 0, 0.05, 0.1, 0.15; the (+) curves meet at (3.3.11)",
        ),
        ("fig3_5.png", "Figure 3.5: r/h = 0.1, μ = 0 … 0.6"),
        (
            "fig3_7.png",
            "Figure 3.7: the unconstrained minimum traces the circle with diameter BC (3.3.20)",
        ),
        (
            "fig3_8.png",
            "Figure 3.8: minimum applied force vs ϑ; zero at D = arctan(2r/h)",
        ),
    ] {
        blocks.push(Block::image(file, caption));
    }
    blocks.push(Block::data(
        "fig3_7_fig3_8.csv",
        "minimum force vs ϑ, with its case",
    ));

    // §3.4: Figures 3.10 and 3.12 (radians, ERRATA 8).
    let mut rows = Vec::new();
    let mut images = Vec::new();
    for case in [PathCase::I, PathCase::II] {
        let fig = Figure310::new(case);
        let (rep, trace) = rectangle_report(&fig.cylinder, fig.theta, &fig.path, 0.0, ROLL)?;
        let name = format!("fig3_10_case_{}", case.name());
        write_trace(
            dir,
            &name,
            &trace,
            &format!("Fig. 3.10 ({}): Δφ = {:.4} rad", case.name(), rep.delta_phi),
        )?;
        rows.push(vec![
            format!("Fig. 3.10 rectangle, Case {}", case.name()),
            format!("{:.6}", rep.delta_phi),
            format!("{:.6}", rep.rolling_delta_phi),
            format!("{:.1e}", rep.product_error),
        ]);
        images.push(Block::image(
            format!("{name}.png"),
            format!(
                "Figure 3.10, Case {}: traces of P (i) and of a rim point X (ii)",
                case.name()
            ),
        ));
    }
    let (cyl, theta12, ell) = figure_3_12();
    for case in [PathCase::I, PathCase::II] {
        let path = CirclePath::new(ell, case, Direction::CounterClockwise)?;
        let (hol, trace) = circle_report(&cyl, theta12, &path, ROLL)?;
        let name = format!("fig3_12_case_{}", case.name());
        write_trace(
            dir,
            &name,
            &trace,
            &format!(
                "Fig. 3.12 ({}): ℓ = {ell:.5} r, k = {:.4} r",
                case.name(),
                hol.k
            ),
        )?;
        rows.push(vec![
            format!(
                "Fig. 3.12 circle, Case {} (k = {:.4} r)",
                case.name(),
                hol.k
            ),
            format!("{:.6}", hol.delta_phi),
            format!("{:.6}", hol.rolling_delta_phi),
            "-".into(),
        ]);
        images.push(Block::image(
            format!("{name}.png"),
            format!(
                "Figure 3.12, Case {}: P traces a circle of radius ℓ = {ell:.5} r",
                case.name()
            ),
        ));
    }
    summary.push(format!(
        "holonomy: Fig. 3.10 Δφ = ±{} rad (= 139π/12), Fig. 3.12 Δφ = ±{} rad (ℓ = {ell:.5} r)",
        rows[0][1], rows[2][1]
    ));
    blocks.push(Block::Table {
        header: [
            "path",
            "Δφ closed form [rad]",
            "Δφ rolled [rad]",
            "product (3.4.3) error [rad]",
        ]
        .map(str::to_owned)
        .to_vec(),
        rows,
    });
    blocks.extend(images);

    // App. D, F: Frobenius ranks (ERRATA 13), the gas cylinder at ϑ = 0.4.
    let mut rows = Vec::new();
    let mut ranks = Vec::new();
    let mut push = |name: &str, r: &IntegrabilityReport| {
        ranks.push(format!("{name} {}", r.rank));
        rows.push(vec![
            name.to_owned(),
            r.rank.to_string(),
            r.nullity.to_string(),
            format!("{:.3e}", r.smallest_nonzero_singular_value()),
            r.integrable
                .iter()
                .enumerate()
                .filter(|(_, b)| **b)
                .map(|(i, _)| format!("Π{}", i + 1))
                .collect::<Vec<_>>()
                .join(" "),
            r.system_integrable.to_string(),
        ]);
    };
    let single = integrability_report(&FrobeniusCase::default())?;
    push("single (6 coords, 3 constraints)", &single);
    for (cfg, configuration) in [
        ("touching", PairConfiguration::Touching),
        ("generic", PairConfiguration::Generic),
    ] {
        for (label, system) in [
            ("pair7", ConstraintSystem::Pair7),
            ("pair9", ConstraintSystem::Pair9),
        ] {
            let r = integrability_report(&FrobeniusCase {
                system,
                configuration,
                ..FrobeniusCase::default()
            })?;
            push(&format!("{label} ({cfg})"), &r);
        }
    }
    summary.push(format!(
        "Frobenius ranks: {} (the nine pair constraints have rank 9, ERRATA 13)",
        ranks.join(", ")
    ));
    blocks.push(Block::Text(
        "Frobenius test (App. D, F) with exact derivatives (forward-mode dual numbers) and an SVD null \
         space. Single cylinder: only Π3 is integrable (D.2.4). Pair: W of the nine rolling constraints \
         has rank 9, not the 8 claimed in (F.2.5) (ERRATA 13); with seven constraints the normal \
         constraint Π7 is the rate of the gap g_N3 and so integrable."
            .into(),
    ));
    blocks.push(Block::Table {
        header: [
            "system",
            "rank",
            "nullity",
            "σ_min (non-zero)",
            "integrable constraints",
            "system integrable",
        ]
        .map(str::to_owned)
        .to_vec(),
        rows,
    });
    Ok(Section {
        title: "Inclined rolling cylinders (Ch. 3, App. D–F)".into(),
        summary,
        blocks,
    })
}
