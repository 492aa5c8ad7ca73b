//! `cargo xtask qemu --animations`: the films of `scenes/` played in the firmware, every
//! frame after the first rendered in its region and whole, both compared with the host's
//! full render of that frame, and the table of docs/animation.md.

use crate::qemu::{Build, Row, Size};
use microray::Scalar;
use microray::animation::Animation;
use microray::host::{Framebuffer, HostScene, texture_files};
use microray::parse::{parse_animation, parse_scene_into};
use microray::region::Region;
use microray::render::render;
use microray::scalar::I16F16;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The RAM the firmware reported for playing (`microray size animation|region N`), and the
/// peak stack of its frames, per machine and number type.
static RAM: Mutex<BTreeMap<(&'static str, &'static str), Ram>> = Mutex::new(BTreeMap::new());

#[derive(Default, Clone, Copy)]
struct Ram {
    animation: u64,
    region: u64,
    incremental_stack: u64,
    full_stack: u64,
}

/// The films played (scenes/).
pub(crate) const FILMS: [&str; 4] = ["bounce", "orbit", "lamp", "juggle"];

/// Where docs/animation.md's table begins (the rest of the file is replaced).
const HEADING: &str = "## On the microcontrollers";

/// The host's full frames of a film at `width` x `height` in `S`, frame 0 on.
fn host_frames<S: Scalar>(path: &Path, width: u16, height: u16) -> Result<Vec<Vec<u8>>, String> {
    let text: &'static [u8] = Box::leak(
        std::fs::read(path)
            .map_err(|e| format!("{}: {e}", path.display()))?
            .into_boxed_slice(),
    );
    let mut scene: Box<HostScene<'static, S>> = Box::new(HostScene::empty());
    let dir = path.parent().unwrap_or(Path::new("."));
    parse_scene_into(text, texture_files(dir), &mut scene).map_err(|e| e.to_string())?;
    scene
        .set_resolution(width, height)
        .map_err(|e| e.to_string())?;
    let animation: Animation<'static, 8> = parse_animation(text)
        .map_err(|e| e.to_string())?
        .ok_or(format!("{}: no animation", path.display()))?;
    let mut frames = Vec::new();
    let size = embedded_graphics::prelude::Size::new(width.into(), height.into());
    for k in 0..animation.frames() {
        if k > 0 {
            let mut region = Region::<1>::new(size);
            animation
                .show_frame(k, &mut scene, &mut region)
                .map_err(|e| format!("{} frame {k}: {e}", path.display()))?;
        }
        let mut image = Framebuffer::new(size);
        render(&*scene, &mut image).map_err(|e| e.to_string())?;
        frames.push(image.rgb().to_vec());
    }
    Ok(frames)
}

/// `frame` with the patches of `bytes` (x, y, width as 16-bit little-endian numbers, then
/// the pixels) drawn over it; `None` if they do not fit.
fn patched(frame: &[u8], bytes: &[u8], width: u16) -> Option<Vec<u8>> {
    let mut out = frame.to_vec();
    let mut rest = bytes;
    let number = |b: &[u8]| usize::from(u16::from_le_bytes([b[0], b[1]]));
    while !rest.is_empty() {
        let header = rest.get(..6)?;
        let (x, y, w) = (
            number(&header[..2]),
            number(&header[2..4]),
            number(&header[4..]),
        );
        let pixels = rest.get(6..6 + 3 * w)?;
        let at = (y * usize::from(width) + x) * 3;
        out.get_mut(at..at + 3 * w)?.copy_from_slice(pixels);
        rest = &rest[6 + 3 * w..];
    }
    Some(out)
}

