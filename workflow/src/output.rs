//! Files written whole or not at all.

use std::io::Write as _;
use std::path::{Component, Path, PathBuf};

/// Writes `bytes` to a temporary file beside `path`, then renames it into place, so a
/// reader never sees a partial file and a failed write leaves any old file untouched. A
/// missing folder is created first ([`check_file_target`] has checked that it can be).
pub fn write_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let name = path.file_name().ok_or_else(|| std::io::Error::other("output path has no file name"))?;
    std::fs::create_dir_all(dir)?;
    let tmp = dir.join(format!(".{}.tmp{}", name.to_string_lossy(), std::process::id()));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// The path the file system will reach by `path`, which need not exist yet: its deepest
/// existing ancestor resolved (symbolic links, `..`), the rest appended with `.` dropped and
/// `..` taken lexically. For comparing two output targets before either is written.
pub fn resolved(path: &Path) -> std::io::Result<PathBuf> {
    let path = std::path::absolute(path)?;
    let (mut real, rest) = path
        .ancestors()
        .find_map(|a| Some((std::fs::canonicalize(a).ok()?, path.strip_prefix(a).ok()?)))
        .unwrap_or((PathBuf::new(), &path));
    for c in rest.components() {
        match c {
            Component::ParentDir => {
                real.pop();
            }
            Component::CurDir => {}
            c => real.push(c),
        }
    }
    Ok(real)
}

/// Checks, before any work, that a file can be written at `path`: its folder accepts a new
/// file, or does not exist yet and can be created ([`check_dir_target`]; the write creates
/// it), and nothing but a regular file is there (a folder, a pipe or a device would be
/// replaced or fail the write after the work). Nothing is left behind.
pub fn check_file_target(path: &Path) -> std::io::Result<()> {
    if path.file_name().is_none() || path.is_dir() {
        return Err(std::io::Error::other("not a file name"));
    }
    if std::fs::symlink_metadata(path).is_ok_and(|m| !m.is_file()) {
        return Err(std::io::Error::other("exists and is not a regular file"));
    }
    let dir = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    check_dir_target(dir)
}

/// Checks, before any work, that files can be written into the folder `dir`: it is a
/// writable folder, or it does not exist yet and its parent is one (it is created later).
pub fn check_dir_target(dir: &Path) -> std::io::Result<()> {
    if dir.is_dir() {
        return check_writable_dir(dir);
    }
    if dir.exists() {
        // Named: a file's folder is in the way, not the file to be written.
        return Err(std::io::Error::other(format!("{} exists and is not a folder", dir.display())));
    }
    // The nearest existing ancestor must accept the folders to be created.
    let mut parent = dir.parent();
    while let Some(p) = parent.filter(|p| !p.as_os_str().is_empty()) {
        if p.exists() {
            if !p.is_dir() {
                return Err(std::io::Error::other(format!("{} exists and is not a folder", p.display())));
            }
            return check_writable_dir(p);
        }
        parent = p.parent();
    }
    check_writable_dir(Path::new("."))
}

/// [`check_dir_target`], and that each of `entries` (file names the work writes into `dir`;
/// a name ending in `/` a folder it creates) is absent there or of that kind, so that no
/// write fails after the work.
pub fn check_dir_entries(dir: &Path, entries: &[&str]) -> std::io::Result<()> {
    check_dir_target(dir)?;
    for entry in entries {
        let (name, folder) = match entry.strip_suffix('/') {
            Some(name) => (name, true),
            None => (*entry, false),
        };
        let path = dir.join(name);
        let Ok(meta) = std::fs::symlink_metadata(&path) else { continue };
        let fine = if folder { path.is_dir() } else { meta.is_file() };
        if !fine {
            let kind = if folder { "a folder" } else { "a regular file" };
            return Err(std::io::Error::other(format!("{} exists and is not {kind}", path.display())));
        }
    }
    Ok(())
}

fn check_writable_dir(dir: &Path) -> std::io::Result<()> {
    if !dir.is_dir() {
        return Err(std::io::Error::new(std::io::ErrorKind::NotFound, format!("no folder {}", dir.display())));
    }
    let probe = dir.join(format!(".kanestop-probe{}", std::process::id()));
    std::fs::File::create(&probe)?;
    let _ = std::fs::remove_file(&probe);
    Ok(())
}

/// Writes the texts `texts` into the folder `dir` (created if needed) under the names
/// `names`, each file whole or not at all ([`write_atomically`]), in order. Returns the paths.
pub fn write_into<const N: usize>(dir: &Path, names: [&str; N], texts: [String; N]) -> crate::Result<[PathBuf; N]> {
    std::fs::create_dir_all(dir).map_err(crate::Error::io("create", dir))?;
    let files = names.map(|f| dir.join(f));
    for (path, text) in files.iter().zip(texts) {
        write_atomically(path, text.as_bytes()).map_err(crate::Error::io("write", path))?;
    }
    Ok(files)
}

