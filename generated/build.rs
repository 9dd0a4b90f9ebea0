//! Generates the kernels that are not checked in: the body counts of the scenes under
//! `../scenes` without a file in `src/`, and the counts listed in the environment variable
//! `KANESTOP_EXTRA_BODY_COUNTS` (comma-separated, e.g. `12,24,100,200` for the benchmarks).
//! They go to OUT_DIR with a registry `extra.rs` that `src/lib.rs` includes.

use std::path::Path;

use kanestop_codegen::emit::{generate, out_dir_registry};
use kanestop_codegen::variants_for;

fn main() {
    let manifest = std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR");
    let out = std::env::var("OUT_DIR").expect("cargo sets OUT_DIR");
    let scenes = Path::new(&manifest).join("../scenes");
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=src/kernels.rs");
    println!("cargo:rerun-if-env-changed=KANESTOP_EXTRA_BODY_COUNTS");
    if scenes.is_dir() {
        println!("cargo:rerun-if-changed={}", scenes.display());
        for file in kanestop_codegen::scenes::scene_files(&scenes) {
            println!("cargo:rerun-if-changed={}", file.display());
        }
    }
    let mut counts = kanestop_codegen::scenes::body_counts(&scenes);
    if let Ok(extra) = std::env::var("KANESTOP_EXTRA_BODY_COUNTS") {
        for part in extra.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            match part.parse::<usize>() {
                Ok(n) if n >= 3 => counts.push(n),
                _ => panic!("KANESTOP_EXTRA_BODY_COUNTS: `{part}` is not a body count ≥ 3"),
            }
        }
    }
    let wanted: Vec<_> = variants_for(&counts)
        .into_iter()
        .filter(|v| !Path::new(&manifest).join("src").join(format!("{}.rs", v.module())).exists())
        .collect();
    for v in &wanted {
        let file = generate(*v);
        write_if_changed(&Path::new(&out).join(&file.file_name), &file.source);
    }
    write_if_changed(&Path::new(&out).join("extra.rs"), &out_dir_registry(&wanted));
}

fn write_if_changed(path: &Path, text: &str) {
    if std::fs::read_to_string(path).ok().as_deref() != Some(text) {
        std::fs::write(path, text).unwrap_or_else(|e| panic!("cannot write {}: {e}", path.display()));
    }
}
