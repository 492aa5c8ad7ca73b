//! The instruction profile of a frame: the plugin's per-address counts mapped to functions
//! (the innermost inlined function at each address, from the firmware's DWARF) and to the
//! stages of the tracer.

use addr2line::gimli;
use object::{Object, ObjectSection, ObjectSymbol};
use std::borrow::Cow;
use std::collections::{BTreeMap, HashMap};
use std::fmt::Write as _;
use std::path::Path;

/// The stages a frame's instructions are sorted into, in report order.
pub(crate) const STAGES: [&str; 16] = [
    "primary rays",
    "closest hit: loop",
    "closest hit: plane",
    "closest hit: sphere",
    "closest hit: other kinds",
    "illumination and surface look-ups",
    "shadow rays",
    "trace: recursion, reflection, transparency",
    "divisions and square roots",
    "shading quotients (wide numbers)",
    "products and dot products (fixed point)",
    "soft float and compiler built-ins",
    "byte conversion",
    "row loop and output",
    "render plan",
    "other",
];

/// Maps addresses of one firmware to functions and stages.
pub(crate) struct Symbolizer {
    context: addr2line::Context<gimli::EndianSlice<'static, gimli::RunTimeEndian>>,
    /// ELF symbols by start address, with their sizes: for code without DWARF.
    symbols: BTreeMap<u64, (u64, String)>,
    cache: HashMap<u64, Vec<String>>,
}

impl Symbolizer {
    pub(crate) fn new(elf: &Path) -> Result<Self, String> {
        let bytes = std::fs::read(elf).map_err(|e| e.to_string())?;
        let file = object::File::parse(&*bytes).map_err(|e| e.to_string())?;
        let endian = if file.is_little_endian() {
            gimli::RunTimeEndian::Little
        } else {
            gimli::RunTimeEndian::Big
        };
        let load = |id: gimli::SectionId| -> Result<_, gimli::Error> {
            let data = file
                .section_by_name(id.name())
                .and_then(|s| s.uncompressed_data().ok())
                .unwrap_or(Cow::Borrowed(&[]));
            // Leaked: the firmware's sections live as long as the task.
            let data: &'static [u8] = Box::leak(data.into_owned().into_boxed_slice());
            Ok(gimli::EndianSlice::new(data, endian))
        };
        let dwarf = gimli::Dwarf::load(load).map_err(|e| e.to_string())?;
        let context = addr2line::Context::from_dwarf(dwarf).map_err(|e| e.to_string())?;
        let mut symbols = BTreeMap::new();
        for symbol in file.symbols() {
            if let (object::SymbolKind::Text, Ok(name)) = (symbol.kind(), symbol.name()) {
                let name = addr2line::demangle_auto(Cow::Borrowed(name), None).into_owned();
                symbols.insert(symbol.address() & !1, (symbol.size(), name));
            }
        }
        Ok(Self {
            context,
            symbols,
            cache: HashMap::new(),
        })
    }

    /// The functions at `address`, innermost (inlined) first.
    pub(crate) fn chain(&mut self, address: u64) -> &[String] {
        if !self.cache.contains_key(&address) {
            let mut chain = Vec::new();
            if let Ok(mut frames) = self.context.find_frames(address).skip_all_loads() {
                while let Ok(Some(frame)) = frames.next() {
                    if let Some(name) = frame
                        .function
                        .and_then(|f| f.demangle().ok().map(Cow::into_owned))
                    {
                        chain.push(simplify(&name));
                    }
                }
            }
            if chain.is_empty() {
                let symbol = self
                    .symbols
                    .range(..=address)
                    .next_back()
                    .filter(|(start, (size, _))| address < *start + (*size).max(1))
                    .map_or_else(|| "?".to_string(), |(_, (_, name))| simplify(name));
                chain.push(symbol);
            }
            self.cache.insert(address, chain);
        }
        self.cache.get(&address).map_or(&[], Vec::as_slice)
    }
}

/// A demangled name without its hash and the crate paths of generic arguments.
fn simplify(name: &str) -> String {
    let name = match name.rfind("::h") {
        Some(i) if name[i + 3..].chars().all(|c| c.is_ascii_hexdigit()) => &name[..i],
        _ => name,
    };
    name.replace("microray::", "")
        .replace("core::ops::arith::", "")
        .replace("scalar::fixed::", "")
        .replace("core::", "")
}

