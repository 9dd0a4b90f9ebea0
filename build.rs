//! Build script of the `kanestop` binary.
//!
//! Its job is to have `kanestop-codegen` emit a kernel for every element count the scenes
//! need that is not checked in under `generated/`. The generator lands with its own
//! issue; until then the runtime evaluates every scene with the reference kernel and this
//! script only declares what it depends on.

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=scenes");
}
