//! Every chart `run --plot`, `plot` and `report accuracy` write, rendered to PNG (resvg) and
//! checked for its size and for curves (enough coloured pixels), and the regression tests of
//! the plot defects of issue 16.
//!
//! Fonts: the SVGs name `sans-serif`; resvg draws text only with a font. The machine's fonts
//! are loaded when it has any (then the PNGs show the labels), but the checks look only at
//! the curves' coloured pixels, so the test passes on a machine with no fonts at all.
//! The PNGs are kept in `target/chart-png/` for a person to look at.

mod scratch;
use scratch::Scratch;

use std::path::{Path, PathBuf};

use kanestop_runtime::model::Model;
use kanestop_runtime::scene::Scene;
use kanestop_runtime::simulate::{self, RunResult};
use kanestop_workflow::kernels::{self, KernelChoice};
use kanestop_workflow::plot;

fn png_dir() -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/chart-png");
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Pixel counts of a rendered chart.
struct Rendered {
    width: u32,
    height: u32,
    /// Pixels not near white.
    inked: usize,
    /// Pixels with a clear hue (curves; axes, text and grid are grey).
    coloured: usize,
}

fn render(svg: &str, png: &Path) -> Rendered {
    let mut options = resvg::usvg::Options::default();
    let fonts = options.fontdb_mut();
    fonts.load_system_fonts();
    // `sans-serif` means Arial to fontdb; take any sans face the machine has.
    let sans = fonts.faces().flat_map(|f| f.families.iter().map(|(name, _)| name.clone())).find(|n| n.contains("Sans"));
    if let Some(name) = sans {
        fonts.set_sans_serif_family(name);
    }
    let tree = resvg::usvg::Tree::from_str(svg, &options).expect("a valid SVG");
    let size = tree.size().to_int_size();
    let mut pixmap = resvg::tiny_skia::Pixmap::new(size.width(), size.height()).unwrap();
    resvg::render(&tree, resvg::tiny_skia::Transform::default(), &mut pixmap.as_mut());
    pixmap.save_png(png).unwrap();
    let (mut inked, mut coloured) = (0, 0);
    for p in pixmap.pixels() {
        let (r, g, b, a) = (p.red() as i32, p.green() as i32, p.blue() as i32, p.alpha() as i32);
        if a > 0 && r.min(g).min(b) < 230 {
            inked += 1;
        }
        if a > 0 && r.max(g).max(b) - r.min(g).min(b) > 60 {
            coloured += 1;
        }
    }
    Rendered { width: size.width(), height: size.height(), inked, coloured }
}

fn assert_chart(svg: &str, name: &str) -> Rendered {
    let r = render(svg, &png_dir().join(name.replace(".svg", ".png")));
    assert!(r.width >= 600 && r.height >= 400, "{name}: {}×{}", r.width, r.height);
    let area = (r.width * r.height) as usize;
    assert!(r.inked > area / 200, "{name} is blank: {} inked pixels", r.inked);
    assert!(r.coloured > area / 500, "{name} has no curve: {} coloured pixels", r.coloured);
    assert!(r.inked < area / 2, "{name} is mostly ink: {} pixels", r.inked);
    r
}

fn paper_run(case: &str) -> (Model, RunResult) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("scenes/paper/{case}.toml"));
    let model = Model::new(&Scene::load(&path).unwrap()).unwrap();
    let result = simulate::run(&model, kernels::factory(KernelChoice::Generated)(&model));
    (model, result)
}

#[test]
fn every_chart_of_plot_and_run_plot_renders() {
    let runs: Vec<(Model, RunResult)> = ["case01", "case15"].into_iter().map(paper_run).collect();
    let refs: Vec<(&Model, &RunResult)> = runs.iter().map(|(m, r)| (m, r)).collect();
    let dir = Scratch::new("png");
    // `plot` (two runs overlaid) and `run --plot` (one run).
    for (tag, set) in [("plot", &refs[..]), ("run", &refs[..1])] {
        let files = plot::write_plots(set, &dir.join(tag)).unwrap();
        assert!(files.len() >= 4, "{files:?}");
        for f in files {
            let svg = std::fs::read_to_string(&f).unwrap();
            let name = format!("{tag}-{}", f.file_name().unwrap().to_string_lossy());
            assert_chart(&svg, &name);
        }
    }
}

