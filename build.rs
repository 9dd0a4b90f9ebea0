//! Build script of the `kanestop` binary.
//!
//! The kernels are generated where they are compiled: `generated/build.rs` has
//! `kanestop-codegen` emit, into OUT_DIR, a kernel for every element count of the scenes
//! under `scenes/` that is not checked in under `generated/src/` (and for the counts in
//! `KANESTOP_EXTRA_BODY_COUNTS`); see docs/codegen.md. This script only declares what the
//! binary depends on.

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=scenes");
}
