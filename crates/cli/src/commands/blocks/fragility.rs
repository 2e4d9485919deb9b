//! `rollstack blocks fragility`: a scene under every record of a directory at every
//! intensity level, with the rows and curves of `blockstack::studies::fragility`, run in
//! parallel and written in input order through the plumbing of the sweeps
//! ([`super::sweep`]: shards, resume, row log, merge, Slurm).

use super::sweep::{check_before_any_run, with_solver_inputs, SweepOutputArgs, SweepRun};
use super::sweep_scene::SCENE_COPY;
use super::SolverArgs;
use crate::output::{ensure_dir, write_csv, write_json};
use anyhow::{Context, Result};
use blockstack::studies::fragility::{
    check_levels, curve_points, fit::CONFIDENCE, fit_curves, records_in, Curve, CurvePoint,
    FragilityRow, FragilityStudy, Measure,
};
use clap::{Args, ValueEnum};
use figures::fragility::plot_fragility;
use input::text::{parse_finite, parse_values};
use shards::InputFile;
use std::path::{Path, PathBuf};

/// What the values of `--scales` are.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MeasureArg {
    /// Factors on each record as read (after its baseline correction): 1 is the record.
    Scale,
    /// Target peak ground accelerations in g: every record scaled to each.
    Pga,
}

impl MeasureArg {
    fn measure(self) -> Measure {
        match self {
            Self::Scale => Measure::Scale,
            Self::Pga => Measure::Pga,
        }
    }
}

/// Arguments of `rollstack blocks fragility`.
#[derive(Debug, Args)]
pub struct FragilityArgs {
    /// The scene: a TOML file (keys: docs/scenes.md) or a built-in scene's name; its
    /// base's x motion is replaced by each record, and it needs `solver.dt`.
    pub scene: PathBuf,
    /// Directory of the records: every `*.AT2` (PEER NGA, in g) and `*.csv` (`t,a`
    /// rows, a in g) in it, sorted by name.
    #[arg(long, value_name = "DIR")]
    pub records: PathBuf,
    /// Intensity levels, as A:B:STEP, one value or a comma list: factors on each record
    /// (`--measure scale`) or target PGAs in g (`--measure pga`).
    #[arg(long, value_name = "LEVELS", allow_hyphen_values = true)]
    pub scales: String,
    /// What the values of `--scales` are.
    #[arg(long, value_enum, default_value = "scale")]
    pub measure: MeasureArg,
    /// End time of every run (s in an SI scene) instead of each record's own length.
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true)]
    pub t_end: Option<f64>,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub solver: SolverArgs,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub output: SweepOutputArgs,
}

/// The folder of `--out` that keeps a copy of every record read (`merge` reads it).
pub const RECORDS_COPY: &str = "records";

/// The files a study writes into `--out`.
pub const FILES: [&str; 4] = ["runs.csv", "fragility.csv", "fit.json", "fragility.png"];

