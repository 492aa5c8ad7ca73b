//! The `microray` binary at its edges: full disks and closed pipes on standard output and
//! error, standard input and output as `-`, outputs written beside their name and put in
//! place when whole, memory that does not grow with the image, and option combinations it
//! refuses with a message.
#![cfg(unix)]

use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

const BINARY: &str = env!("CARGO_BIN_EXE_microray");

fn scene(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name)
        .to_str()
        .unwrap()
        .to_string()
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// A fresh folder of this test's own.
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("microray-edges-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `script` in bash with `$M` naming the binary.
fn shell(script: &str) -> Output {
    Command::new("bash")
        .arg("-c")
        .arg(script)
        .env("M", BINARY)
        .output()
        .unwrap()
}

/// One line on standard error, exit code 1, no panic.
fn assert_one_line_failure(run: &Output, what: &str) {
    let stderr = text(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{what}: {stderr}");
    assert_eq!(stderr.lines().count(), 1, "{what}: {stderr}");
    assert!(!stderr.contains("panicked"), "{what}: {stderr}");
}

#[test]
fn a_full_standard_output_is_a_one_line_error() {
    let many = scene("many_spheres.txt");
    for command in ["check", "print"] {
        let run = shell(&format!("\"$M\" {command} {many} > /dev/full"));
        assert_one_line_failure(&run, command);
        assert!(
            text(&run.stderr).contains("cannot write to standard output"),
            "{}",
            text(&run.stderr)
        );
    }
    let run = shell("\"$M\" --help > /dev/full");
    assert_one_line_failure(&run, "--help");
    let run = shell(&format!(
        "\"$M\" render {} -o - -q > /dev/full",
        scene("minimal.txt")
    ));
    assert_one_line_failure(&run, "render -o -");
}

#[test]
fn a_full_standard_error_ends_with_exit_code_1() {
    let dir = folder("stderr");
    let out = dir.join("minimal.ppm");
    let run = shell(&format!(
        "\"$M\" render {} -o {} 2> /dev/full",
        scene("minimal.txt"),
        out.display()
    ));
    assert_eq!(run.status.code(), Some(1));
    // A usage error (exit code 2) whose message cannot be written: a write error.
    let run = shell("\"$M\" render 2> /dev/full");
    assert_eq!(run.status.code(), Some(1));
    let run = shell("\"$M\" render 2> /dev/null");
    assert_eq!(run.status.code(), Some(2));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_closed_pipe_ends_quietly() {
    for command in ["print", "check"] {
        let mut child = Command::new(BINARY)
            .args([command, &scene("many_spheres.txt")])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // Read one byte, then close the pipe, as `| head -c 1` does.
        let mut first = [0u8; 1];
        child.stdout.take().unwrap().read_exact(&mut first).unwrap();
        let run = child.wait_with_output().unwrap();
        assert!(run.status.success(), "{command}: {}", text(&run.stderr));
        assert!(run.stderr.is_empty(), "{command}: {}", text(&run.stderr));
    }
    // An image, far larger than the pipe holds.
    let run = shell(&format!(
        "set -o pipefail; \"$M\" render {} -o - -q | head -c 10 > /dev/null",
        scene("showcase.txt")
    ));
    assert!(run.status.success(), "{}", text(&run.stderr));
    assert!(run.stderr.is_empty(), "{}", text(&run.stderr));
}

#[test]
fn dash_is_standard_input_and_output() {
    let dir = folder("dash");
    let file = dir.join("minimal.ppm");
    let minimal = scene("minimal.txt");
    let run = Command::new(BINARY)
        .args(["render", &minimal, "-q", "-o", file.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", text(&run.stderr));
    let from_file = std::fs::read(&file).unwrap();
    for format in [None, Some("ppm"), Some("png")] {
        let mut args = vec!["render", "-", "-q", "-o", "-"];
        args.extend(format.iter().flat_map(|f| ["--format", f]));
        let mut child = Command::new(BINARY)
            .args(&args)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut stdin = child.stdin.take().unwrap();
        stdin.write_all(&std::fs::read(&minimal).unwrap()).unwrap();
        drop(stdin);
        let run = child.wait_with_output().unwrap();
        assert!(run.status.success(), "{format:?}: {}", text(&run.stderr));
        if format == Some("png") {
            assert_eq!(
                png_pixels(&run.stdout),
                from_file[from_file.len() - 320 * 240 * 3..]
            );
        } else {
            assert!(run.stdout == from_file, "{format:?}");
        }
    }
    // `check` names standard input in its report and its errors.
    let run = shell(&format!("\"$M\" check - < {minimal}"));
    assert!(
        text(&run.stdout).starts_with("ok: <stdin>: 320x240"),
        "{}",
        text(&run.stdout)
    );
    let run = shell("printf 'camera c { pixeldim 8 }' | \"$M\" check -");
    assert_one_line_failure(&run, "bad scene on standard input");
    assert!(
        text(&run.stderr).starts_with("<stdin>:1:"),
        "{}",
        text(&run.stderr)
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The RGB pixels of a PNG.
fn png_pixels(bytes: &[u8]) -> Vec<u8> {
    let mut reader = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .unwrap();
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut pixels).unwrap();
    pixels.truncate(info.buffer_size());
    pixels
}

#[test]
fn a_failed_write_leaves_the_old_file_and_nothing_else() {
    let dir = folder("staged");
    for format in ["ppm", "png"] {
        let out = dir.join(format!("showcase.{format}"));
        std::fs::write(&out, b"the old picture").unwrap();
        // A file size limit of 16 KiB, hit partway through the picture (with SIGXFSZ
        // ignored, the write fails with EFBIG instead of killing the process).
        let run = shell(&format!(
            "trap '' XFSZ; ulimit -f 16; exec \"$M\" render {} -q -o {}",
            scene("showcase.txt"),
            out.display()
        ));
        assert_one_line_failure(&run, format);
        assert!(
            text(&run.stderr).contains("cannot write"),
            "{}",
            text(&run.stderr)
        );
        assert_eq!(std::fs::read(&out).unwrap(), b"the old picture");
        let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
        assert_eq!(left.len(), 1, "{left:?}");
        std::fs::remove_file(&out).unwrap();
    }
    // A scene that does not load leaves no file at all.
    let out = dir.join("none.png");
    let run = shell(&format!(
        "printf 'sphere' | \"$M\" render - -q -o {}",
        out.display()
    ));
    assert_one_line_failure(&run, "bad scene");
    assert!(!out.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A picture of 512x65535 (100 MB as RGB) renders to PNG and PPM, to a file and to a pipe,
/// in 64 MB of address space: rows are encoded as they arrive, never held all at once.
#[test]
fn a_tall_picture_renders_in_memory_independent_of_its_height() {
    let dir = folder("tall");
    let text_of = std::fs::read_to_string(scene("minimal.txt")).unwrap();
    assert!(text_of.contains("pixeldim 320 240"));
    let tall = dir.join("tall.txt");
    std::fs::write(
        &tall,
        text_of.replace("pixeldim 320 240", "pixeldim 512 65535"),
    )
    .unwrap();
    let (png, ppm) = (dir.join("tall.png"), dir.join("tall.ppm"));
    for (out, pipe) in [(&png, ""), (&ppm, ""), (&dir.join("piped.ppm"), "-")] {
        let target = if pipe.is_empty() {
            out.display().to_string()
        } else {
            format!("- > {}", out.display())
        };
        let run = shell(&format!(
            "ulimit -v 65536; exec \"$M\" render {} -q -o {target}",
            tall.display()
        ));
        assert!(
            run.status.success(),
            "{}: {}",
            out.display(),
            text(&run.stderr)
        );
    }
    let ppm_bytes = std::fs::read(&ppm).unwrap();
    let header = b"P6\n512 65535 255\n";
    assert_eq!(&ppm_bytes[..header.len()], header);
    assert_eq!(ppm_bytes.len(), header.len() + 512 * 65535 * 3);
    assert!(std::fs::read(dir.join("piped.ppm")).unwrap() == ppm_bytes);
    let png_bytes = std::fs::read(&png).unwrap();
    assert!(png_pixels(&png_bytes) == ppm_bytes[header.len()..]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn combinations_it_cannot_honour_are_refused_with_a_message() {
    let dir = folder("refused");
    let minimal = scene("minimal.txt");
    let out = dir.join("out.png");
    let out = out.to_str().unwrap();
    for (args, says) in [
        (
            vec!["--progressive", "--threads", "2"],
            "--progressive renders on one thread",
        ),
        (
            vec!["--dither", "rgb565", "--color", "rgb888"],
            "leave out one of them",
        ),
        (
            vec!["--dither", "rgb565", "--color", "gray4"],
            "name different panels",
        ),
        (
            vec!["--format", "ppm"],
            "the name says png but --format says ppm",
        ),
    ] {
        let mut all = vec!["render", &minimal, "-q", "-o", out];
        all.extend(&args);
        let run = Command::new(BINARY).args(&all).output().unwrap();
        assert_one_line_failure(&run, &args.join(" "));
        assert!(text(&run.stderr).contains(says), "{}", text(&run.stderr));
        assert!(!Path::new(out).exists());
    }
    // What it can honour: dithering for an Rgb565 panel, said both ways, and the
    // progressive order on the one thread it uses, error-diffused too.
    for args in [
        vec!["--dither", "rgb565", "--color", "rgb565"],
        vec!["--progressive", "--threads", "1"],
        vec!["--progressive", "--dither", "binary:atkinson"],
    ] {
        let mut all = vec!["render", &minimal, "-q", "-o", out];
        all.extend(&args);
        let run = Command::new(BINARY).args(&all).output().unwrap();
        assert!(run.status.success(), "{args:?}: {}", text(&run.stderr));
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn unknown_panel_formats_and_methods_are_refused_with_the_list() {
    let dir = folder("panels");
    let minimal = scene("minimal.txt");
    let out = dir.join("out.png");
    let out = out.to_str().unwrap();
    for (args, says) in [
        (
            vec!["--dither", "rgb999"],
            "unknown panel format; expected one of: binary gray2 gray4 gray8 rgb332 rgb444 rgb555 rgb565 rgb666",
        ),
        (
            vec!["--color", "grey4"],
            "expected one of: binary gray2 gray4 gray8 rgb332 rgb444 rgb555 rgb565 rgb666 rgb888",
        ),
        (
            vec!["--dither", "binary:sharp"],
            "unknown dither method; expected one of: bayer2 bayer4 bayer8 blue-noise floyd-steinberg atkinson",
        ),
        (
            vec!["--dither", "gray2:bayer4-serpentine"],
            "unknown dither method",
        ),
    ] {
        let mut all = vec!["render", &minimal, "-q", "-o", out];
        all.extend(&args);
        let run = Command::new(BINARY).args(&all).output().unwrap();
        assert!(!run.status.success(), "{args:?}");
        assert!(text(&run.stderr).contains(says), "{}", text(&run.stderr));
        assert!(!Path::new(out).exists());
    }
    // An animation redraws patches: error diffusion is refused there, by name.
    let film = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/bounce.txt");
    let run = Command::new(BINARY)
        .args([
            "animate",
            film.to_str().unwrap(),
            "-q",
            "-o",
            out,
            "--dither",
            "binary:floyd-steinberg",
        ])
        .output()
        .unwrap();
    assert_one_line_failure(&run, "animate --dither binary:floyd-steinberg");
    assert!(
        text(&run.stderr).contains("use bayer2, bayer4, bayer8 or blue-noise"),
        "{}",
        text(&run.stderr)
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_new_picture_replaces_the_file_a_link_names_with_its_permissions() {
    use std::os::unix::fs::PermissionsExt;
    let dir = folder("link");
    let (file, link) = (dir.join("picture.png"), dir.join("link.png"));
    std::fs::write(&file, b"old").unwrap();
    std::fs::set_permissions(&file, std::fs::Permissions::from_mode(0o600)).unwrap();
    std::os::unix::fs::symlink(&file, &link).unwrap();
    let run = Command::new(BINARY)
        .args([
            "render",
            &scene("minimal.txt"),
            "-q",
            "-o",
            link.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", text(&run.stderr));
    assert!(
        std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    let picture = std::fs::read(&file).unwrap();
    assert_eq!(&picture[1..4], b"PNG");
    let mode = std::fs::metadata(&file).unwrap().permissions().mode();
    assert_eq!(mode & 0o777, 0o600);
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 2);
    std::fs::remove_dir_all(&dir).unwrap();
}
