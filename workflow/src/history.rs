//! The time history of a run as CSV, by channel: each column is named by its role
//! (`ship_x`, `anchor_drag`, `tension_fairlead`, …), its unit and meaning listed in a sidecar
//! file (`<name>.units.csv`). docs/conventions.md has the table of channels; the names are
//! a contract.
//!
//! Channels come in groups a selection can name whole: `ship`, `anchor`, `tension`,
//! `energy`, `bodies` (x, z, θ, vx, vz, ω of every body: `body1_x` …) and `joints` (the
//! tension at every joint: `tension_joint2` …). `t` is always the first column.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use kanestop_runtime::forces::REPORTED_WORK;
use kanestop_runtime::kernel::{AnchorDof, BodyState};
use kanestop_runtime::simulate::{RunResult, Sample};

use crate::output::{write_atomically, CsvNumber};

/// The groups of channels, in column order.
pub const GROUPS: [&str; 6] = ["ship", "anchor", "tension", "energy", "bodies", "joints"];

/// One quantity of a body state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Q {
    X,
    Z,
    Theta,
    Vx,
    Vz,
    Omega,
}

impl Q {
    fn of(self, b: &BodyState) -> f64 {
        match self {
            Q::X => b.x,
            Q::Z => b.z,
            Q::Theta => b.theta,
            Q::Vx => b.vx,
            Q::Vz => b.vz,
            Q::Omega => b.omega,
        }
    }
}

const QUANTITIES: [(Q, &str, &str, &str); 6] = [
    (Q::X, "x", "m", "centroid x (inertial, toward the ship's advance)"),
    (Q::Z, "z", "m", "centroid z (up; still water at 0)"),
    (Q::Theta, "theta", "rad", "angle about y (positive turns x down)"),
    (Q::Vx, "vx", "m/s", "centroid velocity, x"),
    (Q::Vz, "vz", "m/s", "centroid velocity, z"),
    (Q::Omega, "omega", "rad/s", "angular velocity about y"),
];

/// Where a channel's value comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Source {
    T,
    Sliding,
    Body(usize, Q),
    /// x of a body minus its x at the first sample.
    Displacement(usize),
    /// The tension at joint k (2 … N).
    Tension(usize),
    TensionMax,
    Kinetic,
    AddedKinetic,
    Potential,
    Work(usize),
    Balance,
}

/// One column of the CSV history.
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    /// Its column name, e.g. `tension_fairlead`.
    pub name: String,
    /// Its unit (SI), e.g. `N`; `1` for a flag.
    pub unit: &'static str,
    /// What it is, in words.
    pub description: String,
    /// Its group (one of [`GROUPS`]), `time` for `t`.
    pub group: &'static str,
    source: Source,
}

impl Channel {
    fn new(
        name: impl Into<String>,
        unit: &'static str,
        description: impl Into<String>,
        group: &'static str,
        source: Source,
    ) -> Self {
        Channel { name: name.into(), unit, description: description.into(), group, source }
    }

    fn value(&self, s: &Sample, first: &Sample) -> f64 {
        let e = &s.energy;
        match self.source {
            Source::T => s.t,
            Source::Sliding => f64::from(u8::from(s.anchor == AnchorDof::Free)),
            Source::Body(k, q) => q.of(&s.bodies[k]),
            Source::Displacement(k) => s.bodies[k].x - first.bodies[k].x,
            Source::Tension(k) => s.tensions.get(k - 2).copied().unwrap_or(f64::NAN),
            Source::TensionMax => s.tensions.iter().copied().fold(f64::NAN, f64::max),
            Source::Kinetic => e.kinetic,
            Source::AddedKinetic => e.added_kinetic,
            Source::Potential => e.potential,
            Source::Work(i) => e.reported_work()[i].1,
            Source::Balance => e.balance(),
        }
    }
}

