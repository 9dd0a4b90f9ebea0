//! The checked-in paper scenes are generated from `paper::CASES`: a stale file fails this
//! test (and is rewritten, so the diff can be reviewed and committed).

use std::path::Path;

use kanestop_runtime::model::Model;
use kanestop_runtime::paper::{CASES, DEFAULT_SCENE};
use kanestop_runtime::scene::Scene;

#[test]
fn paper_scenes_are_fresh_and_valid() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper");
    let mut stale = Vec::new();
    for case in &CASES {
        let path = dir.join(format!("{}.toml", case.name()));
        let expected = case.scene_file();
        let actual = std::fs::read_to_string(&path).unwrap_or_default();
        if actual != expected {
            std::fs::write(&path, &expected).unwrap();
            stale.push(path.display().to_string());
        }
        let scene = Scene::from_toml(&expected, &path.display().to_string()).unwrap();
        assert_eq!(scene, case.scene());
        let model = Model::new(&scene).unwrap();
        let n = match case.number {
            8 => 48,
            9 => 50,
            _ => 46,
        };
        assert_eq!(model.body_count(), n, "case {}", case.number);
    }
    assert!(stale.is_empty(), "stale scene files were regenerated, review and commit them: {stale:?}");
    assert_eq!(DEFAULT_SCENE, CASES[0].scene_file(), "the embedded default scene is case 1");
}
