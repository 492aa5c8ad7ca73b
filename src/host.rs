//! Host (`std`) support: reading texture files next to a scene file.

use crate::error::TextureError;
use std::path::{Path, PathBuf};

/// A texture resolver that reads files relative to `scene_dir`, the scene file's folder.
///
/// Each file is read once and kept for the rest of the process (the scene borrows the bytes
/// for `'static`), which suits a command-line run; a long-running program that reloads
/// scenes should supply its own resolver.
pub fn texture_files(scene_dir: &Path) -> impl FnMut(&str) -> Result<&'static [u8], TextureError> {
    let dir: PathBuf = scene_dir.to_path_buf();
    move |filename: &str| match std::fs::read(dir.join(filename)) {
        Ok(bytes) => Ok(Box::leak(bytes.into_boxed_slice())),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Err(TextureError::NotFound),
        Err(_) => Err(TextureError::Unreadable),
    }
}

/// The scene type the host tracer uses: room for large scenes and wide images.
pub type HostScene<'t, S> = crate::Scene<'t, S, 256, 64, 32, 16, 8192>;
