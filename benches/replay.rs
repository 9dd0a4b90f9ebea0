//! The whole right-hand side as a run meets it: every solve of a paper case's run recorded,
//! then replayed through [`Dynamics::accelerations`] (kinematics, every load, the anchor's
//! friction and the O(N) solve: what the integrator calls), µs per solve, wall and this
//! thread's CPU time. Also the gravity-only solve at N = 46 on the benchmark chain of
//! `kernels.rs` (loads included, anchor free).
//!
//! ```sh
//! cargo bench --bench replay            # cases 1 and 17
//! cargo bench --bench replay -- 1 5 9   # the named cases
//! ```
//!
//! This file uses only interfaces that the build before issue 14 (commit 4cfb922) already had,
//! so the same file times that build too: `benches/then_and_now.sh` runs both side by side in
//! one session, which is how docs/codegen.md measures the issue's speed ratios on a shared
//! machine whose absolute speed varies by a third from hour to hour.

use std::cell::RefCell;
use std::hint::black_box;
use std::rc::Rc;
use std::time::Instant;

use kanestop_chain::BodyKind;
use kanestop_runtime::chain::{box_inertia, Body, Chain, Shape};
use kanestop_runtime::dynamics::Dynamics;
use kanestop_runtime::forces::Forces;
use kanestop_runtime::generated::GeneratedKernel;
use kanestop_runtime::kernel::{
    AnchorDof, AnchorReaction, Assembly, BodyAcceleration, BodyState, Kernel, LoadModel, RhsError,
};
use kanestop_runtime::model::Model;
use kanestop_runtime::paper::CASES;
use kanestop_runtime::simulate::{self, Stop};

/// One solve of a run: the state and the anchor's degree of freedom and friction factor.
struct Solve {
    q: Vec<f64>,
    u: Vec<f64>,
    anchor: AnchorDof,
    friction: f64,
}

/// A kernel that records every solve and hands it to the generated kernel (unfused: the
/// recording needs only the states, which every form computes alike).
struct Recorder {
    inner: GeneratedKernel,
    solves: Rc<RefCell<Vec<Solve>>>,
}

impl Kernel for Recorder {
    fn name(&self) -> &'static str {
        self.inner.name()
    }
    fn body_count(&self) -> usize {
        self.inner.body_count()
    }
    fn kinematics(&mut self, q: &[f64], u: &[f64], bodies: &mut [BodyState]) {
        self.inner.kinematics(q, u, bodies)
    }
    fn assemble(&mut self, q: &[f64], u: &[f64], model: &mut dyn LoadModel, out: &mut Assembly) {
        self.inner.assemble(q, u, model, out)
    }
    fn accelerations(&mut self, q: &[f64], u: &[f64], qdd: &[f64], out: &mut [BodyAcceleration]) {
        self.inner.accelerations(q, u, qdd, out)
    }
    #[allow(clippy::too_many_arguments)]
    fn solve(
        &mut self,
        q: &[f64],
        u: &[f64],
        anchor: AnchorDof,
        friction: f64,
        model: &mut dyn LoadModel,
        scratch: &mut Assembly,
        qdd: &mut [f64],
    ) -> Result<AnchorReaction, RhsError> {
        let mut solves = self.solves.borrow_mut();
        // Dynamics retries a solve without friction when the seabed's normal force on the
        // anchor comes out negative (the anchor lifts): the same state, anchor free, friction
        // 0 right after the same state with friction. The replay's Dynamics makes that retry
        // itself, so only the first of the two is recorded.
        let retry = matches!(anchor, AnchorDof::Free)
            && friction == 0.0
            && solves
                .last()
                .is_some_and(|s| s.q == q && s.u == u && matches!(s.anchor, AnchorDof::Free) && s.friction != 0.0);
        if !retry {
            solves.push(Solve { q: q.to_vec(), u: u.to_vec(), anchor, friction });
        }
        drop(solves);
        self.inner.solve(q, u, anchor, friction, model, scratch, qdd)
    }
}

/// Every solve of the model's run (the friction-free retries left to the replay), or why the
/// run is no fair sample (it failed).
fn record(model: &Model) -> Result<Vec<Solve>, String> {
    let solves = Rc::new(RefCell::new(Vec::new()));
    let result = simulate::run(model, Box::new(Recorder { inner: kernel(model)?, solves: solves.clone() }));
    match result.stop {
        Stop::ShipStopped | Stop::EndTime => {}
        Stop::Failed(f) => return Err(format!("the recorded run failed: {f:?}")),
    }
    Ok(solves.take())
}

/// The generated kernel of the model's chain, or why there is none.
fn kernel(model: &Model) -> Result<GeneratedKernel, String> {
    GeneratedKernel::new(&model.chain).map_err(|e| format!("no generated kernel: {e}"))
}

/// CPU time of this thread so far, s (Linux: the first field of schedstat, ns on the CPU).
fn thread_cpu() -> f64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next().and_then(|t| t.parse::<f64>().ok()))
        .map_or(f64::NAN, |ns| ns * 1e-9)
}

/// Median over `passes` of (wall, CPU) µs per call of `f`.
fn median_per_call(passes: usize, calls: usize, mut f: impl FnMut()) -> (f64, f64) {
    let (mut walls, mut cpus) = (Vec::new(), Vec::new());
    for _ in 0..passes {
        let (t, cpu) = (Instant::now(), thread_cpu());
        f();
        walls.push(t.elapsed().as_secs_f64() * 1e6 / calls as f64);
        cpus.push((thread_cpu() - cpu) * 1e6 / calls as f64);
    }
    walls.sort_by(f64::total_cmp);
    cpus.sort_by(f64::total_cmp);
    (walls[passes / 2], cpus[passes / 2])
}

