//! `docs/codegen.md`'s operation-count tables are rendered from `kanestop_codegen::generate`
//! (what `kanestop codegen` prints) for case 1's N = 46 and from the rolled kernels' steps: a
//! stale table fails this test and is rewritten between its markers, as `docs_fresh.rs` does
//! for docs/scenes.md. So is the table of case 1's counts with the parameters folded.

use kanestop_chain::{Variant, Water};
use kanestop_codegen::generate;

const BEGIN: &str = "<!-- opcounts:begin";
const END: &str = "<!-- opcounts:end -->";

fn spaced(n: usize) -> String {
    // 6446 → "6 446", as the docs write thousands.
    let s = n.to_string();
    let mut out = String::new();
    for (i, c) in s.chars().enumerate() {
        if i > 0 && (s.len() - i) % 3 == 0 {
            out.push(' ');
        }
        out.push(c);
    }
    out
}

fn render(n: usize) -> String {
    let (dry, wet) = (generate(Variant::new(n, Water::Off)), generate(Variant::new(n, Water::On)));
    let mut o = format!(
        "{BEGIN}: rendered by tests/docs_codegen_fresh.rs from kanestop_codegen::generate -->\n\n\
         Operation counts (`kanestop codegen`, case 1, N = {n}; `assemble` with its 4-flop loop nest counted):\n\n\
         | function | water off | water on |\n| --- | --- | --- |\n"
    );
    for (a, b) in dry.functions.iter().zip(&wet.functions) {
        assert_eq!(a.name, b.name);
        let trig = |f: &kanestop_codegen::emit::FunctionReport| {
            if f.ops.trig > 0 {
                format!(" ({} sin/cos)", f.ops.trig)
            } else {
                String::new()
            }
        };
        o.push_str(&format!(
            "| {} | {}{} | {}{} |\n",
            a.name,
            spaced(a.ops.total()),
            trig(a),
            spaced(b.ops.total()),
            trig(b)
        ));
    }
    o.push('\n');
    o.push_str(END);
    o
}

const ROLLED_BEGIN: &str = "<!-- rolled-opcounts:begin";
const ROLLED_END: &str = "<!-- rolled-opcounts:end -->";

/// The rolled kernels' steps: operations per call (per body of the step's kind), and the
/// O(N) solve's total at N = 46 against the unrolled kernel's.
fn render_rolled(n: usize) -> String {
    use kanestop_codegen::drivers::generate_rolled;
    let (dry, wet) = (generate_rolled(Water::Off), generate_rolled(Water::On));
    let mut o = format!(
        "{ROLLED_BEGIN}: rendered by tests/docs_codegen_fresh.rs from kanestop_codegen::drivers -->\n\n\
         Operations per call of each rolled step (one call per body of its kind):\n\n\
         | step | water off | water on |\n| --- | --- | --- |\n"
    );
    for a in &dry.steps {
        // The solves under weight alone (`_gravity`) exist dry only.
        let b = wet.steps.iter().find(|b| b.name == a.name).map_or("—".to_string(), |b| spaced(b.ops.total()));
        o.push_str(&format!("| `{}` | {} | {b} |\n", a.name, spaced(a.ops.total())));
    }
    assert!(wet.steps.iter().all(|b| dry.steps.iter().any(|a| a.name == b.name)), "a wet step has no dry twin");
    // solve_free over N bodies: ship, N − 3 rods, the first, the anchor, N − 1 outward steps,
    // and the N − 1 additions of the angular velocities.
    let solve_of = |f: &kanestop_codegen::drivers::RolledFile, suffix: &str| {
        let ops = |name: &str| f.steps.iter().find(|s| s.name == format!("{name}{suffix}")).expect("step").ops.total();
        let outward = f.steps.iter().find(|s| s.name == "outward").expect("step").ops.total();
        ops("inward_ship")
            + (n - 3) * ops("inward_rod")
            + ops("inward_first")
            + ops("anchor_free")
            + (n - 1) * (outward + 1)
    };
    let solve = |f| solve_of(f, "");
    let unrolled =
        |w| generate(Variant::new(n, w)).functions.iter().find(|f| f.name == "solve_free").unwrap().ops.total();
    o.push_str(&format!(
        "\n`solve_free` at N = {n}: rolled {} (water off) and {} (water on) operations, unrolled {} and {}.\n\n",
        spaced(solve(&dry)),
        spaced(solve(&wet)),
        spaced(unrolled(Water::Off)),
        spaced(unrolled(Water::On))
    ));
    o.push_str(&format!(
        "The solve inside `rhs_free_dry` at N = {n} (water off, weight alone: the steps compute −m g, no load array \
         read): {} operations with the weights computed, against {} for `solve_free` without its loads.\n\n",
        spaced(solve_of(&dry, "_gravity")),
        spaced(solve(&dry))
    ));
    o.push_str(ROLLED_END);
    o
}