/// Runs `rollstack blocks fragility`.
///
/// # Errors
/// An unreadable scene, an empty or unreadable records directory, a malformed record
/// (naming its file and line), bad levels (naming `--scales`), a scene the study
/// cannot play (all before any run); an unwritable output directory. A run the solver
/// stops is the error of its row.
pub fn run(args: &FragilityArgs) -> Result<()> {
    let (text, what) = super::scenes::scene_text(&args.scene)?;
    let measure = args.measure.measure();
    let levels = parse_values(&args.scales).map_err(|e| anyhow::anyhow!("--scales: {e}"))?;
    check_levels(&levels, measure).map_err(|e| anyhow::anyhow!("--scales: {e}"))?;
    if let Some(t) = args.t_end {
        input::positive("--t-end", t)?;
    }
    let dir = std::path::absolute(&args.records)
        .with_context(|| format!("--records {}", args.records.display()))?;
    let records = records_in(&dir).map_err(|e| anyhow::anyhow!("--records: {e}"))?;
    let study = FragilityStudy::new(&text, records, levels, measure)
        .map_err(|e| anyhow::anyhow!("{what}: {e}"))?
        .in_dir(super::scenes::scene_dir(&args.scene))
        .ending_at(args.t_end);
    let options = args.output.watched(args.solver.run_options(None, false)?);
    let inputs = with_solver_inputs(
        serde_json::json!({
            "scales": args.scales,
            "measure": measure.name(),
            "t_end": args.t_end,
        }),
        &args.solver,
    );
    let all = study.points();
    let scene = InputFile {
        copy: SCENE_COPY.into(),
        source: what.clone(),
        bytes: text.as_bytes().to_vec(),
    };
    let mut run = SweepRun::of_command(
        "blocks fragility".into(),
        "fragility",
        &args.output,
        inputs,
        all.len(),
    )?
    .reading("scene", &args.scene.display().to_string(), scene);
    // The records count by their content, as the scene does, and are kept in
    // OUT/records, which `merge` reads.
    let given = args.records.display().to_string();
    for r in study.records() {
        let bytes = std::fs::read(&r.path)
            .with_context(|| format!("--records: cannot read {}", r.path.display()))?;
        let copy = InputFile {
            copy: format!("{RECORDS_COPY}/{}", r.name),
            source: format!("record {}", r.path.display()),
            bytes,
        };
        run = run.reading("records", &given, copy);
    }
    let points = run.run.select(&all);
    check_before_any_run(&points, &args.solver, &args.output, &options, |(_, p)| {
        let name = &study.records()[p.record].name;
        let loaded = study
            .scene(*p)
            .with_context(|| format!("{what} under {name} at {}", input::Short(p.level)))?;
        Ok(loaded.scene)
    })?;
    let rows = run.rows(&points, |p| study.row(*p, &options))?;
    let curves = fit_curves(&rows);
    let mut files = Vec::new();
    if let Some(out) = &args.output.out {
        ensure_dir(out)?;
        // Every run has the scene's Δt and prox; a record changes only the base's motion.
        let title = match points.first() {
            Some((_, p)) => super::figure_numerics(&study.scene(*p)?.scene, &options).under(&what),
            None => what.clone(),
        };
        write_files(out, &rows, &curves, &study, &what, &title)?;
        files.extend(FILES.map(str::to_owned));
        files.push(SCENE_COPY.to_owned());
        files.push(format!("{RECORDS_COPY}/"));
    }
    let files: Vec<&str> = files.iter().map(String::as_str).collect();
    let mut extra = serde_json::Map::new();
    extra.insert("fits".into(), serde_json::to_value(&curves)?);
    extra.insert("notes".into(), serde_json::to_value(notes(&curves))?);
    run.finish(
        &files,
        extra,
        &rows,
        rows.iter().map(|r| r.wall_time_s).sum(),
        ToString::to_string,
    )
}

/// runs.csv, fragility.csv, fit.json and fragility.png in `out`: `what` names the scene,
/// `title` (it and the runs' caption) heads the figure.
fn write_files(
    out: &Path,
    rows: &[FragilityRow],
    curves: &[Curve],
    study: &FragilityStudy,
    what: &str,
    title: &str,
) -> Result<()> {
    write_csv(
        &out.join("runs.csv"),
        &FragilityRow::CSV_HEADER,
        rows.iter().map(FragilityRow::csv_cells),
    )?;
    let points = curve_points(rows, curves);
    write_csv(
        &out.join("fragility.csv"),
        &CurvePoint::CSV_HEADER,
        points.iter().map(CurvePoint::csv_cells),
    )?;
    let records: Vec<&str> = study.records().iter().map(|r| r.name.as_str()).collect();
    write_json(
        &out.join("fit.json"),
        &serde_json::json!({
            "scene": what,
            "measure": study.measure().name(),
            "records": records,
            "confidence": CONFIDENCE,
            "band": "delta method from the observed Fisher information (docs/fragility.md)",
            "curves": curves,
        }),
    )?;
    plot_fragility(&out.join("fragility.png"), curves, &points, title)?;
    Ok(())
}

/// One line per curve: θ and β with their bands, or why no curve fits.
fn notes(curves: &[Curve]) -> Vec<String> {
    curves
        .iter()
        .map(|c| {
            let name = format!("{} against {}", c.outcome.name(), c.intensity.label());
            let left_out = if c.left_out > 0 {
                format!(" ({} runs left out: stopped on an error or at zero intensity)", c.left_out)
            } else {
                String::new()
            };
            match &c.fit {
                Ok(f) => format!(
                    "{name}: theta = {:.4} [{:.4}, {:.4}], beta = {:.3} [{:.3}, {:.3}] ({} of {} runs collapsed){left_out}",
                    f.theta, f.theta_band[0], f.theta_band[1], f.beta, f.beta_band[0],
                    f.beta_band[1], f.collapsed, f.runs
                ),
                Err(d) => format!("{name}: no fit: {d}{left_out}"),
            }
        })
        .collect()
}
