//! Where a picture goes: a file written under a temporary name beside its own and renamed
//! into place when whole, or standard output (`-`), or a device or pipe named by path; PPM
//! or PNG, encoded row by row in order as the rows arrive
//! ([`microray::host::render_in_order`]).

use embedded_graphics::prelude::Size;
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

/// An image file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum Format {
    /// Binary PPM (`P6`, 8 bits a channel).
    Ppm,
    /// PNG, 8-bit RGB.
    Png,
}

impl Format {
    /// The format a file name's extension names, if any.
    pub(crate) fn of_name(path: &Path) -> Option<Self> {
        let extension = path.extension()?.to_str()?.to_ascii_lowercase();
        match extension.as_str() {
            "ppm" => Some(Format::Ppm),
            "png" => Some(Format::Png),
            _ => None,
        }
    }

    pub(crate) fn extension(self) -> &'static str {
        match self {
            Format::Ppm => "ppm",
            Format::Png => "png",
        }
    }
}

/// A file written under a temporary name in the folder of `path` and renamed to `path` by
/// [`commit`](Self::commit): a render that fails (or a full disk) leaves whatever `path`
/// held before, never half a picture. Dropped before the commit, the temporary file is
/// removed.
pub(crate) struct Staged {
    path: PathBuf,
    temporary: PathBuf,
    file: File,
    committed: bool,
}

impl Staged {
    pub(crate) fn create(path: &Path) -> io::Result<Self> {
        // Through a symbolic link, the file it names is replaced, not the link.
        let is_link = std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink());
        let path = if is_link {
            std::fs::canonicalize(path)?
        } else {
            path.to_path_buf()
        };
        let name = path
            .file_name()
            .unwrap_or(path.as_os_str())
            .to_string_lossy();
        let temporary = path.with_file_name(format!(".{name}.{}.partial", std::process::id()));
        let file = File::create(&temporary)?;
        let staged = Self {
            path,
            temporary,
            file,
            committed: false,
        };
        // The new file keeps the old one's permissions.
        if let Ok(old) = std::fs::metadata(&staged.path) {
            staged.file.set_permissions(old.permissions())?;
        }
        Ok(staged)
    }

    pub(crate) fn file(&self) -> &File {
        &self.file
    }

    /// Puts the finished file in place under its name.
    pub(crate) fn commit(mut self) -> io::Result<()> {
        if swap(&self.temporary, &self.path).is_ok() {
            // The temporary name now holds what the path held: removed on drop.
            return Ok(());
        }
        std::fs::rename(&self.temporary, &self.path)?;
        self.committed = true;
        Ok(())
    }
}

/// Swaps two existing files' names at once (Linux's `renameat2` with `RENAME_EXCHANGE`).
///
/// Why not a rename over the old file: ext4 (its default `auto_da_alloc`) writes the new
/// file's data out to the disk before such a rename, 0.27 ms for a 320x240 PPM (measured:
/// 0.36 ms a replace against 0.09 ms for a swap and removing the old file), a tenth of a
/// small render. The swap is as atomic: the name always holds a whole picture.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn swap(a: &Path, b: &Path) -> io::Result<()> {
    use nix::fcntl::{AT_FDCWD, RenameFlags, renameat2};
    renameat2(AT_FDCWD, a, AT_FDCWD, b, RenameFlags::RENAME_EXCHANGE).map_err(io::Error::from)
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn swap(_a: &Path, _b: &Path) -> io::Result<()> {
    Err(io::Error::from(io::ErrorKind::Unsupported))
}

impl Drop for Staged {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_file(&self.temporary);
        }
    }
}

/// Whether `path` is `-`: standard input or output.
pub(crate) fn is_stdio(path: &Path) -> bool {
    path == Path::new("-")
}

/// Whether `path` names something to write into as it is, not a file to replace: standard
/// output (`-`), or an existing path that is not a regular file (a device, a pipe).
pub(crate) fn writes_in_place(path: &Path) -> bool {
    is_stdio(path) || std::fs::metadata(path).is_ok_and(|m| !m.is_file())
}

/// An image file being written: its header is out, its rows go through an [`Encoder`].
pub(crate) enum Image<W: Write> {
    Ppm(W),
    Png(png::Writer<W>),
}

impl<W: Write> Image<W> {
    /// Writes the header of an image of `size` in `format` to `out`.
    pub(crate) fn start(format: Format, size: Size, mut out: W) -> io::Result<Self> {
        match format {
            Format::Ppm => {
                out.write_all(microray::host::ppm_header(size).as_bytes())?;
                Ok(Image::Ppm(out))
            }
            Format::Png => {
                let mut encoder = png::Encoder::new(out, size.width, size.height);
                encoder.set_color(png::ColorType::Rgb);
                encoder.set_depth(png::BitDepth::Eight);
                Ok(Image::Png(encoder.write_header().map_err(encoding)?))
            }
        }
    }

    /// The rows' encoder.
    pub(crate) fn encoder(&mut self) -> io::Result<Encoder<'_, W>> {
        match self {
            Image::Ppm(out) => Ok(Encoder::Ppm(out)),
            Image::Png(writer) => Ok(Encoder::Png(Box::new(
                writer.stream_writer().map_err(encoding)?,
            ))),
        }
    }

    /// Writes the end of the file and flushes it (after the encoder's [`Encoder::finish`]).
    pub(crate) fn finish(self) -> io::Result<()> {
        match self {
            Image::Ppm(mut out) => out.flush(),
            Image::Png(writer) => writer.finish().map_err(encoding),
        }
    }
}

/// Takes an image's rows, whole, top first.
pub(crate) enum Encoder<'a, W: Write> {
    Ppm(&'a mut W),
    Png(Box<png::StreamWriter<'a, W>>),
}

impl<W: Write> Encoder<'_, W> {
    pub(crate) fn rows(&mut self, pixels: &[u8]) -> io::Result<()> {
        match self {
            Encoder::Ppm(out) => out.write_all(pixels),
            Encoder::Png(stream) => stream.write_all(pixels),
        }
    }

    /// Ends the rows (checking that all of them came).
    pub(crate) fn finish(self) -> io::Result<()> {
        match self {
            Encoder::Ppm(_) => Ok(()),
            Encoder::Png(stream) => (*stream).finish().map_err(encoding),
        }
    }
}

fn encoding(e: png::EncodingError) -> io::Error {
    match e {
        png::EncodingError::IoError(e) => e,
        other => io::Error::other(other),
    }
}

/// `path` (`-`: standard output) opened to write into as it is, buffered.
pub(crate) fn stream(path: &Path) -> io::Result<BufWriter<Box<dyn Write + Send>>> {
    let out: Box<dyn Write + Send> = if is_stdio(path) {
        Box::new(io::stdout())
    } else {
        Box::new(std::fs::OpenOptions::new().write(true).open(path)?)
    };
    Ok(BufWriter::with_capacity(64 * 1024, out))
}
