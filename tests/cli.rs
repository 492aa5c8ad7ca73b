//! The `microray` binary: `check` and `print` on good and bad files.

mod common;

use std::path::Path;
use std::process::{Command, Output};

fn microray(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_microray"))
        .args(args)
        .output()
        .unwrap()
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn check_accepts_project_scenes() {
    for path in common::project_scenes() {
        let path = path.to_str().unwrap();
        let out = microray(&["check", path]);
        assert!(out.status.success(), "{path}: {}", text(&out.stderr));
        let stdout = text(&out.stdout);
        assert!(
            stdout.starts_with(&format!("ok: {path}: ")) && stdout.contains(" pixels, "),
            "{stdout}"
        );
    }
}

#[test]
fn check_and_render_warn_about_ill_posed_scenes() {
    let dir = std::env::temp_dir().join(format!("microray-cli-warnings-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("twin.txt");
    std::fs::write(
        &scene,
        "camera c { pixeldim 8 6 worlddim 8 6 viewpoint 4 3 3 }
         material m { diffuse 1 1 1 }
         light lamp { location 4 5 -1 emissivity 1 1 1 }
         sphere a { material m center 4 3 -2 radius 1 }
         sphere b { material m center 4 3 -2 radius 1 }",
    )
    .unwrap();
    let path = scene.to_str().unwrap();
    let warning = format!(
        "{path}: warning: sphere `a` and sphere `b` coincide: which one a ray meets is decided by rounding\n"
    );
    let out = microray(&["check", path]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(
        text(&out.stdout).ends_with(&warning),
        "{}",
        text(&out.stdout)
    );
    let image = dir.join("twin.ppm");
    let out = microray(&["render", path, "-o", image.to_str().unwrap()]);
    assert!(out.status.success());
    assert!(
        text(&out.stderr).starts_with(&warning),
        "{}",
        text(&out.stderr)
    );
    let out = microray(&["render", "-q", path, "-o", image.to_str().unwrap()]);
    assert!(
        out.status.success() && out.stderr.is_empty(),
        "{}",
        text(&out.stderr)
    );
}

#[test]
#[cfg_attr(
    not(microray_conformance),
    ignore = "needs the course's scenes: set MICRORAY_CONFORMANCE to their folder"
)]
fn check_accepts_every_conformance_scene() {
    let dir = common::required_conformance_dir();
    for path in common::scene_files(&dir) {
        let out = microray(&["check", path.to_str().unwrap()]);
        assert!(
            out.status.success(),
            "{}: {}",
            path.display(),
            text(&out.stderr)
        );
        assert!(text(&out.stdout).starts_with("ok: "));
    }
}

#[test]
fn check_rejects_malformed_files_with_position_and_exit_1() {
    let dir = std::env::temp_dir().join(format!("microray-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cases: [(&str, &[u8], &str); 4] = [
        ("typo.txt", b"camera c { pixeldim 64 48 worlddim 8 6 viewpoint 4 3 3 }\nsphere s {\n  material m center 0 0 -5 radius 1 }\n", "typo.txt:3:12: error: undefined material `m`"),
        ("braces.txt", &[b'{'; 20_000], "braces.txt:1:1: error: expected an entity"),
        ("binary.txt", b"\x7fELF\x02\x01\x01\x00\x00", "binary.txt:1:1: error: invalid character 0x7f"),
        ("texture.txt", b"camera c { pixeldim 64 48 worlddim 8 6 viewpoint 4 3 3 }\ntexture t { filename missing.ppm }", "texture.txt:2:22: error: texture file `missing.ppm`: file not found"),
    ];
    for (name, contents, expected) in cases {
        let path = dir.join(name);
        std::fs::write(&path, contents).unwrap();
        let out = microray(&["check", path.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(1), "{name}");
        let stderr = text(&out.stderr);
        let expected = format!("{}/{expected}", dir.display());
        assert!(stderr.starts_with(&expected), "{name}: {stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
        assert!(out.stdout.is_empty());
    }
    let missing = microray(&["check", "no/such/file.txt"]);
    assert_eq!(missing.status.code(), Some(1));
    assert!(text(&missing.stderr).starts_with("no/such/file.txt: error: cannot read: "));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn print_writes_text_that_checks() {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/gallery.txt");
    let out = microray(&["print", scene.to_str().unwrap()]);
    assert!(out.status.success());
    let printed = text(&out.stdout);
    assert!(
        printed.contains("texplane picture\n{\n  material matte\n  normal 0 0 1\n"),
        "{printed}"
    );
    // Written next to the original so the texture's relative path still resolves.
    let copy = scene.with_file_name(format!("printed-{}.txt", std::process::id()));
    std::fs::write(&copy, &printed).unwrap();
    let again = microray(&["print", copy.to_str().unwrap()]);
    std::fs::remove_file(&copy).unwrap();
    assert_eq!(text(&again.stdout), printed);
}

#[test]
fn check_reports_the_plan_and_no_plan_renders_the_same_image() {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/many_spheres.txt");
    let scene = scene.to_str().unwrap();
    let out = microray(&["check", scene]);
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("plan: illumination, shadows, any-hit shadows; 101 objects kept"),
        "{stdout}"
    );
    let dir = std::env::temp_dir().join(format!("microray-cli-plan-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (planned, unplanned) = (dir.join("planned.ppm"), dir.join("unplanned.ppm"));
    for (file, extra) in [(&planned, None), (&unplanned, Some("--no-plan"))] {
        let mut args = vec!["render", scene, "-q", "--number", "f32", "-o"];
        args.push(file.to_str().unwrap());
        args.extend(extra);
        let out = microray(&args);
        assert!(out.status.success(), "{}", text(&out.stderr));
    }
    let (a, b) = (
        std::fs::read(&planned).unwrap(),
        std::fs::read(&unplanned).unwrap(),
    );
    assert_eq!(a.len(), 15 + 320 * 240 * 3);
    assert!(a == b, "--no-plan renders another image");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn compile_writes_the_scene_at_the_size_asked_for() {
    use microray::Scene;
    use microray::parse::{no_textures, parse_scene};
    use microray::scalar::I16F16;
    let dir = std::env::temp_dir().join(format!("microray-compile-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("minimal.mray");
    let scene_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/minimal.txt");
    let run = microray(&[
        "compile",
        scene_path.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--number",
        "i16f16",
        "--size",
        "80x60",
    ]);
    assert!(run.status.success(), "{}", text(&run.stderr));
    let bytes = std::fs::read(&out).unwrap();
    let mut expected: microray::host::HostScene<'_, I16F16> =
        parse_scene(&std::fs::read(&scene_path).unwrap(), no_textures).unwrap();
    expected.set_resolution(80, 60).unwrap();
    let mut loaded: Box<microray::host::HostScene<'_, I16F16>> = Box::new(Scene::empty());
    loaded.load_compiled(&bytes, no_textures).unwrap();
    assert_eq!(*loaded, expected);
    // A size that is not WIDTHxHEIGHT is a usage error.
    let bad = microray(&[
        "compile",
        scene_path.to_str().unwrap(),
        "-o",
        "x",
        "--number",
        "f32",
        "--size",
        "80",
    ]);
    assert!(!bad.status.success());
    assert!(
        text(&bad.stderr).contains("WIDTHxHEIGHT"),
        "{}",
        text(&bad.stderr)
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn render_progressive_writes_the_previews_and_the_same_image() {
    let dir = std::env::temp_dir().join(format!("microray-cli-progressive-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/vases.txt");
    let (plain, progressive) = (dir.join("plain.ppm"), dir.join("vases.ppm"));
    for (out, extra) in [(&plain, None), (&progressive, Some("--progressive"))] {
        let mut args = vec!["render", scene.to_str().unwrap(), "-q", "-o"];
        args.push(out.to_str().unwrap());
        args.extend(extra);
        let run = microray(&args);
        assert!(run.status.success(), "{}", text(&run.stderr));
    }
    assert_eq!(
        std::fs::read(&plain).unwrap(),
        std::fs::read(&progressive).unwrap()
    );
    for block in [8, 4, 2] {
        let preview = std::fs::read(dir.join(format!("vases-{block}.ppm"))).unwrap();
        assert_eq!(preview.len(), std::fs::read(&plain).unwrap().len());
        assert_ne!(
            preview,
            std::fs::read(&plain).unwrap(),
            "pass {block} is a preview"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn render_writes_a_panels_colours_truncated_and_dithered() {
    use embedded_graphics::pixelcolor::{BinaryColor, Gray2, Rgb565, Rgb888, RgbColor};
    use embedded_graphics::prelude::{OriginDimensions, Point};
    use microray::dither::{Kernel, Matrix, dither_ordered, dither_rgb565, shown, truncate_rgb565};
    let dir = std::env::temp_dir().join(format!("microray-cli-panel-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/vases.txt");
    let render = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args = vec![
            "render",
            scene.to_str().unwrap(),
            "-q",
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let run = microray(&args);
        assert!(run.status.success(), "{}", text(&run.stderr));
        microray::host::read_ppm(&std::fs::read(&out).unwrap()).unwrap()
    };
    let plain = render("plain.ppm", &[]);
    let width = plain.size().width as usize;
    let pixels: Vec<Rgb888> = plain
        .rgb()
        .chunks(3)
        .map(|c| Rgb888::new(c[0], c[1], c[2]))
        .collect();
    let bytes = |c: Rgb888| [c.r(), c.g(), c.b()];
    let check = |name: &str, extra: &[&str], expected: &dyn Fn(usize, Rgb888) -> Rgb888| {
        let got = render(name, extra);
        for (i, &c) in pixels.iter().enumerate() {
            assert_eq!(
                got.rgb()[3 * i..3 * i + 3],
                bytes(expected(i, c)),
                "{extra:?} pixel {i}"
            );
        }
    };
    let at = |i: usize| Point::new((i % width) as i32, (i / width) as i32);
    check("truncated.ppm", &["--color", "rgb565"], &|_, c| {
        Rgb888::from(truncate_rgb565(c))
    });
    check("bayer4.ppm", &["--dither", "rgb565:bayer4"], &|i, c| {
        Rgb888::from(dither_rgb565(c, at(i)))
    });
    check("blue.ppm", &["--dither", "binary:blue-noise"], &|i, c| {
        shown(dither_ordered::<BinaryColor>(c, at(i), Matrix::BlueNoise))
    });
    // Error diffusion: the library's, row after row.
    // `--dither rgb565` without a method is the format's best: Floyd-Steinberg.
    let fs: Vec<Rgb888> =
        common::diffused_by_hand::<Rgb565>(&pixels, width, Kernel::FloydSteinberg, false)
            .into_iter()
            .map(shown)
            .collect();
    check(
        "fs.ppm",
        &["--dither", "rgb565", "--threads", "2"],
        &|i, _| fs[i],
    );
    let atkinson: Vec<Rgb888> =
        common::diffused_by_hand::<Gray2>(&pixels, width, Kernel::Atkinson, true)
            .into_iter()
            .map(shown)
            .collect();
    check(
        "atkinson.ppm",
        &["--dither", "gray2:atkinson-serpentine"],
        &|i, _| atkinson[i],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn render_antialiased_matches_the_library_and_rejects_bad_counts() {
    use microray::host::{HostRenderer, HostScene, antialiased, texture_files};
    use microray::render::{Antialias, Pattern, Renderer, Samples};
    let dir = std::env::temp_dir().join(format!("microray-cli-aa-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/vases.txt");
    let render = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args = vec!["render", scene_path.to_str().unwrap(), "-q", "-o"];
        args.push(out.to_str().unwrap());
        args.extend_from_slice(extra);
        microray(&args)
    };
    let read = |name: &str| std::fs::read(dir.join(name)).unwrap();
    let text_of_scene = std::fs::read(&scene_path).unwrap();
    let scene: HostScene<'_, f32> =
        microray::parse::parse_scene(&text_of_scene, texture_files(scene_path.parent().unwrap()))
            .unwrap();
    let renderer: HostRenderer<'_, f32> = Renderer::new(&scene);
    for (name, extra, aa) in [
        ("one.ppm", vec!["--aa", "1"], Antialias::Grid(Samples::ONE)),
        (
            "nine.ppm",
            vec!["--aa", "9", "--aa-pattern", "regular"],
            Antialias::Grid(Samples::new(9, Pattern::Regular).unwrap()),
        ),
        (
            "adaptive.ppm",
            vec!["--aa", "adaptive:4", "--aa-threshold", "20"],
            Antialias::Adaptive {
                samples: Samples::rotated(4).unwrap(),
                threshold: 20,
            },
        ),
    ] {
        let mut args = extra.clone();
        args.extend(["--number", "f32"]);
        let run = render(name, &args);
        assert!(run.status.success(), "{}", text(&run.stderr));
        let expected = antialiased(&renderer, aa).unwrap().to_ppm();
        assert!(read(name) == expected, "{name}: not the library's image");
    }
    let plain = render("plain.ppm", &["--number", "f32"]);
    assert!(plain.status.success());
    assert_eq!(read("plain.ppm"), read("one.ppm"));
    assert_ne!(read("plain.ppm"), read("nine.ppm"));
    for bad in ["3", "0", "289", "adaptive:5", "many"] {
        let run = render("bad.ppm", &["--aa", bad]);
        assert_eq!(run.status.code(), Some(2), "--aa {bad}");
        assert!(
            text(&run.stderr).contains("expected a square sample count from 1 to 256"),
            "{}",
            text(&run.stderr)
        );
    }
    let both = render("both.ppm", &["--aa", "4", "--progressive"]);
    assert_eq!(both.status.code(), Some(1));
    assert!(
        text(&both.stderr).contains("cannot be combined"),
        "{}",
        text(&both.stderr)
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn render_with_threads_writes_the_one_thread_image() {
    let dir = std::env::temp_dir().join(format!("microray-cli-threads-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/vases.txt");
    let render = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args = vec!["render", scene.to_str().unwrap(), "-q", "-o"];
        args.push(out.to_str().unwrap());
        args.extend_from_slice(extra);
        microray(&args)
    };
    for (name, extra) in [
        ("one.ppm", vec!["--threads", "1"]),
        ("three.ppm", vec!["--threads", "3"]),
        ("all.ppm", vec![]),
    ] {
        let run = render(name, &extra);
        assert!(run.status.success(), "{}", text(&run.stderr));
    }
    let one = std::fs::read(dir.join("one.ppm")).unwrap();
    assert!(one == std::fs::read(dir.join("three.ppm")).unwrap());
    assert!(one == std::fs::read(dir.join("all.ppm")).unwrap());
    let zero = render("zero.ppm", &["--threads", "0"]);
    assert_eq!(zero.status.code(), Some(2));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn render_over_an_existing_file_leaves_exactly_the_new_image() {
    let dir = std::env::temp_dir().join(format!("microray-cli-over-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/vases.txt");
    let render = |out: &Path| {
        let run = microray(&[
            "render",
            scene.to_str().unwrap(),
            "-q",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(run.status.success(), "{}", text(&run.stderr));
        std::fs::read(out).unwrap()
    };
    for ext in ["ppm", "png"] {
        let fresh = render(&dir.join(format!("fresh.{ext}")));
        assert!(fresh.len() > 1000);
        // Written over a longer file (the tail must go) and over a shorter one.
        for old_len in [fresh.len() * 3, 10] {
            let over = dir.join(format!("over-{old_len}.{ext}"));
            std::fs::write(&over, vec![0xa5; old_len]).unwrap();
            assert!(render(&over) == fresh, "{ext} over {old_len} bytes");
        }
        // To a pipe, which cannot be written at an offset: the whole image in order.
        let pipe = dir.join(format!("pipe.{ext}"));
        let made = std::process::Command::new("mkfifo").arg(&pipe).status();
        assert!(made.is_ok_and(|s| s.success()), "mkfifo {}", pipe.display());
        let reader = {
            let pipe = pipe.clone();
            std::thread::spawn(move || std::fs::read(pipe).unwrap())
        };
        let run = microray(
            &["render", scene.to_str().unwrap(), "-q", "-o"]
                .into_iter()
                .chain([pipe.to_str().unwrap()])
                .collect::<Vec<_>>(),
        );
        assert!(run.status.success(), "{}", text(&run.stderr));
        assert!(reader.join().unwrap() == fresh, "{ext} through a pipe");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Whether an ELF file names a program interpreter (the dynamic loader): its program
/// headers hold a `PT_INTERP`. `None` when the file is not a 64-bit little-endian ELF.
fn names_interpreter(elf: &[u8]) -> Option<bool> {
    let u16_at = |at: usize| Some(u16::from_le_bytes(elf.get(at..at + 2)?.try_into().ok()?));
    let u32_at = |at: usize| Some(u32::from_le_bytes(elf.get(at..at + 4)?.try_into().ok()?));
    let u64_at = |at: usize| Some(u64::from_le_bytes(elf.get(at..at + 8)?.try_into().ok()?));
    if elf.get(..6)? != b"\x7fELF\x02\x01" {
        return None;
    }
    let (first, size, count) = (u64_at(0x20)? as usize, u16_at(0x36)?, u16_at(0x38)?);
    const PT_INTERP: u32 = 3;
    let mut types = (0..usize::from(count)).map(|k| u32_at(first + k * usize::from(size)));
    Some(types.any(|t| t == Some(PT_INTERP)))
}

#[test]
fn the_binary_is_a_static_pie_where_the_build_links_it_so() {
    let binary = std::fs::read(env!("CARGO_BIN_EXE_microray")).unwrap();
    let dynamic = names_interpreter(&binary);
    if option_env!("MICRORAY_STATIC_PIE").is_some() {
        // build.rs linked it with -static-pie: no loader, yet still position independent
        // (ELF type ET_DYN).
        assert_eq!(dynamic, Some(false));
        assert_eq!(binary.get(0x10..0x12), Some(&[3u8, 0][..]));
    } else if cfg!(all(target_os = "linux", target_env = "gnu")) {
        assert_eq!(dynamic, Some(true));
    }
    // And it runs.
    let out = microray(&["check", "scenes/minimal.txt"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
}

/// The report a render ends with (without `-q`): the scene, its size, the render stage's
/// time in milliseconds below a second, the number type and threads, and the output.
/// `cargo xtask host-bench` reads the time from it.
#[test]
fn render_reports_its_time_in_milliseconds() {
    let dir = std::env::temp_dir().join(format!("microray-cli-report-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("minimal.ppm");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/minimal.txt");
    let (scene, out) = (scene.to_str().unwrap(), out.to_str().unwrap());
    let run = microray(&["render", scene, "-o", out, "--threads", "2"]);
    assert!(run.status.success(), "{}", text(&run.stderr));
    let report = text(&run.stderr);
    let rest = report
        .strip_prefix(&format!("{scene}: "))
        .unwrap_or_else(|| panic!("{report}"));
    let (size, rest) = rest.split_once(" in ").unwrap();
    let (width, height) = size.split_once('x').unwrap();
    assert!(width.parse::<u32>().unwrap() > 0 && height.parse::<u32>().unwrap() > 0);
    let (ms, rest) = rest
        .split_once(" ms (")
        .unwrap_or_else(|| panic!("{report}"));
    let ms: f64 = ms.parse().unwrap();
    assert!(ms > 0.0 && ms < 1000.0, "{report}");
    assert_eq!(rest.trim_end(), format!("f64, 2 threads) -> {out}"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The frames of an animated PNG as a player shows them (each drawn over the last at its
/// place), as RGB bytes.
fn apng_frames(bytes: &[u8]) -> Vec<Vec<u8>> {
    let mut reader = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .unwrap();
    let (width, height) = (reader.info().width as usize, reader.info().height as usize);
    let count = reader.info().animation_control().unwrap().num_frames;
    let mut canvas = vec![0u8; width * height * 3];
    let mut frames = Vec::new();
    for _ in 0..count {
        let mut frame = vec![0; reader.output_buffer_size().unwrap()];
        reader.next_frame(&mut frame).unwrap();
        let control = reader.info().frame_control().copied().unwrap();
        let (x, y) = (control.x_offset as usize, control.y_offset as usize);
        let (w, h) = (control.width as usize, control.height as usize);
        for row in 0..h {
            let to = ((y + row) * width + x) * 3;
            canvas[to..to + w * 3].copy_from_slice(&frame[row * w * 3..(row + 1) * w * 3]);
        }
        frames.push(canvas.clone());
    }
    frames
}

#[test]
fn animate_writes_every_frame_as_the_moved_scene_renders() {
    let dir = std::env::temp_dir().join(format!("microray-cli-animate-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let still = "camera c { pixeldim 32 24 worlddim 8 6 viewpoint 4 3 6 }
         material m { diffuse 3 3 3 ambient 0.2 0.2 0.2 }
         plane floor { material m normal 0 1 0 point 0 0 0 }
         light lamp { location 2 9 2 emissivity 8 8 8 }\n";
    let film = dir.join("film.txt");
    std::fs::write(
        &film,
        format!(
            "{still}sphere ball {{ material m center 2 1 -4 radius 1 }}
             animation a {{ frames 5 }}
             line roll {{ target ball by 4 0 0 }}"
        ),
    )
    .unwrap();
    let film = film.to_str().unwrap();
    let (incremental, full) = (dir.join("film.png"), dir.join("full.png"));
    for (out, extra) in [(&incremental, None), (&full, Some("--full"))] {
        let mut args = vec![
            "animate",
            film,
            "-o",
            out.to_str().unwrap(),
            "--number",
            "f32",
        ];
        args.extend(extra);
        let run = microray(&args);
        assert!(run.status.success(), "{}", text(&run.stderr));
        assert!(
            text(&run.stderr).contains("5 frames of 32x24"),
            "{}",
            text(&run.stderr)
        );
    }
    let frames = apng_frames(&std::fs::read(&incremental).unwrap());
    assert_eq!(frames.len(), 5);
    assert_eq!(frames, apng_frames(&std::fs::read(&full).unwrap()));
    // The last frame is the scene with the ball moved by the whole line.
    let moved = dir.join("moved.txt");
    std::fs::write(
        &moved,
        format!("{still}sphere ball {{ material m center 6 1 -4 radius 1 }}"),
    )
    .unwrap();
    let image = dir.join("moved.png");
    let run = microray(&[
        "render",
        moved.to_str().unwrap(),
        "-o",
        image.to_str().unwrap(),
        "--number",
        "f32",
        "-q",
    ]);
    assert!(run.status.success(), "{}", text(&run.stderr));
    let mut reader = png::Decoder::new(std::io::Cursor::new(std::fs::read(&image).unwrap()))
        .read_info()
        .unwrap();
    let mut last = vec![0; reader.output_buffer_size().unwrap()];
    reader.next_frame(&mut last).unwrap();
    // Only the region is stored after the first frame.
    let bytes = |p: &std::path::Path| std::fs::metadata(p).unwrap().len();
    assert!(bytes(&incremental) < bytes(&full));
    assert!(frames[4] == last, "the last frame is not the moved scene's");
    assert!(frames[0] != last, "nothing moved");
    // A scene without motion, and an output that is not PNG, are refused in one line.
    let run = microray(&[
        "animate",
        moved.to_str().unwrap(),
        "-o",
        image.to_str().unwrap(),
    ]);
    assert_eq!(run.status.code(), Some(1));
    assert!(
        text(&run.stderr).contains("error: no `animation` block: nothing moves"),
        "{}",
        text(&run.stderr)
    );
    let run = microray(&[
        "animate",
        film,
        "-o",
        dir.join("film.ppm").to_str().unwrap(),
    ]);
    assert_eq!(run.status.code(), Some(1));
    assert!(
        text(&run.stderr).ends_with("error: animate writes an animated PNG: name it .png\n")
            || text(&run.stderr).contains("--format"),
        "{}",
        text(&run.stderr)
    );
    // `print` writes the film's blocks back.
    let run = microray(&["print", film]);
    assert!(
        text(&run.stdout).ends_with("line roll\n{\n  target ball\n  by 4 0 0\n}\n"),
        "{}",
        text(&run.stdout)
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
