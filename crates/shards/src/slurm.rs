//! Slurm batch scripts for a sweep: a job array whose tasks are the shards
//! (`--shard auto`), a merge job that runs once every task succeeded
//! (`--dependency=afterok:`), and a script that submits both.
//!
//! The time and memory a task requests come from a calibration run of one row
//! ([`estimate`]): a request too small gets the task killed, one too large waits longer
//! in the queue, so the estimate is generous but bounded.

use crate::{Manifest, ShardError};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// What a calibration run of a few rows measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Calibration {
    /// Rows of the whole sweep.
    pub total_rows: usize,
    /// Rows the calibration computed.
    pub rows: usize,
    /// Its wall time, s.
    pub seconds: f64,
    /// Its peak resident memory, bytes, where the system says.
    pub peak_memory_bytes: Option<u64>,
}

/// What one job asks the scheduler for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Resources {
    /// `--time`, minutes.
    pub minutes: u64,
    /// `--mem`, MiB.
    pub mem_mib: u64,
}

/// The requests of each of `tasks` tasks of `cpus` cores: three times the measured time
/// per row (rows of one sweep differ, and the calibration ran one of them) for the task's
/// share of the rows, plus a minute to start; twice the peak memory plus 256 MiB (1 GiB
/// when the peak is unknown). The merge job reads rows and draws plots: 10 minutes and the
/// same memory.
#[must_use]
pub fn estimate(c: &Calibration, tasks: usize, cpus: usize) -> Resources {
    let tasks = tasks.max(1);
    let rows_per_task = c.total_rows.div_ceil(tasks) as f64;
    let per_row = c.seconds / c.rows.max(1) as f64;
    let rounds = (rows_per_task / cpus.max(1) as f64).ceil();
    let seconds = 3.0 * per_row * rounds + 60.0;
    let mib = c
        .peak_memory_bytes
        .map_or(1024, |b| 2 * b.div_ceil(1 << 20) + 256);
    Resources {
        minutes: (seconds / 60.0).ceil().max(2.0) as u64,
        mem_mib: mib,
    }
}