/// Every channel of an N-body run, in column order.
pub fn all_channels(n: usize) -> Vec<Channel> {
    let ship = n - 1;
    let mut c = vec![Channel::new("t", "s", "time", "time", Source::T)];
    for (q, name, unit, what) in QUANTITIES {
        c.push(Channel::new(format!("ship_{name}"), unit, format!("ship {what}"), "ship", Source::Body(ship, q)));
    }
    c.push(Channel::new(
        "ship_displacement",
        "m",
        "ship surge displacement since t = 0",
        "ship",
        Source::Displacement(ship),
    ));
    c.push(Channel::new("anchor_x", "m", "anchor centroid x", "anchor", Source::Body(0, Q::X)));
    c.push(Channel::new("anchor_vx", "m/s", "anchor surge speed", "anchor", Source::Body(0, Q::Vx)));
    c.push(Channel::new("anchor_drag", "m", "anchor drag distance since t = 0 (its displacement along the seabed; work_anchor_drag is the water's drag on it)", "anchor", Source::Displacement(0)));
    c.push(Channel::new(
        "anchor_sliding",
        "1",
        "1 while the anchor slides, 0 while friction holds it",
        "anchor",
        Source::Sliding,
    ));
    c.push(Channel::new(
        "tension_fairlead",
        "N",
        format!("tension at the rod–ship joint (joint {n}), the load on the ship"),
        "tension",
        Source::Tension(n),
    ));
    c.push(Channel::new(
        "tension_anchor",
        "N",
        "tension at the anchor–chain joint (joint 2)",
        "tension",
        Source::Tension(2),
    ));
    c.push(Channel::new(
        "tension_max",
        "N",
        "largest joint tension along the line at this time",
        "tension",
        Source::TensionMax,
    ));
    c.push(Channel::new("energy_kinetic", "J", "kinetic energy of the bodies", "energy", Source::Kinetic));
    c.push(Channel::new(
        "energy_added_kinetic",
        "J",
        "kinetic energy of the entrained water",
        "energy",
        Source::AddedKinetic,
    ));
    c.push(Channel::new("energy_potential", "J", "gravitational potential energy", "energy", Source::Potential));
    for (i, term) in REPORTED_WORK.iter().enumerate() {
        c.push(Channel::new(
            format!("work_{term}"),
            "J",
            format!("work done by {} since t = 0 (negative: dissipated)", crate::summary::work_term_words(term)),
            "energy",
            Source::Work(i),
        ));
    }
    c.push(Channel::new(
        "energy_balance",
        "J",
        "kinetic + potential − work (Eq. 63): constant when exact",
        "energy",
        Source::Balance,
    ));
    for k in 1..=n {
        for (q, name, unit, what) in QUANTITIES {
            c.push(Channel::new(
                format!("body{k}_{name}"),
                unit,
                format!("B_{k} {what}"),
                "bodies",
                Source::Body(k - 1, q),
            ));
        }
    }
    for k in 2..=n {
        c.push(Channel::new(
            format!("tension_joint{k}"),
            "N",
            format!("tension at joint {k} (B_{} – B_{k})", k - 1),
            "joints",
            Source::Tension(k),
        ));
    }
    c
}

/// The channels named by `spec` (channel names and group names, in any order) for an
/// N-body run, in column order, `t` first; an empty `spec` selects every channel.
pub fn select(n: usize, spec: &[String]) -> Result<Vec<Channel>, String> {
    let all = all_channels(n);
    if spec.is_empty() {
        return Ok(all);
    }
    for name in spec {
        if !GROUPS.contains(&name.as_str()) && !all.iter().any(|c| &c.name == name) {
            return Err(format!(
                "unknown channel {name:?}: give channel names (ship_x, anchor_drag, tension_fairlead, …; see \
                 docs/conventions.md) or groups ({})",
                GROUPS.join(", ")
            ));
        }
    }
    let keep = |c: &Channel| c.group == "time" || spec.iter().any(|s| *s == c.name || *s == c.group);
    Ok(all.into_iter().filter(keep).collect())
}

/// The CSV time history with every channel.
pub fn csv(result: &RunResult) -> String {
    let n = result.samples.first().map_or(0, |s| s.bodies.len());
    if n == 0 {
        return "t\n".to_string();
    }
    csv_of(result, &all_channels(n))
}

/// The CSV time history of `channels` (from [`select`]): a header of names, a row per sample.
pub fn csv_of(result: &RunResult, channels: &[Channel]) -> String {
    let mut out = channels.iter().map(|c| c.name.as_str()).collect::<Vec<_>>().join(",");
    out.push('\n');
    let Some(first) = result.samples.first() else { return out };
    for s in &result.samples {
        for (i, c) in channels.iter().enumerate() {
            let v = c.value(s, first);
            let sep = if i == 0 { "" } else { "," };
            let _ = match c.source {
                Source::T | Source::Sliding => write!(out, "{sep}{v}"),
                _ => write!(out, "{sep}{}", CsvNumber(v)),
            };
        }
        out.push('\n');
    }
    out
}

