//! The adaptive method against the paper's RK4 on case 1: CPU time (each run's own thread;
//! wall time and right-hand-side evaluations beside) at equal stopping-time accuracy,
//! measured side by side in one run.
//!
//! ```sh
//! cargo bench --bench integrators      # about 75 s
//! ```
//!
//! The study of `report accuracy` (reference DP5 at rtol 1e-10) over RK4 at dt = 2 ms and
//! DP5 at tolerances 1, 0.5 and 0.2 per decade from 1e-4 to 1e-7, observed every 0.02 s, each setting
//! timed 7 times (median), for two absolute tolerances: atol = rtol/100 (the ratio of the
//! scenes' defaults) and atol = rtol. The DP5 run that matches RK4's stopping-time error is
//! the loosest tolerance from which every tighter one matches it too
//! ([`accuracy::matched`]); the ratio of the two CPU-time medians is the speed-up (the
//! ratio of evaluations is printed beside it). The issue's goal
//! is 3×.
//!
//! A control follows: case 1 with the line elements' drag coefficients ×20, which damps the
//! ringing of the cable and chain (atol = rtol/100). It shows whether the model's lightly
//! damped modes are what holds the ratio down. Results are recorded in docs/integrators.md.

use kanestop_runtime::generated::GeneratedKernel;
use kanestop_runtime::kernel::Kernel;
use kanestop_runtime::model::Model;
use kanestop_runtime::paper::CASES;
use kanestop_runtime::scene::Method;
use kanestop_workflow::accuracy::{self, Setting, DEFAULT_ATOL_RATIO};

/// The speed-up the issue asks of the adaptive method at RK4's (2 ms) accuracy.
const GOAL: f64 = 3.0;

fn main() {
    let scene = CASES[0].scene();
    let mut plan: Vec<Setting> = vec![(Method::Rk4, 0.002, 1e-6)];
    for decade in [1e-4, 1e-5, 1e-6] {
        for mantissa in [1.0, 0.5, 0.2] {
            plan.push((Method::Dp5, 0.02, mantissa * decade));
        }
    }
    plan.push((Method::Dp5, 0.02, 1e-7));
    let kernel = |m: &Model| -> Box<dyn Kernel> {
        Box::new(GeneratedKernel::new(&m.chain).expect("case 1 has a checked-in kernel"))
    };
    let mut damped = scene.clone();
    damped.meta.name = "case01, line drag ×20 (control)".into();
    damped.hydrodynamics.normal_drag_coefficient *= 20.0;
    damped.hydrodynamics.tangential_drag_coefficient *= 20.0;
    for (scene, atol_ratio) in [(&scene, DEFAULT_ATOL_RATIO), (&scene, 1.0), (&damped, DEFAULT_ATOL_RATIO)] {
        println!("{}", scene.meta.name);
        let study = match accuracy::study(scene, &plan, atol_ratio, &kernel, 7, &|_| {}) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("error: {e}");
                std::process::exit(1);
            }
        };
        print!("{}", accuracy::table(&study));
        let first = accuracy::matched(&study, Method::Rk4, 0.002).and_then(|(_, runs)| runs.first().cloned());
        match first.map(|m| (m.speedup, m.evaluation_ratio)) {
            Some((speedup, evaluations)) => println!(
                "goal: {GOAL}x the speed (CPU time) of RK4 (2 ms) at its stopping-time accuracy, atol = {atol_ratio:e} × rtol: \
                 {} ({speedup:.2}x; evaluations RK4 / DP5 {evaluations:.2})\n",
                if speedup >= GOAL { "met" } else { "NOT met" }
            ),
            None => println!("goal: {GOAL}x, atol = {atol_ratio:e} × rtol: NOT met (no DP5 tolerance reaches it)\n"),
        }
    }
}
