//! µs per evaluation of the generalised accelerations ẍ (Eq. 27), gravity only, for the
//! generated O(N) fast path, the generated a_lp/f_l + Cholesky path and the reference, at
//! N = 12, 24, 46, 100, 200 (the sizes that are built), plus the water-on variant at N = 46.
//!
//! ```sh
//! KANESTOP_EXTRA_BODY_COUNTS=12,24,100,200 cargo bench --bench kernels
//! ```
//!
//! Without the variable only the checked-in sizes (3, 5, 46, 48, 50) have generated kernels
//! and the others are skipped. Medians of 15 batches of at least 20 ms each; the ratios are
//! measured side by side in one run. Results are recorded in docs/codegen.md. Then the
//! rolled kernel (any N) against the unrolled ones, to N = 520, and whole runs of paper cases
//! 1 and 17 with full physics. And issue 14's comparator (section `c_aba`): weight alone
//! through `Dynamics` (the generated, fused right-hand side, loads included) against a
//! hand-written planar articulated-body algorithm in C (`benches/c-aba`), alternated in one
//! run.

use std::hint::black_box;
use std::time::Instant;

use kanestop_chain::BodyKind;
use kanestop_runtime::chain::{box_inertia, Body, Chain, Shape};
use kanestop_runtime::forces::Forces;
use kanestop_runtime::generated::{available, Form, GeneratedKernel, SolvePath};
use kanestop_runtime::kernel::{AnchorDof, Assembly, Kernel};
use kanestop_runtime::reference::ReferenceKernel;

/// A paper-like chain of `n` bodies: a 5 t anchor, 1–10 m rods of 14–140 kg, a 500 t ship.
fn chain(n: usize, wet: bool) -> Chain {
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
        let mut rod = Body::rod(BodyKind::ChainLink, length, 0.07, 14.0 + 10.0 * (i % 5) as f64, joint);
        if wet {
            rod.added_mass = 1025.0 * std::f64::consts::PI * 0.14 * 0.14 / 4.0 * length;
            rod.added_inertia = rod.added_mass * length * length / 12.0;
        }
        bodies.push(rod);
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

/// A smooth, non-trivial state: small alternating angles, slow rates.
fn state(n: usize) -> (Vec<f64>, Vec<f64>) {
    let q = (0..n).map(|i| 0.05 * ((i as f64) * 0.7).sin()).collect();
    let u = (0..n).map(|i| 0.1 * ((i as f64) * 1.3).cos()).collect();
    (q, u)
}

/// Median µs per call of `f` over 15 batches of at least 20 ms.
fn time(mut f: impl FnMut()) -> f64 {
    let mut reps = 1usize;
    loop {
        let t = Instant::now();
        for _ in 0..reps {
            f();
        }
        if t.elapsed().as_secs_f64() >= 0.02 {
            break;
        }
        reps *= 2;
    }
    let mut samples: Vec<f64> = (0..15)
        .map(|_| {
            let t = Instant::now();
            for _ in 0..reps {
                f();
            }
            t.elapsed().as_secs_f64() * 1e6 / reps as f64
        })
        .collect();
    samples.sort_by(f64::total_cmp);
    samples[samples.len() / 2]
}

fn per_solve(kernel: &mut dyn Kernel, chain: &Chain, anchor: AnchorDof) -> f64 {
    let n = chain.len();
    let (q, u) = state(n);
    let mut forces = Forces::gravity_only(chain, 9.81);
    let mut scratch = Assembly::new(n);
    let mut qdd = vec![0.0; n];
    time(|| {
        let f = kernel.solve(black_box(&q), black_box(&u), anchor, 0.0, &mut forces, &mut scratch, &mut qdd).unwrap();
        black_box((f, &qdd));
    })
}

fn main() {
    // `cargo bench --bench kernels -- whole_rhs whole_runs`: only the named sections (solves,
    // rolled_vs_unrolled, fused_gravity, whole_rhs, folded, whole_runs, c_aba); none named: all.
    let only: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with('-')).collect();
    let wanted = |name: &str| only.is_empty() || only.iter().any(|o| o == name);
    let sections: [(&str, fn()); 6] = [
        ("rolled_vs_unrolled", rolled_vs_unrolled),
        ("fused_gravity", fused_gravity),
        ("whole_rhs", whole_rhs),
        ("folded", folded),
        ("whole_runs", whole_runs),
        ("c_aba", c_aba),
    ];
    if wanted("solves") {
        solves();
    }
    for (name, section) in sections {
        if wanted(name) {
            section();
        }
    }
}

