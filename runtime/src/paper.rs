//! The paper's data (Section 4.1, Tables 1–3) and its 19 cases as scenes.
//!
//! This table is the single source of `scenes/paper/caseNN.toml`: a test renders every
//! case and fails when a checked-in file differs (it rewrites the file, so a rerun passes
//! and the diff is reviewable).

use crate::scene::{
    Anchor, Cable, CableStage, ChainSpec, Environment, Hydrodynamics, Initial, Meta, Method, Rod, Scene, Ship, Solver,
};

/// g, m/s².
pub const GRAVITY: f64 = 9.81;
/// ρ, sea water, kg/m³.
pub const WATER_DENSITY: f64 = 1025.0;
/// ϑ, sea water, m²/s.
pub const KINEMATIC_VISCOSITY: f64 = 1.05e-6;
/// ρ_s, steel, kg/m³.
pub const STEEL_DENSITY: f64 = 7850.0;
/// k_z, soft soil, N/m³ (Eq. 41).
pub const SEABED_STIFFNESS: f64 = 5.0e6;
/// Cable equivalent radius R_RE, m.
pub const CABLE_RADIUS: f64 = 0.0237;
/// Cable break load, N.
pub const CABLE_BREAK_LOAD: f64 = 2520.0e3;

/// Mass per metre of the 2D element of equivalent radius R: ρ_s π R², kg/m.
pub fn mass_per_length(radius: f64) -> f64 {
    STEEL_DENSITY * std::f64::consts::PI * radius * radius
}

/// One row of Table 1 (studless chain, grade R4).
#[derive(Clone, Copy, Debug)]
pub struct ChainGrade {
    /// Equivalent radius R_CE, m.
    pub radius: f64,
    /// Proof load, N.
    pub proof_load: f64,
    /// Break load, N.
    pub break_load: f64,
}

/// Table 1.
pub const TABLE_1: [ChainGrade; 3] = [
    ChainGrade { radius: 0.0763, proof_load: 2709e3, break_load: 3866e3 },
    ChainGrade { radius: 0.0863, proof_load: 3423e3, break_load: 4885e3 },
    ChainGrade { radius: 0.0970, proof_load: 4205e3, break_load: 6001e3 },
];

/// The solver settings of every paper scene: RK4 at 2 ms for up to 60 s.
const SOLVER: Solver = Solver {
    integrator: Method::Rk4,
    dt: 0.002,
    rtol: 1e-6,
    atol: 1e-8,
    end_time: 60.0,
    output_interval: 0.02,
    stop_when_ship_stops: true,
    max_energy_drift: 0.05,
};

/// One row of Table 2 with its Table 3 stopping time.
#[derive(Clone, Copy, Debug)]
pub struct Case {
    /// The case number of Table 2 (1 … 10).
    pub number: usize,
    /// μ.
    pub friction: f64,
    /// Anchor mass, t.
    pub anchor_tonnes: f64,
    /// Index into [`TABLE_1`].
    pub chain_grade: usize,
    /// Cable length L_c, m.
    pub cable_length: f64,
    /// x_L, m.
    pub horizontal: f64,
    /// h_L, m.
    pub vertical: f64,
    /// Initial ship speed, m/s.
    pub ship_speed: f64,
    /// Ship mass, t.
    pub ship_tonnes: f64,
    /// U_ST, m/s.
    pub current: f64,
    /// Table 3, s.
    pub stopping_time: f64,
    /// Table 3's "parameter change".
    pub change: &'static str,
}

// One argument per column of Tables 2 and 3, in the tables' order.
#[allow(clippy::too_many_arguments)]
const fn case(
    number: usize,
    friction: f64,
    anchor_tonnes: f64,
    chain_grade: usize,
    cable_length: f64,
    horizontal: f64,
    vertical: f64,
    ship_speed: f64,
    ship_tonnes: f64,
    current: f64,
    stopping_time: f64,
    change: &'static str,
) -> Case {
    Case {
        number,
        friction,
        anchor_tonnes,
        chain_grade,
        cable_length,
        horizontal,
        vertical,
        ship_speed,
        ship_tonnes,
        current,
        stopping_time,
        change,
    }
}

