//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// The course's conformance folder from `MICRORAY_CONFORMANCE`: `None` (and a note) when the
/// variable is unset; a failure when it is set and the folder is missing.
pub fn conformance_dir() -> Option<PathBuf> {
    let Some(dir) = std::env::var_os("MICRORAY_CONFORMANCE") else {
        eprintln!("skipped: MICRORAY_CONFORMANCE is not set (CI sets it to ../shared/conformance)");
        return None;
    };
    let dir = PathBuf::from(dir);
    assert!(
        dir.is_dir(),
        "MICRORAY_CONFORMANCE={} is not a folder",
        dir.display()
    );
    Some(dir)
}

/// Every `*.txt` under `dir`, sorted.
pub fn scene_files(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "txt") {
                found.push(path);
            }
        }
    }
    found.sort();
    found
}

/// The project's own scenes.
pub fn project_scenes() -> Vec<PathBuf> {
    scene_files(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes"))
}
