//! Scenes built from other scenes: `extends = "base.toml"` with overrides, and values set by
//! dotted path (`ship.mass`, `cable.stages[1].elements`), as sweeps and the Python package
//! set them.
//!
//! Both work on the TOML value before it becomes a [`crate::scene::Scene`], so the result is
//! checked exactly as a whole file would be: a variant of a few lines gives the same scene,
//! field for field, as the full file it stands for.

use std::path::{Path, PathBuf};

use toml::Value;

/// Why a dotted path or an `extends` chain could not be applied.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum OverrideError {
    /// The path is not `table.field`, `table.array[index].field`, ….
    #[error("{path}: not a field path (write it as table.field or table.array[index].field)")]
    Syntax {
        /// The path as given.
        path: String,
    },
    /// A part of the path names no field of the scene.
    #[error("{path}: no field `{part}` here (valid: {valid})")]
    NoSuchField {
        /// The path as given.
        path: String,
        /// The part that was not found.
        part: String,
        /// The keys that exist at that level.
        valid: String,
    },
    /// An index past the end of an array.
    #[error("{path}: index {index} is out of range (the array has {len} entries)")]
    Index {
        /// The path as given.
        path: String,
        /// The index given.
        index: usize,
        /// The array's length.
        len: usize,
    },
    /// A part of the path goes into what cannot take it: a plain value (`ship.mass.x`), an
    /// array by name (`cable.stages.elements`) or a table by index.
    #[error("{path}: `{part}` is {what}")]
    NotAContainer {
        /// The path as given.
        path: String,
        /// The part the path goes on from.
        part: String,
        /// What it is, and what the path would need.
        what: String,
    },
    /// Two fields of one group of [`ALTERNATIVES`] set together: which one lays the scene
    /// would depend on their order.
    #[error("{first} and {second} are both set: they give one quantity in two ways (set one of them)")]
    Alternatives {
        /// The first path.
        first: String,
        /// The second path.
        second: String,
    },
    /// `extends` is not a string, or an empty one.
    #[error("extends must be a file name, e.g. extends = \"base.toml\"")]
    ExtendsType,
    /// A file extends itself, directly or round a chain.
    #[error("extends chain loops back to {0}")]
    ExtendsCycle(PathBuf),
}

/// One step of a dotted path.
#[derive(Debug, PartialEq)]
enum Step<'a> {
    Key(&'a str),
    Index(usize),
}

/// `cable.stages[1].elements` → [Key(cable), Key(stages), Index(1), Key(elements)].
fn steps(path: &str) -> Result<Vec<Step<'_>>, OverrideError> {
    let syntax = || OverrideError::Syntax { path: path.to_string() };
    let mut out = Vec::new();
    for part in path.split('.') {
        let (key, mut rest) = match part.find('[') {
            Some(i) => (&part[..i], &part[i..]),
            None => (part, ""),
        };
        let is_key = !key.is_empty() && key.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
        if !is_key {
            return Err(syntax());
        }
        out.push(Step::Key(key));
        while !rest.is_empty() {
            let close = rest.find(']').ok_or_else(syntax)?;
            let index = rest[1..close].parse::<usize>().map_err(|_| syntax())?;
            out.push(Step::Index(index));
            rest = &rest[close + 1..];
            if !rest.is_empty() && !rest.starts_with('[') {
                return Err(syntax());
            }
        }
    }
    Ok(out)
}

/// Fields that give one quantity in different ways, by table: a scene gives one of each
/// group, so setting one (by path, or in a file that extends another) drops the others. The
/// initial line is laid by its horizontal projection x_L, its horizontal tension T_h or its
/// top tension T_t (`crate::scene::Initial`).
pub const ALTERNATIVES: &[(&str, &[&str])] =
    &[("initial", &["horizontal_projection", "horizontal_tension", "top_tension"])];

/// Optional tables and their fields, which a scene may leave out: setting one by path adds
/// it (a scene without `[checks]` takes `checks.max_stopping_distance`).
pub const OPTIONAL: &[(&str, &[&str])] = &[("checks", &crate::design::CHECK_FIELDS)];