/// Table 3's stopping time is marked on a paper case's speed chart only. Regression: a
/// variant of case 1 (a heavier ship by `extends`) inherits its meta.paper_stopping_time,
/// and its chart was marked with Table 3's 20 s though that ship stops at 55 s.
#[test]
fn the_paper_s_time_is_marked_for_its_cases_only() {
    let dir = Scratch::new("paper-mark");
    let speed_chart = |scene: &Scene, tag: &str| {
        let model = Model::new(scene).unwrap();
        let result = simulate::run(&model, kernels::factory(KernelChoice::Generated)(&model));
        let files = plot::write_plots(&[(&model, &result)], &dir.join(tag)).unwrap();
        let speed = files.iter().find(|f| f.file_name().unwrap().to_string_lossy().contains("speed")).unwrap();
        std::fs::read_to_string(speed).unwrap()
    };
    let mut case1 = Scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper/case01.toml")).unwrap();
    case1.solver.end_time = 0.1;
    let mut heavier = case1.clone();
    heavier.ship.mass *= 3.0;
    assert!(heavier.meta.paper_stopping_time.is_some());
    // The legend's words (the SVG writes the apostrophe as &apos;).
    assert!(speed_chart(&case1, "case1").contains("stopping time (Table 3)"));
    assert!(!speed_chart(&heavier, "heavier").contains("stopping time (Table 3)"));
}

#[test]
fn the_accuracy_chart_renders() {
    let mut rows = Vec::new();
    for (i, (method, settings)) in [
        (kanestop_runtime::scene::Method::Rk4, [0.004, 0.002, 0.001, 0.0005]),
        (kanestop_runtime::scene::Method::Dp5, [1e-3, 1e-4, 1e-5, 1e-6]),
        (kanestop_runtime::scene::Method::Sdirk4, [1e-3, 1e-4, 1e-5, 1e-6]),
    ]
    .into_iter()
    .enumerate()
    {
        for (j, s) in settings.into_iter().enumerate() {
            let wall = 0.1 * (1.0 + i as f64) * 2f64.powi(j as i32);
            let error = 10f64.powi(-2 - 2 * j as i32) * (1.0 + i as f64);
            rows.push(kanestop_workflow::accuracy::AccuracyRow {
                method,
                setting: s,
                status: "stopped".into(),
                stopping_time_error: Some(error),
                ship_displacement_error: Some(error),
                anchor_displacement_error: Some(error),
                peak_tension_error: Some(error),
                trajectory_error: Some(error * 3.0),
                wall_time: wall,
                cpu_time: Some(0.9 * wall),
                rhs_evaluations: 1000 * (j as u64 + 1),
                best: j == 3,
            });
        }
    }
    let study = kanestop_workflow::accuracy::AccuracyStudy {
        scene: "case01".into(),
        reference_stopping_time: 19.81,
        reference_error: 1e-9,
        reference_trajectory_error: 1e-8,
        atol_ratio: 1e-2,
        rows,
    };
    let svg = kanestop_workflow::accuracy::work_precision(&study).unwrap();
    assert_chart(&svg, "accuracy.svg");
}