/// Gravity-only solves by N, and the variants at N = 46.
fn solves() {
    let built = available();
    println!("µs per evaluation of qdd (gravity only, anchor free; median of 15 batches)");
    println!(
        "{:>5} {:>12} {:>14} {:>12} {:>10} {:>10}",
        "N", "generated", "gen a_lp/f_l", "reference", "ref/gen", "ref/a_lp"
    );
    let mut fast: Vec<(usize, f64)> = Vec::new();
    for n in [12, 24, 46, 100, 200] {
        if !built.contains(&(n, false)) {
            println!("{n:>5} (no generated kernel in this build: set KANESTOP_EXTRA_BODY_COUNTS)");
            continue;
        }
        let c = chain(n, false);
        let mut gen = GeneratedKernel::new(&c).unwrap();
        let mut asm = GeneratedKernel::new(&c).unwrap().with_solve_path(SolvePath::Assembled);
        let mut reference = ReferenceKernel::new(&c);
        let t_gen = per_solve(&mut gen, &c, AnchorDof::Free);
        let t_asm = per_solve(&mut asm, &c, AnchorDof::Free);
        let t_ref = per_solve(&mut reference, &c, AnchorDof::Free);
        fast.push((n, t_gen));
        println!("{n:>5} {t_gen:>12.2} {t_asm:>14.2} {t_ref:>12.1} {:>9.0}× {:>9.0}×", t_ref / t_gen, t_ref / t_asm);
    }
    if let (Some(&(n0, t0)), Some(&(n1, t1))) = (fast.iter().find(|x| x.0 == 46), fast.iter().find(|x| x.0 == 200)) {
        println!(
            "growth exponent of the fast path, N = {n0} → {n1}: {:.2}",
            (t1 / t0).ln() / (n1 as f64 / n0 as f64).ln()
        );
    }

    println!("\nvariants at N = 46 (µs per call)");
    println!("{:>22} {:>10} {:>10}", "", "water off", "water on");
    let (dry, wet) = (chain(46, false), chain(46, true));
    let mut rows: Vec<(&str, [f64; 2])> = Vec::new();
    let mut row = |name, f: &mut dyn FnMut(&Chain) -> f64| rows.push((name, [f(&dry), f(&wet)]));
    row("solve, anchor free", &mut |c| per_solve(&mut GeneratedKernel::new(c).unwrap(), c, AnchorDof::Free));
    row("solve, anchor stuck", &mut |c| per_solve(&mut GeneratedKernel::new(c).unwrap(), c, AnchorDof::Stuck));
    row("a_lp/f_l + Cholesky", &mut |c| {
        per_solve(&mut GeneratedKernel::new(c).unwrap().with_solve_path(SolvePath::Assembled), c, AnchorDof::Free)
    });
    row("assemble only", &mut |c| {
        let mut k = GeneratedKernel::new(c).unwrap();
        let (q, u) = state(c.len());
        let mut forces = Forces::gravity_only(c, 9.81);
        let mut out = Assembly::new(c.len());
        time(|| {
            k.assemble(black_box(&q), black_box(&u), &mut forces, &mut out);
            black_box(&out.mass);
        })
    });
    row("reference solve", &mut |c| per_solve(&mut ReferenceKernel::new(c), c, AnchorDof::Free));
    for (name, [a, b]) in rows {
        println!("{name:>22} {a:>10.2} {b:>10.2}");
    }
}

/// Weight alone, the loads included: the kernel handed `Forces::gravity_only`'s loads
/// (unrolled where built, and rolled) against the rolled solve with the weights fused into
/// its steps (`Kernel::fuse_loads` of weight alone), side by side, µs per call (wall median; CPU over the
/// whole measurement divided by its calls).
fn fused_gravity() {
    println!("\ngravity only, loads included: fed by the force modules vs fused (µs per solve, anchor free)");
    println!(
        "{:>5} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>12}",
        "N", "unrolled", "CPU", "rolled", "CPU", "fused", "CPU", "fused/best"
    );
    let built = available();
    for n in [12, 46, 200, 520] {
        let c = chain(n, false);
        let timed = |mut k: GeneratedKernel| {
            let cpu = thread_cpu();
            let mut calls = 0u64;
            let wall = per_solve_counted(&mut k, &c, &mut calls);
            (wall, (thread_cpu() - cpu) * 1e6 / calls as f64)
        };
        let unrolled =
            built.contains(&(n, false)).then(|| timed(GeneratedKernel::with_form(&c, Form::Unrolled).unwrap()));
        let rolled = timed(GeneratedKernel::with_form(&c, Form::Rolled).unwrap());
        let mut k = GeneratedKernel::with_form(&c, Form::Rolled).unwrap();
        assert!(k.fuse_loads(&kanestop_runtime::dynamics::fused_loads(&Forces::gravity_only(&c, 9.81)).unwrap()));
        let fused = timed(k);
        let best = unrolled.map_or(rolled.0, |u| u.0.min(rolled.0));
        let (u, uc) =
            unrolled.map_or(("—".to_string(), "—".to_string()), |(w, c)| (format!("{w:.2}"), format!("{c:.2}")));
        println!(
            "{n:>5} {u:>9} {uc:>9} {:>9.2} {:>9.2} {:>9.2} {:>9.2} {:>11.2}×",
            rolled.0,
            rolled.1,
            fused.0,
            fused.1,
            fused.0 / best
        );
    }
}

