//! Snapshots of the generated source for small chains, every variant: a change to the
//! generator shows as a reviewable diff under `tests/snapshots/`.

use kanestop_chain::{Variant, Water};
use kanestop_codegen::generate;

fn snapshot(n: usize, water: Water) {
    let file = generate(Variant::new(n, water));
    insta::assert_snapshot!(file.file_name.trim_end_matches(".rs"), file.source);
}

#[test]
fn chain3_dry() {
    snapshot(3, Water::Off);
}

#[test]
fn chain3_wet() {
    snapshot(3, Water::On);
}

#[test]
fn chain5_dry() {
    snapshot(5, Water::Off);
}

#[test]
fn chain5_wet() {
    snapshot(5, Water::On);
}

/// Only non-zero entries are emitted: a dry kernel reads no added mass, no rod centroid
/// height and no joint height beyond B_2.
#[test]
fn structural_zeros_are_not_emitted() {
    let dry = generate(Variant::new(5, Water::Off)).source;
    assert!(!dry.contains("added_mass"));
    let wet = generate(Variant::new(5, Water::On)).source;
    assert!(wet.contains("p[1].added_mass") && !wet.contains("p[0].added_mass") && !wet.contains("p[4].added_mass"));
    for k in 1..4 {
        assert!(!wet.contains(&format!("p[{k}].centroid[1]")), "rod B_{} centroid height", k + 1);
    }
    for k in 2..5 {
        assert!(!wet.contains(&format!("p[{k}].joint[1]")), "joint height of B_{}", k + 1);
    }
}
