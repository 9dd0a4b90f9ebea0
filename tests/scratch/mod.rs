//! A test's scratch folder under the system's temporary folder: made empty at the start,
//! removed when the test passes, and kept when it fails (its path on standard error), so a
//! failure's files can be looked at and a passing run leaves nothing behind.
#![allow(dead_code)]

use std::ffi::OsStr;
use std::ops::Deref;
use std::path::{Path, PathBuf};

/// The folder `kanestop-NAME-PID` under the temporary folder, empty; see the module's doc.
pub struct Scratch(PathBuf);

impl Scratch {
    /// Makes the folder, emptied of what an earlier run of the same process id left.
    pub fn new(name: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("kanestop-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        Scratch(dir)
    }

    /// The folder's path.
    pub fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if std::thread::panicking() {
            eprintln!("scratch folder kept: {}", self.0.display());
        } else {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

impl Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<OsStr> for Scratch {
    fn as_ref(&self) -> &OsStr {
        self.0.as_os_str()
    }
}
