//! `docs/scenes.md` is rendered from the doc comments of `runtime/src/scene.rs`: the field
//! reference has one source. A stale file fails this test and is rewritten.

use std::path::Path;

/// TOML table → Rust struct, in file order.
const TABLES: [(&str, &str); 11] = [
    ("meta", "Meta"),
    ("environment", "Environment"),
    ("hydrodynamics", "Hydrodynamics"),
    ("anchor", "Anchor"),
    ("chain", "ChainSpec"),
    ("cable", "Cable"),
    ("[cable.stages]", "CableStage"),
    ("rod", "Rod"),
    ("ship", "Ship"),
    ("initial", "Initial"),
    ("solver", "Solver"),
];

/// (field, doc, optional) of `pub struct name` in `source`: optional when serde defaults it
/// (`#[serde(default…)]`, an `Option`).
fn fields(source: &str, name: &str) -> Vec<(String, String, bool)> {
    parsed_fields(source, name).into_iter().map(|(field, _, doc, optional)| (field, doc, optional)).collect()
}

/// A table's rows: `| `field` | doc |`, the field marked "(optional)" where it is.
fn rows(out: &mut String, source: &str, name: &str) {
    for (field, doc, optional) in fields(source, name) {
        if field == "stages" {
            continue; // its own table below
        }
        let mark = if optional { " (optional)" } else { "" };
        out.push_str(&format!("| `{field}`{mark} | {} |\n", doc.replace('|', "\\|")));
    }
}

/// `scene` is runtime/src/scene.rs, `design` runtime/src/design.rs (`[checks]`).
fn render(scene: &str, design: &str) -> String {
    let mut out = String::from(
        "# Scene files\n\n<!-- Rendered from runtime/src/scene.rs by tests/docs_fresh.rs; edit the doc comments there. -->\n\n\
         Scenes are TOML. Every field is required unless marked optional, unknown keys are\n\
         rejected, and every value is checked (finite, in range) before a run; an error names the\n\
         file, the field, the value and the valid range. Every positive or non-negative\n\
         quantity but `solver.end_time` is at most 1e15 in its SI unit (far beyond any\n\
         mooring; larger values overflow the equations' products), and every positive one at\n\
         least 1e-15 (smaller ones underflow them). The paper's 19 cases are in\n\
         `scenes/paper/`, generated from `runtime/src/paper.rs`.\n\n\
         A scene can be a few lines over another: `extends = \"base.toml\"` (a path relative to the\n\
         file; chains allowed) takes every table of the base and lays the file's own over it, key\n\
         by key; an array such as `[[cable.stages]]` replaces the base's whole. Where it does not\n\
         set them, its `name` is the file's stem and its `description` says which file it extends.\n\
         An `extends` chain that comes back to a file is refused. Sweeps and the Python package set\n\
         single fields by dotted path: `ship.mass`, `cable.stages[1].elements`.\n\n\
         Reports compare a run with the paper's Table 3 when its scene is one of the paper's 19\n\
         cases: the same environment, bodies, line and initial state (its name, `[solver]` and\n\
         `[checks]` may differ), whatever file it came from; any other scene (a heavier ship, a\n\
         copy edited) is not compared, whatever its `meta.paper_stopping_time` says.\n",
    );
    for (table, name) in TABLES {
        out.push_str(&format!("\n## `[{table}]`\n\n| field | meaning and unit |\n| --- | --- |\n"));
        rows(&mut out, scene, name);
    }
    out.push_str(
        "\nThe integrators a scene can name: `rk4` (classic fourth-order Runge–Kutta, fixed step), `dp5`\n\
         (Dormand–Prince 5(4), adaptive) and `sdirk4` (L-stable SDIRK of order 4, adaptive, for stiff\n\
         scenes); see docs/integrators.md.\n",
    );
    out.push_str(
        "\n## `[checks]` (optional)\n\n\
         Design checks the run's results are held to, each a limit; a check that is absent is not\n\
         made. `run`, `batch` and `sweep` report them (`run --json`: `checks`, `checks_pass`, see\n\
         docs/conventions.md) and exit 4 when one fails; a sweep spec's `[checks]` replaces its base\n\
         scene's (docs/sweeps.md). The break-load check needs no entry: every run makes it.\n\n\
         | field | meaning and unit |\n| --- | --- |\n",
    );
    rows(&mut out, design, "DesignChecks");
    out
}