/// The peak resident memory of process `pid` so far (Linux: `VmHWM` of
/// `/proc/PID/status`), or `None` elsewhere.
#[must_use]
pub fn peak_memory_of(pid: u32) -> Option<u64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// Runs the last row of the sweep `sweep` alone (`binary SWEEP --shard N/N --out dir`
/// with N ten million, which leaves one row to the last shard of any sweep this size or
/// smaller), timing it and watching its memory, and reads the sweep's size from the
/// manifest it writes. A run whose row failed (status 3) still measured its cost.
///
/// # Errors
/// A run that cannot start or fails otherwise (with its stderr), or no manifest.
pub fn calibrate(binary: &Path, sweep: &[String], dir: &Path) -> Result<Calibration, ShardError> {
    let start = Instant::now();
    let mut child = std::process::Command::new(binary)
        .args(sweep)
        .args(["--shard", "10000000/10000000", "--out"])
        .arg(dir)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .map_err(|e| ShardError::io(binary, e))?;
    let mut peak = None;
    let status = loop {
        peak = peak_memory_of(child.id()).or(peak);
        if let Some(status) = child.try_wait().map_err(|e| ShardError::io(binary, e))? {
            break status;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let seconds = start.elapsed().as_secs_f64();
    if !(status.success() || status.code() == Some(3)) {
        let mut err = String::new();
        if let Some(mut e) = child.stderr.take() {
            let _ = std::io::Read::read_to_string(&mut e, &mut err);
        }
        return Err(ShardError::Shard(format!(
            "the calibration run failed: {}",
            err.trim()
        )));
    }
    let m = Manifest::read(dir)?;
    Ok(Calibration {
        total_rows: m.total_rows,
        rows: m.rows.len(),
        seconds,
        peak_memory_bytes: peak,
    })
}

/// What a user asks `rollstack slurm` for.
#[derive(Debug, Clone)]
pub struct Request {
    /// The sweep's short name (`frequency`), for the job names.
    pub name: String,
    /// Tasks of the job array.
    pub tasks: usize,
    /// Cores per task.
    pub cpus_per_task: usize,
    /// `--time` of each task, minutes, instead of the estimate.
    pub minutes: Option<u64>,
    /// `--mem` of each task and of the merge, MiB, instead of the estimate.
    pub mem_mib: Option<u64>,
    /// `--partition`, if any.
    pub partition: Option<String>,
    /// The sweep's arguments, with its `--out`.
    pub sweep: Vec<String>,
    /// The rollstack binary.
    pub binary: PathBuf,
    /// The directory the jobs run in.
    pub workdir: PathBuf,
}

/// The most tasks of a job array `rollstack slurm` writes (Slurm's own `MaxArraySize`
/// is usually far lower): a bound checked before anything is sized by it.
pub const MAX_TASKS: usize = 100_000;

impl Request {
    /// Checks the counts and requests, and that no value the scripts hold has a control
    /// character (a newline would end an `#SBATCH` line and start a command).
    ///
    /// # Errors
    /// The first bad value, naming its flag.
    pub fn check(&self) -> Result<(), ShardError> {
        let bad = |message: String| Err(ShardError::Shard(message));
        if !(1..=MAX_TASKS).contains(&self.tasks) {
            return bad(format!(
                "--tasks must be between 1 and {MAX_TASKS}, got {} (one shard per task)",
                self.tasks
            ));
        }
        if self.cpus_per_task == 0 {
            return bad("--cpus-per-task must be at least 1".into());
        }
        if self.minutes == Some(0) {
            return bad("--time must be at least 1 minute".into());
        }
        if self.mem_mib == Some(0) {
            return bad("--mem must be at least 1 MiB".into());
        }
        if let Some(p) = &self.partition {
            no_control_character("--partition", p)?;
        }
        for a in &self.sweep {
            no_control_character(&format!("the sweep's argument {a:?}"), a)?;
        }
        no_control_character(
            "the rollstack binary's path",
            &self.binary.to_string_lossy(),
        )?;
        no_control_character("the working directory", &self.workdir.to_string_lossy())
    }
}

/// Refuses `text` (of `what`) when it holds a control character.
fn no_control_character(what: &str, text: &str) -> Result<(), ShardError> {
    match text.chars().find(|c| c.is_control()) {
        Some(c) => Err(ShardError::Shard(format!(
            "{what} holds the control character {c:?}: a batch script has no safe place for it"
        ))),
        None => Ok(()),
    }
}

/// A sweep to run as a job array.
#[derive(Debug, Clone)]
pub struct Job {
    /// The job name (`rollstack-frequency`).
    pub name: String,
    /// Tasks of the array, one shard each.
    pub tasks: usize,
    /// Cores per task (the sweep's threads).
    pub cpus_per_task: usize,
    /// Requests of each task.
    pub task: Resources,
    /// Requests of the merge job.
    pub merge: Resources,
    /// `--partition`, if any.
    pub partition: Option<String>,
    /// The rollstack binary, absolute.
    pub binary: PathBuf,
    /// The directory the jobs run in (relative paths of the sweep are read from there).
    pub workdir: PathBuf,
    /// The sweep's arguments, without `--out` and `--shard`.
    pub sweep: Vec<String>,
    /// Where the merged sweep goes; the shards go to `OUT/shards/task-I`, the scripts
    /// and logs to `OUT/slurm`.
    pub out: PathBuf,
}

impl Job {
    /// The job for `r`: the sweep's `--out` taken out ([`split_out`]) and made absolute,
    /// and, unless both `--time` and `--mem` are given, a calibration run in
    /// `OUT/calibration` ([`calibrate`]) for the [`estimate`].
    ///
    /// # Errors
    /// Bad counts or requests, a value holding a control character, a sweep without
    /// `--out` or with `--shard`, or a failed calibration.
    pub fn plan(r: Request) -> Result<(Self, Option<Calibration>), ShardError> {
        r.check()?;
        let (sweep, out) = split_out(&r.sweep).map_err(ShardError::Shard)?;
        let out = r.workdir.join(out);
        let (calibration, task) = match (r.minutes, r.mem_mib) {
            (Some(minutes), Some(mem_mib)) => (None, Resources { minutes, mem_mib }),
            _ => {
                let c = calibrate(&r.binary, &sweep, &out.join("calibration"))?;
                let e = estimate(&c, r.tasks, r.cpus_per_task);
                let minutes = r.minutes.unwrap_or(e.minutes);
                (
                    Some(c),
                    Resources {
                        minutes,
                        mem_mib: r.mem_mib.unwrap_or(e.mem_mib),
                    },
                )
            }
        };
        let job = Self {
            name: format!("rollstack-{}", r.name),
            tasks: r.tasks,
            cpus_per_task: r.cpus_per_task,
            task,
            merge: Resources {
                minutes: 10,
                mem_mib: task.mem_mib,
            },
            partition: r.partition,
            binary: r.binary,
            workdir: r.workdir,
            sweep,
            out,
        };
        Ok((job, calibration))
    }

    /// What `rollstack slurm` prints once the scripts are written: the calibration, the
    /// requests, and how to submit.
    #[must_use]
    pub fn summary(&self, calibration: Option<&Calibration>, submit: &Path) -> String {
        let mut s = String::new();
        if let Some(c) = calibration {
            let peak = c
                .peak_memory_bytes
                .map_or("unknown".into(), |b| format!("{} MiB", b >> 20));
            let _ = writeln!(
                s,
                "calibration: {} of {} rows in {:.2} s, peak memory {peak}",
                c.rows, c.total_rows, c.seconds
            );
        }
        let _ = writeln!(
            s,
            "each of {} tasks: --time={} --mem={}M, {} rows at most\n\
             wrote shards.sbatch, merge.sbatch and submit.sh into {}\n\
             submit with: bash {}\n\
             the merged sweep will be in {}",
            self.tasks,
            self.task.minutes,
            self.task.mem_mib,
            calibration.map_or("?".into(), |c| c
                .total_rows
                .div_ceil(self.tasks)
                .to_string()),
            self.script_dir().display(),
            shell_quote_path(submit),
            self.out.display()
        );
        s
    }

    /// The output directory of array task `id`.
    #[must_use]
    pub fn task_dir(&self, id: &str) -> PathBuf {
        self.out.join("shards").join(format!("task-{id}"))
    }

    /// The directory of the scripts and the jobs' logs.
    #[must_use]
    pub fn script_dir(&self) -> PathBuf {
        self.out.join("slurm")
    }

    /// The `#SBATCH` lines of a job. sbatch reads their values with the quotes of a
    /// shell, so every value is [`shell_quote`]d; `%` of the log's directory is doubled
    /// (sbatch expands `%a` and the like in `--output`, and reads `%%` as `%`).
    fn directives(&self, out: &mut String, name: &str, r: Resources, log: &str) {
        let logs = self.script_dir().join("logs");
        let output = format!("{}/{log}", logs.to_string_lossy().replace('%', "%%"));
        let _ = writeln!(out, "#SBATCH --job-name={}", shell_quote(name));
        let _ = writeln!(out, "#SBATCH --time={}", r.minutes);
        let _ = writeln!(out, "#SBATCH --mem={}M", r.mem_mib);
        let _ = writeln!(out, "#SBATCH --output={}", shell_quote(&output));
        if let Some(p) = &self.partition {
            let _ = writeln!(out, "#SBATCH --partition={}", shell_quote(p));
        }
    }

    /// `shards.sbatch`: the job array. A task runs shard `SLURM_ARRAY_TASK_ID + 1` of
    /// `tasks`; resubmitted after a kill, it resumes from its row log.
    #[must_use]
    pub fn shard_script(&self) -> String {
        let mut s = String::from("#!/bin/bash\n");
        let _ = writeln!(s, "#SBATCH --array=0-{}", self.tasks.saturating_sub(1));
        let _ = writeln!(s, "#SBATCH --cpus-per-task={}", self.cpus_per_task);
        self.directives(&mut s, &self.name, self.task, "shard-%a.out");
        let _ = writeln!(
            s,
            "# One shard of the sweep per array task; a task killed and run again computes\n\
             # only the rows its directory lacks. Written by `rollstack slurm`.\n\
             set -euo pipefail\n\
             cd {}\n\
             export RAYON_NUM_THREADS=\"${{SLURM_CPUS_PER_TASK:-1}}\"\n\
             exec {} {} --shard auto --out {}\"$SLURM_ARRAY_TASK_ID\"",
            shell_quote_path(&self.workdir),
            shell_quote_path(&self.binary),
            self.sweep
                .iter()
                .map(|a| shell_quote(a))
                .collect::<Vec<_>>()
                .join(" "),
            shell_quote_path(&self.task_dir("")),
        );
        s
    }

    /// `merge.sbatch`: joins the shards into `out`.
    #[must_use]
    pub fn merge_script(&self) -> String {
        let mut s = String::from("#!/bin/bash\n");
        let _ = writeln!(s, "#SBATCH --cpus-per-task=1");
        self.directives(
            &mut s,
            &format!("{}-merge", self.name),
            self.merge,
            "merge.out",
        );
        let dirs: Vec<String> = (0..self.tasks)
            .map(|i| shell_quote_path(&self.task_dir(&i.to_string())))
            .collect();
        let _ = writeln!(
            s,
            "# Joins the shards once every array task succeeded. Written by `rollstack slurm`.\n\
             set -euo pipefail\n\
             cd {}\n\
             exec {} merge {} --out {}",
            shell_quote_path(&self.workdir),
            shell_quote_path(&self.binary),
            dirs.join(" "),
            shell_quote_path(&self.out),
        );
        s
    }

    /// Writes `shards.sbatch`, `merge.sbatch` and `submit.sh` into [`Self::script_dir`]
    /// (with a `logs` directory for the jobs' output) and returns the path of
    /// `submit.sh`.
    ///
    /// # Errors
    /// An unwritable directory.
    pub fn write(&self) -> Result<PathBuf, ShardError> {
        let dir = self.script_dir();
        let logs = dir.join("logs");
        std::fs::create_dir_all(&logs).map_err(|e| ShardError::io(&logs, e))?;
        let files = [
            ("shards.sbatch", self.shard_script()),
            ("merge.sbatch", self.merge_script()),
            ("submit.sh", self.submit_script()),
        ];
        for (name, text) in files {
            let path = dir.join(name);
            std::fs::write(&path, text).map_err(|e| ShardError::io(&path, e))?;
        }
        Ok(dir.join("submit.sh"))
    }

    /// `submit.sh`: submits the array, then the merge job with `afterok` on it, and
    /// prints both job ids.
    #[must_use]
    pub fn submit_script(&self) -> String {
        format!(
            "#!/bin/bash\n\
             # Submits the shards and the merge job that waits for them. Written by `rollstack slurm`.\n\
             set -euo pipefail\n\
             cd \"$(dirname \"$0\")\"\n\
             mkdir -p logs\n\
             array=$(sbatch --parsable shards.sbatch)\n\
             array=${{array%%;*}}\n\
             merge=$(sbatch --parsable --dependency=afterok:\"$array\" merge.sbatch)\n\
             merge=${{merge%%;*}}\n\
             echo \"submitted job array $array ({} tasks) and merge job $merge\"\n\
             echo \"follow them with: squeue -j $array,$merge\"\n\
             echo \"the merged sweep will be in \"{}\n",
            self.tasks,
            shell_quote_path(&self.out),
        )
    }
}

/// A sweep's arguments for a job array: `argv` without its `--out DIR` (or
/// `--out=DIR`), and DIR. The array gives each task its own `--shard` and `--out`, so a
/// sweep that names its shard, or prints JSON nobody reads, is refused.
///
/// # Errors
/// No `--out`, or a `--shard` or `--json`.
pub fn split_out(argv: &[String]) -> Result<(Vec<String>, String), String> {
    let mut rest = Vec::new();
    let mut out = None;
    let mut args = argv.iter();
    while let Some(a) = args.next() {
        if a == "--out" {
            out = args.next().cloned();
        } else if let Some(dir) = a.strip_prefix("--out=") {
            out = Some(dir.to_owned());
        } else if a == "--shard" || a.starts_with("--shard=") || a == "--json" {
            return Err(format!(
                "the sweep must not have {a}: each task of the array gets its own shard"
            ));
        } else {
            rest.push(a.clone());
        }
    }
    let out = out.ok_or("the sweep needs --out DIR: the merged sweep is written there")?;
    Ok((rest, out))
}

/// `text` quoted for a POSIX shell (single quotes, a quote inside as `'\''`), left bare
/// when it holds only characters no shell treats specially. Every value a script of
/// this module holds goes through it.
#[must_use]
pub fn shell_quote(text: &str) -> String {
    let plain = !text.is_empty()
        && text
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b"-_./:=,+@%".contains(&b));
    if plain {
        text.to_owned()
    } else {
        format!("'{}'", text.replace('\'', "'\\''"))
    }
}

/// A path quoted for a POSIX shell ([`shell_quote`]).
#[must_use]
pub fn shell_quote_path(path: &Path) -> String {
    shell_quote(&path.to_string_lossy())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn estimates_scale_with_rows_per_core() {
        let c = Calibration {
            total_rows: 100,
            rows: 1,
            seconds: 30.0,
            peak_memory_bytes: Some(100 << 20),
        };
        let r = estimate(&c, 4, 1);
        assert_eq!(
            r,
            Resources {
                minutes: 39,
                mem_mib: 456
            }
        );
        assert_eq!(estimate(&c, 4, 5).minutes, 9);
        let unknown = Calibration {
            peak_memory_bytes: None,
            ..c
        };
        assert_eq!(estimate(&unknown, 100, 1).mem_mib, 1024);
    }

    #[test]
    fn the_output_directory_is_taken_out_of_the_sweep() {
        let argv = |s: &str| s.split(' ').map(str::to_owned).collect::<Vec<_>>();
        let (rest, out) = split_out(&argv("blocks sweep frequency --out f --omega 2")).unwrap();
        assert_eq!(
            (rest.join(" ").as_str(), out.as_str()),
            ("blocks sweep frequency --omega 2", "f")
        );
        assert!(split_out(&argv("blocks sweep slide --v0 1")).is_err());
        assert!(split_out(&argv("blocks sweep slide --out=x --shard 1/2")).is_err());
    }

    #[test]
    fn scripts_quote_their_arguments() {
        assert_eq!(shell_quote("2:20:1"), "2:20:1");
        assert_eq!(shell_quote("a b'c"), "'a b'\\''c'");
        let job = Job {
            name: "rollstack-frequency".into(),
            tasks: 4,
            cpus_per_task: 2,
            task: Resources {
                minutes: 5,
                mem_mib: 512,
            },
            merge: Resources {
                minutes: 10,
                mem_mib: 512,
            },
            partition: None,
            binary: "/opt/rollstack".into(),
            workdir: "/home/me".into(),
            sweep: vec![
                "blocks".into(),
                "sweep".into(),
                "frequency".into(),
                "--omega".into(),
                "2,3".into(),
            ],
            out: "/scratch/my run".into(),
        };
        let s = job.shard_script();
        assert!(s.contains("#SBATCH --array=0-3\n"), "{s}");
        assert!(
            s.contains("exec /opt/rollstack blocks sweep frequency --omega 2,3 --shard auto --out '/scratch/my run/shards/task-'\"$SLURM_ARRAY_TASK_ID\""),
            "{s}"
        );
        let m = job.merge_script();
        assert!(
            m.contains("merge '/scratch/my run/shards/task-0' '/scratch/my run/shards/task-1'"),
            "{m}"
        );
        assert!(job.submit_script().contains("--dependency=afterok:"));
        // Every value is quoted, in the #SBATCH lines and in submit.sh's echo too; a %
        // of a directory is no pattern of sbatch's.
        let job = Job {
            partition: Some("gpu; rm".into()),
            out: "/scratch/o4 $(touch x) 100%".into(),
            ..job
        };
        let s = job.shard_script();
        assert!(s.contains("#SBATCH --partition='gpu; rm'\n"), "{s}");
        assert!(
            s.contains("#SBATCH --output='/scratch/o4 $(touch x) 100%%/slurm/logs/shard-%a.out'\n"),
            "{s}"
        );
        let submit = job.submit_script();
        assert!(
            submit.contains("echo \"the merged sweep will be in \"'/scratch/o4 $(touch x) 100%'\n"),
            "{submit}"
        );
    }

    #[test]
    fn requests_are_bounded_and_control_characters_refused() {
        let request = Request {
            name: "frequency".into(),
            tasks: 4,
            cpus_per_task: 1,
            minutes: Some(5),
            mem_mib: Some(512),
            partition: None,
            sweep: vec!["--out".into(), "x".into()],
            binary: "/opt/rollstack".into(),
            workdir: "/home/me".into(),
        };
        assert!(request.check().is_ok());
        let err = |r: Request| r.check().unwrap_err().to_string();
        for (bad, says) in [
            (
                Request {
                    tasks: MAX_TASKS + 1,
                    ..request.clone()
                },
                "--tasks must be between 1 and 100000, got 100001",
            ),
            (
                Request {
                    minutes: Some(0),
                    ..request.clone()
                },
                "--time must be at least 1 minute",
            ),
            (
                Request {
                    mem_mib: Some(0),
                    ..request.clone()
                },
                "--mem must be at least 1 MiB",
            ),
            (
                Request {
                    partition: Some("a\n#SBATCH --x".into()),
                    ..request.clone()
                },
                "--partition holds the control character '\\n'",
            ),
            (
                Request {
                    sweep: vec!["--out".into(), "x\ry".into()],
                    ..request.clone()
                },
                "the sweep's argument \"x\\ry\" holds the control character '\\r'",
            ),
        ] {
            assert!(err(bad.clone()).starts_with(says), "{}", err(bad));
        }
    }
}
