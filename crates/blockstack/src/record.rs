//! Recording a run: the trajectory as CSV streamed to any writer, and, in memory, the
//! frames a caller draws (snapshots nearest to chosen times, animation frames), the top
//! block's angle and height (Figure 4.5 (b), (c)) and the last state.
//!
//! [`simulate`](crate::simulate) calls its observer once per step with a
//! [`StepRecord`]; a [`Recorder`] is such an observer:
//!
//! ```
//! use blockstack::record::{RecordPlan, Recorder};
//! use blockstack::scenarios::{lire, Perturbation};
//!
//! let scene = lire(2, Perturbation::None)?;
//! let options = blockstack::RunOptions { t_end: Some(0.05), ..Default::default() };
//! let plan = RecordPlan { snapshots: vec![0.0, 0.05], max_frames: 0 };
//! let mut recorder = Recorder::new(&scene, 0.05, &plan, Some(Vec::<u8>::new()))?;
//! let summary = blockstack::simulate(&scene, &options, |r| recorder.on_step(r))?;
//! let (recording, csv, write_error) = recorder.finish();
//! assert!(write_error.is_none());
//! let text = String::from_utf8(csv.unwrap()).unwrap();
//! // A header and one row per state: t = 0 and each of the 5 steps.
//! assert_eq!(text.lines().count(), 1 + 1 + summary.steps);
//! assert!(text.starts_with("t,x1,y1,theta1,x2,y2,theta2,n1a,n1b,f1,"));
//! assert_eq!(recording.snapshots.len(), 2);
//! assert_eq!(recording.last.unwrap().t, 0.05);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::coordinates::Pose;
use crate::corners::corners;
use crate::scene::Scene;
use crate::simulation::{BlockPose, StepRecord};
use std::fmt;
use std::io::Write;

/// The base and block poses of one moment, bottom to top (base first).
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Time.
    pub t: f64,
    /// The prescribed base.
    pub base: Pose,
    /// The free blocks, bottom to top.
    pub blocks: Vec<Pose>,
}

fn pose_of(p: &BlockPose) -> Pose {
    Pose::new(p.x, p.y, p.theta)
}

impl Frame {
    /// The frame of one recorded step.
    #[must_use]
    pub fn from_record(rec: &StepRecord) -> Self {
        Self {
            t: rec.t,
            base: pose_of(&rec.base),
            blocks: rec.poses.iter().map(pose_of).collect(),
        }
    }

    /// The scene at time t with block coordinates q = (x¹, y¹, θ¹, …).
    #[must_use]
    pub fn from_coordinates(scene: &Scene, q: &[f64], t: f64) -> Self {
        Self {
            t,
            base: scene.base().state(t).pose,
            blocks: q.chunks_exact(3).map(Pose::from_slice).collect(),
        }
    }

    /// Whether every pose and the time are finite (only such frames can be drawn).
    #[must_use]
    pub fn is_finite(&self) -> bool {
        let ok = |p: &Pose| p.x.is_finite() && p.y.is_finite() && p.theta.is_finite();
        self.t.is_finite() && ok(&self.base) && self.blocks.iter().all(ok)
    }

    /// The outlines (four corners, (G.1.1)) of the base and the blocks, base first.
    #[must_use]
    pub fn outlines(&self, scene: &Scene) -> Vec<[(f64, f64); 4]> {
        let outline = |pose: &Pose, k: usize| {
            let s = scene.size(k);
            corners(pose, s.width, s.height).map(|c| (c.x, c.y))
        };
        std::iter::once(outline(&self.base, 0))
            .chain(
                self.blocks
                    .iter()
                    .enumerate()
                    .map(|(k, p)| outline(p, k + 1)),
            )
            .collect()
    }
}

/// The top block at one step (Figure 4.5 (b), (c)).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct TopSample {
    /// Time.
    pub t: f64,
    /// Angle θ (rad).
    pub theta: f64,
    /// Height y of its centre of mass.
    pub y: f64,
}

/// What to keep in memory besides the trajectory CSV.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RecordPlan {
    /// Snapshot times: for each, the step nearest to it is kept.
    pub snapshots: Vec<f64>,
    /// Largest number of animation frames (0: none).
    pub max_frames: usize,
}

impl RecordPlan {
    /// One animation frame every this many steps: every 10th, sparser for runs of more
    /// than 10 `max_frames` steps, so that the animation has at most `max_frames` frames.
    #[must_use]
    pub fn frame_every(&self, t_end: f64, dt: f64) -> usize {
        if self.max_frames == 0 {
            return 1;
        }
        let planned_steps = (t_end / dt).ceil().max(1.0);
        // A count of steps: finite and positive here.
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let every = (planned_steps / self.max_frames as f64).ceil() as usize;
        every.max(10)
    }
}

/// What a run recorded in memory.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Recording {
    /// For each requested snapshot time (in the plan's order), the nearest step.
    pub snapshots: Vec<(f64, Frame)>,
    /// Animation frames, ending on the last state computed.
    pub frames: Vec<Frame>,
    /// The top block at every step with a finite state.
    pub top: Vec<TopSample>,
    /// The last state recorded.
    pub last: Option<Frame>,
}