/// The heat maps of a two-axis sweep (ship mass × speed on case 1, three of nine rows
/// passing): each output over the grid, failing cells hatched, the check boundary drawn;
/// rendered, sized and not blank; `target/chart-png/heatmap-*.png` to look at.
#[test]
fn the_sweep_heat_maps_render_with_the_check_boundary() {
    use kanestop_workflow::sweep::{self, heatmap};
    let spec = sweep::Spec::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/sweeps/mass_speed.toml")).unwrap();
    assert_eq!(heatmap::unsupported(&spec), None);
    let plan = spec.plan();
    let rows = sweep::run(&plan, &kernels::factory(KernelChoice::Generated), None, &|_| {}).unwrap();
    assert!(rows.iter().any(|r| r.checks_pass == Some(false)) && rows.iter().any(|r| r.checks_pass == Some(true)));
    let dir = Scratch::new("heatmap");
    let files = heatmap::write(&spec, &rows, &heatmap::Output::ALL, &dir).unwrap();
    assert_eq!(files.len(), heatmap::Output::ALL.len());
    for f in &files {
        let svg = std::fs::read_to_string(f).unwrap();
        let name = f.file_name().unwrap().to_string_lossy().into_owned();
        assert!(
            svg.contains("mass_speed") && svg.contains("ship.mass") && svg.contains("initial.ship_speed"),
            "{name}"
        );
        assert!(svg.contains("hatched: fails a design check"), "{name}: the legend");
        let r = render(&svg, &png_dir().join(name.replace(".svg", ".png")));
        assert!(r.width >= 900 && r.height >= 600, "{name}: {}×{}", r.width, r.height);
        let area = (r.width * r.height) as usize;
        // Nine coloured cells and the colour scale fill a good part of the chart.
        assert!(r.coloured > area / 5, "{name}: {} coloured pixels", r.coloured);
        assert!(r.inked < area * 9 / 10, "{name}: {} inked pixels", r.inked);
    }
    // Cut short at 1 s, no ship stops: the stopping distance has no values and says so (no
    // made-up scale of 0 to 1), and the peaks are daggered as values up to the end time.
    let mut short = spec.clone();
    short.base.solver.end_time = 1.0;
    // A limit inside the 0–1 an empty scale spans, where a red line would be drawn on it.
    short.base.checks.as_mut().expect("the spec's [checks]").max_stopping_distance = Some(0.5);
    let rows_short = sweep::run(&short.plan(), &kernels::factory(KernelChoice::Generated), None, &|_| {}).unwrap();
    assert!(rows_short.iter().all(|r| r.status == kanestop_workflow::batch::Status::EndTime));
    let cut = Scratch::new("heatmap-cut");
    let outputs = [heatmap::Output::StoppingDistance, heatmap::Output::PeakTension];
    let files = heatmap::write(&short, &rows_short, &outputs, &cut).unwrap();
    let svg = |k: usize| std::fs::read_to_string(&files[k]).unwrap();
    let (distance, peak) = (svg(0), svg(1));
    assert!(distance.contains("stopping distance (m): no values") && distance.contains("9 of 9 cells"), "{distance}");
    assert!(!distance.contains(">0.5<") && !distance.contains(">1<"), "no scale without values");
    assert!(!distance.contains("off the scale"), "no scale for the limit to be off");
    assert!(!distance.to_uppercase().contains("#E61E1E"), "no red limit line on the grey bar");
    assert!(peak.contains("†: the ship had not stopped at solver.end_time") && peak.contains("(9 of 9 cells)"));
    assert!(!peak.contains("no values"));
    let name = |k: usize| format!("cut-{}", files[k].file_name().unwrap().to_string_lossy().replace(".svg", ".png"));
    // All grey: drawn, with no colour.
    let r = render(&distance, &png_dir().join(name(0)));
    assert!(
        r.inked > (r.width * r.height) as usize / 5 && r.coloured < 1000,
        "{}: {} {}",
        name(0),
        r.inked,
        r.coloured
    );
    assert_chart(&peak, &name(1));
    // A one-axis sweep has none (and says why).
    let mut one = spec.clone();
    one.axes.truncate(1);
    assert!(heatmap::unsupported(&one).unwrap().contains("two grid axes"));
    assert!(heatmap::write(&one, &rows, &heatmap::DEFAULT_OUTPUTS, &dir).unwrap().is_empty());
}
