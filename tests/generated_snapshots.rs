//! Snapshots of the generated source for small chains, every variant, the rolled kernels and
//! the load code of every signature: a change to the generator shows as a reviewable diff
//! under `tests/snapshots/`.

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

fn rolled_snapshot(water: Water) {
    let file = kanestop_codegen::drivers::generate_rolled(water);
    insta::assert_snapshot!(file.file_name.trim_end_matches(".rs"), file.source);
}

#[test]
fn rolled_dry() {
    rolled_snapshot(Water::Off);
}

#[test]
fn rolled_wet() {
    rolled_snapshot(Water::On);
}

/// The generated loads of every load signature (`generated/src/loads.rs`): a change to a
/// term's emitted code shows here, per signature.
#[test]
fn loads() {
    insta::assert_snapshot!("loads", kanestop_codegen::loads::generate_loads().source);
}

/// The fused right-hand side of every load signature (`generated/src/rhs.rs`): which steps
/// and load functions each drives, in which order.
#[test]
fn rhs() {
    insta::assert_snapshot!("rhs", kanestop_codegen::rhs::generate_rhs().source);
}

/// The rolled steps fold per body kind what the unrolled kernels fold per body: the dry
/// kernel reads no added mass, no step reads the anchor's inertia, the rods' centroid height
/// or the ship's added mass, and only B_2 (the first) reads its joint height.
#[test]
fn rolled_steps_fold_the_structural_zeros_of_their_kind() {
    use kanestop_codegen::rolled::{steps, Kind};
    assert!(!kanestop_codegen::drivers::generate_rolled(Water::Off).source.contains("added_mass"));
    let text = kanestop_codegen::drivers::generate_rolled(Water::On).source;
    for step in steps(Water::On) {
        let start = text.find(&format!("fn {}(", step.name)).expect("every step is emitted");
        let end = text[start..].find("\n}\n").map_or(text.len(), |e| start + e);
        let body = &text[start..end];
        let reads = |field: &str| body.contains(&format!("p.{field}"));
        match step.kind {
            Some(Kind::Anchor) => assert!(!reads("inertia") && !reads("added_mass"), "{}", step.name),
            Some(Kind::Rod) => assert!(!reads("centroid[1]") && !reads("joint[1]"), "{}", step.name),
            Some(Kind::First) => assert!(!reads("centroid[1]"), "{}", step.name),
            Some(Kind::Ship) => assert!(!reads("added_mass") && !reads("joint[1]"), "{}", step.name),
            None => assert!(!body.contains("p."), "{} reads no parameters", step.name),
        }
    }
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