/// The whole right-hand side of case 1 (N = 46, its full physics: water, seabed, drag,
/// buoyancy, the ship): kinematics, loads and the O(N) solve, at the scene's starting state
/// with the anchor sliding under friction. The kernels fed by the force modules against the
/// same kernels running the generated load code of the scene's signature
/// (`Kernel::fuse_loads`), side by side, µs per call (wall median; CPU over the whole
/// measurement divided by its calls).
fn whole_rhs() {
    use kanestop_runtime::dynamics::fused_loads;
    use kanestop_runtime::model::Model;
    use kanestop_runtime::paper::CASES;
    println!("\nwhole right-hand side, case 1 physics, N = 46: loads by the force modules vs generated (µs per solve)");
    println!("{:>10} {:>9} {:>9} {:>9} {:>9} {:>12}", "form", "fed", "CPU", "fused", "CPU", "fused/fed");
    let model = Model::new(&CASES[0].scene()).unwrap();
    let (q, u) = (model.q0.clone(), model.u0.clone());
    let n = model.body_count();
    for form in [Form::Unrolled, Form::Rolled] {
        let timed = |fuse: bool| {
            let mut k = GeneratedKernel::with_form(&model.chain, form).unwrap();
            let mut forces = Forces::new(&model);
            if fuse {
                assert!(k.fuse_loads(&fused_loads(&forces).unwrap()));
            }
            let mut scratch = Assembly::new(n);
            let mut qdd = vec![0.0; n];
            let (cpu, mut calls) = (thread_cpu(), 0u64);
            let wall = time(|| {
                calls += 1;
                let f =
                    k.solve(black_box(&q), black_box(&u), AnchorDof::Free, 0.3, &mut forces, &mut scratch, &mut qdd);
                black_box((f.unwrap(), &qdd));
            });
            (wall, (thread_cpu() - cpu) * 1e6 / calls as f64)
        };
        let (fed, fused) = (timed(false), timed(true));
        println!(
            "{:>10} {:>9.2} {:>9.2} {:>9.2} {:>9.2} {:>11.2}×",
            form.name(),
            fed.0,
            fed.1,
            fused.0,
            fused.1,
            fused.0 / fed.0
        );
    }
}

/// Parameters kept or folded (docs/codegen.md): case 1's right-hand side with the loads of
/// the force modules on the unrolled kernel with the parameters as inputs and on the checked-in
/// kernel with case 1's numbers folded in, beside the default (the fused right-hand side on the
/// rolled steps), side by side, µs per solve (wall median; CPU over the measurement).
fn folded() {
    use kanestop_runtime::dynamics::fused_loads;
    use kanestop_runtime::model::Model;
    use kanestop_runtime::paper::CASES;
    println!("\nparameters kept or folded, case 1 (N = 46, water on), anchor free (µs per solve)");
    println!("{:>34} {:>9} {:>9}", "kernel", "wall", "CPU");
    let model = Model::new(&CASES[0].scene()).unwrap();
    let (q, u) = (model.q0.clone(), model.u0.clone());
    let n = model.body_count();
    let timed = |form: Form, fuse: bool| {
        let mut k = GeneratedKernel::with_form(&model.chain, form).unwrap();
        let mut forces = Forces::new(&model);
        if fuse {
            assert!(k.fuse_loads(&fused_loads(&forces).unwrap()));
        }
        let (mut scratch, mut qdd) = (Assembly::new(n), vec![0.0; n]);
        let (cpu, mut calls) = (thread_cpu(), 0u64);
        let wall = time(|| {
            calls += 1;
            let f = k.solve(black_box(&q), black_box(&u), AnchorDof::Free, 0.3, &mut forces, &mut scratch, &mut qdd);
            black_box((f.unwrap(), &qdd));
        });
        (wall, (thread_cpu() - cpu) * 1e6 / calls as f64)
    };
    for (name, form, fuse) in [
        ("unrolled, kept, force modules", Form::Unrolled, false),
        ("unrolled, folded, force modules", Form::Folded, false),
        ("rolled, fused (the default)", Form::Rolled, true),
    ] {
        let (wall, cpu) = timed(form, fuse);
        println!("{name:>34} {wall:>9.2} {cpu:>9.2}");
    }
}

