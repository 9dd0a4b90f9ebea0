//! No panic on any command line: random subcommands, flags and values (a fixed seed) each end
//! with a documented exit code (0–4) and, when not 0, a message on standard error.

mod scratch;
use scratch::Scratch;

use std::process::Command;

use rand::rngs::StdRng;
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};

#[test]
fn random_command_lines_end_cleanly() {
    let dir = Scratch::new("fuzz");
    let short = dir.join("short.toml");
    std::fs::write(&short, kanestop_runtime::paper::DEFAULT_SCENE.replace("end_time = 60.0", "end_time = 0.02"))
        .unwrap();
    let garbage = dir.join("garbage.toml");
    std::fs::write(&garbage, "[solver]\ndt = \"fast\"\n").unwrap();
    // A sweep of two short rows, and a shard file edited to nonsense (for `sweep merge`).
    let spec = dir.join("spec.toml");
    std::fs::write(&spec, "base = \"short.toml\"\n[[axis]]\npath = \"anchor.mass\"\nvalues = [40000.0, 42000.0]\n")
        .unwrap();
    let shard = dir.join("shard.json");
    std::fs::write(
        &shard,
        r#"{"format": "kanestop-sweep-shard/1", "shard": {"index": 5, "count": 0}, "rows_total": 1e30}"#,
    )
    .unwrap();
    let (short, garbage) = (short.display().to_string(), garbage.display().to_string());
    let (spec, shard) = (spec.display().to_string(), shard.display().to_string());
    let out_dir = dir.join("out").display().to_string();
    let values: Vec<String> = [
        "0",
        "-1",
        "1e-3",
        "0.01",
        "nan",
        "inf",
        "1e308",
        "abc",
        "",
        "rk4",
        "dp5",
        "euler",
        "ship_x",
        "bodies",
        "x_46",
        "/nonexistent/x",
        "/",
        "reference",
        "generated",
        "rk4,dp5@0.01",
        "dp5@x",
    ]
    .iter()
    .map(|s| s.to_string())
    .chain(["0/1", "1/0", "3/2", "1e300", "stopping_time,bogus", "none"].map(String::from))
    .chain([short.clone(), garbage.clone(), out_dir.clone(), spec.clone(), shard.clone()])
    .collect();
    let flags = [
        "--out",
        "--plot",
        "--json",
        "--verbose",
        "--kernel",
        "--integrator",
        "--dt",
        "--rtol",
        "--atol",
        "--end-time",
        "--output-interval",
        "--channels",
        "--state",
        "--scene",
        "--tolerance",
        "--methods",
        "--repeats",
        "--atol-ratio",
        "--write",
        "--root",
        "--jobs",
        "--shard",
        "--shards",
        "--resume",
        "--checkpoint",
        "--slurm",
        "--heatmap",
        "--step",
        "--uncertain",
        "--spec",
        "--bogus",
    ];
    let mut rng = StdRng::seed_from_u64(16);
    let subcommands =
        ["run", "eval", "plot", "codegen", "report", "sensitivity", "batch", "sweep", "merge", "help", "nope"];
    for _ in 0..100 {
        let sub = *subcommands.choose(&mut rng).unwrap();
        let mut args: Vec<String> = vec![sub.to_string()];
        match sub {
            // Only cheap work: a short scene, or input that is refused before any run.
            "run" | "plot" => args.push([short.clone(), garbage.clone()].choose(&mut rng).unwrap().clone()),
            "report" => args.extend(["accuracy".to_string(), garbage.clone()]),
            "sensitivity" => args = vec!["report".into(), "sensitivity".into(), garbage.clone()],
            "batch" => args.push("/nonexistent".to_string()),
            "sweep" => args.push([spec.clone(), garbage.clone()].choose(&mut rng).unwrap().clone()),
            "merge" => {
                let target = [shard.clone(), out_dir.clone()].choose(&mut rng).unwrap().clone();
                args = vec!["sweep".into(), "merge".into(), target];
            }
            _ => {}
        }
        for _ in 0..rng.gen_range(0..4) {
            args.push(flags.choose(&mut rng).unwrap().to_string());
            if rng.gen_bool(0.8) {
                args.push(values.choose(&mut rng).unwrap().clone());
            }
        }
        if sub == "run" && !args.iter().any(|a| a == "--end-time") {
            args.extend(["--end-time".to_string(), "0.02".to_string()]);
        }
        if sub == "codegen" && args.iter().any(|a| a == "--write") {
            continue; // would rewrite the checked-in kernels
        }
        let out = Command::new(env!("CARGO_BIN_EXE_kanestop")).args(&args).current_dir(&dir).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        let code = out.status.code();
        assert!(!stderr.contains("panicked"), "{args:?} panicked: {stderr}");
        assert!(matches!(code, Some(0..=4)), "{args:?} exited {code:?}: {stderr}");
        if code != Some(0) {
            assert!(!stderr.trim().is_empty(), "{args:?} exited {code:?} with no message");
        }
    }
}
