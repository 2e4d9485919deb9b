//! A slender block rocking on a rigid base, against Housner's equation (Housner 1963)
//! integrated here, independently of rollstack: RK4 of
//!
//! ```text
//! θ'' = −p² (sin(α sgn θ − θ) + (ü_g/g) cos(α sgn θ − θ)),   p² = 3g/(4R),
//! ```
//!
//! R the half-diagonal and tan α = b/h, with the impact rule θ'⁺ = η θ'⁻,
//! η = 1 − (3/2) sin² α (e_N = 0, corners that stick). Housner's θ is positive when the
//! block turns clockwise (onto its right corner), rollstack's counterclockwise: θ_H = −θ.
//!
//! The block is the built-in `rocking-block` (2b × 2h = 0.2 × 1.0, tan α = 0.2, μ = 1,
//! e_N = 0, g = 1), with μ raised to 2 under a moving base so that it never slides. The
//! base's motion is a displacement whose acceleration is a sine (docs/rocking.md), given
//! as samples: the spline through them has the sine's acceleration to 1e-4.
//!
//! The measured figures of docs/rocking.md are these tests' output
//! (`cargo test -p blockstack --test rocking -- --nocapture`): each test checks that the
//! page shows its lines as they are.

use blockstack::{scenes, LoadedScene, RunOptions, StepRecord};
use std::f64::consts::PI;

const DOC: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../docs/rocking.md"
));

/// Prints a measured line and checks that docs/rocking.md shows it.
fn report(line: &str) {
    eprintln!("{line}");
    assert!(
        DOC.contains(line),
        "docs/rocking.md does not show the measured line\n{line}"
    );
}

/// Half-width b, half-height h and gravity g of the built-in scene.
const B: f64 = 0.1;
const H: f64 = 0.5;
const G: f64 = 1.0;

/// Housner's model of the block.
struct Housner {
    alpha: f64,
    p2: f64,
    eta: f64,
}

/// A Housner motion: θ_H every step, the impacts (t, θ'⁻, θ'⁺), and when it overturned.
#[derive(Default)]
struct Motion {
    t: Vec<f64>,
    theta: Vec<f64>,
    impacts: Vec<(f64, f64, f64)>,
    uplift: Option<f64>,
    overturned: Option<f64>,
}

impl Housner {
    fn new() -> Self {
        let alpha = (B / H).atan();
        Self {
            alpha,
            p2: 3.0 * G / (4.0 * B.hypot(H)),
            eta: 1.0 - 1.5 * alpha.sin().powi(2),
        }
    }

    /// θ'' rocking on corner `s` (the sign of θ) under the base acceleration `ug`.
    fn accel(&self, s: f64, theta: f64, ug: f64) -> f64 {
        let a = self.alpha * s - theta;
        -self.p2 * (a.sin() + ug / G * a.cos())
    }

    /// One RK4 step of length `dt` on corner `s` from `(θ, θ')` at `t`.
    fn rk4(&self, s: f64, t: f64, x: (f64, f64), dt: f64, ug: &dyn Fn(f64) -> f64) -> (f64, f64) {
        let f = |t: f64, (th, om): (f64, f64)| (om, self.accel(s, th, ug(t)));
        let at = |x: (f64, f64), k: (f64, f64), h: f64| (x.0 + h * k.0, x.1 + h * k.1);
        let k1 = f(t, x);
        let k2 = f(t + dt / 2.0, at(x, k1, dt / 2.0));
        let k3 = f(t + dt / 2.0, at(x, k2, dt / 2.0));
        let k4 = f(t + dt, at(x, k3, dt));
        (
            x.0 + dt / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0),
            x.1 + dt / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1),
        )
    }

    /// Housner's motion from θ_H = `theta0` at rest, base acceleration `ug`, steps `dt`,
    /// until `t_end`, overturning (|θ| > α), or, once `quiet_after` is past, energy too low
    /// to overturn. Impacts and uplift are located within their step by bisection.
    fn run(
        &self,
        theta0: f64,
        ug: &dyn Fn(f64) -> f64,
        t_end: f64,
        dt: f64,
        quiet_after: f64,
    ) -> Motion {
        let mut m = Motion::default();
        let (mut t, mut x, mut s) = (0.0, (theta0, 0.0), theta0.signum());
        if theta0 == 0.0 {
            s = 0.0;
        }
        let lifts = |t: f64| ug(t).abs() > G * (B / H);
        while t < t_end {
            m.t.push(t);
            m.theta.push(x.0);
            let mut left = dt;
            while left > 0.0 {
                if s == 0.0 {
                    // At rest on both corners: it lifts when |ü_g| passes g tan α.
                    if !lifts(t + left) {
                        t += left;
                        break;
                    }
                    let tau = bisect(|tau| lifts(t + tau), left);
                    t += tau;
                    left -= tau;
                    s = -ug(t).signum();
                    m.uplift.get_or_insert(t);
                    continue;
                }
                let next = self.rk4(s, t, x, left, ug);
                if next.0 * s >= 0.0 {
                    (t, x, left) = (t + left, next, 0.0);
                    continue;
                }
                // An impact on the other corner within the step.
                let tau = bisect(|tau| self.rk4(s, t, x, tau, ug).0 * s < 0.0, left);
                let before = self.rk4(s, t, x, tau, ug).1;
                t += tau;
                left -= tau;
                m.impacts.push((t, before, self.eta * before));
                (x, s) = ((0.0, self.eta * before), -s);
                if x.1.abs() < 1e-9 {
                    // The impacts accumulate (each takes a factor η off θ'): at rest.
                    (x, s) = ((0.0, 0.0), 0.0);
                }
            }
            if x.0.abs() > self.alpha {
                m.overturned = Some(t);
                break;
            }
            if t > quiet_after && self.energy(x) < 1.0 - 1e-6 {
                break;
            }
        }
        m
    }

    /// Energy over m g R: ½ I_O θ'²/(m g R) + cos(α − |θ|), with I_O = (4/3) m R²; it
    /// overturns only above 1.
    fn energy(&self, (th, om): (f64, f64)) -> f64 {
        om * om / (2.0 * self.p2) + (self.alpha - th.abs()).cos()
    }
}

