//! # kanestop-codegen
//!
//! The build-time generator of kanestop: it expands the planar Kane quantities of a
//! restraining chain (Huston's form of Kane's method, Liu et al., Eqs. 1–27) into flat,
//! specialised Rust kernels.
//!
//! The generator is a pure function from an input model to code: [`generate`] takes a
//! [`Variant`] (the number of bodies and the water switch, from the shared crate
//! `kanestop-chain`) and returns the emitted source. The runtime reads the same
//! `kanestop-chain` types, so the generator and the runtime can never disagree about which
//! parameters a kernel folds; it never depends on this crate (docs/architecture.md).
//!
//! - [`expr`]: the hash-consed expression DAG (sharing, folding, exact zeros);
//! - `body` (private): one body's share of every recursion, the steps both expansions drive;
//! - [`planar`]: the unrolled expansion of the chain's kinematics, a_lp, f_l and the O(N) solve;
//! - [`rolled`]: the same steps expanded once per body kind, for a chain of any N;
//! - [`emit`]: Rust emission (quote → syn → prettyplease), one file per variant;
//! - [`drivers`]: the rolled kernels' emission: their steps and the loops that drive them;
//! - [`loads`]: the load terms of Section 3.2, one function per load signature;
//! - [`scenes`]: the element counts the scene files need, for `build.rs` and the CLI.

pub(crate) mod body;
pub mod drivers;
pub mod emit;
pub mod expr;
pub mod loads;
pub mod planar;
pub mod rhs;
pub mod rolled;
pub mod scenes;

pub use emit::{generate, GeneratedFile};
use kanestop_chain::{Variant, Water};

/// The largest body count an unrolled kernel is expanded for (the build script's kernels,
/// `kanestop codegen --fold`): the expression DAG recurses with N and overflows the build
/// script's default stack from about N = 490 (docs/model-choices.md). Above it the rolled
/// kernel serves.
pub const MAX_UNROLLED_BODIES: usize = 400;

/// Body counts generated for the tests (snapshots and generated-vs-reference checks) on top
/// of the counts the scenes need.
pub const TEST_BODY_COUNTS: [usize; 2] = [3, 5];

/// Both water variants of every count in `counts`, sorted and deduplicated.
pub fn variants_for(counts: &[usize]) -> Vec<Variant> {
    let mut out: Vec<Variant> =
        counts.iter().flat_map(|&n| [Variant::new(n, Water::Off), Variant::new(n, Water::On)]).collect();
    out.sort();
    out.dedup();
    out
}

/// The variants checked in under `generated/src/`: [`TEST_BODY_COUNTS`] and every count in
/// `scene_counts` (the paper's scenes'), each dry and wet.
pub fn checked_in_variants(scene_counts: &[usize]) -> Vec<Variant> {
    let counts: Vec<usize> = scene_counts.iter().copied().chain(TEST_BODY_COUNTS).collect();
    variants_for(&counts)
}

/// The folded kernel checked in (`generated/src/folded_case01.rs`): the paper's case 1 with
/// its parameters as literals, for the benchmark of folded against kept parameters and the
/// tests of the folded path. Its values come from the runtime's model of
/// `scenes/paper/case01.toml`, so `kanestop codegen --write` and `tests/generated_fresh.rs`
/// write and check it; [`checked_in_files`] has only its registry `folded.rs`.
pub const CHECKED_IN_FOLDED: &str = "folded_case01";

/// Every checked-in file as (name under `generated/src/`, text): the unrolled kernels, the
/// registry `kernels.rs`, which lists them, the two rolled kernels (any N), the load
/// code of every signature (`loads.rs`) and the fused right-hand sides (`rhs.rs`), for the
/// body counts `scene_counts` of the paper's scenes (the caller reads them: the generator
/// does no I/O).
pub fn checked_in_files(scene_counts: &[usize]) -> Vec<(String, String)> {
    let variants = checked_in_variants(scene_counts);
    let mut out: Vec<(String, String)> = variants
        .iter()
        .map(|&v| {
            let g = generate(v);
            (g.file_name, g.source)
        })
        .collect();
    out.push(("kernels.rs".to_string(), emit::registry(&variants)));
    for water in [Water::Off, Water::On] {
        let rolled = drivers::generate_rolled(water);
        out.push((rolled.file_name, rolled.source));
    }
    out.push(("folded.rs".to_string(), emit::folded_registry(&[(CHECKED_IN_FOLDED.to_string(), None)])));
    out.push(("loads.rs".to_string(), loads::generate_loads().source));
    out.push(("rhs.rs".to_string(), rhs::generate_rhs().source));
    out
}
