//! Scenes from scenes: `extends` with overrides, and dotted-path overrides, give exactly the
//! scene (and the run) of the full file they stand for.

mod scratch;
use scratch::Scratch;

use std::path::PathBuf;

use kanestop_runtime::generated::GeneratedKernel;
use kanestop_runtime::model::Model;
use kanestop_runtime::paper::DEFAULT_SCENE;
use kanestop_runtime::scene::{Scene, SceneError};
use kanestop_runtime::simulate;

/// The test's scratch folder, removed when it passes (tests/scratch).
fn temp_dir(name: &str) -> Scratch {
    Scratch::new(&format!("extends-{name}"))
}

/// Case 1 as a file, cut to 2 s of simulated time.
fn base_text() -> String {
    DEFAULT_SCENE.replace("end_time = 60.0", "end_time = 2.0")
}

fn run_key(scene: &Scene) -> (u64, Vec<u64>) {
    let model = Model::new(scene).unwrap();
    let r = simulate::run(&model, Box::new(GeneratedKernel::new(&model.chain).unwrap()));
    let last = r.samples.last().unwrap();
    (r.steps, last.bodies.iter().flat_map(|b| [b.x.to_bits(), b.vx.to_bits()]).collect())
}

#[test]
fn a_variant_of_a_few_lines_is_the_full_file() {
    let dir = temp_dir("variant");
    std::fs::create_dir_all(dir.join("base")).unwrap();
    std::fs::write(dir.join("base/case01.toml"), base_text()).unwrap();
    std::fs::write(
        dir.join("heavy.toml"),
        "extends = \"base/case01.toml\"\n\n[ship]\nmass = 750000.0\n\n[initial]\nship_speed = 4.0\n",
    )
    .unwrap();
    let full =
        base_text().replace("mass = 500000.0", "mass = 750000.0").replace("ship_speed = 3.0", "ship_speed = 4.0");
    assert_ne!(full, base_text(), "the replacements hit the ship's fields");
    std::fs::write(dir.join("full.toml"), &full).unwrap();

    let variant = Scene::load(&dir.join("heavy.toml")).unwrap();
    let whole = Scene::load(&dir.join("full.toml")).unwrap();
    assert!(variant.same_case(&whole));
    // Its own name and description, and no paper time: a heavier, faster ship is no paper case.
    assert_eq!(variant.meta.name, "heavy");
    assert_eq!(variant.meta.description, "base/case01.toml with the changes of heavy.toml");
    assert_eq!(kanestop_runtime::paper::stopping_time(&variant), None);
    assert_eq!(Scene { meta: whole.meta.clone(), ..variant.clone() }, whole);
    assert_eq!(variant.ship.mass, 750000.0);
    assert_eq!(run_key(&variant), run_key(&whole), "the same run, bit for bit");

    // The same by dotted paths.
    let base = Scene::load(&dir.join("base/case01.toml")).unwrap();
    let overridden =
        base.with_overrides(&[("ship.mass", 750000.0.into()), ("initial.ship_speed", 4.0.into())]).unwrap();
    assert_eq!(overridden, whole);
}

#[test]
fn a_variant_has_its_own_name_and_table_3_only_when_it_is_the_paper_case() {
    use kanestop_runtime::paper::stopping_time;
    let dir = temp_dir("meta");
    std::fs::write(dir.join("case01.toml"), base_text()).unwrap();
    let write = |name: &str, text: &str| std::fs::write(dir.join(name), text).unwrap();
    let load = |name: &str| Scene::load(&dir.join(name)).unwrap();
    // A design check and another integrator: still the paper's case 1, under the file's name.
    write(
        "checked.toml",
        "extends = \"case01.toml\"\n[checks]\nmax_anchor_drag = 30.0\n[solver]\nintegrator = \"dp5\"\n",
    );
    let checked = load("checked.toml");
    assert_eq!((checked.meta.name.as_str(), stopping_time(&checked)), ("checked", Some(20.01)));
    assert_eq!(checked.meta.description, "case01.toml with the changes of checked.toml");
    // A chain whose middle file changes the physics is no paper case, whatever comes after it
    // or what the files' [meta] claims.
    write("light.toml", "extends = \"case01.toml\"\n[ship]\nmass = 400000.0\n");
    write(
        "light-checked.toml",
        "extends = \"light.toml\"\n[meta]\nname = \"light ship\"\n[checks]\nmax_anchor_drag = 30.0\n",
    );
    let light = load("light-checked.toml");
    assert_eq!((light.meta.name.as_str(), stopping_time(&light)), ("light ship", None));
    write("claims.toml", "extends = \"case01.toml\"\n[meta]\npaper_stopping_time = 25.0\n[ship]\nmass = 400000.0\n");
    assert_eq!(stopping_time(&load("claims.toml")), None);
    // A chain that comes back to its start by way of ../ is a loop.
    write("loop.toml", &format!("extends = \"../{}/loop.toml\"\n", dir.file_name().unwrap().to_string_lossy()));
    let e = Scene::load(&dir.join("loop.toml")).unwrap_err();
    assert!(e.to_string().contains("extends chain loops back to"), "{e}");
}