/// The trajectory CSV header for a column of n blocks: t, x1, y1, theta1, …, then n{k}a,
/// n{k}b, f{k} per interface k (k = 1 between the base and block 1), then base_x,
/// min_gap, newton_iterations, energy.
#[must_use]
pub fn trajectory_header(n: usize) -> Vec<String> {
    header(n, n)
}

/// [`trajectory_header`] for any scene: its blocks, then its interfaces in their order
/// ([`crate::arrangement`]; interface k is the k-th of them).
#[must_use]
pub fn trajectory_header_of(scene: &Scene) -> Vec<String> {
    header(scene.n_blocks(), scene.n_interfaces())
}

/// The header for n blocks and m interfaces.
fn header(n: usize, m: usize) -> Vec<String> {
    let mut h = vec!["t".to_owned()];
    for k in 1..=n {
        h.extend([format!("x{k}"), format!("y{k}"), format!("theta{k}")]);
    }
    for k in 1..=m {
        h.extend([format!("n{k}a"), format!("n{k}b"), format!("f{k}")]);
    }
    h.extend(
        ["base_x", "min_gap", "newton_iterations", "energy"]
            .iter()
            .map(|s| (*s).to_owned()),
    );
    h
}

/// A number as the files write it: the shortest text that reads back as the same
/// number (`0.1`, `2.7755575615628914e-17`). Written straight into a writer or made a
/// string ([`number_text`]): the one place the format is chosen.
struct Number(f64);

impl fmt::Display for Number {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:?}", self.0)
    }
}

/// A finite number as [`Number`], or nothing: never NaN or inf in a file.
struct Finite(f64);

impl fmt::Display for Finite {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.is_finite() {
            Number(self.0).fmt(f)
        } else {
            Ok(())
        }
    }
}

/// Shortest text that reads back as the same number (`0.1`, `2.7755575615628914e-17`).
#[must_use]
pub fn number_text(v: f64) -> String {
    Number(v).to_string()
}

/// A finite number as [`number_text`], or an empty cell: never NaN or inf in a file.
#[must_use]
pub fn finite_text(v: f64) -> String {
    Finite(v).to_string()
}

/// An optional number as [`finite_text`]; an empty cell when absent.
#[must_use]
pub fn optional_text(v: Option<f64>) -> String {
    v.map_or_else(String::new, finite_text)
}

/// Why the trajectory stopped being written.
#[derive(Debug, thiserror::Error)]
pub enum TrajectoryError {
    /// A state or force was NaN or infinite: no such row is ever written.
    #[error("non-finite state or force at t = {0}: trajectory stopped there")]
    NonFinite(f64),
    /// The writer failed.
    #[error("cannot write the trajectory: {0}")]
    Io(#[from] std::io::Error),
}

/// One CSV row of the trajectory ([`trajectory_header`]).
///
/// # Errors
/// [`TrajectoryError::NonFinite`] for a non-finite pose, force or base position (the
/// row is then not written); the writer's error.
pub fn write_trajectory_row<W: Write>(
    out: &mut W,
    rec: &StepRecord,
) -> Result<(), TrajectoryError> {
    let mut cells: Vec<f64> = vec![rec.t];
    cells.extend(rec.poses.iter().flat_map(|p| [p.x, p.y, p.theta]));
    cells.extend(
        rec.forces
            .iter()
            .flat_map(|f| [f.normal[0], f.normal[1], f.friction]),
    );
    cells.push(rec.base.x);
    if !cells.iter().all(|v| v.is_finite()) {
        return Err(TrajectoryError::NonFinite(rec.t));
    }
    // Each cell formatted straight into the writer, not into a string of its own: a
    // row per step.
    for &v in &cells {
        write!(out, "{},", Number(v))?;
    }
    // The minimum gap is +inf when no contact is closed: left empty then.
    let (gap, energy) = (Finite(rec.min_gap), Finite(rec.energy));
    writeln!(out, "{gap},{},{energy}", rec.iterations)?;
    Ok(())
}

/// Records a run step by step: streams the trajectory CSV to a writer (if any) and keeps
/// the frames of a [`RecordPlan`].
#[derive(Debug)]
pub struct Recorder<W: Write> {
    csv: Option<W>,
    write_error: Option<TrajectoryError>,
    plan: RecordPlan,
    snapshots: Vec<Option<Frame>>,
    frame_every: usize,
    recording: Recording,
    count: usize,
}

impl<W: Write> Recorder<W> {
    /// A recorder for a run of `scene` to `t_end`, writing the CSV header to `csv` now.
    ///
    /// # Errors
    /// The writer's error on the header.
    pub fn new(
        scene: &Scene,
        t_end: f64,
        plan: &RecordPlan,
        mut csv: Option<W>,
    ) -> Result<Self, TrajectoryError> {
        if let Some(w) = &mut csv {
            writeln!(w, "{}", trajectory_header_of(scene).join(","))?;
        }
        Ok(Self {
            csv,
            write_error: None,
            snapshots: vec![None; plan.snapshots.len()],
            frame_every: plan.frame_every(t_end, scene.solver.dt),
            plan: plan.clone(),
            recording: Recording::default(),
            count: 0,
        })
    }

