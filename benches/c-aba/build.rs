//! Compiles `aba.c` with the system C compiler, `-O3` in every profile (the comparator is
//! timed as a C programmer would build it for speed), for the portable target the Rust
//! crates are built for (no `-march`).
fn main() {
    println!("cargo:rerun-if-changed=aba.c");
    println!("cargo:rerun-if-changed=aba.h");
    cc::Build::new().file("aba.c").opt_level(3).warnings(true).extra_warnings(true).compile("kanestop_c_aba");
}