/// A text as one CSV field (RFC 4180): quoted when it holds a comma, a quote or a line
/// break, a quote inside doubled.
pub fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        csv_quoted(s)
    } else {
        s.to_string()
    }
}

/// A text as one CSV field, always quoted (RFC 4180, a quote inside doubled): the columns
/// of messages and descriptions, quoted whatever they hold.
pub fn csv_quoted(s: &str) -> String {
    format!("\"{}\"", s.replace('"', "\"\""))
}

/// The units sidecar of a table's CSV (`batch.units.csv`, `sweep.units.csv`, …):
/// `column,unit,description`, one line per (column, unit, description) in the CSV's column
/// order ([`csv_field`]s); the unit "" for a number without one (a fraction, a ratio), a
/// count or text.
pub fn units_csv<'a>(columns: impl IntoIterator<Item = (&'a str, &'a str, &'a str)>) -> String {
    let mut out = String::from("column,unit,description\n");
    for (name, unit, description) in columns {
        out.push_str(&format!("{},{},{}\n", csv_field(name), csv_field(unit), csv_field(description)));
    }
    out
}

/// A number as every CSV file writes it (history, batch, sweep): its shortest form that reads back to the same f64,
/// positional for ordinary magnitudes (`3`, `1669.9795856262342`), with an exponent for the
/// very small and very large (`-7.531752999057062e-12`), as spreadsheets and pandas read both;
/// zero is `0`, whatever its sign.
pub struct CsvNumber(pub f64);

impl std::fmt::Display for CsvNumber {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let v = self.0;
        if v == 0.0 {
            write!(f, "0") // −0 too (a term that did no work, negated)
        } else if !v.is_finite() || (1e-5..1e16).contains(&v.abs()) {
            write!(f, "{v}")
        } else {
            write!(f, "{v:e}")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_target_is_resolved_through_dots_and_links_before_it_exists() {
        let dir = std::env::temp_dir().join(format!("kanestop-resolved-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("real")).unwrap();
        let real = std::fs::canonicalize(dir.join("real")).unwrap();
        // Not yet there, reached through `..` and `.`.
        assert_eq!(resolved(&dir.join("real/new/.././h.csv")).unwrap(), real.join("h.csv"));
        assert_eq!(resolved(&dir.join("real/../real/h.csv/plots")).unwrap(), real.join("h.csv/plots"));
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(&real, dir.join("link")).unwrap();
            assert_eq!(resolved(&dir.join("link/h.csv")).unwrap(), real.join("h.csv"));
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn csv_numbers_are_shortest_and_zero_has_no_sign() {
        let s = |v: f64| CsvNumber(v).to_string();
        assert_eq!(
            (s(3.0), s(-0.0), s(0.0), s(1669.9795856262342)),
            ("3".into(), "0".into(), "0".into(), "1669.9795856262342".into())
        );
        assert_eq!(
            (s(-7.531752999057062e-12), s(2.5e20), s(f64::NAN)),
            ("-7.531752999057062e-12".into(), "2.5e20".into(), "NaN".into())
        );
    }

    #[test]
    fn targets_are_checked_before_any_work() {
        let dir = std::env::temp_dir().join(format!("kanestop-output-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        assert!(check_file_target(&dir.join("a.csv")).is_ok());
        assert!(check_file_target(&dir.join("missing/a.csv")).is_ok(), "its folder is created by the write");
        std::fs::write(dir.join("plain"), "x").unwrap();
        let e = check_file_target(&dir.join("plain/a.csv")).unwrap_err();
        assert!(e.to_string().ends_with("plain exists and is not a folder"), "{e}");
        std::fs::remove_file(dir.join("plain")).unwrap();
        assert!(check_file_target(&dir).is_err(), "a folder is not a file");
        assert!(check_dir_target(&dir.join("new/deeper")).is_ok(), "created later");
        std::fs::write(dir.join("file"), "x").unwrap();
        assert!(check_dir_target(&dir.join("file")).is_err());
        assert!(!dir.join("new").exists(), "a check creates nothing");
        std::fs::create_dir_all(dir.join("out/sweep.json")).unwrap();
        let e = check_dir_entries(&dir.join("out"), &["sweep.csv", "sweep.json", "scenes/"]).unwrap_err();
        assert!(e.to_string().contains("sweep.json exists and is not a regular file"), "{e}");
        assert!(check_dir_entries(&dir.join("out"), &["sweep.csv", "sweep.json/"]).is_ok());
        assert!(check_file_target(&dir.join("out/sweep.json")).is_err());
        std::fs::remove_dir_all(dir.join("out")).unwrap();
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1, "no probe left behind");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
