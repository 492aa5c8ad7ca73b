//! Scene files and the texture files they name, for the firmware's build scripts (this
//! one's and the Pico's), which embed them with `include_str!` and `include_bytes!`.

use std::path::{Path, PathBuf};

/// The `filename` values of a scene and the files they name, and the `texname` values that
/// name a file (`texname FILE`, read as an image when no texture block has that name).
pub fn texture_files(text: &str, dir: &Path) -> Vec<(String, PathBuf)> {
    let mut words = text.split_whitespace();
    let mut found: Vec<(String, PathBuf)> = Vec::new();
    while let Some(word) = words.next() {
        let Some(name) = words.clone().next() else {
            break;
        };
        let file = dir.join(name);
        let named = word == "filename" || (word == "texname" && file.is_file());
        if named && !found.iter().any(|(written, _)| written == name) {
            found.push((name.to_string(), file.canonicalize().unwrap()));
        }
    }
    found
}
