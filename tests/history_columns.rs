//! The history's columns (the Python package's channels) against the CSV history: the
//! same numbers, for any selection of channels.

use kanestop_runtime::{generated::GeneratedKernel, model::Model, paper::DEFAULT_SCENE, scene::Scene};
use kanestop_workflow::history::{all_channels, columns, csv_of, Channel};

#[test]
fn columns_hold_the_numbers_the_csv_writes() {
    let mut scene = Scene::from_toml(DEFAULT_SCENE, "case01.toml").unwrap();
    scene.solver.end_time = 0.1;
    scene.solver.output_interval = 0.02;
    let model = Model::new(&scene).unwrap();
    let result = kanestop_runtime::simulate::run(&model, Box::new(GeneratedKernel::new(&model.chain).unwrap()));
    // A selection that interleaves body channels with others, as `--channels` may.
    let channels: Vec<Channel> = all_channels(model.body_count()).into_iter().step_by(5).collect();
    let columns = columns(&result, &channels);
    let csv = csv_of(&result, &channels);
    let rows: Vec<Vec<f64>> = csv.lines().skip(1).map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect();
    assert_eq!(rows.len(), result.samples.len());
    assert!(rows.len() > 2);
    for (i, column) in columns.iter().enumerate() {
        let from_csv: Vec<f64> = rows.iter().map(|r| r[i]).collect();
        assert_eq!(column.len(), from_csv.len(), "{}", channels[i].name);
        for (a, b) in column.iter().zip(&from_csv) {
            assert!(a == b || (a.is_nan() && b.is_nan()), "{}: {a} against {b}", channels[i].name);
        }
    }
}