#[test]
fn overrides_are_checked_like_a_file() {
    let base = Scene::from_toml(&base_text(), "case01.toml").unwrap();
    let e = base.with_overrides(&[("anchor.mass", (-1.0).into())]).unwrap_err();
    assert!(matches!(&e, SceneError::Invalid { problems, .. } if problems[0].field == "anchor.mass"), "{e}");
    let e = base.with_overrides(&[("ship.mas", 1.0.into())]).unwrap_err();
    assert!(e.to_string().contains("ship.mas: no field `mas` here (valid: "), "{e}");
    let e = base.with_overrides(&[("cable.stages[9].elements", 3.into())]).unwrap_err();
    assert!(e.to_string().contains("index 9 is out of range (the array has 3 entries)"), "{e}");
    let e = base.with_overrides(&[("ship.mass", "heavy".into())]).unwrap_err();
    assert!(matches!(e, SceneError::Parse { .. }), "{e}");
    // 12 instead of 13 top-stage elements of 2 m: 150 m of cable, still reaching x_L = 148 m.
    let staged = base.with_overrides(&[("cable.stages[2].elements", 12.into())]).unwrap();
    assert_eq!(staged.cable.stages[2].elements, 12);
    // Two more 10 m elements in the middle stage: 172 m of cable cannot end at x_L = 148 m
    // with h_L = 6 m and still lie on the seabed; the cross-field check says so.
    let e = base.with_overrides(&[("cable.stages[1].elements", 14.into())]).unwrap_err();
    assert!(e.to_string().contains("initial.horizontal_projection"), "{e}");
}

#[test]
fn extends_errors_name_the_file() {
    let dir = temp_dir("errors");
    std::fs::write(dir.join("a.toml"), "extends = \"b.toml\"\n").unwrap();
    std::fs::write(dir.join("b.toml"), "extends = \"a.toml\"\n").unwrap();
    let e = Scene::load(&dir.join("a.toml")).unwrap_err();
    assert!(e.to_string().contains("extends chain loops back to"), "{e}");
    std::fs::write(dir.join("c.toml"), "extends = \"missing.toml\"\n").unwrap();
    let e = Scene::load(&dir.join("c.toml")).unwrap_err();
    assert!(
        matches!(&e, SceneError::Io { file, extended_by: Some(by), .. }
        if file.ends_with("missing.toml") && by.ends_with("c.toml")),
        "{e}"
    );
    assert!(e.to_string().contains("the base that `extends` names in"), "{e}");
    std::fs::write(dir.join("d.toml"), "extends = 3\n").unwrap();
    let e = Scene::load(&dir.join("d.toml")).unwrap_err();
    assert!(e.to_string().contains("extends must be a file name"), "{e}");
    // A base with a key the scene does not have is refused as a file would be.
    std::fs::write(dir.join("base.toml"), base_text()).unwrap();
    std::fs::write(dir.join("e.toml"), "extends = \"base.toml\"\n[ship]\nmas = 1.0\n").unwrap();
    let e = Scene::load(&dir.join("e.toml")).unwrap_err();
    assert!(e.to_string().contains("mas"), "{e}");
}

/// Text laid over a file chain (Python's `Scene.from_toml(text, base_dir=…)`): its `extends`
/// is resolved from the folder it is named in, and a file there of the text's own name is a
/// base like any other, not the text itself (no false cycle).
#[test]
fn text_that_extends_a_file_of_its_own_name_is_laid_over_it() {
    let paper = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes/paper");
    let text = "extends = \"case01.toml\"\n[ship]\nmass = 6e5\n";
    let scene = Scene::from_toml_at(text, &paper.join("case01.toml")).unwrap_or_else(|e| panic!("{e}"));
    let base = Scene::load(&paper.join("case01.toml")).unwrap();
    assert_eq!(scene.ship.mass, 6e5);
    assert_eq!(scene.chain, base.chain);
    assert_eq!(scene.meta.name, "case01");
    assert_eq!(scene.meta.description, "case01.toml with the changes of case01.toml");
    // A missing base is named.
    let e = Scene::from_toml_at(text, &paper.join("none/x.toml")).unwrap_err().to_string();
    assert!(e.contains("case01.toml"), "{e}");
    assert!(e.contains("the base that `extends` names in") && e.contains("x.toml"), "{e}");
}

/// An edit that changes nothing (a batch without flags) is a plain load: errors name the
/// file alone and point at its lines, a `nan` in it (not equal to itself by `==`) included;
/// an edit that changes a value names the overrides.
#[test]
fn an_edit_that_changes_nothing_is_a_plain_load() {
    let dir = temp_dir("edit");
    let path = dir.join("nan.toml");
    std::fs::write(&path, base_text().replace("[anchor]\nmass = 40000.0", "[anchor]\nmass = nan")).unwrap();
    let e = Scene::load_edited(&path, &|_| {}).unwrap_err().to_string();
    assert!(e.contains("anchor.mass = nan") && !e.contains("command-line"), "{e}");
    let e = Scene::load_edited(&path, &|v| v["solver"]["dt"] = toml::Value::Float(0.001)).unwrap_err().to_string();
    assert!(e.contains("anchor.mass = nan") && e.contains("(with command-line overrides)"), "{e}");
}