/// `path` (`table.field`) split, when it is a field of [`OPTIONAL`].
fn optional_of(path: &str) -> Option<(&str, &str)> {
    let (table, key) = path.split_once('.')?;
    OPTIONAL.iter().any(|(t, keys)| *t == table && keys.contains(&key)).then_some((table, key))
}

/// The group of [`ALTERNATIVES`] that `path` (`table.field`) belongs to.
fn alternatives_of(path: &str) -> Option<(&'static str, &'static [&'static str], &str)> {
    let (table, key) = path.split_once('.')?;
    ALTERNATIVES.iter().find(|(t, keys)| *t == table && keys.contains(&key)).map(|(t, keys)| (*t, *keys, key))
}

/// Sets the field at `path` of `root` to `value`. A path that names no field of `root` is
/// refused with the keys that exist there (a new key is a typing error), except a field of
/// [`ALTERNATIVES`], which takes the place of the one of its group that `root` has.
pub fn set(root: &mut Value, path: &str, value: Value) -> Result<(), OverrideError> {
    let steps = steps(path)?;
    if let Some((table, group, key)) = alternatives_of(path) {
        if let Some(t) = root.get_mut(table).and_then(Value::as_table_mut) {
            if !t.contains_key(key) && group.iter().any(|k| t.contains_key(*k)) {
                for k in group {
                    t.remove(*k);
                }
                // The group's fields are real: a whole number sets it as that number.
                let value = match value {
                    Value::Integer(n) => Value::Float(n as f64),
                    v => v,
                };
                t.insert(key.to_string(), value);
                return Ok(());
            }
        }
    }
    add_optional(root, &steps, path)?;
    let mut node = root;
    let mut at = String::new();
    for (depth, step) in steps.iter().enumerate() {
        node = match (step, node) {
            (Step::Key(k), Value::Table(t)) => {
                let valid = valid_keys(t, depth, &at);
                t.get_mut(*k).ok_or_else(|| OverrideError::NoSuchField {
                    path: path.to_string(),
                    part: k.to_string(),
                    valid,
                })?
            }
            (Step::Index(i), Value::Array(a)) => {
                let len = a.len();
                a.get_mut(*i).ok_or(OverrideError::Index { path: path.to_string(), index: *i, len })?
            }
            (step, node) => {
                let what = match (step, node) {
                    (Step::Key(k), Value::Array(_)) => format!("an array: give an index, as {at}[0].{k}"),
                    (Step::Index(_), Value::Table(_)) => "a table, not an array: give a field".to_string(),
                    _ => "a value, not a table or an array".to_string(),
                };
                return Err(OverrideError::NotAContainer { path: path.to_string(), part: at, what });
            }
        };
        at = match step {
            Step::Key(k) => k.to_string(),
            Step::Index(i) => format!("{at}[{i}]"),
        };
    }
    // A whole number given as a float (3.0, numpy's float64(3)) sets an integer field, as a
    // sweep axis's values do; an integer sets a real field as that number.
    *node = match (&*node, value) {
        (Value::Integer(_), Value::Float(x)) if x.fract() == 0.0 && x.abs() < 9e15 => Value::Integer(x as i64),
        (Value::Float(_), Value::Integer(n)) => Value::Float(n as f64),
        (_, value) => value,
    };
    Ok(())
}

/// An optional table (`[checks]`) that `root` does not have, added for a path into it (its
/// `steps`): with the field named, when it is one of the table's
/// (`checks.max_stopping_distance`); a name that is none of them is refused with those
/// there are.
fn add_optional(root: &mut Value, steps: &[Step<'_>], path: &str) -> Result<(), OverrideError> {
    if let (Some(Step::Key(table)), Value::Table(top)) = (steps.first(), &mut *root) {
        if let Some((_, fields)) = OPTIONAL.iter().find(|(t, _)| t == table) {
            if let (None, Some(Step::Key(key))) = (top.get(*table), steps.get(1)) {
                if !fields.contains(key) {
                    let mut valid = fields.to_vec();
                    valid.sort_unstable();
                    let (path, part, valid) = (path.to_string(), key.to_string(), valid.join(", "));
                    return Err(OverrideError::NoSuchField { path, part, valid });
                }
            }
            let t = top.entry(*table).or_insert_with(|| Value::Table(toml::Table::new()));
            if let (Value::Table(t), Some(Step::Key(key))) = (t, steps.get(1)) {
                if fields.contains(key) {
                    t.entry(*key).or_insert(Value::Float(0.0));
                }
            }
        }
    }
    Ok(())
}

/// The keys a path may take in table `t` at `depth` below the root, after the step `at`:
/// those it has, and those of [`OPTIONAL`] it may gain (a scene without `[checks]`, or
/// `[checks]` with some of its fields), sorted.
fn valid_keys(t: &toml::Table, depth: usize, at: &str) -> String {
    let mut keys: Vec<&str> = t.keys().map(String::as_str).collect();
    for (table, fields) in OPTIONAL {
        match depth {
            0 => keys.push(table),
            1 if at == *table => keys.extend(fields.iter().copied()),
            _ => {}
        }
    }
    keys.sort_unstable();
    keys.dedup();
    keys.join(", ")
}

/// The first two of `paths` (by position) that are fields of one group of [`ALTERNATIVES`]:
/// set together, the last set would silently replace the other.
pub fn conflicting_alternatives(paths: &[&str]) -> Option<(usize, usize)> {
    let group = |p: &str| alternatives_of(p).map(|(table, keys, _)| (table, keys));
    (0..paths.len()).find_map(|j| {
        let of_j = group(paths[j])?;
        (0..j).find(|&i| paths[i] != paths[j] && group(paths[i]) == Some(of_j)).map(|i| (i, j))
    })
}

/// The value at `path` of `root`, or for a field of [`ALTERNATIVES`] that `root` does not
/// have, the value of the one of its group it has, or for a field of [`OPTIONAL`] that it
/// does not have, a real number (the checks' type): what [`set`] would replace (its type is
/// the one `path` takes).
pub fn get_or_alternative<'a>(root: &'a Value, path: &str) -> Option<&'a Value> {
    static REAL: Value = Value::Float(0.0);
    get(root, path).or_else(|| {
        if optional_of(path).is_some() {
            return Some(&REAL);
        }
        let (table, group, _) = alternatives_of(path)?;
        group.iter().find_map(|k| get(root, &format!("{table}.{k}")))
    })
}

