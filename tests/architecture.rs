//! The boundaries of docs/architecture.md, held by tests:
//!
//! - the crate graph has exactly the arrows the document allows (from `cargo metadata`), and
//!   the lean runtime's normal dependencies exclude plotting, thread pools, terminal and JSON
//!   output and the generator's parsing crates;
//! - no two top-level modules of a crate import each other, directly or round a cycle;
//! - the reference formulation, the force modules and Newton's joint forces (the oracles) never
//!   name generated code;
//! - no function of the runtime is over [`MAX_FUNCTION_LINES`] lines without a reason written
//!   beside it.
//!
//! Each checker is a plain function over data, tested on the real tree (it passes) and on the
//! real tree with one violation added (it fails and names it).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use syn::spanned::Spanned;
use syn::visit::Visit;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

// ---------------------------------------------------------------------------------------
// The crate graph.

/// Crate → the workspace crates it may depend on (normal dependencies). A workspace crate
/// missing here may depend on no other workspace crate.
const ALLOWED_ARROWS: [(&str, &[&str]); 8] = [
    ("kanestop-chain", &[]),
    ("kanestop-codegen", &["kanestop-chain"]),
    ("kanestop-generated", &[]),
    ("kanestop-runtime", &["kanestop-chain", "kanestop-generated"]),
    ("kanestop-workflow", &["kanestop-chain", "kanestop-runtime"]),
    ("kanestop", &["kanestop-chain", "kanestop-codegen", "kanestop-runtime", "kanestop-workflow"]),
    ("kanestop-python", &["kanestop-chain", "kanestop-runtime", "kanestop-workflow"]),
    ("kanestop-c-aba", &[]),
];

/// Packages the runtime must not pull in, even transitively: plotting, thread pools,
/// terminal output, JSON, and the generator with its parsing and printing crates.
const NOT_IN_RUNTIME: [&str; 8] =
    ["plotters", "rayon", "indicatif", "syn", "prettyplease", "serde_json", "kanestop-codegen", "kanestop-workflow"];

/// Normal (not dev, not build) dependency arrows between packages, by name.
type Graph = BTreeMap<String, BTreeSet<String>>;

/// The resolved normal-dependency graph of the workspace, from `cargo metadata`, without the
/// dependencies *of* proc-macro crates: those (syn, quote under `thiserror-impl`,
/// `serde_derive`, `nalgebra-macros`) run in the compiler and are never linked, as
/// `cargo tree -e normal,no-proc-macro` shows. The proc-macro crates themselves stay in.
fn crate_graph() -> Graph {
    let out = std::process::Command::new(env!("CARGO"))
        .args(["metadata", "--format-version", "1"])
        .current_dir(root())
        .output()
        .expect("cargo metadata runs");
    assert!(out.status.success(), "cargo metadata: {}", String::from_utf8_lossy(&out.stderr));
    let meta: serde_json::Value = serde_json::from_slice(&out.stdout).expect("cargo metadata prints JSON");
    let names: BTreeMap<&str, &str> = meta["packages"]
        .as_array()
        .expect("packages")
        .iter()
        .map(|p| (p["id"].as_str().expect("id"), p["name"].as_str().expect("name")))
        .collect();
    let proc_macro = |p: &serde_json::Value| {
        p["targets"]
            .as_array()
            .into_iter()
            .flatten()
            .any(|t| t["kind"].as_array().into_iter().flatten().any(|k| k == "proc-macro"))
    };
    let compile_time: BTreeSet<&str> = meta["packages"]
        .as_array()
        .expect("packages")
        .iter()
        .filter(|p| proc_macro(p))
        .map(|p| p["id"].as_str().expect("id"))
        .collect();
    let mut graph = Graph::new();
    for node in meta["resolve"]["nodes"].as_array().expect("resolve.nodes") {
        let id = node["id"].as_str().expect("node id");
        if compile_time.contains(id) {
            continue;
        }
        let from = names[id].to_string();
        let deps = graph.entry(from).or_default();
        for dep in node["deps"].as_array().expect("deps") {
            let normal = dep["dep_kinds"].as_array().expect("dep_kinds").iter().any(|k| k["kind"].is_null());
            if normal {
                deps.insert(names[dep["pkg"].as_str().expect("dep pkg")].to_string());
            }
        }
    }
    graph
}

/// Everything `package` depends on through normal dependencies.
fn closure(graph: &Graph, package: &str) -> BTreeSet<String> {
    let mut seen = BTreeSet::new();
    let mut todo = vec![package.to_string()];
    while let Some(p) = todo.pop() {
        for d in graph.get(&p).into_iter().flatten() {
            if seen.insert(d.clone()) {
                todo.push(d.clone());
            }
        }
    }
    seen
}

