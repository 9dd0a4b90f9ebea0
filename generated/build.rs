//! Generates the kernels that are not checked in: the body counts of the scenes under
//! `../scenes` without a file in `src/`, and the counts listed in the environment variable
//! `KANESTOP_EXTRA_BODY_COUNTS` (comma-separated, e.g. `12,24,100,200` for the benchmarks).
//! They go to OUT_DIR with a registry `extra.rs` that `src/lib.rs` includes. The folded
//! kernels in the folder `KANESTOP_FOLDED_KERNELS` names (`kanestop codegen --scene SCENE
//! --fold DIR`) are remade from their parameters there and listed in `folded.rs`.
//!
//! Counts above `kanestop_codegen::MAX_UNROLLED_BODIES` (400) are not generated: the generator's expression DAG
//! recurses and overflows the build script's default stack from about N = 490 (with a
//! 256 MB stack N = 518 builds in 15 min and 3.9 GB). Such a scene, from `../scenes`, is
//! skipped with a cargo warning and runs on the rolled kernel (any N, checked in); in
//! `KANESTOP_EXTRA_BODY_COUNTS` it stops the build with this reason.

use std::path::{Path, PathBuf};

use kanestop_codegen::emit::{folded_registry, generate, out_dir_registry, refold};
use kanestop_codegen::variants_for;

/// The largest body count the build script generates a kernel for.
const MAX_GENERATED_BODIES: usize = kanestop_codegen::MAX_UNROLLED_BODIES;

fn main() {
    let manifest = std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR");
    let out = std::env::var("OUT_DIR").expect("cargo sets OUT_DIR");
    let scenes = Path::new(&manifest).join("../scenes");
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=src/kernels.rs");
    println!("cargo:rerun-if-env-changed=KANESTOP_EXTRA_BODY_COUNTS");
    if scenes.is_dir() {
        println!("cargo:rerun-if-changed={}", scenes.display());
        for file in scene_files(&scenes) {
            println!("cargo:rerun-if-changed={}", file.display());
        }
    }
    let mut counts = body_counts(&scenes);
    for n in counts.iter().filter(|&&n| n > MAX_GENERATED_BODIES) {
        println!(
            "cargo:warning=a scene under scenes/ has N = {n} bodies, above the {MAX_GENERATED_BODIES} the build script \
             generates unrolled kernels for: it runs on the rolled kernel"
        );
    }
    counts.retain(|&n| n <= MAX_GENERATED_BODIES);
    if let Ok(extra) = std::env::var("KANESTOP_EXTRA_BODY_COUNTS") {
        for part in extra.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            match part.parse::<usize>() {
                Ok(n) if (3..=MAX_GENERATED_BODIES).contains(&n) => counts.push(n),
                Ok(n) if n > MAX_GENERATED_BODIES => panic!(
                    "KANESTOP_EXTRA_BODY_COUNTS: {n} bodies is above the build script's limit of {MAX_GENERATED_BODIES} \
                     (the generator's recursion overflows the default stack from about N = 490); such a scene runs \
                     on the rolled kernel"
                ),
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
    let folded = folded_kernels(Path::new(&manifest), Path::new(&out));
    write_if_changed(&Path::new(&out).join("folded.rs"), &folded_registry(&folded));
}

/// The folded kernels in the folder `KANESTOP_FOLDED_KERNELS` names (written by `kanestop
/// codegen --scene SCENE --fold DIR`; a relative path is taken from the repository's root,
/// an empty value is no folder): every `folded_<name>.rs` in it, remade by this generator
/// from the `PARAMS` it lists (so it cannot go stale) into `out`, by name and path there.
fn folded_kernels(manifest: &Path, out: &Path) -> Vec<(String, Option<String>)> {
    println!("cargo:rerun-if-env-changed=KANESTOP_FOLDED_KERNELS");
    let Some(dir) = std::env::var_os("KANESTOP_FOLDED_KERNELS").filter(|d| !d.is_empty()) else { return Vec::new() };
    let dir = manifest.join("..").join(dir);
    let entries = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("KANESTOP_FOLDED_KERNELS: cannot read the folder {}: {e}", dir.display()));
    println!("cargo:rerun-if-changed={}", dir.display());
    let mut kernels = Vec::new();
    for path in entries.flatten().map(|e| e.path()) {
        let Some(name) = path.file_name().and_then(|n| n.to_str()).and_then(|n| n.strip_suffix(".rs")) else {
            continue;
        };
        if !name.starts_with("folded_") {
            continue;
        }
        println!("cargo:rerun-if-changed={}", path.display());
        let tail = &name["folded_".len()..];
        assert!(
            !tail.is_empty() && tail.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_'),
            "KANESTOP_FOLDED_KERNELS: {} is not named as `kanestop codegen --fold` names its files \
             (folded_ then lower-case letters, digits and _)",
            path.display()
        );
        assert!(
            name != kanestop_codegen::CHECKED_IN_FOLDED,
            "KANESTOP_FOLDED_KERNELS: {} has the name of the folded kernel checked in under generated/src; rename it",
            path.display()
        );
        let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
        let file = refold(&text, name).unwrap_or_else(|e| panic!("KANESTOP_FOLDED_KERNELS: {}: {e}", path.display()));
        if file.source != text {
            println!(
                "cargo:warning={} was written by another version of the generator: built from its PARAMS",
                path.display()
            );
        }
        let target = out.join(&file.file_name);
        write_if_changed(&target, &file.source);
        kernels.push((name.to_string(), Some(target.to_string_lossy().into_owned())));
    }
    kernels.sort();
    kernels
}

fn write_if_changed(path: &Path, text: &str) {
    if std::fs::read_to_string(path).ok().as_deref() != Some(text) {
        std::fs::write(path, text).unwrap_or_else(|e| panic!("cannot write {}: {e}", path.display()));
    }
}

/// Every `*.toml` below `dir`, sorted.
fn scene_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else { continue };
        for e in entries.flatten() {
            let path = e.path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|x| x == "toml") {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}

/// The sorted, distinct body counts of the scenes below `dir`; files that are not scenes
/// are skipped.
fn body_counts(dir: &Path) -> Vec<usize> {
    let mut counts: Vec<usize> = scene_files(dir)
        .iter()
        .filter_map(|p| std::fs::read_to_string(p).ok())
        .filter_map(|t| kanestop_codegen::scenes::body_count(&t).ok())
        .collect();
    counts.sort_unstable();
    counts.dedup();
    counts
}