/// The value at `path` of `root`, if there is one.
pub fn get<'a>(root: &'a Value, path: &str) -> Option<&'a Value> {
    let mut node = root;
    for step in steps(path).ok()? {
        node = match step {
            Step::Key(k) => node.as_table()?.get(k)?,
            Step::Index(i) => node.as_array()?.get(i)?,
        };
    }
    Some(node)
}

/// The file an `extends` value names: a non-empty string, else none (the value is refused
/// with [`OverrideError::ExtendsType`]).
pub fn extends_target(value: &Value) -> Option<&str> {
    value.as_str().filter(|b| !b.trim().is_empty())
}

/// The one rule for a step laid over a scene without an output interval beside it
/// (`run --dt`, `batch --methods rk4@0.01`, Python's `dt=`): where the scene's own
/// `solver.output_interval` is shorter than the step `dt`, it is raised to the step (the
/// output grid holds at least one step), and the interval it had is returned, for a note.
/// A value out of its own range (0, negative, not a number) is left for the scene's check
/// to refuse.
pub fn raise_output_interval(value: &mut Value, dt: f64) -> Option<f64> {
    let solver = value.get_mut("solver")?.as_table_mut()?;
    let interval = solver.get("output_interval").and_then(|v| v.as_float().or(v.as_integer().map(|i| i as f64)))?;
    (interval > 0.0 && interval < dt).then(|| {
        solver.insert("output_interval".into(), Value::Float(dt));
        interval
    })
}

