//! `sweep.units.csv`: the unit and meaning of every column of `sweep.csv`, in its order, like
//! `history.units.csv` beside a run's history (docs/sweeps.md says the same in words).

use kanestop_runtime::scene;

/// A column's unit ("" for a number without one, a count or text) and what it holds, by its
/// name in [`super::cells`]'s header; none for a name that is no column of a sweep.
pub fn column(name: &str, inputs: &[&str]) -> Option<(&'static str, String)> {
    if inputs.contains(&name) {
        return Some((scene::unit(name).unwrap_or(""), format!("input: the scene field {name}")));
    }
    let fixed = |unit: &'static str, what: &str| Some((unit, what.to_string()));
    if let Some(term) = name.strip_prefix("work_") {
        let words = crate::summary::work_term_words(term);
        return Some(("J", format!("work done on the system by {words} by the end of the run (negative: taken out)")));
    }
    if let Some(term) = name.strip_prefix("dissipated_") {
        let words = crate::summary::work_term_words(term);
        let share =
            format!("share of initial_kinetic_energy that {words} took (-work_{term} / initial_kinetic_energy)");
        return Some((
            "",
            match term {
                // `run`'s energy line nets it with the ship's weight (summary.rs).
                "hydrostatic" => format!(
                    "{share}: the ship's buoyancy times its heave, which its weight's potential energy (no column) \
                     all but cancels; run's energy line shows the two netted, as ship heave and pitch"
                ),
                _ => share,
            },
        ));
    }
    if let Some(check) = name.strip_prefix("check_") {
        if let Some(c) = check.strip_suffix("_value") {
            let what = match c {
                "safety_factor" => "the largest break utilisation times the factor (pass: at most 1)".to_string(),
                _ => format!("what the run gave against [checks] {c}"),
            };
            return Some((scene::unit(&format!("checks.{c}")).unwrap_or(""), what));
        }
        if check == "safety_factor_achieved" {
            return Some(("", "the safety factor the run achieved: break load over peak tension at the worst joint (pass: at least the factor set)".to_string()));
        }
        if let Some(c) = check.strip_suffix("_pass") {
            return Some(("", format!("[checks] {c}: pass, fail")));
        }
    }
    // The peaks (`record::RunSummary`): over the whole line against the weaker member's
    // loads at its joint; a member's against that member's own loads.
    for (segment, joints, loads) in [
        ("peak", "the largest tension at any joint", "its joint's (the weaker member's there)"),
        ("chain_peak", "the largest tension at a joint of the chain", "the chain's"),
        ("cable_peak", "the largest tension at a joint of the cable (the rod's foot included)", "the cable's"),
        ("rod_peak", "the peak tension at the rod-ship joint (the fairlead)", "the cable's"),
    ] {
        let Some(field) = name.strip_prefix(segment).and_then(|f| f.strip_prefix('_')) else { continue };
        return Some(match field {
            "tension" => ("N", joints.to_string()),
            "joint" => ("", format!("{joints}: its joint k (between bodies k-1 and k)")),
            "t" => ("s", format!("{joints}: when")),
            "proof_utilisation" => ("", format!("{joints} over {loads} proof load")),
            "break_utilisation" => ("", format!("{joints} over {loads} break load")),
            _ => continue,
        });
    }
    match name {
        "index" => fixed("", "row number in spec order"),
        "name" => fixed("", "row name (its scene: scenes/NAME.toml)"),
        "status" => fixed("", "how the run ended: stopped, end time, failed, invalid"),
        "checks" => fixed("", "design checks (break loads and [checks]): pass, fail, empty when none was made"),
        "stopping_time" => fixed("s", "first zero of the ship's surge speed"),
        "paper_stopping_time" => fixed("s", "Table 3's stopping time (paper cases)"),
        "stopping_distance" => fixed("m", "ship's surge displacement when it stopped"),
        "ship_displacement" => fixed("m", "ship's surge displacement at the end of the run"),
        "anchor_drag_distance" => fixed("m", "anchor's drag distance at the end of the run"),
        "anchor_start" => fixed("s", "when the anchor first slid"),
        "initial_energy" => fixed("J", "E_0: the energy balance at t = 0 (Eq. 63)"),
        "energy_drift" => fixed("", crate::batch::ENERGY_DRIFT_MEANING),
        "t_end" => fixed("s", "time the run ended"),
        "steps" => fixed("", "intervals of solver.dt completed (the adaptive methods' observation intervals)"),
        "rhs_evaluations" => fixed("", "right-hand-side evaluations"),
        "wall_time" => fixed("s", "wall-clock time of the run"),
        "message" => fixed("", "error, diagnostic or failed check"),
        "cpu_time" => fixed("s", "CPU time of the run on its own thread"),
        "initial_kinetic_energy" => fixed("J", "kinetic energy at t = 0, the entrained water's included"),
        "initial_horizontal_projection" => fixed("m", "x_L of the laid line"),
        "initial_horizontal_tension" => fixed("N", "T_h of the laid line"),
        "water_depth" => fixed("m", "water depth d"),
        "initial_top_tension" => fixed("N", "T_t = T_h + w_c h_L of the laid line"),
        "energy_scale" => fixed(
            "J",
            "largest kinetic energy over the run, the entrained water's included: the scale of energy_drift at the end",
        ),
        _ => None,
    }
}

/// Each column of `head` ([`super::cells`]'s header, whose input columns are `inputs`) with
/// its unit and meaning ([`column()`]).
pub fn described(head: &[String], inputs: &[&str]) -> Vec<(String, &'static str, String)> {
    head.iter()
        .map(|name| {
            let (unit, what) = column(name, inputs).unwrap_or(("", String::new()));
            (name.clone(), unit, what)
        })
        .collect()
}