/// The rows of an animated build's run: each frame's count, with the region's pixels for
/// the frames rendered in their region.
pub(crate) fn compare(
    build: &Build,
    console: &str,
    log: &str,
    out: &Path,
    scenes: &BTreeMap<String, PathBuf>,
    width: u16,
    height: u16,
) -> Result<Vec<Row>, String> {
    let mut counts = crate::qemu::frame_totals(log);
    let mut host: BTreeMap<String, Result<Vec<Vec<u8>>, String>> = BTreeMap::new();
    // The firmware's frames so far, per film, rebuilt from its patches.
    let mut shown: BTreeMap<String, Vec<u8>> = BTreeMap::new();
    let mut rows = Vec::new();
    let mut lines = console.lines().peekable();
    while let Some(line) = lines.next() {
        let words: Vec<&str> = line.split_whitespace().collect();
        if let ["microray", "size", what, bytes] = words.as_slice() {
            let mut ram = RAM.lock().map_err(|e| e.to_string())?;
            let entry = ram.entry((build.machine, build.number)).or_default();
            let bytes = bytes.parse().unwrap_or(0);
            match *what {
                "animation" => entry.animation = bytes,
                "region" => entry.region = bytes,
                _ => {}
            }
            continue;
        }
        let (name, stack) = match words.as_slice() {
            ["microray", "scene", name, "stack", stack, ..] => {
                (name.to_string(), stack.parse().unwrap_or(0))
            }
            ["microray", "scene", name, ..] => {
                return Err(format!(
                    "{} {}: {name}: {line}",
                    build.machine, build.number
                ));
            }
            _ => continue,
        };
        let frame_line: Vec<&str> = lines
            .next()
            .map(|l| l.split_whitespace().collect())
            .unwrap_or_default();
        let (k, pixels) = match frame_line.as_slice() {
            ["microray", "frame", k, "full"] => (k.parse::<usize>().ok(), None),
            ["microray", "frame", k, "region", p] => (k.parse().ok(), p.parse::<u64>().ok()),
            _ => (None, None),
        };
        let k = k.ok_or(format!("{name}: no frame line after its report"))?;
        let (insns, vdiv, vsqrt) = counts
            .next()
            .ok_or(format!("no instruction count for {name}"))?;
        let film = name.split('+').next().unwrap_or(&name).to_string();
        let path = scenes
            .get(&film)
            .ok_or(format!("{film}: no such scene on the host"))?;
        let frames = host
            .entry(film.clone())
            .or_insert_with(|| match build.number {
                "f32" => host_frames::<f32>(path, width, height),
                _ => host_frames::<I16F16>(path, width, height),
            });
        let dump =
            std::fs::read(out.join(format!("{name}.rgb"))).map_err(|e| format!("{name}: {e}"))?;
        let picture = match pixels {
            // A region: drawn over the firmware's last frame.
            Some(_) => shown
                .get(&film)
                .and_then(|last| patched(last, &dump, width))
                .ok_or(format!("{name}: its patches do not fit the frame"))?,
            None => dump,
        };
        let identical = match frames {
            Ok(frames) => Ok(frames.get(k).is_some_and(|h| *h == picture)),
            Err(e) => Err(e.clone()),
        };
        // Frame 0 and the regions build the film as a panel would show it.
        if k == 0 || pixels.is_some() {
            shown.insert(film.clone(), picture);
        }
        if let Ok(mut ram) = RAM.lock() {
            let entry = ram.entry((build.machine, build.number)).or_default();
            let peak = if pixels.is_some() {
                &mut entry.incremental_stack
            } else {
                &mut entry.full_stack
            };
            *peak = (*peak).max(stack);
        }
        rows.push(Row {
            scene: name,
            machine: build.machine,
            number: build.number,
            identical,
            insns,
            vdiv,
            vsqrt,
            stack,
            renderer_stack: 0,
            size: Size { flash: 0, ram: 0 },
            region: pixels,
        });
    }
    Ok(rows)
}