/// Lays `over` onto `base`: tables merge key by key, recursively; anything else (values,
/// arrays such as `cable.stages`) replaces what `base` had; a field of [`ALTERNATIVES`] in
/// `over` drops the others of its group from `base`.
pub fn merge(base: &mut Value, over: Value) {
    for (table, group) in ALTERNATIVES {
        let given = over.get(table).and_then(Value::as_table).map(|t| group.iter().any(|k| t.contains_key(*k)));
        if given == Some(true) {
            if let Some(t) = base.get_mut(table).and_then(Value::as_table_mut) {
                for k in *group {
                    t.remove(*k);
                }
            }
        }
    }
    merge_tables(base, over);
}

/// [`merge`] without the rule of alternatives.
fn merge_tables(base: &mut Value, over: Value) {
    match (base, over) {
        (Value::Table(b), Value::Table(o)) => {
            for (k, v) in o {
                match b.get_mut(&k) {
                    Some(existing) => merge_tables(existing, v),
                    None => {
                        b.insert(k, v);
                    }
                }
            }
        }
        (b, o) => *b = o,
    }
}

/// Reads a file's text: the file at the path, and the file whose `extends` named it (`None`
/// for the first).
pub type ReadFile<'a, E> = dyn FnMut(&Path, Option<&Path>) -> Result<String, E> + 'a;

/// Reads a scene file's TOML and resolves its `extends` chain: each file's tables are laid
/// over the file it extends (a path relative to the extending file). `read` reads a file's
/// text (the file system, or a test's table), given with the file whose `extends` named it
/// (`named_by` for `path`: `None`, or the text that extends it); its error is passed through.
pub fn resolve<E>(
    path: &Path,
    named_by: Option<&Path>,
    read: &mut ReadFile<'_, E>,
    parse: &mut dyn FnMut(&Path, &str) -> Result<Value, E>,
    wrap: &dyn Fn(&Path, OverrideError) -> E,
) -> Result<Value, E> {
    let mut chain: Vec<(PathBuf, Value)> = Vec::new();
    let mut seen: Vec<PathBuf> = Vec::new();
    let mut next = Some(path.to_path_buf());
    let mut named_by: Option<PathBuf> = named_by.map(Path::to_path_buf);
    while let Some(file) = next.take() {
        // Files are read by the path as joined (`../` after a symbolic link goes where the
        // system takes it); a loop is found by the file itself, the same whichever way its
        // path is written.
        let key = std::fs::canonicalize(&file).unwrap_or_else(|_| lexically_normal(&file));
        if seen.contains(&key) {
            return Err(wrap(path, OverrideError::ExtendsCycle(file)));
        }
        seen.push(key);
        let mut value = parse(&file, &read(&file, named_by.as_deref())?)?;
        if let Some(table) = value.as_table_mut() {
            if let Some(base) = table.remove("extends") {
                let base = extends_target(&base).ok_or_else(|| wrap(&file, OverrideError::ExtendsType))?;
                let dir = file.parent().unwrap_or(Path::new(""));
                next = Some(dir.join(base));
            }
        }
        named_by = Some(file.clone());
        chain.push((file, value));
    }
    let (_, mut merged) = chain.pop().expect("at least the file itself");
    while let Some((_, over)) = chain.pop() {
        merge(&mut merged, over);
    }
    Ok(merged)
}

/// Whether two tables hold the same values, a float by its bits (so that a `nan` equals
/// itself and `-0.0` differs from `0.0`, where `==` says otherwise): whether an edit changed
/// a scene.
pub fn same(a: &Value, b: &Value) -> bool {
    match (a, b) {
        (Value::Float(x), Value::Float(y)) => x.to_bits() == y.to_bits(),
        (Value::Table(x), Value::Table(y)) => {
            x.len() == y.len() && x.iter().all(|(k, v)| y.get(k).is_some_and(|w| same(v, w)))
        }
        (Value::Array(x), Value::Array(y)) => x.len() == y.len() && x.iter().zip(y).all(|(v, w)| same(v, w)),
        _ => a == b,
    }
}