/// Every arrow between workspace crates that [`ALLOWED_ARROWS`] does not allow, and every
/// package of [`NOT_IN_RUNTIME`] in the runtime's closure.
fn crate_violations(graph: &Graph) -> Vec<String> {
    let workspace: BTreeSet<&str> = ALLOWED_ARROWS.iter().map(|(c, _)| *c).collect();
    let mut out = Vec::new();
    for (from, allowed) in ALLOWED_ARROWS {
        for to in graph.get(from).into_iter().flatten() {
            if workspace.contains(to.as_str()) && !allowed.contains(&to.as_str()) {
                out.push(format!("{from} → {to} is not an allowed arrow"));
            }
        }
    }
    let runtime = closure(graph, "kanestop-runtime");
    for p in NOT_IN_RUNTIME {
        if runtime.contains(p) {
            out.push(format!("kanestop-runtime depends on {p}"));
        }
    }
    out
}

#[test]
fn crates_depend_only_along_the_allowed_arrows() {
    let graph = crate_graph();
    for (c, _) in ALLOWED_ARROWS {
        assert!(graph.contains_key(c), "{c} is not in the workspace: update ALLOWED_ARROWS and docs/architecture.md");
    }
    // A new crate of the project's must say where it sits.
    for c in graph.keys().filter(|c| c.starts_with("kanestop")) {
        assert!(
            ALLOWED_ARROWS.iter().any(|(a, _)| a == c),
            "{c} has no entry in ALLOWED_ARROWS: add its arrows here and to docs/architecture.md"
        );
    }
    assert_eq!(crate_violations(&graph), Vec::<String>::new());
    // The runtime does use what it needs (the check reads the right graph).
    let runtime = closure(&graph, "kanestop-runtime");
    for p in ["nalgebra", "serde", "toml", "thiserror", "kanestop-generated", "kanestop-chain"] {
        assert!(runtime.contains(p), "kanestop-runtime should depend on {p}");
    }
}

#[test]
fn an_arrow_against_the_rules_is_caught() {
    let mut graph = crate_graph();
    graph.get_mut("kanestop-runtime").expect("runtime").insert("kanestop-codegen".into());
    let v = crate_violations(&graph);
    assert!(v.iter().any(|m| m == "kanestop-runtime → kanestop-codegen is not an allowed arrow"), "{v:?}");
    assert!(v.iter().any(|m| m == "kanestop-runtime depends on kanestop-codegen"), "{v:?}");
    // syn through the generator: a transitive arrow counts too.
    assert!(v.iter().any(|m| m == "kanestop-runtime depends on syn"), "{v:?}");

    let mut graph = crate_graph();
    graph.get_mut("kanestop-chain").expect("chain").insert("kanestop-runtime".into());
    assert_eq!(crate_violations(&graph), vec!["kanestop-chain → kanestop-runtime is not an allowed arrow".to_string()]);
}

// ---------------------------------------------------------------------------------------
// Module imports.