/// The run's solves replayed through the production right-hand side: (wall, CPU) µs per
/// solve, or how many of them failed (the run itself solved every one).
fn replay(model: &Model, solves: &[Solve]) -> Result<(f64, f64), String> {
    let mu = Forces::new(model).anchor.friction_coefficient;
    let kernel = kernel(model)?;
    let mut dynamics = Dynamics::new(Box::new(kernel), Forces::new(model), AnchorDof::Stuck);
    let mut qdd = vec![0.0; model.body_count()];
    let mut failed = 0usize;
    let timing = median_per_call(7, solves.len(), || {
        for s in solves {
            match s.anchor {
                AnchorDof::Stuck => dynamics.stick_anchor(),
                AnchorDof::Free => dynamics.slide_anchor(if mu > 0.0 { s.friction / mu } else { 0.0 }),
            }
            failed += usize::from(dynamics.accelerations(black_box(&s.q), black_box(&s.u), &mut qdd).is_err());
        }
        black_box(&qdd);
    });
    match failed {
        0 => Ok(timing),
        n => Err(format!("{n} of {} replayed solves failed", 7 * solves.len())),
    }
}

/// `kernels.rs`'s paper-like chain of `n` dry bodies: a 5 t anchor, 1–10 m rods, a 500 t ship.
fn chain(n: usize) -> Chain {
    let mut bodies = vec![Body {
        kind: BodyKind::Anchor,
        mass: 5000.0,
        inertia: box_inertia(5000.0, 2.0, 4.0, 2.1, 0.0),
        centroid: [1.0, 1.05],
        joint: [-300.0, -30.0],
        shape: Shape::Box { length: 2.0, width: 4.0, height: 2.1 },
        added_mass: 0.0,
        added_inertia: 0.0,
    }];
    let mut joint = [2.0, 0.08];
    for i in 0..n - 2 {
        let length = [1.0, 2.0, 10.0][i % 3];
        bodies.push(Body::rod(BodyKind::ChainLink, length, 0.07, 14.0 + 10.0 * (i % 5) as f64, joint));
        joint = [length, 0.0];
    }
    let mass = 5.0e5;
    bodies.push(Body {
        kind: BodyKind::Ship,
        mass,
        inertia: box_inertia(mass, 50.0, 10.0, 5.0, 1.5),
        centroid: [-25.0, -1.0],
        joint,
        shape: Shape::Box { length: 50.0, width: 10.0, height: 5.0 },
        added_mass: 0.0,
        added_inertia: 0.0,
    });
    Chain { bodies }
}

/// Weight alone at N = 46 through the same `Dynamics`, anchor free without friction, over
/// 1000 smooth states (small alternating angles, slow rates).
fn gravity_only() -> (f64, f64) {
    let n = 46;
    let c = chain(n);
    let states: Vec<(Vec<f64>, Vec<f64>)> = (0..1000)
        .map(|s| {
            let phase = s as f64 * 0.01;
            let q = (0..n).map(|i| 0.05 * ((i as f64) * 0.7 + phase).sin()).collect();
            let u = (0..n).map(|i| 0.1 * ((i as f64) * 1.3 + phase).cos()).collect();
            (q, u)
        })
        .collect();
    let kernel = GeneratedKernel::new(&c).expect("N = 46 is one of the built kernels");
    let mut dynamics = Dynamics::new(Box::new(kernel), Forces::gravity_only(&c, 9.81), AnchorDof::Free);
    let mut qdd = vec![0.0; n];
    let calls = 200 * states.len();
    let mut failed = 0usize;
    let timing = median_per_call(7, calls, || {
        for _ in 0..200 {
            for (q, u) in &states {
                failed += usize::from(dynamics.accelerations(black_box(q), black_box(u), &mut qdd).is_err());
            }
        }
        black_box(&qdd);
    });
    assert_eq!(failed, 0, "weight alone: solves failed on smooth states");
    timing
}

/// Ends the bench with exit code 1: a replay that is not the run's is no measurement.
fn fail(case: usize, why: &str) -> ! {
    eprintln!("case {case}: {why}");
    std::process::exit(1);
}

fn main() {
    let mut cases: Vec<usize> = std::env::args().skip(1).filter_map(|a| a.parse().ok()).collect();
    if cases.is_empty() {
        cases = vec![1, 17];
    }
    println!("whole right-hand side replayed over a run's solves (median of 7 passes)");
    println!("{:>6} {:>8} {:>8} {:>12} {:>12}  solver", "case", "N", "solves", "µs/solve", "CPU µs/solve");
    for number in cases {
        let Some(case) = CASES.get(number.wrapping_sub(1)) else {
            eprintln!("no paper case {number}: 1 to {}", CASES.len());
            std::process::exit(2);
        };
        let model = Model::new(&case.scene()).unwrap_or_else(|e| fail(number, &e.to_string()));
        let solves = record(&model).unwrap_or_else(|e| fail(number, &e));
        let (wall, cpu) = replay(&model, &solves).unwrap_or_else(|e| fail(number, &e));
        let solver = &model.scene.solver;
        println!(
            "{number:>6} {:>8} {:>8} {wall:>12.3} {cpu:>12.3}  {:?} dt = {} s",
            model.body_count(),
            solves.len(),
            solver.integrator,
            solver.dt
        );
    }
    let (wall, cpu) = gravity_only();
    println!("\nweight alone, N = 46, anchor free (1000 states, 200 passes, median of 7)");
    println!("{:>12} {:>12}", "µs/solve", "CPU µs/solve");
    println!("{wall:>12.3} {cpu:>12.3}");
}