/// The value of each of `channels` at every sample of `result`: one column per channel, in
/// order (the numbers the CSV history writes; the Python package's `channels`).
///
/// The body states are most of the columns (276 of case 1's 351, 992 samples each): the
/// columns of one body are filled together, each sample's state read once for all of them,
/// which makes the whole conversion about 3× faster than a column at a time (a sample's
/// bodies are a heap block of their own, so reading one value per block is a cache miss).
pub fn columns(result: &RunResult, channels: &[Channel]) -> Vec<Vec<f64>> {
    let mut out: Vec<Vec<f64>> = channels.iter().map(|_| Vec::with_capacity(result.samples.len())).collect();
    let Some(first) = result.samples.first() else { return out };
    let mut i = 0;
    while i < channels.len() {
        let Source::Body(k, _) = channels[i].source else {
            out[i].extend(result.samples.iter().map(|s| channels[i].value(s, first)));
            i += 1;
            continue;
        };
        let quantities: Vec<Q> = channels[i..]
            .iter()
            .map_while(|c| match c.source {
                Source::Body(j, q) if j == k => Some(q),
                _ => None,
            })
            .collect();
        let filled = &mut out[i..i + quantities.len()];
        for s in &result.samples {
            let b = &s.bodies[k];
            for (column, q) in filled.iter_mut().zip(&quantities) {
                column.push(q.of(b));
            }
        }
        i += quantities.len();
    }
    out
}

/// The units sidecar: `channel,unit,description`, one line per column of the history.
pub fn units_csv(channels: &[Channel]) -> String {
    let mut out = String::from("channel,unit,description\n");
    for c in channels {
        let _ = writeln!(out, "{},{},{}", c.name, c.unit, crate::output::csv_quoted(&c.description));
    }
    out
}

/// The sidecar of `path`: `history.csv` → `history.units.csv`.
pub fn units_path(path: &Path) -> PathBuf {
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    path.with_file_name(format!("{stem}.units.csv"))
}

/// Writes the CSV time history with every channel to `path`, whole or not at all.
pub fn write_csv(result: &RunResult, path: &Path) -> std::io::Result<()> {
    write_atomically(path, csv(result).as_bytes())
}

/// Writes the history of `channels` to `path` and their units beside it
/// ([`units_path`]), each whole or not at all. Returns the two files.
pub fn write_channels(result: &RunResult, channels: &[Channel], path: &Path) -> std::io::Result<[PathBuf; 2]> {
    let units = units_path(path);
    write_atomically(path, csv_of(result, channels).as_bytes())?;
    write_atomically(&units, units_csv(channels).as_bytes())?;
    Ok([path.to_path_buf(), units])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_read_back_exactly_and_plainly() {
        for (v, text) in [
            (3.0, "3"),
            (0.0, "0"),
            (-0.0, "0"),
            (1669.9795856262342, "1669.9795856262342"),
            (-7.531752999057062e-12, "-7.531752999057062e-12"),
            (2.5e20, "2.5e20"),
            (1e-5, "0.00001"),
        ] {
            let written = CsvNumber(v).to_string();
            assert_eq!(written, text);
            // Exact: the same value read back (a zero's sign is not kept, see CsvNumber).
            assert_eq!(written.parse::<f64>().unwrap(), v, "{text}");
        }
    }

    #[test]
    fn names_are_unique_and_groups_select() {
        let all = all_channels(5);
        let mut names: Vec<&str> = all.iter().map(|c| c.name.as_str()).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), all.len());
        assert_eq!(all.len(), 1 + 7 + 4 + 3 + 15 + 6 * 5 + 4);
        let sel = select(5, &["tension_fairlead".into(), "ship".into()]).unwrap();
        let names: Vec<&str> = sel.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names[0], "t");
        assert!(names.contains(&"ship_x") && names.contains(&"tension_fairlead") && !names.contains(&"anchor_x"));
        assert!(select(5, &["x_5".into()]).unwrap_err().contains("unknown channel \"x_5\""));
        assert!(all.iter().any(|c| c.name == "tension_joint5" && c.unit == "N"));
    }
}