/// The `.rs` files of a crate's `src/`, recursively, sorted.
fn sources(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).unwrap_or_else(|e| panic!("{}: {e}", d.display())).flatten() {
            let p = e.path();
            if p.is_dir() {
                todo.push(p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// The top-level module a file of `src/` belongs to (`lib.rs` and `main.rs`: the crate root,
/// named "").
fn top_module(src: &Path, file: &Path) -> String {
    let rel = file.strip_prefix(src).expect("file under src");
    let first = rel.components().next().expect("a component").as_os_str().to_string_lossy();
    match first.strip_suffix(".rs") {
        Some("lib" | "main") => String::new(),
        Some(m) => m.to_string(),
        None => first.into_owned(),
    }
}

/// The first segment after `crate::` of every path in `text` (use trees and expressions).
fn crate_references(text: &str) -> BTreeSet<String> {
    struct Paths(BTreeSet<String>);
    impl<'ast> Visit<'ast> for Paths {
        fn visit_path(&mut self, p: &'ast syn::Path) {
            let segments: Vec<String> = p.segments.iter().map(|s| s.ident.to_string()).collect();
            if segments.len() > 1 && segments[0] == "crate" {
                self.0.insert(segments[1].clone());
            }
            syn::visit::visit_path(self, p);
        }
        fn visit_item_use(&mut self, u: &'ast syn::ItemUse) {
            fn walk(tree: &syn::UseTree, prefix: &mut Vec<String>, out: &mut BTreeSet<String>) {
                match tree {
                    syn::UseTree::Path(p) => {
                        prefix.push(p.ident.to_string());
                        walk(&p.tree, prefix, out);
                        prefix.pop();
                    }
                    syn::UseTree::Group(g) => g.items.iter().for_each(|t| walk(t, prefix, out)),
                    syn::UseTree::Name(n) => record(prefix, &n.ident, out),
                    syn::UseTree::Rename(r) => record(prefix, &r.ident, out),
                    syn::UseTree::Glob(_) => {
                        if prefix.len() > 1 && prefix[0] == "crate" {
                            out.insert(prefix[1].clone());
                        }
                    }
                }
            }
            fn record(prefix: &[String], last: &syn::Ident, out: &mut BTreeSet<String>) {
                match prefix {
                    [first, second, ..] if first == "crate" => {
                        out.insert(second.clone());
                    }
                    [first] if first == "crate" => {
                        out.insert(last.to_string());
                    }
                    _ => {}
                }
            }
            walk(&u.tree, &mut Vec::new(), &mut self.0);
        }
    }
    let file = syn::parse_file(text).expect("a source file parses");
    let mut v = Paths(BTreeSet::new());
    v.visit_file(&file);
    v.0
}

/// Top-level module → the top-level modules it names through `crate::`.
fn module_graph(src: &Path) -> Graph {
    let mut graph = Graph::new();
    for file in sources(src) {
        let from = top_module(src, &file);
        let text = std::fs::read_to_string(&file).expect("readable source");
        let refs = graph.entry(from.clone()).or_default();
        for to in crate_references(&text) {
            if to != from && !to.is_empty() {
                refs.insert(to);
            }
        }
    }
    graph
}

/// One cycle of `graph`, as the modules along it, if there is any.
fn find_cycle(graph: &Graph) -> Option<Vec<String>> {
    fn visit(
        graph: &Graph,
        node: &str,
        state: &mut BTreeMap<String, u8>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(node.to_string(), 1);
        stack.push(node.to_string());
        for next in graph.get(node).into_iter().flatten() {
            match state.get(next.as_str()).copied().unwrap_or(0) {
                1 => {
                    let start = stack.iter().position(|m| m == next).expect("on the stack");
                    let mut cycle = stack[start..].to_vec();
                    cycle.push(next.clone());
                    return Some(cycle);
                }
                0 => {
                    if let Some(c) = visit(graph, next, state, stack) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        stack.pop();
        state.insert(node.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for node in graph.keys() {
        if state.get(node.as_str()).copied().unwrap_or(0) == 0 {
            if let Some(c) = visit(graph, node, &mut state, &mut Vec::new()) {
                return Some(c);
            }
        }
    }
    None
}

const CRATE_SOURCES: [&str; 7] =
    ["chain/src", "codegen/src", "runtime/src", "workflow/src", "src", "generated/src", "python/src"];

#[test]
fn no_import_cycle_between_modules() {
    for dir in CRATE_SOURCES {
        let graph = module_graph(&root().join(dir));
        assert!(graph.len() > 1 || dir == "generated/src" || dir == "chain/src", "{dir}: no modules found");
        assert_eq!(find_cycle(&graph), None, "{dir}: modules import each other round a cycle");
    }
}

#[test]
fn an_import_cycle_is_caught() {
    let mut graph = module_graph(&root().join("runtime/src"));
    // The kernels are below the scene-independent physics; an arrow back closes a cycle.
    assert!(graph["dynamics"].contains("kernel"), "dynamics uses the kernel interface");
    graph.get_mut("kernel").expect("kernel module").insert("dynamics".into());
    let cycle = find_cycle(&graph).expect("a cycle");
    assert!(cycle.contains(&"kernel".to_string()) && cycle.contains(&"dynamics".to_string()), "{cycle:?}");
    assert_eq!(cycle.first(), cycle.last());
}

#[test]
fn references_are_read_from_use_trees_and_paths() {
    let refs = crate_references(
        "use crate::a::{b, c::D};\nuse crate::{e, f::g};\nfn x() { crate::h::y(); super::z(); other::w(); }",
    );
    assert_eq!(refs, ["a", "e", "f", "h"].into_iter().map(String::from).collect());
}

// ---------------------------------------------------------------------------------------
// The oracles.

#[test]
fn the_oracles_never_name_generated_code() {
    let oracles = ["runtime/src/reference", "runtime/src/forces"];
    // Newton's joint forces, the oracle of the solve's own.
    let files = oracles.iter().flat_map(|dir| sources(&root().join(dir))).chain([root().join("runtime/src/joints.rs")]);
    let mut offenders = Vec::new();
    {
        for file in files {
            let text = std::fs::read_to_string(&file).expect("readable");
            for needle in ["kanestop_generated", "crate::generated", "GeneratedKernel"] {
                if text.contains(needle) {
                    offenders.push(format!("{} names {needle}", file.display()));
                }
            }
        }
    }
    assert!(offenders.is_empty(), "{offenders:?}");
    // Reports only read results: no report module runs a simulation.
    for report in ["summary.rs", "history.rs", "checks.rs", "diagnostic.rs", "plot.rs"] {
        let text = std::fs::read_to_string(root().join("workflow/src").join(report)).expect("readable");
        assert!(!text.contains("simulate::run"), "workflow/src/{report} runs a simulation");
    }
}

/// The generator is a pure function from its input model to code: no file, environment or
/// I/O of its own (its callers, the build script and the CLI, read the scenes).
#[test]
fn the_generator_does_no_io() {
    let mut offenders = Vec::new();
    for file in sources(&root().join("codegen/src")) {
        let text = std::fs::read_to_string(&file).expect("readable");
        offenders.extend(io_names(&text).into_iter().map(|n| format!("{} names {n}", file.display())));
    }
    assert!(offenders.is_empty(), "{offenders:?}");
}

/// The I/O modules of std that `text` names: by path (`std::fs::read`) or in a `use std::{…}`.
fn io_names(text: &str) -> Vec<String> {
    let modules = ["fs", "env", "io", "process", "net"];
    let mut found = Vec::new();
    for m in modules {
        let by_path = text.contains(&format!("std::{m}"));
        let in_group = text.split("std::{").skip(1).any(|rest| {
            let group = rest.split('}').next().unwrap_or("");
            group.split([',', ' ', '\n']).any(|w| w.trim() == m || w.trim().starts_with(&format!("{m}::")))
        });
        if by_path || in_group {
            found.push(format!("std::{m}"));
        }
    }
    found
}

#[test]
fn io_is_found_however_it_is_imported() {
    assert_eq!(io_names("use std::fs;"), ["std::fs"]);
    assert_eq!(io_names("use std::{collections::BTreeMap, fs, env};"), ["std::fs", "std::env"]);
    assert_eq!(io_names("use std::{\n    io::Write,\n};"), ["std::io"]);
    assert!(io_names("use std::{collections::BTreeMap, fmt};\nlet profile = 1;").is_empty());
}

// ---------------------------------------------------------------------------------------
// Function length.

/// Longest function body allowed in the runtime without a written reason.
const MAX_FUNCTION_LINES: usize = 80;

/// Functions of `text` longer than `max` lines with no `// Long by design: …` comment in
/// the three lines above them: (name, first line, lines).
fn long_functions(text: &str, max: usize) -> Vec<(String, usize, usize)> {
    struct Fns<'a> {
        lines: Vec<&'a str>,
        max: usize,
        out: Vec<(String, usize, usize)>,
    }
    impl Fns<'_> {
        fn check(&mut self, name: String, span: proc_macro2::Span) {
            let (start, end) = (span.start().line, span.end().line);
            let len = end + 1 - start;
            let above = self.lines[start.saturating_sub(4)..start.saturating_sub(1)].join("\n");
            if len > self.max && !above.contains("// Long by design:") {
                self.out.push((name, start, len));
            }
        }
    }
    impl<'ast> Visit<'ast> for Fns<'_> {
        fn visit_item_fn(&mut self, f: &'ast syn::ItemFn) {
            self.check(f.sig.ident.to_string(), f.span());
            syn::visit::visit_item_fn(self, f);
        }
        fn visit_impl_item_fn(&mut self, f: &'ast syn::ImplItemFn) {
            self.check(f.sig.ident.to_string(), f.span());
            syn::visit::visit_impl_item_fn(self, f);
        }
        fn visit_item_mod(&mut self, m: &'ast syn::ItemMod) {
            // Tests are exempt: a scenario reads best whole.
            let is_test =
                m.attrs.iter().any(|a| a.path().is_ident("cfg") && quote::quote!(#a).to_string().contains("test"));
            if !is_test {
                syn::visit::visit_item_mod(self, m);
            }
        }
    }
    let file = syn::parse_file(text).expect("a source file parses");
    let mut v = Fns { lines: text.lines().collect(), max, out: Vec::new() };
    v.visit_file(&file);
    v.out
}

#[test]
fn runtime_functions_are_short_or_say_why() {
    let mut long = Vec::new();
    for file in sources(&root().join("runtime/src")) {
        let text = std::fs::read_to_string(&file).expect("readable");
        for (name, line, len) in long_functions(&text, MAX_FUNCTION_LINES) {
            long.push(format!("{}:{line} {name}: {len} lines", file.strip_prefix(root()).unwrap_or(&file).display()));
        }
    }
    assert!(
        long.is_empty(),
        "functions over {MAX_FUNCTION_LINES} lines with no `// Long by design:` reason: {long:#?}"
    );
}

#[test]
fn a_long_function_is_caught_unless_it_says_why() {
    let body: String = (0..90).map(|i| format!("    let x{i} = {i};\n")).collect();
    let text = format!("fn short() {{}}\n\nfn long() {{\n{body}}}\n");
    assert_eq!(long_functions(&text, 80), vec![("long".to_string(), 3, 92)]);
    let excused = format!("// Long by design: a straight-line expansion.\nfn long() {{\n{body}}}\n");
    assert_eq!(long_functions(&excused, 80), vec![]);
}