    /// Records one step (or the initial state): the observer to give
    /// [`simulate`](crate::simulate). After a write error, rows are no longer written
    /// (the frames are still kept).
    pub fn on_step(&mut self, rec: &StepRecord) {
        let i = self.count;
        self.count += 1;
        let r = &mut self.recording;
        if let Some(top) = rec.poses.last() {
            if rec.t.is_finite() && top.theta.is_finite() && top.y.is_finite() {
                r.top.push(TopSample {
                    t: rec.t,
                    theta: top.theta,
                    y: top.y,
                });
            }
        }
        if self.write_error.is_none() {
            if let Some(w) = &mut self.csv {
                if let Err(e) = write_trajectory_row(w, rec) {
                    self.write_error = Some(e);
                }
            }
        }
        // Keep, for each snapshot time, the nearest step seen so far.
        for (ts, best) in self.plan.snapshots.iter().zip(&mut self.snapshots) {
            if best
                .as_ref()
                .is_none_or(|b| (rec.t - ts).abs() < (b.t - ts).abs())
            {
                *best = Some(Frame::from_record(rec));
            }
        }
        if self.plan.max_frames > 0
            && i.is_multiple_of(self.frame_every)
            && r.frames.len() < self.plan.max_frames
        {
            r.frames.push(Frame::from_record(rec));
        }
        r.last = Some(Frame::from_record(rec));
    }

    /// The recording (animation frames ending on the last state), the writer, and the
    /// first write error.
    pub fn finish(mut self) -> (Recording, Option<W>, Option<TrajectoryError>) {
        let r = &mut self.recording;
        r.snapshots = self
            .plan
            .snapshots
            .iter()
            .zip(self.snapshots)
            .filter_map(|(ts, f)| f.map(|f| (*ts, f)))
            .collect();
        if self.plan.max_frames > 0 {
            if let Some(last) = &r.last {
                if r.frames.last().is_none_or(|f| f.t < last.t) {
                    r.frames.push(last.clone());
                }
            }
        }
        (self.recording, self.csv, self.write_error)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulation::InterfaceForce;

    fn record(t: f64, x: f64) -> StepRecord {
        StepRecord {
            t,
            poses: vec![BlockPose {
                x,
                y: 0.25,
                theta: 0.0,
            }],
            base: BlockPose {
                x: 0.0,
                y: 0.0,
                theta: 0.0,
            },
            velocities: vec![[0.0; 3]],
            forces: vec![InterfaceForce {
                normal: [0.5, 0.5],
                friction: 0.0,
            }],
            gaps: vec![[0.0, 0.0]],
            min_gap: f64::INFINITY,
            iterations: 1,
            energy: 0.25,
        }
    }

    #[test]
    fn trajectory_rows_are_shortest_round_trip_and_never_non_finite() {
        let mut out = Vec::new();
        writeln!(out, "{}", trajectory_header(1).join(",")).unwrap();
        write_trajectory_row(&mut out, &record(0.0, 0.0)).unwrap();
        write_trajectory_row(&mut out, &record(0.01, 1e-20)).unwrap();
        assert!(matches!(
            write_trajectory_row(&mut out, &record(0.02, f64::NAN)),
            Err(TrajectoryError::NonFinite(t)) if t == 0.02
        ));
        assert_eq!(
            String::from_utf8(out).unwrap(),
            "t,x1,y1,theta1,n1a,n1b,f1,base_x,min_gap,newton_iterations,energy\n\
             0.0,0.0,0.25,0.0,0.5,0.5,0.0,0.0,,1,0.25\n\
             0.01,1e-20,0.25,0.0,0.5,0.5,0.0,0.0,,1,0.25\n"
        );
    }

    #[test]
    fn the_recorder_keeps_the_nearest_snapshots_and_ends_the_animation_on_the_last_state() {
        let scene = crate::scenarios::lire(1, crate::scenarios::Perturbation::None).unwrap();
        let plan = RecordPlan {
            snapshots: vec![0.012, 10.0],
            max_frames: 3,
        };
        let mut r = Recorder::new(&scene, 0.05, &plan, None::<Vec<u8>>).unwrap();
        for k in 0..6 {
            r.on_step(&record(0.01 * f64::from(k), 0.0));
        }
        // A non-finite state stops nothing in memory but is never a top sample.
        r.on_step(&record(f64::NAN, 0.0));
        let (rec, csv, err) = r.finish();
        assert!(csv.is_none() && err.is_none());
        let times: Vec<f64> = rec.snapshots.iter().map(|(ts, f)| ts + f.t).collect();
        assert_eq!(times, vec![0.012 + 0.01, 10.0 + 0.05]);
        // One frame every 10th step: only the first; the last state is appended only when
        // it is later than the last frame, which a NaN time is not.
        assert_eq!(rec.frames.len(), 1);
        assert_eq!(rec.top.len(), 6);
        assert!(rec.last.is_some_and(|f| f.t.is_nan()));
    }
}