/// CPU time of this thread so far, s (Linux: the first field of schedstat, ns on the CPU).
fn thread_cpu() -> f64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next().and_then(|t| t.parse::<f64>().ok()))
        .map_or(f64::NAN, |ns| ns * 1e-9)
}

/// The rolled kernel (any N) against the unrolled one where the build has it, side by side:
/// µs per solve (wall median, and CPU time over the whole measurement divided by its calls).
fn rolled_vs_unrolled() {
    println!("\nrolled vs unrolled kernel, solve with the anchor free, gravity only (µs per call)");
    println!(
        "{:>5} {:>10} {:>10} {:>12} {:>12} {:>8}",
        "N", "rolled", "rolled CPU", "unrolled", "unrolled CPU", "ratio"
    );
    let built = available();
    let mut rolled_at = Vec::new();
    for n in [12, 24, 46, 100, 200, 520] {
        let c = chain(n, false);
        let timed = |form: Form| {
            let mut k = GeneratedKernel::with_form(&c, form).unwrap();
            let cpu = thread_cpu();
            let mut calls = 0u64;
            let wall = per_solve_counted(&mut k, &c, &mut calls);
            (wall, (thread_cpu() - cpu) * 1e6 / calls as f64)
        };
        let (rolled, rolled_cpu) = timed(Form::Rolled);
        rolled_at.push((n, rolled));
        if built.contains(&(n, false)) {
            let (unrolled, unrolled_cpu) = timed(Form::Unrolled);
            println!(
                "{n:>5} {rolled:>10.2} {rolled_cpu:>10.2} {unrolled:>12.2} {unrolled_cpu:>12.2} {:>7.2}×",
                rolled / unrolled
            );
        } else {
            println!("{n:>5} {rolled:>10.2} {rolled_cpu:>10.2} {:>12} {:>12} {:>8}", "not built", "", "");
        }
    }
    if let (Some(&(n0, t0)), Some(&(n1, t1))) = (rolled_at.iter().find(|x| x.0 == 46), rolled_at.last()) {
        println!(
            "growth exponent of the rolled kernel, N = {n0} → {n1}: {:.2}",
            (t1 / t0).ln() / (n1 as f64 / n0 as f64).ln()
        );
    }
}

/// As [`per_solve`] (anchor free), counting the calls made.
fn per_solve_counted(kernel: &mut dyn Kernel, chain: &Chain, calls: &mut u64) -> f64 {
    let n = chain.len();
    let (q, u) = state(n);
    let mut forces = Forces::gravity_only(chain, 9.81);
    let mut scratch = Assembly::new(n);
    let mut qdd = vec![0.0; n];
    time(|| {
        *calls += 1;
        let f = kernel.solve(black_box(&q), black_box(&u), AnchorDof::Free, 0.0, &mut forces, &mut scratch, &mut qdd);
        black_box((f.unwrap(), &qdd));
    })
}

/// Whole runs of paper cases with full physics (RK4, dt = 0.002 s, generated kernel): wall
/// time of `simulate::run`, median of 5, one core.
fn whole_runs() {
    use kanestop_runtime::model::Model;
    use kanestop_runtime::paper::CASES;
    use kanestop_runtime::simulate;
    println!(
        "
whole runs, full physics, RK4 dt = 0.002 s, generated kernel (median of 5)"
    );
    println!(
        "{:>8} {:>12} {:>10} {:>10} {:>12} {:>12} {:>12}",
        "case", "simulated s", "wall s", "CPU s", "solves", "µs/solve", "CPU µs/solve"
    );
    for number in [1, 17] {
        let model = Model::new(&CASES[number - 1].scene()).unwrap();
        let (mut walls, mut cpus) = (Vec::new(), Vec::new());
        let mut last = None;
        for _ in 0..5 {
            let cpu = thread_cpu();
            let r = simulate::run(&model, Box::new(GeneratedKernel::new(&model.chain).unwrap()));
            cpus.push(thread_cpu() - cpu);
            walls.push(r.wall_time.as_secs_f64());
            last = Some(r);
        }
        walls.sort_by(f64::total_cmp);
        cpus.sort_by(f64::total_cmp);
        let r = last.unwrap();
        let (wall, cpu) = (walls[walls.len() / 2], cpus[cpus.len() / 2]);
        let solves = r.rhs_evaluations as f64;
        println!(
            "{:>8} {:>12.3} {:>10.3} {:>10.3} {:>12} {:>12.2} {:>12.2}",
            number,
            r.t_end,
            wall,
            cpu,
            r.rhs_evaluations,
            1e6 * wall / solves,
            1e6 * cpu / solves
        );
    }
}