/// Tables 2 and 3.
#[rustfmt::skip]
pub const CASES: [Case; 19] = [
    case(1,  0.3, 40.0, 0, 152.0, 148.0,  6.0, 3.0,  500.0, 0.0, 20.010, "base case"),
    case(2,  0.5, 40.0, 0, 152.0, 148.0,  6.0, 3.0,  500.0, 0.0, 13.228, "seabed friction 0.5"),
    case(3,  0.7, 40.0, 0, 152.0, 148.0,  6.0, 3.0,  500.0, 0.0, 10.054, "seabed friction 0.7"),
    case(4,  0.3, 50.0, 0, 152.0, 148.0,  6.0, 3.0,  500.0, 0.0, 16.774, "anchor 50 t"),
    case(5,  0.3, 60.0, 0, 152.0, 148.0,  6.0, 3.0,  500.0, 0.0, 14.498, "anchor 60 t"),
    case(6,  0.3, 40.0, 1, 152.0, 148.0,  6.0, 3.0,  500.0, 0.0, 19.992, "chain radius 0.0863 m"),
    case(7,  0.3, 40.0, 2, 152.0, 148.0,  6.0, 3.0,  500.0, 0.0, 19.976, "chain radius 0.0970 m"),
    case(8,  0.3, 40.0, 0, 172.0, 168.0,  6.0, 3.0,  500.0, 0.0, 19.972, "cable 172 m"),
    case(9,  0.3, 40.0, 0, 192.0, 188.0,  6.0, 3.0,  500.0, 0.0, 19.936, "cable 192 m"),
    case(10, 0.3, 40.0, 0, 152.0, 149.0,  6.0, 3.0,  500.0, 0.0, 19.702, "horizontal projection 149 m"),
    case(11, 0.3, 40.0, 0, 152.0, 150.0,  6.0, 3.0,  500.0, 0.0, 19.386, "horizontal projection 150 m"),
    case(12, 0.3, 40.0, 0, 152.0, 148.0,  8.0, 3.0,  500.0, 0.0, 19.908, "vertical projection 8 m"),
    case(13, 0.3, 40.0, 0, 152.0, 148.0, 10.0, 3.0,  500.0, 0.0, 19.798, "vertical projection 10 m"),
    case(14, 0.3, 40.0, 0, 152.0, 148.0,  6.0, 4.0,  500.0, 0.0, 23.654, "ship speed 4 m/s"),
    case(15, 0.3, 40.0, 0, 152.0, 148.0,  6.0, 5.0,  500.0, 0.0, 26.516, "ship speed 5 m/s"),
    case(16, 0.3, 40.0, 0, 152.0, 148.0,  6.0, 3.0,  750.0, 0.0, 29.134, "ship 750 t"),
    case(17, 0.3, 40.0, 0, 152.0, 148.0,  6.0, 3.0, 1000.0, 0.0, 38.242, "ship 1000 t"),
    case(18, 0.3, 40.0, 0, 152.0, 148.0,  6.0, 3.0,  500.0, 1.0, 22.122, "current 1 m/s"),
    case(19, 0.3, 40.0, 0, 152.0, 148.0,  6.0, 3.0,  500.0, 2.0, 24.126, "current 2 m/s"),
];

/// Table 3's stopping time of `scene` when it is one of the 19 cases (the same physical case:
/// [`Scene::same_case`], whatever its name, solver or design checks), s; none for any other
/// scene, whatever its `meta.paper_stopping_time` says (a variant of a paper case, a scene
/// copied and edited). The one rule every report follows.
pub fn stopping_time(scene: &Scene) -> Option<f64> {
    CASES.iter().find(|case| case.scene().same_case(scene)).map(|case| case.stopping_time)
}

