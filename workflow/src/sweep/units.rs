//! `sweep.units.csv`: the unit and meaning of every column of `sweep.csv`, in its order, as
//! the run's history has `history.units.csv` beside it (docs/sweeps.md says the same in words).

use kanestop_runtime::scene;

/// A column's unit ("" for a number without one, a count or text) and what it holds, by its
/// name in [`super::cells`]'s header; none for a name that is no column of a sweep.
pub fn column(name: &str, inputs: &[&str]) -> Option<(&'static str, String)> {
    if inputs.contains(&name) {
        return Some((scene::unit(name).unwrap_or(""), format!("input: the scene field {name}")));
    }
    let fixed = |unit: &'static str, what: &str| Some((unit, what.to_string()));
    if let Some(term) = name.strip_prefix("work_") {
        return Some(("J", format!("work done on the system by {term} by the end of the run (negative: taken out)")));
    }
    if let Some(term) = name.strip_prefix("dissipated_") {
        return Some((
            "",
            format!("share of initial_kinetic_energy that {term} took (-work_{term} / initial_kinetic_energy)"),
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
        if let Some(c) = check.strip_suffix("_pass") {
            return Some(("", format!("[checks] {c}: pass, fail")));
        }
    }
    for (segment, joints) in [
        ("peak", "any joint"),
        ("chain_peak", "the chain's joints"),
        ("cable_peak", "the cable's joints"),
        ("rod_peak", "the rod's joints"),
    ] {
        let Some(field) = name.strip_prefix(segment).and_then(|f| f.strip_prefix('_')) else { continue };
        let (unit, what) = match field {
            "tension" => ("N", "largest tension"),
            "joint" => ("", "joint k (between bodies k-1 and k) of the largest tension"),
            "t" => ("s", "when the largest tension occurred"),
            "proof_utilisation" => ("", "the largest tension over its joint's proof load"),
            "break_utilisation" => ("", "the largest tension over its joint's break load"),
            _ => continue,
        };
        return Some((unit, format!("{what}, over {joints}")));
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
        "energy_drift" => fixed("", "largest energy-balance drift, relative to energy_scale"),
        "t_end" => fixed("s", "time the run ended"),
        "steps" => fixed("", "integrator steps"),
        "rhs_evaluations" => fixed("", "right-hand-side evaluations"),
        "wall_time" => fixed("s", "wall-clock time of the run"),
        "message" => fixed("", "error, diagnostic or failed check"),
        "cpu_time" => fixed("s", "CPU time of the run on its own thread"),
        "initial_kinetic_energy" => fixed("J", "kinetic energy at t = 0, the entrained water's included"),
        "initial_horizontal_projection" => fixed("m", "x_L of the laid line"),
        "initial_horizontal_tension" => fixed("N", "T_h of the laid line"),
        "water_depth" => fixed("m", "water depth d"),
        "initial_top_tension" => fixed("N", "T_t = T_h + w_c h_L of the laid line"),
        "energy_scale" => fixed("J", "largest kinetic energy over the run: the scale of energy_drift"),
        _ => None,
    }
}

/// `sweep.units.csv` ([`crate::output::units_csv`]) of the columns `head` ([`super::cells`]'s
/// header, whose input columns are `inputs`).
pub fn csv(head: &[String], inputs: &[&str]) -> String {
    let described: Vec<(&str, &str, String)> = head
        .iter()
        .map(|name| {
            let (unit, what) = column(name, inputs).unwrap_or(("", String::new()));
            (name.as_str(), unit, what)
        })
        .collect();
    crate::output::units_csv(described.iter().map(|(n, u, w)| (*n, *u, w.as_str())))
}