const FOLDED_BEGIN: &str = "<!-- folded-opcounts:begin";
const FOLDED_END: &str = "<!-- folded-opcounts:end -->";

/// Case 1's unrolled kernel with its parameters kept and folded as the scene's literals:
/// what `kanestop codegen --scene scenes/paper/case01.toml` prints.
fn render_folded() -> String {
    let scene = kanestop_runtime::paper::CASES[0].scene();
    let model = kanestop_runtime::model::Model::new(&scene).unwrap();
    let values: Vec<kanestop_codegen::planar::BodyValues> = kanestop_runtime::generated::body_params(&model.chain)
        .into_iter()
        .map(|b| kanestop_codegen::planar::BodyValues {
            mass: b.mass,
            inertia: b.inertia,
            centroid: b.centroid,
            joint: b.joint,
            added_mass: b.added_mass,
        })
        .collect();
    let wet = model.chain.bodies.iter().any(|b| b.added_mass > 0.0);
    let variant = Variant::new(model.body_count(), if wet { Water::On } else { Water::Off });
    let kept = generate(variant);
    let folded = kanestop_codegen::emit::folded_op_counts(variant, &values);
    let mut o = format!(
        "{FOLDED_BEGIN}: rendered by tests/docs_codegen_fresh.rs from kanestop_codegen::emit::folded_op_counts -->\n\n\
         Case 1 (N = {}, water {}):\n\n| function | kept | folded | saved |\n| --- | --- | --- | --- |\n",
        variant.bodies,
        if wet { "on" } else { "off" }
    );
    let mut most = 0.0f64;
    for (k, f) in kept.functions.iter().zip(&folded) {
        assert_eq!(k.name, f.name);
        let (a, b) = (k.ops.total(), f.ops.total());
        let saved = 100.0 * (a as f64 - b as f64) / a as f64;
        most = most.max(saved);
        o.push_str(&format!("| {} | {} | {} | {saved:.1} % |\n", k.name, spaced(a), spaced(b)));
    }
    o.push_str(&format!("\nFolding saves at most {:.0} % of a function's operations.\n\n", most.ceil()));
    o.push_str(FOLDED_END);
    o
}

const LOADS_BEGIN: &str = "<!-- load-opcounts:begin";
const LOADS_END: &str = "<!-- load-opcounts:end -->";

/// The generated load code of every signature: its operations per call of each body's
/// function, and what it leaves out.
fn render_loads() -> String {
    use kanestop_chain::{LoadSignature, LoadTerm};
    use kanestop_codegen::loads::{generate_loads, LoadBody};
    let mut o = format!(
        "{LOADS_BEGIN}: rendered by tests/docs_codegen_fresh.rs from kanestop_codegen::loads -->\n\n\
         | signature | anchor | element | ship | left out |\n| --- | --- | --- | --- | --- |\n"
    );
    for r in generate_loads().reports {
        let sig: LoadSignature = r.signature;
        let out: Vec<&str> = LoadTerm::ALL.iter().filter(|t| !sig.has(**t)).map(|t| t.name()).collect();
        o.push_str(&format!(
            "| `{}` | {} | {} | {} | {} |\n",
            sig.name(),
            r.body_total(LoadBody::Anchor),
            r.body_total(LoadBody::Element),
            r.body_total(LoadBody::Ship),
            if out.is_empty() { "nothing".to_string() } else { out.join(", ") }
        ));
    }
    o.push('\n');
    o.push_str(LOADS_END);
    o
}

/// Rewrites the block between `begin` and `end` with `fresh`; true when it was stale.
fn refresh(text: &mut String, begin: &str, end: &str, fresh: &str) -> bool {
    let a = text.find(begin).unwrap_or_else(|| panic!("docs/codegen.md: marker {begin}"));
    let b = text.find(end).unwrap_or_else(|| panic!("docs/codegen.md: marker {end}")) + end.len();
    let stale = &text[a..b] != fresh;
    text.replace_range(a..b, fresh);
    stale
}

#[test]
fn op_count_table_is_fresh() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/codegen.md");
    let mut text = std::fs::read_to_string(&path).unwrap();
    let stale = refresh(&mut text, BEGIN, END, &render(46))
        | refresh(&mut text, ROLLED_BEGIN, ROLLED_END, &render_rolled(46))
        | refresh(&mut text, FOLDED_BEGIN, FOLDED_END, &render_folded())
        | refresh(&mut text, LOADS_BEGIN, LOADS_END, &render_loads());
    if stale {
        std::fs::write(&path, &text).unwrap();
        panic!("docs/codegen.md's op counts were stale and have been regenerated: review and commit it");
    }
}

#[test]
fn thousands_are_spaced() {
    assert_eq!(spaced(899), "899");
    assert_eq!(spaced(6446), "6 446");
    assert_eq!(spaced(1234567), "1 234 567");
}