/// The stage an address belongs to, from its chain of functions (innermost first).
fn stage(chain: &[String]) -> &'static str {
    let any = |patterns: &[&str]| {
        chain
            .iter()
            .any(|name| patterns.iter().any(|p| name.contains(p)))
    };
    let primitive = |patterns: &[&str]| {
        chain
            .iter()
            .take(3)
            .any(|name| patterns.iter().any(|p| name.contains(p)))
    };
    if chain
        .iter()
        .any(|n| n.starts_with("__") || n.contains("compiler_builtins"))
    {
        return "soft float and compiler built-ins";
    }
    if primitive(&[
        "::sqrt",
        "sqrtf",
        "isqrt",
        "Div>::div",
        "div_vec",
        "::recip",
        "Divisor",
        "reciprocal",
        "mul_ratio",
        "unit_and_length",
    ]) {
        return "divisions and square roots";
    }
    if any(&["to_byte"]) {
        return "byte conversion";
    }
    if primitive(&[
        "Wide",
        "::scale",
        "positive_dot",
        "to_wide",
        "wide_mul",
        "wide_recip",
        "normalise_u64",
    ]) {
        return "shading quotients (wide numbers)";
    }
    if primitive(&[
        "mul_q16_small",
        "dot_q16_small",
        "dot_i64_small",
        "all_below",
        "I16F16 as Mul>::mul",
        "I16F16 as scalar::Scalar>::dot",
        "mul_i32",
        "mul_u32",
    ]) {
        return "products and dot products (fixed point)";
    }
    if any(&["any_hit", "shadow_filter", "occluded", "shadow"]) {
        return "shadow rays";
    }
    if any(&["plane::", "plane_hits"]) && !any(&["tiled_plane", "texplane", "fplane"]) {
        return "closest hit: plane";
    }
    if any(&["sphere"]) {
        return "closest hit: sphere";
    }
    if any(&[
        "fplane",
        "tiled_plane_hits",
        "texplane_hits",
        "Rect<S>>::intersect",
        "bvh",
    ]) {
        return "closest hit: other kinds";
    }
    if any(&["closest_hit"]) {
        return "closest hit: loop";
    }
    if any(&[
        "illuminate",
        "::local",
        "object_ambient",
        "object_diffuse",
        "object_specular",
        "object_material",
        "tiled_plane_material",
        "texel",
        "texplane_",
        "shade::",
    ]) && !any(&["trace"])
    {
        return "illumination and surface look-ups";
    }
    if any(&["primary_ray", "camera::", "Rays"]) {
        return "primary rays";
    }
    if any(&["trace", "reflect"]) {
        return "trace: recursion, reflection, transparency";
    }
    if any(&["plan::", "objects_in_row", "row_objects"]) {
        return "render plan";
    }
    if any(&[
        "render",
        "fill_contiguous",
        "pixel_among",
        "RowFile",
        "microray_count",
    ]) {
        return "row loop and output";
    }
    "other"
}

/// One frame's counts by function and by stage.
pub(crate) struct Profile {
    pub(crate) by_function: Vec<(String, u64)>,
    pub(crate) by_stage: Vec<(&'static str, u64)>,
}

impl Profile {
    pub(crate) fn of(symbolizer: &mut Symbolizer, counts: &HashMap<u64, u64>) -> Self {
        let mut functions: HashMap<String, u64> = HashMap::new();
        let mut stages: HashMap<&'static str, u64> = HashMap::new();
        for (&address, &count) in counts {
            let chain = symbolizer.chain(address);
            let name = chain.first().cloned().unwrap_or_default();
            *stages.entry(stage(chain)).or_insert(0) += count;
            *functions.entry(name).or_insert(0) += count;
        }
        let mut by_function: Vec<(String, u64)> = functions.into_iter().collect();
        by_function.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        let by_stage = STAGES
            .iter()
            .map(|s| (*s, stages.get(s).copied().unwrap_or(0)))
            .collect();
        Self {
            by_function,
            by_stage,
        }
    }