#[test]
fn scene_reference_is_fresh() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let source = std::fs::read_to_string(root.join("runtime/src/scene.rs")).unwrap();
    let design = std::fs::read_to_string(root.join("runtime/src/design.rs")).unwrap();
    let expected = render(&source, &design);
    let path = root.join("docs/scenes.md");
    let actual = std::fs::read_to_string(&path).unwrap_or_default();
    if actual != expected {
        std::fs::write(&path, &expected).unwrap();
        panic!("docs/scenes.md was stale and has been regenerated: review and commit it");
    }
}

/// (field, type, doc) of every `pub` field of `pub struct name` in `source`.
fn typed_fields(source: &str, name: &str) -> Vec<(String, String, String)> {
    parsed_fields(source, name).into_iter().map(|(field, ty, doc, _)| (field, ty, doc)).collect()
}

/// (field, type, doc, optional) of every `pub` field of `pub struct name` in `source`.
fn parsed_fields(source: &str, name: &str) -> Vec<(String, String, String, bool)> {
    let start = source.find(&format!("pub struct {name} {{")).unwrap_or_else(|| panic!("struct {name}"));
    let body = &source[start..];
    let body = &body[..body.find("\n}").unwrap()];
    let mut out = Vec::new();
    let mut doc = Vec::new();
    let mut defaulted = false;
    for line in body.lines().skip(1) {
        let line = line.trim();
        if let Some(d) = line.strip_prefix("///") {
            doc.push(d.trim().to_string());
        } else if line.starts_with("#[serde(default") {
            defaulted = true;
        } else if let Some(f) = line.strip_prefix("pub ") {
            let (field, ty) = f.split_once(':').unwrap();
            let ty = ty.trim().trim_end_matches(',').to_string();
            let optional = defaulted || ty.starts_with("Option<");
            out.push((field.trim().to_string(), ty, doc.join(" "), optional));
            doc.clear();
            defaulted = false;
        }
    }
    out
}

/// `scene::UNITS` (axis labels of charts, the sensitivity table) holds every numeric scene
/// field, each with the unit its doc comment states: ", kg" in the comment for "kg", the word
/// "dimensionless" (or a count, or the state's units) for "".
#[test]
fn every_numeric_field_has_the_unit_its_documentation_states() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = std::fs::read_to_string(root.join("runtime/src/scene.rs")).unwrap();
    let design = std::fs::read_to_string(root.join("runtime/src/design.rs")).unwrap();
    let tables = TABLES
        .iter()
        .map(|&(table, name)| (table.trim_matches(|c| c == '[' || c == ']').to_string(), typed_fields(&scene, name)))
        .chain([("checks".to_string(), typed_fields(&design, "DesignChecks"))]);
    let mut numeric = Vec::new();
    for (table, fields) in tables {
        for (field, ty, doc) in fields {
            if !["f64", "usize", "Option<f64>"].contains(&ty.as_str()) {
                continue;
            }
            let path = format!("{table}.{field}");
            let unit =
                kanestop_runtime::scene::unit(&path).unwrap_or_else(|| panic!("{path}: no unit in scene::UNITS"));
            if unit.is_empty() {
                assert!(
                    ["dimensionless", "Number of", "state's units"].iter().any(|w| doc.contains(w)),
                    "{path}: unit \"\" but the doc states no dimensionless number: {doc}"
                );
            } else {
                let stated = [".", " ", ","].iter().any(|end| doc.contains(&format!(", {unit}{end}")));
                assert!(stated, "{path}: unit {unit} is not the doc's: {doc}");
            }
            numeric.push(path);
        }
    }
    // No entry for a field that is not there.
    for (path, _) in kanestop_runtime::scene::UNITS {
        assert!(numeric.iter().any(|p| p == path), "scene::UNITS has {path}, which is no numeric field");
    }
    assert_eq!(kanestop_runtime::scene::unit("cable.stages[2].element_length"), Some("m"));
    assert_eq!(kanestop_runtime::scene::labelled("ship.mass"), "ship.mass (kg)");
    assert_eq!(kanestop_runtime::scene::labelled("environment.seabed_friction"), "environment.seabed_friction");
    assert_eq!(kanestop_runtime::scene::unit("ship.name"), None);
}