/// `path` with its `.` components dropped and each `..` taking the folder before it away
/// (a leading `..` kept): a file's key for loop detection where the file system cannot say
/// (a file that does not exist, or a test's files in memory).
fn lexically_normal(path: &Path) -> PathBuf {
    use std::path::Component;
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir if matches!(out.components().next_back(), Some(Component::Normal(_))) => {
                out.pop();
            }
            Component::ParentDir if out.has_root() => {} // `/..` is `/`
            other => out.push(other),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn value(text: &str) -> Value {
        text.parse::<toml::Table>().map(Value::Table).unwrap()
    }

    #[test]
    fn dotted_paths_set_fields_and_array_entries() {
        let mut v = value("[ship]\nmass = 1.0\n[[cable.stages]]\nelements = 3\n[[cable.stages]]\nelements = 12\n");
        set(&mut v, "ship.mass", Value::Float(2.5)).unwrap();
        set(&mut v, "cable.stages[1].elements", Value::Float(20.0)).unwrap();
        assert_eq!(get(&v, "ship.mass"), Some(&Value::Float(2.5)));
        assert_eq!(get(&v, "cable.stages[1].elements"), Some(&Value::Integer(20)));
        assert_eq!(get(&v, "cable.stages[0].elements"), Some(&Value::Integer(3)));
        set(&mut v, "ship.mass", Value::Integer(3)).unwrap();
        assert_eq!(get(&v, "ship.mass"), Some(&Value::Float(3.0)));
        set(&mut v, "cable.stages[0].elements", Value::Float(2.5)).unwrap();
        assert_eq!(get(&v, "cable.stages[0].elements"), Some(&Value::Float(2.5)), "refused by the scene's check");
    }

    #[test]
    fn bad_paths_are_refused_with_what_exists() {
        let mut v = value("[ship]\nmass = 1.0\nlength = 2.0\n[[cable.stages]]\nelements = 3\n");
        let e = set(&mut v, "ship.mas", Value::Float(1.0)).unwrap_err();
        assert_eq!(e.to_string(), "ship.mas: no field `mas` here (valid: length, mass)");
        let e = set(&mut v, "cable.stages[4].elements", Value::Integer(1)).unwrap_err();
        assert_eq!(e, OverrideError::Index { path: "cable.stages[4].elements".into(), index: 4, len: 1 });
        // The part in the way is named, with what the path would need.
        let e = set(&mut v, "ship.mass.x", Value::Integer(1)).unwrap_err();
        assert_eq!(e.to_string(), "ship.mass.x: `mass` is a value, not a table or an array");
        let e = set(&mut v, "ship.mass[0]", Value::Integer(1)).unwrap_err();
        assert_eq!(e.to_string(), "ship.mass[0]: `mass` is a value, not a table or an array");
        let e = set(&mut v, "cable.stages.elements", Value::Integer(1)).unwrap_err();
        assert_eq!(e.to_string(), "cable.stages.elements: `stages` is an array: give an index, as stages[0].elements");
        let e = set(&mut v, "ship[0]", Value::Integer(1)).unwrap_err();
        assert_eq!(e.to_string(), "ship[0]: `ship` is a table, not an array: give a field");
        // A typing error among the optional checks lists them all, at the top and inside.
        let e = set(&mut v, "checks.max_stoping", Value::Float(1.0)).unwrap_err();
        let OverrideError::NoSuchField { part, valid, .. } = &e else { panic!("{e}") };
        let mut sorted = crate::design::CHECK_FIELDS.to_vec();
        sorted.sort_unstable();
        assert_eq!((part.as_str(), valid.as_str()), ("max_stoping", sorted.join(", ").as_str()));
        // Deeper or indexed paths into a [checks] not there: the part in the way, as anywhere.
        for (bad, said) in [
            ("checks.max_stopping_time.x", "`max_stopping_time` is a value"),
            ("checks.max_stopping_time[0]", "`max_stopping_time` is a value"),
            ("checks[0]", "`checks` is a table, not an array"),
        ] {
            let mut fresh = value("[ship]\nmass = 1.0\n");
            let e = set(&mut fresh, bad, Value::Float(1.0)).unwrap_err().to_string();
            assert!(e.contains(said), "{bad}: {e}");
        }
        let e = set(&mut v, "chekcs.max_stopping_time", Value::Float(1.0)).unwrap_err();
        let OverrideError::NoSuchField { valid, .. } = &e else { panic!("{e}") };
        assert!(valid.contains("checks") && valid.contains("ship"), "{valid}");
        set(&mut v, "checks.max_stopping_distance", Value::Float(40.0)).unwrap();
        let e = set(&mut v, "checks.max_stoping", Value::Float(1.0)).unwrap_err();
        let OverrideError::NoSuchField { valid, .. } = &e else { panic!("{e}") };
        assert!(crate::design::CHECK_FIELDS.iter().all(|f| valid.contains(f)), "{valid}");
        // The whole table, on a scene without it.
        let mut w = value("[ship]\nmass = 1.0\n");
        set(&mut w, "checks", value("max_stopping_time = 30.0\n")).unwrap();
        assert_eq!(get(&w, "checks.max_stopping_time"), Some(&Value::Float(30.0)));
        for bad in ["", "ship..mass", "ship.mass[", "ship.mass[x]", "ship mass", "cable.stages[0]x"] {
            assert!(matches!(set(&mut v, bad, Value::Integer(1)), Err(OverrideError::Syntax { .. })), "{bad}");
        }
    }

    #[test]
    fn a_field_of_a_group_of_alternatives_takes_the_place_of_the_other() {
        let base = "[initial]\nhorizontal_projection = 148.0\nvertical_projection = 6.0\n";
        // By path: the tension replaces the projection (a whole number as a real), and back.
        let mut v = value(base);
        set(&mut v, "initial.horizontal_tension", Value::Integer(150)).unwrap();
        assert_eq!(v, value("[initial]\nhorizontal_tension = 150.0\nvertical_projection = 6.0\n"));
        set(&mut v, "initial.horizontal_projection", Value::Float(149.0)).unwrap();
        assert_eq!(v, value("[initial]\nhorizontal_projection = 149.0\nvertical_projection = 6.0\n"));
        // What a sweep's axis on the tension finds in a base that has the projection.
        assert_eq!(get(&value(base), "initial.horizontal_tension"), None);
        assert_eq!(get_or_alternative(&value(base), "initial.horizontal_tension"), Some(&Value::Float(148.0)));
        assert_eq!(get_or_alternative(&value(base), "initial.ship_speed"), None);
        // Other new keys are still typing errors, in a group's table too.
        assert!(matches!(
            set(&mut v, "initial.horizontal_tensoin", Value::Float(1.0)),
            Err(OverrideError::NoSuchField { .. })
        ));
        // By `extends`: the file's tension drops its base's projection; a file that gives
        // neither keeps the base's.
        let mut b = value(base);
        merge(&mut b, value("[initial]\nhorizontal_tension = 150.0\n"));
        assert_eq!(b, value("[initial]\nvertical_projection = 6.0\nhorizontal_tension = 150.0\n"));
        let mut b = value(base);
        merge(&mut b, value("[initial]\nvertical_projection = 8.0\n"));
        assert_eq!(b, value("[initial]\nhorizontal_projection = 148.0\nvertical_projection = 8.0\n"));
    }

    #[test]
    fn merge_lays_tables_over_tables_and_replaces_the_rest() {
        let mut base = value("[ship]\nmass = 1.0\nlength = 2.0\n[[cable.stages]]\nelements = 3\n");
        merge(&mut base, value("[ship]\nmass = 5.0\n[[cable.stages]]\nelements = 7\n[[cable.stages]]\nelements = 8\n"));
        assert_eq!(get(&base, "ship.mass"), Some(&Value::Float(5.0)));
        assert_eq!(get(&base, "ship.length"), Some(&Value::Float(2.0)));
        assert_eq!(get(&base, "cable.stages").and_then(Value::as_array).map(Vec::len), Some(2));
    }

    #[test]
    fn same_takes_floats_by_their_bits() {
        let a = value("x = nan\n[t]\ny = [1.0, -0.0]\nz = 1\n");
        assert!(same(&a, &a.clone()), "nan is the same nan");
        assert!(!same(&a, &value("x = nan\n[t]\ny = [1.0, 0.0]\nz = 1\n")), "-0.0 is not 0.0");
        assert!(!same(&a, &value("x = nan\n[t]\ny = [1.0, -0.0]\nz = 1.0\n")), "1 is not 1.0");
        assert!(!same(&a, &value("x = nan\n[t]\ny = [1.0, -0.0]\n")));
        assert!(!same(&a, &value("x = 1.0\n[t]\ny = [1.0, -0.0]\nz = 1\n")));
    }

    #[test]
    fn extends_chains_resolve_and_loops_are_refused() {
        let files = [
            ("dir/c.toml", "extends = \"b.toml\"\n[ship]\nmass = 3.0\n"),
            ("dir/b.toml", "extends = \"sub/a.toml\"\n[ship]\nlength = 9.0\n"),
            ("dir/sub/a.toml", "[ship]\nmass = 1.0\nlength = 2.0\nwidth = 4.0\n"),
            ("dir/loop1.toml", "extends = \"loop2.toml\"\n"),
            ("dir/loop2.toml", "extends = \"loop1.toml\"\n"),
            ("dir/loop3.toml", "extends = \"../dir/./loop3.toml\"\n"),
        ];
        let mut read = |p: &Path, by: Option<&Path>| -> Result<String, String> {
            let key = p.to_string_lossy().replace('\\', "/");
            let by = by.map(|b| format!(" (named by {})", b.display())).unwrap_or_default();
            files.iter().find(|(n, _)| *n == key).map(|(_, t)| t.to_string()).ok_or(format!("no {key}{by}"))
        };
        let mut parse = |_: &Path, t: &str| -> Result<Value, String> { Ok(value(t)) };
        let wrap = |p: &Path, e: OverrideError| format!("{}: {e}", p.display());
        let v = resolve(Path::new("dir/c.toml"), None, &mut read, &mut parse, &wrap).unwrap();
        assert_eq!(v, value("[ship]\nmass = 3.0\nlength = 9.0\nwidth = 4.0\n"));
        let e = resolve(Path::new("dir/loop1.toml"), None, &mut read, &mut parse, &wrap).unwrap_err();
        assert!(e.contains("loops back to dir/loop1.toml"), "{e}");
        let e = resolve(Path::new("dir/loop3.toml"), None, &mut read, &mut parse, &wrap).unwrap_err();
        assert!(e.contains("loops back to dir/../dir/./loop3.toml"), "{e}");
        for (path, normal) in [("a/../b/./c", "b/c"), ("../a/../../b", "../../b"), ("/../a", "/a"), ("a/b/..", "a")] {
            assert_eq!(lexically_normal(Path::new(path)), Path::new(normal), "{path}");
        }
        let e = resolve(Path::new("dir/missing.toml"), None, &mut read, &mut parse, &wrap).unwrap_err();
        assert_eq!(e, "no dir/missing.toml");
        let files = [("dir/d.toml", "extends = \"gone.toml\"\n")];
        let mut read = |p: &Path, by: Option<&Path>| -> Result<String, String> {
            let key = p.to_string_lossy().replace('\\', "/");
            let by = by.map(|b| format!(" (named by {})", b.display())).unwrap_or_default();
            files.iter().find(|(n, _)| *n == key).map(|(_, t)| t.to_string()).ok_or(format!("no {key}{by}"))
        };
        let e = resolve(Path::new("dir/d.toml"), None, &mut read, &mut parse, &wrap).unwrap_err();
        assert_eq!(e, "no dir/gone.toml (named by dir/d.toml)");
    }
}