/// A right-hand side timed by [`c_aba`]: `(q, u, qdd)`.
type Solver<'a> = dyn FnMut(&[f64], &[f64], &mut [f64]) + 'a;

/// Weight alone, anchor free: the generated right-hand side as the integrator calls it
/// (`Dynamics::accelerations`, the weights fused into the rolled or unrolled kernel's steps)
/// against the hand-written C articulated-body algorithm (`kanestop_c_aba`, its own `sin` and
/// `cos`, gravity as the base's acceleration), over the same 1 000 smooth states, the two
/// alternated for 7 rounds: medians of CPU µs per call (this thread) and of wall µs.
/// `tests/c_aba.rs` checks the two give the same accelerations.
fn c_aba() {
    use kanestop_runtime::dynamics::Dynamics;
    println!("\nweight alone, anchor free: generated (Dynamics) vs hand-written C planar ABA (µs per call, medians of 7 rounds)");
    println!("{:>5} {:>10} {:>10} {:>10} {:>10} {:>14}", "N", "generated", "CPU", "C ABA", "CPU", "C / generated");
    for n in [12, 46, 200, 520] {
        let c = chain(n, false);
        let states: Vec<(Vec<f64>, Vec<f64>)> = (0..1000)
            .map(|s| {
                let phase = s as f64 * 0.01;
                let q = (0..n).map(|i| 0.05 * ((i as f64) * 0.7 + phase).sin()).collect();
                let u = (0..n).map(|i| 0.1 * ((i as f64) * 1.3 + phase).cos()).collect();
                (q, u)
            })
            .collect();
        let kernel = GeneratedKernel::new(&c).unwrap();
        let mut dynamics = Dynamics::new(Box::new(kernel), Forces::gravity_only(&c, 9.81), AnchorDof::Free);
        let bodies = c
            .bodies
            .iter()
            .map(|b| kanestop_c_aba::Body { mass: b.mass, inertia: b.inertia[1], centroid: b.centroid, joint: b.joint })
            .collect();
        let mut aba = kanestop_c_aba::Aba::new(bodies, 9.81);
        let mut qdd = vec![0.0; n];
        let passes = (20_000 / n).max(2);
        let calls = (passes * states.len()) as f64;
        let mut timed = |f: &mut Solver| {
            let (t, cpu) = (Instant::now(), thread_cpu());
            for _ in 0..passes {
                for (q, u) in &states {
                    f(black_box(q), black_box(u), &mut qdd);
                }
                black_box(&qdd);
            }
            (t.elapsed().as_secs_f64() * 1e6 / calls, (thread_cpu() - cpu) * 1e6 / calls)
        };
        let (mut generated, mut c_aba) = (Vec::new(), Vec::new());
        for round in 0..7 {
            let mut ours = |q: &[f64], u: &[f64], qdd: &mut [f64]| {
                dynamics.accelerations(q, u, qdd).unwrap();
            };
            let mut theirs = |q: &[f64], u: &[f64], qdd: &mut [f64]| aba.accelerations(q, u, qdd);
            if round % 2 == 0 {
                generated.push(timed(&mut ours));
                c_aba.push(timed(&mut theirs));
            } else {
                c_aba.push(timed(&mut theirs));
                generated.push(timed(&mut ours));
            }
        }
        let median = |v: &[(f64, f64)], pick: fn(&(f64, f64)) -> f64| {
            let mut x: Vec<f64> = v.iter().map(pick).collect();
            x.sort_by(f64::total_cmp);
            x[x.len() / 2]
        };
        let (gw, gc) = (median(&generated, |x| x.0), median(&generated, |x| x.1));
        let (cw, cc) = (median(&c_aba, |x| x.0), median(&c_aba, |x| x.1));
        println!("{n:>5} {gw:>10.3} {gc:>10.3} {cw:>10.3} {cc:>10.3} {:>13.2}×", cc / gc);
    }
}