    /// The report: stages, then the functions that make up 99 % of the frame.
    pub(crate) fn report(&self, title: &str, pixels: f64, vdiv: u64, vsqrt: u64) -> String {
        let total: u64 = self.by_stage.iter().map(|(_, c)| c).sum();
        let mut out =
            format!("### {title}\n\n| stage | instructions/pixel | share |\n|---|---|---|\n");
        for (stage, count) in &self.by_stage {
            if *count > 0 {
                let _ = writeln!(
                    out,
                    "| {stage} | {:.1} | {:.1} % |",
                    *count as f64 / pixels,
                    100.0 * *count as f64 / total.max(1) as f64
                );
            }
        }
        let _ = writeln!(
            out,
            "| **total** | **{:.1}** | VDIV {:.2}/pixel, VSQRT {:.2}/pixel |\n",
            total as f64 / pixels,
            vdiv as f64 / pixels,
            vsqrt as f64 / pixels
        );
        out.push_str(
            "| function (innermost, inlined ones included) | instructions/pixel |\n|---|---|\n",
        );
        let mut running = 0;
        for (name, count) in &self.by_function {
            if running as f64 > 0.99 * total as f64 {
                break;
            }
            running += count;
            let _ = writeln!(
                out,
                "| `{}` | {:.1} |",
                name.replace('|', "\\|"),
                *count as f64 / pixels
            );
        }
        out
    }
}

/// The plugin's `icount addr FRAME ADDRESS COUNT` lines, by frame.
pub(crate) fn frame_counts(log: &str) -> BTreeMap<u64, HashMap<u64, u64>> {
    let mut frames: BTreeMap<u64, HashMap<u64, u64>> = BTreeMap::new();
    for line in log.lines() {
        let mut words = line.split_whitespace();
        if (words.next(), words.next()) != (Some("icount"), Some("addr")) {
            continue;
        }
        let (Some(frame), Some(address), Some(count)) = (
            words.next().and_then(|w| w.parse().ok()),
            words
                .next()
                .and_then(|w| u64::from_str_radix(w.trim_start_matches("0x"), 16).ok()),
            words.next().and_then(|w| w.parse::<u64>().ok()),
        ) else {
            continue;
        };
        *frames.entry(frame).or_default().entry(address).or_insert(0) += count;
    }
    frames
}

/// A build's stages (name, instructions a pixel) and its total, VDIV and VSQRT a pixel.
type StageTable = (Vec<(String, f64)>, [f64; 3]);

/// Stage rows of one profile report (`docs/profile-LABEL.md`) by build (`machine in type`):
/// the stages' instructions a pixel, then the total, VDIV and VSQRT a pixel.
fn stages_of(text: &str) -> BTreeMap<String, StageTable> {
    let mut builds = BTreeMap::new();
    let mut current: Option<String> = None;
    for line in text.lines() {
        if let Some(title) = line.strip_prefix("### ") {
            // `spec0 on mps2-an386 in f32 (320x240)` -> `mps2-an386 in f32`.
            current = title
                .split_once(" on ")
                .map(|(_, rest)| rest.split(" (").next().unwrap_or(rest).to_string());
            continue;
        }
        let Some(build) = &current else { continue };
        let cells: Vec<&str> = line.trim_matches('|').split('|').map(str::trim).collect();
        if cells.len() < 3 {
            continue;
        }
        let entry = builds
            .entry(build.clone())
            .or_insert_with(|| (Vec::new(), [0.0; 3]));
        if cells[0] == "**total**" {
            let number = |s: &str| s.trim_matches('*').parse::<f64>().unwrap_or(0.0);
            let per = |key: &str| {
                cells[2]
                    .split(',')
                    .find_map(|part| part.trim().strip_prefix(key))
                    .and_then(|v| v.trim().trim_end_matches("/pixel").parse::<f64>().ok())
                    .unwrap_or(0.0)
            };
            entry.1 = [number(cells[1]), per("VDIV"), per("VSQRT")];
            current = None;
        } else if let (Ok(value), true) = (cells[1].parse::<f64>(), STAGES.contains(&cells[0])) {
            entry.0.push((cells[0].to_string(), value));
        }
    }
    builds
}

/// The before-and-after section of `docs/firmware.md`: spec0's stages at 320x240 from
/// `docs/profile-before.md` and `docs/profile-after.md` (both written by `cargo xtask qemu
/// --size 320x240 --only spec0 --profile LABEL`), and `docs/speed-log.md` (what each change
/// bought, written by hand from such runs).
pub(crate) fn comparison(root: &Path) -> String {
    let read = |name: &str| std::fs::read_to_string(root.join("docs").join(name)).ok();
    let (Some(before), Some(after)) = (read("profile-before.md"), read("profile-after.md")) else {
        return String::new();
    };
    let (before, after) = (stages_of(&before), stages_of(&after));
    let mut out = String::from(
        "\n## Where the instructions go: spec0 at 320x240, before and after\n\n\
         Instructions a pixel by stage, from the per-address counts of the QEMU plugin mapped \
         to the innermost (inlined) function by the firmware's DWARF (`cargo xtask qemu --size \
         320x240 --only spec0 --profile LABEL`; the function tables are in \
         [profile-before.md](profile-before.md) and [profile-after.md](profile-after.md)). \
         Before: the commit before the speed work (25e5e90), profiled with the same tool.\n",
    );
    for (build, (after_stages, after_total)) in &after {
        let Some((before_stages, before_total)) = before.get(build) else {
            continue;
        };
        let _ = write!(
            out,
            "\n### {build}\n\n| stage | before | after |\n|---|---|---|\n"
        );
        for stage in STAGES {
            let get = |rows: &Vec<(String, f64)>| {
                rows.iter()
                    .find(|(s, _)| s == stage)
                    .map_or(0.0, |(_, v)| *v)
            };
            let (b, a) = (get(before_stages), get(after_stages));
            if b > 0.05 || a > 0.05 {
                let _ = writeln!(out, "| {stage} | {b:.1} | {a:.1} |");
            }
        }
        let _ = writeln!(
            out,
            "| **total** | **{:.0}** | **{:.0}** ({:.2}x fewer) |\n| VDIV + VSQRT a pixel | {:.2} | {:.2} |",
            before_total[0],
            after_total[0],
            before_total[0] / after_total[0].max(1.0),
            before_total[1] + before_total[2],
            after_total[1] + after_total[2]
        );
    }
    if let Some(log) = read("speed-log.md") {
        out.push('\n');
        out.push_str(&log);
    }
    out
}

/// The parts a firmware's flash is told in (`flash_parts`).
pub(crate) const PARTS: [&str; 8] = [
    "microray: shading and geometry",
    "microray: scene set-up (loading, render plan, tree)",
    "microray: parser",
    "microray: decimal reader",
    "core::fmt",
    "soft float and compiler built-ins",
    "runtime and QEMU harness",
    "other (core, heapless, embedded-graphics; constants and padding)",
];

/// The part of a function, from its demangled name (`None`: generic code such as `core`'s
/// iterators, which counts for the function it is inlined into).
fn part_of_name(name: &str) -> Option<usize> {
    let crate_of = |prefix: &str| {
        name.starts_with(prefix)
            || name.starts_with(&format!("<{prefix}"))
            || name.contains(&format!(" as {prefix}"))
    };
    if crate_of("core::fmt") || name.contains("core::num::flt2dec") || name.contains("fmt::float") {
        Some(4)
    } else if crate_of("compiler_builtins") || crate_of("libm") || name.starts_with("__") {
        Some(5)
    } else if crate_of("microray::parse") || crate_of("nom::") {
        Some(2)
    } else if crate_of("microray::decimal") {
        Some(3)
    } else if ["scene", "plan", "bvh", "range", "name", "error"]
        .iter()
        .any(|module| crate_of(&format!("microray::{module}::")))
    {
        Some(1)
    } else if crate_of("microray::") {
        Some(0)
    } else if crate_of("microray_firmware") || name.contains("cortex_m") {
        Some(6)
    } else {
        None
    }
}

/// Bytes of a firmware's flash (`.vector_table`, `.text`, `.rodata`, `.data`) by part, in
/// the order of [`PARTS`]: code by the innermost inlined function that belongs to a part
/// (from the DWARF inline records, so a loop inlined into the harness counts for microray),
/// data by its symbol's name.
pub(crate) fn flash_parts(elf: &Path) -> Result<[u64; 8], String> {
    let bytes = std::fs::read(elf).map_err(|e| e.to_string())?;
    let file = object::File::parse(&*bytes).map_err(|e| e.to_string())?;
    let symbolizer = Symbolizer::new(elf)?;
    let mut parts = [0u64; 8];
    let mut data_symbols = BTreeMap::new();
    for symbol in file.symbols() {
        if let (object::SymbolKind::Data, Ok(name)) = (symbol.kind(), symbol.name()) {
            let name = addr2line::demangle_auto(Cow::Borrowed(name), None).into_owned();
            data_symbols.insert(symbol.address(), (symbol.size(), name));
        }
    }
    for section in file.sections() {
        let (start, size) = (section.address(), section.size());
        match section.name() {
            Ok(".vector_table") => parts[6] += size,
            Ok(".text") => {
                // Thumb code: one look-up per halfword.
                for address in (start..start + size).step_by(2) {
                    let mut part = None;
                    if let Ok(mut frames) = symbolizer.context.find_frames(address).skip_all_loads()
                    {
                        while let Ok(Some(frame)) = frames.next() {
                            let name = frame
                                .function
                                .and_then(|f| f.demangle().ok().map(Cow::into_owned));
                            if let Some(found) = name.as_deref().and_then(part_of_name) {
                                part = Some(found);
                                break;
                            }
                        }
                    }
                    if part.is_none() {
                        // No DWARF (the compiler's built-ins, assembly): the ELF symbol.
                        part = symbolizer
                            .symbols
                            .range(..=address)
                            .next_back()
                            .filter(|(s, (len, _))| address < *s + (*len).max(1))
                            .and_then(|(_, (_, name))| part_of_name(name));
                    }
                    parts[part.unwrap_or(7)] += 2.min(start + size - address);
                }
            }
            Ok(".rodata" | ".data") => {
                let mut named = 0;
                for (_, (len, name)) in data_symbols.range(start..start + size) {
                    if let Some(part) = part_of_name(name) {
                        parts[part] += len;
                        named += len;
                    }
                }
                parts[7] += size.saturating_sub(named);
            }
            _ => {}
        }
    }
    Ok(parts)
}
