//! The paper's cases 1, 2, 14 and 17 against Table 3 (the full 19-case check is
//! `cargo run --release -- batch scenes/paper --tolerance 0.05`).

use kanestop_runtime::model::Model;
use kanestop_runtime::paper::CASES;
use kanestop_runtime::reference::ReferenceKernel;
use kanestop_runtime::report::break_exceedances;
use kanestop_runtime::simulate::{self, RunResult, Stop};

fn run(number: usize) -> (Model, RunResult) {
    let case = CASES.iter().find(|c| c.number == number).unwrap();
    let model = Model::new(&case.scene()).unwrap();
    let result = simulate::run(&model, Box::new(ReferenceKernel::new(&model.chain)));
    (model, result)
}

#[test]
fn cases_1_2_14_17_reproduce_table_3() {
    let numbers = [1, 2, 14, 17];
    let runs: Vec<(Model, RunResult)> =
        std::thread::scope(|s| numbers.map(|n| s.spawn(move || run(n))).map(|h| h.join().unwrap()).to_vec());
    let mut summary = Vec::new();
    for (n, (model, r)) in numbers.iter().zip(&runs) {
        let paper = model.scene.meta.paper_stopping_time.unwrap();
        assert_eq!(r.stop, Stop::ShipStopped, "case {n} did not stop: {:?}", r.stop);
        let t = r.stopping_time.unwrap();
        let rel = (t - paper) / paper;
        summary.push(format!("case {n}: {t:.3} s vs {paper:.3} s ({:+.2} %)", 100.0 * rel));
        assert!(rel.abs() < 0.05, "case {n}: stopping time {t:.3} s vs Table 3 {paper:.3} s ({:+.2} %)", 100.0 * rel);
        assert!(r.max_energy_drift < 0.005, "case {n}: energy balance drift {:.2e}", r.max_energy_drift);
        let over = break_exceedances(model, r);
        assert!(over.is_empty(), "case {n}: break load exceeded at {over:?}");
    }
    // The order of the cases by stopping time is Table 3's: 2 < 1 < 14 < 17.
    let times: Vec<f64> = runs.iter().map(|(_, r)| r.stopping_time.unwrap()).collect();
    assert!(times[1] < times[0] && times[0] < times[2] && times[2] < times[3], "order: {summary:?}");
    // The anchor starts to slide about 1.5 s after the start in case 1.
    let start = runs[0].1.anchor_start().expect("the anchor slides in case 1");
    assert!((start - 1.5).abs() < 0.5, "case 1: anchor starts at {start:.3} s");
    println!("{}", summary.join("\n"));
}
