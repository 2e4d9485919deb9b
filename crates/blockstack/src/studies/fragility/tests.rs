use super::*;

/// A slender block (0.2 × 1.0 m, tan α = 0.2) whose corners stick (μ = 1) on a base
/// playing a record with no baseline correction, a floor, SI units.
const BLOCK: &str = r#"
[base]
width = 2.0
height = 0.2

[base.x]
motion = "record"
record = "replaced.csv"
baseline = "none"

[[blocks]]
width = 0.2
height = 1.0

[contact]
mu = 1.0
e_n = 0.0

[solver]
dt = 0.005
gravity = 9.81

[floor]
"#;

/// A directory of its own for one test.
fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("fragility-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A one-sine acceleration pulse of `peak` g and period `period` s at 100 Hz, then
/// quiet to 1.5 s, as `t,a` CSV.
fn one_sine(peak: f64, period: f64) -> String {
    let mut text = String::from("t,a\n");
    for i in 0..=150 {
        let t = f64::from(i) * 0.01;
        let a = if t < period {
            peak * (2.0 * std::f64::consts::PI * t / period).sin()
        } else {
            0.0
        };
        text.push_str(&format!("{t},{a}\n"));
    }
    text
}

fn study_dir(name: &str) -> PathBuf {
    let dir = temp_dir(name);
    std::fs::write(dir.join("b-pulse.csv"), one_sine(1.2, 0.8)).unwrap();
    std::fs::write(dir.join("a-pulse.csv"), one_sine(1.5, 1.0)).unwrap();
    std::fs::write(dir.join("notes.txt"), "not a record").unwrap();
    dir
}

#[test]
fn records_are_every_at2_and_csv_file_sorted_by_name() {
    let dir = study_dir("list");
    std::fs::write(dir.join("C.at2"), "").unwrap();
    let names: Vec<String> = records_in(&dir)
        .unwrap()
        .into_iter()
        .map(|r| r.name)
        .collect();
    assert_eq!(names, ["C.at2", "a-pulse.csv", "b-pulse.csv"]);
    assert!(records_in(&dir)
        .unwrap()
        .iter()
        .all(|r| r.path.is_absolute()));
    let empty = temp_dir("empty");
    let e = records_in(&empty).unwrap_err().to_string();
    assert!(e.contains("holds no record (*.AT2 or *.csv)"), "{e}");
    // A malformed record stops the study before any run, naming its file and line.
    std::fs::write(empty.join("bad.csv"), "t,a\n0,0\n0.01,x\n").unwrap();
    let records = records_in(&empty).unwrap();
    let e = FragilityStudy::new(BLOCK, records, vec![1.0], Measure::Scale)
        .unwrap_err()
        .to_string();
    assert!(e.contains("bad.csv") && e.contains("line 3"), "{e}");
    for d in [dir, empty] {
        std::fs::remove_dir_all(d).unwrap();
    }
}

#[test]
fn levels_and_scenes_a_study_cannot_play_are_refused_before_any_run() {
    let dir = study_dir("refused");
    let records = || records_in(&dir).unwrap();
    let e = |levels: Vec<f64>, measure| {
        FragilityStudy::new(BLOCK, records(), levels, measure)
            .unwrap_err()
            .to_string()
    };
    assert!(e(vec![], Measure::Scale).contains("no intensity level"));
    assert!(e(vec![0.0], Measure::Pga).contains("level 0: a target PGA (g)"));
    assert!(e(vec![-1.0], Measure::Scale).contains("level -1: a factor"));
    let shaking = crate::scenes::find("shaking").unwrap().toml;
    let e = FragilityStudy::new(shaking, records(), vec![1.0], Measure::Scale)
        .unwrap_err()
        .to_string();
    assert!(e.contains("give [solver] dt"), "{e}");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_weak_motion_leaves_the_block_standing_and_a_strong_one_overturns_it() {
    let dir = study_dir("runs");
    let study = FragilityStudy::new(
        BLOCK,
        records_in(&dir).unwrap(),
        vec![0.1, 1.0],
        Measure::Scale,
    )
    .unwrap()
    .ending_at(Some(4.0));
    let points = study.points();
    let order: Vec<(usize, f64)> = points.iter().map(|p| (p.record, p.level)).collect();
    assert_eq!(order, [(0, 0.1), (0, 1.0), (1, 0.1), (1, 1.0)]);
    let rows: Vec<FragilityRow> = points
        .iter()
        .map(|&p| study.row(p, &RunOptions::default()))
        .collect();
    for r in &rows {
        assert!(r.error.is_none(), "{r}");
        assert_eq!(r.t_final.map(|t| (t - 4.0).abs() < 0.01), Some(true), "{r}");
    }
    // 0.15 g and 0.12 g are below g tan α = 0.2 g: the block does not even rock.
    for weak in [&rows[0], &rows[2]] {
        assert_eq!(
            (weak.overturned, weak.failed),
            (Some(false), Some(false)),
            "{weak}"
        );
    }
    for strong in [&rows[1], &rows[3]] {
        assert_eq!(
            (strong.overturned, strong.failed),
            (Some(true), Some(true)),
            "{strong}"
        );
        assert!(strong.failure_time.is_some_and(|t| t < 4.0));
    }
    // PGA of the scaled record; PGV of a one-sine pulse A sin(2πt/T): A T / π.
    assert!((rows[1].pga_g.unwrap() - 1.5).abs() < 1e-12);
    let pgv = 1.5 * 9.81 * 1.0 / std::f64::consts::PI;
    assert!(
        (rows[1].pgv.unwrap() / pgv - 1.0).abs() < 1e-3,
        "{}",
        rows[1]
    );
    assert!((rows[0].pgv.unwrap() / (0.1 * pgv) - 1.0).abs() < 1e-3);
    // Two levels that separate the outcomes: no curve, and the fit says why.
    let curves = fit_curves(&rows);
    assert_eq!(curves.len(), 4);
    for c in &curves {
        assert!(matches!(c.fit, Err(Degenerate::Separated { .. })), "{c:?}");
        assert_eq!(c.left_out, 0);
    }
    let points = curve_points(&rows, &curves);
    let levels: Vec<&CurvePoint> = points.iter().filter(|p| p.kind == "level").collect();
    assert_eq!(levels.len(), 8);
    assert_eq!(
        (levels[0].p, levels[1].p, levels[1].runs),
        (0.0, 1.0, Some(2))
    );
    let cells = rows[1].csv_cells();
    assert_eq!(cells.len(), FragilityRow::CSV_HEADER.len());
    assert_eq!(&cells[..2], ["a-pulse.csv", "1.0"]);
    assert_eq!(&cells[4..6], ["1", "1"]);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn target_pga_levels_scale_every_record_to_the_same_peak() {
    let dir = study_dir("pga");
    let study = FragilityStudy::new(BLOCK, records_in(&dir).unwrap(), vec![0.05], Measure::Pga)
        .unwrap()
        .ending_at(Some(0.1));
    for p in study.points() {
        let row = study.row(p, &RunOptions::default());
        assert!((row.pga_g.unwrap() - 0.05).abs() < 1e-12, "{row}");
    }
    std::fs::remove_dir_all(dir).unwrap();
}