/// The distinct body counts N of the 19 cases, sorted: the unrolled kernels checked in
/// under `generated/src/` (`kanestop codegen --write`, `tests/generated_fresh.rs`).
pub fn body_counts() -> Vec<usize> {
    let mut counts: Vec<usize> = CASES.iter().map(|c| c.scene().body_count()).collect();
    counts.sort_unstable();
    counts.dedup();
    counts
}

/// Anchor length for the paper's anchor masses: 40 t → 2.0 m, 50 t → 2.5 m, 60 t → 3.0 m.
fn anchor_length(tonnes: f64) -> f64 {
    tonnes / 20.0
}

impl Case {
    /// File stem of the case's scene, e.g. `case01`.
    pub fn name(&self) -> String {
        format!("case{:02}", self.number)
    }

    /// The environment of every case: water, current and seabed on (Section 4), with the
    /// case's friction μ and surface current.
    fn environment(&self) -> Environment {
        Environment {
            gravity: GRAVITY,
            water: true,
            water_density: WATER_DENSITY,
            kinematic_viscosity: KINEMATIC_VISCOSITY,
            seabed: true,
            seabed_stiffness: SEABED_STIFFNESS,
            seabed_friction: self.friction,
            line_friction: 0.0,
            current_surface_speed: self.current,
            current_exponent: 1.0 / 7.0,
        }
    }

    /// The case as a scene. The cable's middle stage takes whatever length the first
    /// (3 × 2 m) and last (13 × 2 m) stages leave: 12, 14, 16 × 10 m for 152, 172, 192 m.
    pub fn scene(&self) -> Scene {
        let grade = TABLE_1[self.chain_grade];
        let middle = ((self.cable_length - 6.0 - 26.0) / 10.0).round() as usize;
        let cable_mpl = mass_per_length(CABLE_RADIUS);
        Scene {
            meta: Meta {
                name: self.name(),
                description: format!("Liu et al., Table 2, case {}: {}", self.number, self.change),
                paper_stopping_time: Some(self.stopping_time),
            },
            environment: self.environment(),
            hydrodynamics: Hydrodynamics {
                added_mass_coefficient: 1.0,
                normal_drag_coefficient: 1.21,
                tangential_drag_coefficient: 0.062,
                anchor_drag_coefficient: 1.05,
            },
            anchor: Anchor {
                mass: self.anchor_tonnes * 1e3,
                length: anchor_length(self.anchor_tonnes),
                width: 4.0,
                height: 2.1,
            },
            chain: ChainSpec {
                elements: 15,
                element_length: 1.0,
                radius: grade.radius,
                mass_per_length: mass_per_length(grade.radius),
                proof_load: grade.proof_load,
                break_load: grade.break_load,
            },
            cable: Cable {
                radius: CABLE_RADIUS,
                mass_per_length: cable_mpl,
                break_load: CABLE_BREAK_LOAD,
                stages: vec![
                    CableStage { elements: 3, element_length: 2.0 },
                    CableStage { elements: middle, element_length: 10.0 },
                    CableStage { elements: 13, element_length: 2.0 },
                ],
            },
            rod: Rod { length: 1.0, radius: CABLE_RADIUS, mass_per_length: cable_mpl },
            ship: Ship {
                mass: self.ship_tonnes * 1e3,
                length: 50.0,
                beam: 10.0,
                depth: 5.0,
                hull_roughness: 150e-6,
                hinge_x: -25.0,
                hinge_z: 1.0,
            },
            initial: Initial {
                horizontal_projection: Some(self.horizontal),
                horizontal_tension: None,
                top_tension: None,
                vertical_projection: self.vertical,
                ship_speed: self.ship_speed,
            },
            solver: SOLVER,
            checks: None,
        }
    }

    /// The scene file's text: a header, then the TOML.
    pub fn scene_file(&self) -> String {
        format!(
            "# Generated from kanestop_runtime::paper::CASES (Tables 2 and 3); edit the table, not this file.\n\
             # Field reference with units: docs/scenes.md.\n\n{}",
            self.scene().to_toml()
        )
    }
}

/// Case 1, the default scene, as embedded in the binary.
pub const DEFAULT_SCENE: &str = include_str!("../../scenes/paper/case01.toml");
