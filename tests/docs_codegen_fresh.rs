//! `docs/codegen.md`'s operation-count table is rendered from `kanestop_codegen::generate`
//! (what `kanestop codegen` prints) for case 1's N = 46: a stale table fails this test and is
//! rewritten between its markers, as `docs_fresh.rs` does for docs/scenes.md.

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

#[test]
fn op_count_table_is_fresh() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/codegen.md");
    let text = std::fs::read_to_string(&path).unwrap();
    let a = text.find(BEGIN).expect("docs/codegen.md: op-count begin marker");
    let b = text.find(END).expect("docs/codegen.md: op-count end marker") + END.len();
    let fresh = format!("{}{}{}", &text[..a], render(46), &text[b..]);
    if fresh != text {
        std::fs::write(&path, &fresh).unwrap();
        panic!("docs/codegen.md's op counts were stale and have been regenerated: review and commit it");
    }
}

#[test]
fn thousands_are_spaced() {
    assert_eq!(spaced(899), "899");
    assert_eq!(spaced(6446), "6 446");
    assert_eq!(spaced(1234567), "1 234 567");
}
