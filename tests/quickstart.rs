//! docs/quickstart.md as a user meets it: every `cargo run --release -- …` command of its
//! `sh` blocks runs (from a folder that holds the repository's `scenes/`, as the root does),
//! exits as the text says (0, or 4 for a failed design check), and prints every line of the
//! `text` block that follows it; the TOML blocks are the example files' own lines.

mod scratch;
use scratch::Scratch;

use std::path::Path;
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The fenced blocks of a Markdown text: (language, lines).
fn blocks(text: &str) -> Vec<(String, Vec<String>)> {
    let mut out = Vec::new();
    let mut open: Option<(String, Vec<String>)> = None;
    for line in text.lines() {
        match (line.strip_prefix("```"), open.take()) {
            (Some(_), Some(block)) => out.push(block),
            (Some(lang), None) => open = Some((lang.trim().to_string(), Vec::new())),
            (None, Some(mut block)) => {
                block.1.push(line.to_string());
                open = Some(block);
            }
            (None, None) => {}
        }
    }
    out
}

#[test]
fn the_quickstart_runs_as_written() {
    let doc = std::fs::read_to_string(root().join("docs/quickstart.md")).unwrap();
    let blocks = blocks(&doc);
    let dir = Scratch::new("quickstart");
    std::os::unix::fs::symlink(root().join("scenes"), dir.join("scenes")).unwrap();
    let mut commands = 0;
    for (i, (lang, lines)) in blocks.iter().enumerate() {
        if lang != "sh" {
            continue;
        }
        assert_eq!(lines.len(), 1, "one command a block: {lines:?}");
        let args: Vec<&str> =
            lines[0].strip_prefix("cargo run --release -- ").expect("a kanestop command").split_whitespace().collect();
        let out = Command::new(env!("CARGO_BIN_EXE_kanestop")).args(&args).current_dir(&*dir).output().unwrap();
        let (stdout, stderr) = (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
        assert!(matches!(out.status.code(), Some(0 | 4)), "{}: {:?}\n{stdout}{stderr}", lines[0], out.status);
        if let Some((lang, shown)) = blocks.get(i + 1) {
            if lang == "text" {
                let printed: Vec<&str> = stdout.lines().map(str::trim_end).collect();
                for line in shown.iter().filter(|l| !l.trim().is_empty()) {
                    assert!(printed.contains(&line.trim_end()), "{}: no line {line:?} in\n{stdout}", lines[0]);
                }
            }
        }
        commands += 1;
    }
    assert_eq!(commands, 3, "the three commands of the walk-through");
    // The files it writes, as the text names them.
    for file in [
        "out/patrol_boat/history.csv",
        "out/patrol_boat/history.units.csv",
        "out/patrol_boat/ship-speed.svg",
        "out/patrol_boat_sweep/sweep.csv",
        "out/patrol_boat_sweep/heatmap-stopping_distance.svg",
        "out/patrol_boat_sensitivity/sensitivity.csv",
    ] {
        assert!(dir.join(file).is_file(), "{file} not written");
    }
    // The TOML blocks are the example files, line for line (comments aside).
    for (name, lang_block) in [("patrol_boat", 0), ("patrol_boat_sweep", 1)] {
        let toml: Vec<&(String, Vec<String>)> = blocks.iter().filter(|b| b.0 == "toml").collect();
        let file = std::fs::read_to_string(root().join(format!("scenes/examples/{name}.toml"))).unwrap();
        let own: Vec<&str> = file.lines().filter(|l| !l.starts_with('#')).skip_while(|l| l.is_empty()).collect();
        assert_eq!(own, toml[lang_block].1.iter().map(String::as_str).collect::<Vec<_>>(), "{name}.toml");
    }
}