/// The smallest τ in (0, `len`] where `past(τ)` holds (it holds at `len`), to round-off.
fn bisect(past: impl Fn(f64) -> bool, len: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, len);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if past(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

/// The base's displacement whose acceleration is `a` sin(ωt) from rest (one sine, or
/// `cycles` of them), then still: u = (a/ω)(t − sin(ωt)/ω), ending at rest.
fn sine_pulse_samples(a: f64, omega: f64, cycles: usize, t_end: f64) -> String {
    let end = cycles as f64 * 2.0 * PI / omega;
    let u = |t: f64| {
        let t = t.min(end);
        a / omega * (t - (omega * t).sin() / omega)
    };
    let h = 2.0 * PI / omega / 400.0;
    let mut times: Vec<f64> = (0..=400 * cycles + 400).map(|k| k as f64 * h).collect();
    let mut t = *times.last().unwrap();
    while t < t_end + 1.0 {
        t += 0.5;
        times.push(t);
    }
    let pairs: Vec<String> = times
        .iter()
        .map(|&t| format!("[{t:?}, {:?}]", u(t)))
        .collect();
    format!(
        "motion = \"displacement\"\nsamples = [{}]\n",
        pairs.join(", ")
    )
}

/// The built-in scene with `base` as its base motion, the block at `theta` (rollstack's
/// sign), μ = `mu`, Δt = `dt`, t_end.
fn scene(base: &str, theta: f64, mu: f64, dt: f64, t_end: f64) -> LoadedScene {
    let text = scenes::find("rocking-block").unwrap().toml;
    let text = text
        .replace("motion = \"fixed\"\n", base)
        .replace("theta = -0.1\n", &format!("theta = {theta:?}\n"))
        .replace("mu = 1.0\n", &format!("mu = {mu:?}\n"))
        .replace("dt = 0.001\n", &format!("dt = {dt:?}\n"))
        .replace("t_end = 10.0\n", &format!("t_end = {t_end:?}\n"));
    LoadedScene::from_toml(&text).unwrap()
}

/// rollstack's run: t, θ_H = −θ and θ'_H of every step, until `stop` says so.
#[derive(Default)]
struct Run {
    t: Vec<f64>,
    theta: Vec<f64>,
    omega: Vec<f64>,
    /// How far the middle of the block's bottom face moved along the base, largest |Δx|:
    /// a block rocking without sliding moves it by b(1 − cos θ) only.
    slid: f64,
}

fn run(loaded: &LoadedScene, stop: impl Fn(&StepRecord) -> bool) -> Run {
    let mut r = Run::default();
    let options = RunOptions::default();
    let summary = blockstack::simulation::simulate_until(&loaded.scene, &options, |s| {
        r.t.push(s.t);
        r.theta.push(-s.poses[0].theta);
        r.omega.push(-s.velocities[0][2]);
        let p = &s.poses[0];
        r.slid = r.slid.max((p.x + H * p.theta.sin() - s.base.x).abs());
        if stop(s) {
            std::ops::ControlFlow::Break(())
        } else {
            std::ops::ControlFlow::Continue(())
        }
    })
    .unwrap();
    assert!(summary.error.is_none(), "{:?}", summary.error);
    r
}

/// Under a base acceleration a sin(ωt), ω = 2p, for two periods: at 0.95 g tan α the
/// block stays upright, at 1.05 g tan α it rocks as Housner's does, to 1e-3 in its
/// largest angle. With μ = 0.15 < tan α the block slides before it can rock: rollstack
/// stays upright where Housner's model, which has no sliding, rocks.
#[test]
fn rocking_starts_when_the_base_acceleration_exceeds_g_tan_alpha() {
    let housner = Housner::new();
    let omega = 2.0 * housner.p2.sqrt();
    let t_end = 2.0 * 2.0 * PI / omega;
    let largest = |theta: &[f64]| theta.iter().fold(0.0_f64, |m, th| m.max(th.abs()));
    for (factor, mu) in [(0.95, 2.0), (1.05, 2.0), (1.05, 0.15)] {
        let a = factor * G * (B / H);
        let ug = move |t: f64| a * (omega * t).sin();
        let h = housner.run(0.0, &ug, t_end, 1e-4, f64::INFINITY);
        let base = sine_pulse_samples(a, omega, 3, t_end);
        let r = run(&scene(&base, 0.0, mu, 1e-3, t_end), |_| false);
        let (most, most_h) = (largest(&r.theta), largest(&h.theta));
        report(&format!(
            "a = {factor} g tan(alpha), mu = {mu}: largest |theta| rollstack {most:.4e}, Housner {most_h:.4e}; block slid {:.1e}",
            r.slid
        ));
        match (factor < 1.0, mu < B / H) {
            (true, _) => assert!(h.uplift.is_none() && most < 1e-12, "{most}"),
            (false, false) => {
                assert!(h.uplift.is_some() && most > 1e-4, "{most}");
                assert!((most - most_h).abs() < 1e-3 * most_h, "{most} {most_h}");
                assert!(r.slid < 1e-5, "{}", r.slid);
            }
            (false, true) => assert!(most < 1e-12 && r.slid > 1e-3, "{most} {}", r.slid),
        }
    }
}

/// θ'² at θ = 0 from a state (θ, θ') of the rocking motion before or after an impact:
/// ½ I_O θ'² + m g R cos(α − |θ|) is constant between impacts.
fn omega_at_zero(h: &Housner, (th, om): (f64, f64)) -> f64 {
    (om * om + 2.0 * h.p2 * ((h.alpha - th.abs()).cos() - h.alpha.cos())).sqrt()
}

/// The impacts of a run (θ changes sign between two steps) as the ratio of the angular
/// velocities just after and just before, each carried to θ = 0 along the rocking
/// motion ([`omega_at_zero`]), and the largest |θ| between impacts.
fn impacts_and_amplitudes(h: &Housner, r: &Run) -> (Vec<f64>, Vec<f64>) {
    let (mut ratios, mut peaks, mut peak) = (vec![], vec![], 0.0_f64);
    for k in 1..r.t.len() {
        peak = peak.max(r.theta[k - 1].abs());
        if r.theta[k - 1] * r.theta[k] < 0.0 {
            let before = omega_at_zero(h, (r.theta[k - 1], r.omega[k - 1]));
            let after = omega_at_zero(h, (r.theta[k], r.omega[k]));
            ratios.push(after / before);
            peaks.push(peak);
            peak = 0.0;
        }
    }
    (ratios, peaks)
}

/// The largest |θ| between the impacts of a Housner motion.
fn housner_amplitudes(m: &Motion) -> Vec<f64> {
    let mut peaks = vec![];
    let mut k = 0;
    for &(t, _, _) in &m.impacts {
        let mut peak = 0.0_f64;
        while k < m.t.len() && m.t[k] <= t {
            peak = peak.max(m.theta[k].abs());
            k += 1;
        }
        peaks.push(peak);
    }
    peaks
}

/// Released at rest from θ_H = 0.1 (about α/2) on a fixed base, for 10 time units: the
/// ratio of angular velocities across each impact tends to η with Δt (first order:
/// within 1e-3 of it from Δt = 2.5e-4), and so do the amplitudes between impacts
/// (the largest |θ| between two impacts, the first five) to Housner's.
#[test]
fn free_rocking_loses_housners_ratio_at_each_impact() {
    let h = Housner::new();
    let theta0 = 0.1;
    let t_end = 10.0;
    let m = h.run(theta0, &|_| 0.0, t_end, 1e-4, f64::INFINITY);
    let amplitudes_h = housner_amplitudes(&m);
    report(&format!(
        "Housner: eta = {:.6}, {} impacts, amplitudes {:.6?}",
        h.eta,
        m.impacts.len(),
        &amplitudes_h[..5]
    ));
    let mut errors = vec![];
    for dt in [1e-3, 5e-4, 2.5e-4] {
        let r = run(
            &scene("motion = \"fixed\"\n", -theta0, 1.0, dt, t_end),
            |_| false,
        );
        let (ratios, amplitudes) = impacts_and_amplitudes(&h, &r);
        assert!(ratios.len() >= 5 && amplitudes.len() >= 5);
        let ratio_error = ratios.iter().fold(0.0_f64, |w, q| w.max((q - h.eta).abs()));
        let amplitude_error = (0..5)
            .map(|k| (amplitudes[k] - amplitudes_h[k]).abs() / amplitudes_h[k])
            .fold(0.0_f64, f64::max);
        report(&format!(
            "dt = {dt:e}: {} impacts, ratios {:.4?}; largest |ratio - eta| {ratio_error:.1e}, amplitudes within {amplitude_error:.1e} of Housner's",
            ratios.len(),
            ratios
        ));
        errors.push((ratio_error, amplitude_error));
    }
    let (coarse, fine) = (errors[0], errors[2]);
    assert!(fine.0 < 1e-3 && fine.0 < coarse.0 / 2.0, "{errors:?}");
    assert!(fine.1 < 5e-3 && fine.1 < coarse.1 / 2.0, "{errors:?}");
}

/// Whether a one-sine pulse of amplitude `a` and frequency `omega` overturns rollstack's
/// block; the run stops when it tips past α or when, the pulse over, its energy is below
/// the overturning energy m g (y_top + R) (base top at y_top = 0.05, m = 1).
fn rollstack_overturns(h: &Housner, a: f64, omega: f64, dt: f64) -> bool {
    let end = 2.0 * PI / omega;
    let t_end = end + 40.0;
    let r = run(
        &scene(&sine_pulse_samples(a, omega, 1, t_end), 0.0, 2.0, dt, t_end),
        |s| {
            s.poses[0].theta.abs() > h.alpha
                || (s.t > end && s.energy < G * (0.05 + B.hypot(H)) - 1e-6)
        },
    );
    r.theta.last().is_some_and(|th| th.abs() > h.alpha)
}

/// Whether Housner's block overturns under the same pulse.
fn housner_overturns(h: &Housner, a: f64, omega: f64) -> bool {
    let end = 2.0 * PI / omega;
    let ug = move |t: f64| if t < end { a * (omega * t).sin() } else { 0.0 };
    h.run(0.0, &ug, end + 40.0, 1e-3, end).overturned.is_some()
}

/// The smallest amplitude in [lo, hi] for which `overturns` holds (it holds at hi and
/// not at lo), to `rel` of hi.
fn threshold(lo: f64, hi: f64, rel: f64, overturns: impl Fn(f64) -> bool) -> f64 {
    let (mut lo, mut hi) = (lo, hi);
    while hi - lo > rel * hi {
        let mid = 0.5 * (lo + hi);
        if overturns(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

/// One sine of base acceleration a_p sin(ω_p t) at ω_p/p = 2, 3, 4 (Zhang & Makris
/// 2001): Housner's least overturning a_p, found here to 1e-5, overturns rollstack's
/// block at 1.01 of it and not at 0.99 (Δt = 1e-3); rollstack's own least a_p, bisected
/// to 1e-3, is reported.
#[test]
fn the_least_one_sine_pulse_that_overturns_the_block_is_housners() {
    let h = Housner::new();
    let p = h.p2.sqrt();
    let tan = B / H;
    for ratio in [2.0, 3.0, 4.0] {
        let omega = ratio * p;
        // Housner's: the first overturning amplitude above g tan α, in steps of 2 %.
        let mut a = G * tan;
        while !housner_overturns(&h, a, omega) {
            a += 0.02 * G * tan;
        }
        let a_h = threshold(a - 0.02 * G * tan, a, 1e-5, |a| {
            housner_overturns(&h, a, omega)
        });
        assert!(!rollstack_overturns(&h, 0.99 * a_h, omega, 1e-3), "{ratio}");
        assert!(rollstack_overturns(&h, 1.01 * a_h, omega, 1e-3), "{ratio}");
        let a_r = threshold(0.99 * a_h, 1.01 * a_h, 1e-3, |a| {
            rollstack_overturns(&h, a, omega, 1e-3)
        });
        report(&format!(
            "omega_p/p = {ratio}: least overturning a_p/(g tan alpha) Housner {:.4}, rollstack {:.4} ({:+.1} %)",
            a_h / (G * tan),
            a_r / (G * tan),
            100.0 * (a_r / a_h - 1.0)
        ));
    }
}