/// The table: per film, machine and number type, the mean instructions of a frame whole and
/// in its region (frames 1 on: frame 0 is whole either way), and the region's share.
pub(crate) fn table(rows: &[Row], width: u16, height: u16, frames: Option<u16>) -> String {
    let mut out = format!(
        "{HEADING}\n\nWritten by `cargo xtask qemu --animations`{}: each film of `scenes/` at \
         {width}x{height} on both machines in both of their number types. Every frame after the \
         first is rendered in its region (the scene moved, the region worked out, the plan \
         rebuilt, the region's rectangles traced) and then whole, each counted in QEMU; each \
         is compared with the host's full render of that frame (the regions drawn over the \
         firmware's previous frame). Instructions are the frame's own (the rows' output is \
         not counted), the mean over frames 1 on; ratio = incremental / full; pixels \
         re-traced = the regions' mean share of the frame.\n\n\
         | animation | machine | number | frames | identical | full instr/frame | \
         incremental instr/frame | ratio | pixels re-traced |\n\
         |---|---|---|---|---|---|---|---|---|\n",
        frames.map(|n| format!(" --frames {n}")).unwrap_or_default()
    );
    let pixels = f64::from(width) * f64::from(height);
    let mut groups: BTreeMap<(usize, &str, &str), Vec<&Row>> = BTreeMap::new();
    for row in rows {
        let film = row.scene.split('+').next().unwrap_or(&row.scene);
        let order = FILMS.iter().position(|f| *f == film).unwrap_or(FILMS.len());
        groups
            .entry((order, row.machine, row.number))
            .or_default()
            .push(row);
    }
    for ((_, machine, _), rows) in groups {
        let film = rows[0].scene.split('+').next().unwrap_or("").to_string();
        let mean = |kind: &str| {
            let picked: Vec<&&Row> = rows
                .iter()
                .filter(|r| {
                    r.scene
                        .split_once('+')
                        .is_some_and(|(_, s)| s.starts_with(kind))
                })
                .collect();
            let n = picked.len().max(1) as f64;
            (
                picked.iter().map(|r| r.insns as f64).sum::<f64>() / n,
                picked.iter().filter_map(|r| r.region).sum::<u64>() as f64 / n,
            )
        };
        let (full, _) = mean("f");
        let (incremental, region) = mean("i");
        let identical = rows.iter().all(|r| r.identical == Ok(true));
        let count = rows.iter().filter(|r| !r.scene.contains("+i")).count();
        let number = rows[0].number_name();
        writeln!(
            out,
            "| {film} | {machine} | {number} | {count} | {} | {:.0} | {:.0} | {:.2} | {:.1} % |",
            if identical { "yes" } else { "NO" },
            full,
            incremental,
            incremental / full.max(1.0),
            100.0 * region / pixels,
        )
        .unwrap();
    }
    out.push_str(
        "\nRAM (bytes, as the firmware reports them): the film (`Animation<4>`, its motions \
         with their targets' definitions) and the regions (a frame's `Region<8>` and the \
         last frame's, `LastFrame<8>`), which live as long as the film plays, and the peak \
         stack of the frames rendered in their region (moving the scene and working out the region included) and whole.\n\n\
         | machine | number | film | region | peak stack, region frames | peak stack, whole frames |\n\
         |---|---|---|---|---|---|\n",
    );
    if let Ok(ram) = RAM.lock() {
        for ((machine, number), r) in ram.iter() {
            let number = if *number == "fixed" { "i16f16" } else { number };
            writeln!(
                out,
                "| {machine} | {number} | {} | {} | {} | {} |",
                r.animation, r.region, r.incremental_stack, r.full_stack
            )
            .unwrap();
        }
    }
    out
}

/// The flash the `animate` feature adds: the full firmware with one film (bounce), built
/// with it (and playing the film) and without.
pub(crate) fn flash(root: &Path) -> Result<String, String> {
    let mut out = String::from(
        "\nFlash (bytes): the full firmware embedding `bounce`, without the `animate` feature \
         (it renders the scene) and with it (it plays the film: the motions' reader, \
         `show_frame`, the region).\n\n\
         | machine | number | without | with | the feature |\n|---|---|---|---|---|\n",
    );
    for (machine, number) in [("mps2-an386", "f32"), ("microbit", "fixed")] {
        let without = crate::qemu::flash_of(root, machine, number, "bounce", "")?;
        let with = crate::qemu::flash_of(root, machine, number, "bounce", "animate")?;
        let shown = if number == "fixed" { "i16f16" } else { number };
        writeln!(
            out,
            "| {machine} | {shown} | {without} | {with} | +{} |",
            with.saturating_sub(without)
        )
        .unwrap();
    }
    Ok(out)
}

/// The film's and the region's bytes for a build (`mps2-an386-f32`, `microbit-fixed`), read
/// from docs/animation.md's RAM table (empty before `--animations` has written it).
pub(crate) fn ram_of(root: &Path, build: &str) -> Vec<(&'static str, u64)> {
    let text = std::fs::read_to_string(root.join("docs/animation.md")).unwrap_or_default();
    let (machine, number) = build.rsplit_once('-').unwrap_or((build, ""));
    let number = if number == "fixed" { "i16f16" } else { number };
    for line in text.lines() {
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        if let ["", m, n, film, region, _, _, ""] = cells.as_slice()
            && *m == machine
            && *n == number
        {
            let bytes = |v: &str| v.parse().unwrap_or(0);
            return vec![("film", bytes(film)), ("region", bytes(region))];
        }
    }
    Vec::new()
}

/// Replaces docs/animation.md's table (from its heading to the end).
pub(crate) fn write_table(root: &Path, table: &str) -> Result<(), String> {
    let path = root.join("docs/animation.md");
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let kept = text.split(HEADING).next().unwrap_or(&text).trim_end();
    std::fs::write(&path, format!("{kept}\n\n{table}")).map_err(|e| e.to_string())
}
