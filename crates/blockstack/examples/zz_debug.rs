use blockstack::broad_phase::corner_contacts;
use blockstack::overlap::deepest_penetration;
use blockstack::simulation::{simulate, RunOptions};
use blockstack::SceneFile;
fn main() {
    let text = std::fs::read_to_string("/tmp/m6.toml").unwrap();
    let scene = SceneFile::parse(&text).unwrap().to_scene().unwrap();
    let opts = RunOptions {
        t_end: Some(6.2),
        ..Default::default()
    };
    let dt = scene.solver.dt;
    let mut prev: Option<(f64, Vec<f64>, Vec<f64>)> = None;
    let mut reported = false;
    simulate(&scene, &opts, |r| {
        let q: Vec<f64> = r.poses.iter().flat_map(|p| [p.x, p.y, p.theta]).collect();
        let u: Vec<f64> = r.velocities.iter().flatten().copied().collect();
        let p = deepest_penetration(&scene, r.t, &q);
        if p.depth > 1e-6 && !reported {
            reported = true;
            println!("t {} depth {:?}", r.t, p);
            if let Some((t0, q0, u0)) = &prev {
                println!("before: t {t0} q {q0:?}\n u {u0:?}");
                for c in corner_contacts(&scene, *t0, q0, u0, dt) {
                    println!("  {c:?}");
                }
            }
            println!("after q {q:?}");
        }
        prev = Some((r.t, q, u));
    })
    .unwrap();
}
