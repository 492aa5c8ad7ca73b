//! One test per class of bad input: each asserts the line, the column and the message.

use microray::error::TextureError;
use microray::host::HostScene;
use microray::parse::{no_textures, parse_scene, parse_scene_with_scale};
use microray::{Error, Scene};

const CAM: &str = "camera c { pixeldim 64 48 worlddim 8 6 viewpoint 4 3 3 }\n";
const MAT: &str = "material m { diffuse 1 1 1 }\n";
const PPM: &[u8] = b"P6 2 1 255 \x01\x02\x03\x04\x05\x06";

fn textures(name: &str) -> Result<&'static [u8], TextureError> {
    match name {
        "ok.ppm" => Ok(PPM),
        "p3.ppm" => Ok(b"P3 1 1 255 0 0 0"),
        "short.ppm" => Ok(b"P6 4 4 255 \x00\x00\x00"),
        "locked.ppm" => Err(TextureError::Unreadable),
        _ => Err(TextureError::NotFound),
    }
}

fn error_of(text: &str) -> Error {
    match parse_scene::<f64, 32, 16, 8, 16, 1024>(text.as_bytes(), textures) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e,
    }
}

/// Asserts `LINE:COL: MESSAGE`.
#[track_caller]
fn assert_error(text: &str, line: u32, column: u32, message: &str) {
    let e = error_of(text);
    let p = e.position.expect("parse errors have a position");
    assert_eq!(
        (p.line, p.column, e.kind.to_string().as_str()),
        (line, column, message),
        "{text}"
    );
}

fn scene(body: &str) -> String {
    format!("{CAM}{MAT}{body}")
}

#[test]
fn unknown_entity() {
    assert_error(
        "sphear s { }",
        1,
        1,
        "expected an entity (camera, material, light, spotlight, plane, sphere, fplane, tiled_plane, texture, texplane, projector, revsurf, animation, line, orbit, bounce), found `sphear`",
    );
}

#[test]
fn unknown_attribute() {
    assert_error(
        &scene("sphere s { material m centre 1 2 3 radius 1 }"),
        3,
        23,
        "unknown attribute `centre` in sphere (expected material, center, radius or `}`)",
    );
}

#[test]
fn missing_values() {
    assert_error(
        &scene("sphere s { material m center 1 2 radius 1 }"),
        3,
        34,
        "`center` takes 3 numbers, found 2 before `radius`",
    );
    assert_error(
        &scene("sphere s { material m center 1 2"),
        3,
        33,
        "`center` takes 3 numbers, found 2 before end of file",
    );
    assert_error(
        &scene("sphere s { material m radius }"),
        3,
        30,
        "`radius` takes 1 number, found 0 before `}`",
    );
}

#[test]
fn extra_values() {
    assert_error(
        &scene("sphere s { material m center 1 2 3 4 radius 1 }"),
        3,
        36,
        "extra value: `center` takes 3 numbers",
    );
}

#[test]
fn missing_closing_brace() {
    assert_error(
        &scene("sphere s {\n  material m\n  center 1 2 3\n  radius 1\n"),
        7,
        1,
        "expected `}` to close the sphere block opened at 3:10, found end of file",
    );
}

#[test]
fn undefined_material() {
    let message =
        "undefined material `wood` (materials must be defined before the objects that use them)";
    assert_error(
        &scene("sphere s { material wood center 0 0 -5 radius 1 }"),
        3,
        21,
        message,
    );
    // Defined after the object is too late, as in the course.
    assert_error(
        &format!("{CAM}sphere s {{ material wood center 0 0 -5 radius 1 }}\nmaterial wood {{ }}"),
        2,
        21,
        message,
    );
    assert_error(
        &scene(
            "tiled_plane t { material m normal 0 1 0 point 0 0 0 xdir 1 0 0 dimensions 1 1 altmaterial wood }",
        ),
        3,
        91,
        message,
    );
}

#[test]
fn undefined_texture() {
    assert_error(
        &scene(
            "texplane t { material m normal 0 0 1 point 0 0 -5 xdir 1 0 0 dimensions 2 2 texname card mode 0 }",
        ),
        3,
        85,
        "undefined texture `card` (textures must be defined before the planes and projectors that use them)",
    );
}

#[test]
fn second_camera_and_no_camera() {
    assert_error(
        &format!("{CAM}{CAM}"),
        2,
        1,
        "second camera (a scene has exactly one)",
    );
    assert_error(
        &format!("{MAT}\n"),
        3,
        1,
        "no camera (a scene needs exactly one `camera` block)",
    );
    assert_error(
        "",
        1,
        1,
        "no camera (a scene needs exactly one `camera` block)",
    );
}

#[test]
fn non_finite_numbers() {
    let not_finite = "is not a finite number (scene files hold finite decimals)";
    assert_error(
        &scene("sphere s { material m center nan 0 0 radius 1 }"),
        3,
        30,
        &format!("`nan` {not_finite}"),
    );
    assert_error(
        &scene("sphere s { material m center 0 0 0 radius -inf }"),
        3,
        43,
        &format!("`-inf` {not_finite}"),
    );
    assert_error(
        &scene("sphere s { material m center 1e999 0 0 radius 1 }"),
        3,
        30,
        "`1e999` is out of range (beyond ±1.8e308)",
    );
    assert_error(
        &scene("sphere s { material m center 1..2 0 0 radius 1 }"),
        3,
        30,
        "expected a number for `center`, found `1..2`",
    );
}

#[test]
fn radius_not_positive() {
    for radius in ["0", "-2", "-0"] {
        assert_error(
            &scene(&format!(
                "sphere s {{ material m center 0 0 -5 radius {radius} }}"
            )),
            3,
            37,
            "`radius` must be greater than 0",
        );
    }
}

#[test]
fn zero_and_degenerate_vectors() {
    assert_error(
        &scene("plane p { material m normal 0 0 0 point 0 0 0 }"),
        3,
        22,
        "`normal` must not be the zero vector",
    );
    assert_error(
        &scene("fplane f { material m normal 0 1 0 point 0 0 0 xdir 0 -3 0 dimensions 1 1 }"),
        3,
        48,
        "`xdir` is parallel to the normal, so it gives no direction in the plane",
    );
    assert_error(
        &scene("fplane f { material m normal 0 1 0 point 0 0 0 xdir 0 0 0 dimensions 1 1 }"),
        3,
        48,
        "`xdir` must not be the zero vector",
    );
    assert_error(
        "spotlight s { location 1 2 3 emissivity 1 1 1 point 1 2 3 theta 10 }",
        1,
        47,
        "spotlight `point` equals its `location`, so it has no direction",
    );
}

#[test]
fn camera_sizes() {
    let camera = |pixels: &str, world: &str| {
        format!("camera c {{ pixeldim {pixels} worlddim {world} viewpoint 4 3 3 }}")
    };
    let too_small = "`pixeldim` must be at least 2 by 2 (pixels map through pixeldim - 1)";
    for pixels in ["0 48", "-5 10", "1 1", "64 0"] {
        assert_error(&camera(pixels, "8 6"), 1, 12, too_small);
    }
    assert_error(
        &camera("64.5 48", "8 6"),
        1,
        21,
        "`pixeldim` takes whole numbers, found `64.5`",
    );
    assert_error(
        &camera("64 48", "0 6"),
        1,
        27,
        "`worlddim` must be greater than 0",
    );
    assert_error(
        &camera("64 48", "8 -6"),
        1,
        27,
        "`worlddim` must be greater than 0",
    );
    assert_error(
        &camera("1025 2", "8 6"),
        1,
        12,
        "image is 1025 pixels wide; this build's row buffer holds 1024",
    );
    assert_error(
        &camera("64 70000", "8 6"),
        1,
        12,
        "image is 70000 pixels tall; at most 65535 rows are supported",
    );
}

#[test]
fn image_wider_than_a_small_build() {
    let text = CAM.as_bytes();
    let e = parse_scene::<f32, 4, 4, 2, 0, 32>(text, no_textures).unwrap_err();
    assert_eq!(
        e.to_string(),
        "1:12: image is 64 pixels wide; this build's row buffer holds 32"
    );
}

#[test]
fn names_too_long() {
    let long = "n".repeat(5000);
    assert_error(
        &format!("material {long} {{ }}"),
        1,
        10,
        "name is longer than 32 bytes",
    );
    let long_path = "d/".repeat(100);
    assert_error(
        &format!("texture t {{ filename {long_path} }}"),
        1,
        22,
        "name is longer than 128 bytes",
    );
    // Exactly 32 bytes fits.
    assert!(
        parse_scene::<f64, 1, 1, 1, 1, 64>(
            format!("{CAM}material {} {{ }}", "n".repeat(32)).as_bytes(),
            no_textures
        )
        .is_ok()
    );
}

#[test]
fn capacity_exceeded() {
    let spheres: String = (0..33)
        .map(|i| format!("sphere s{i} {{ material m center 0 0 -5 radius 1 }}\n"))
        .collect();
    assert_error(
        &scene(&spheres),
        35,
        1,
        "too many objects: this build holds 32",
    );
    let lights: String = (0..9)
        .map(|i| format!("light l{i} {{ location 0 0 0 emissivity 1 1 1 }}\n"))
        .collect();
    assert_error(
        &scene(&lights),
        11,
        1,
        "too many lights: this build holds 8",
    );
    let materials: String = (0..17).map(|i| format!("material m{i} {{ }}\n")).collect();
    assert_error(
        &format!("{CAM}{materials}"),
        18,
        1,
        "too many materials: this build holds 16",
    );
}

#[test]
fn texture_files() {
    assert_error(
        "texture t { filename nope.ppm }",
        1,
        22,
        "texture file `nope.ppm`: file not found",
    );
    assert_error(
        "texture t { filename locked.ppm }",
        1,
        22,
        "texture file `locked.ppm`: file cannot be read",
    );
    assert_error(
        "texture t { filename p3.ppm }",
        1,
        22,
        "texture file `p3.ppm`: not a binary PPM image (it must start with `P6`)",
    );
    assert_error(
        "texture t { filename short.ppm }",
        1,
        22,
        "texture file `short.ppm`: the file ends before the last pixel",
    );
    assert_error("texture t { }", 1, 1, "texture is missing `filename`");
    let ok = parse_scene::<f64, 1, 1, 1, 1, 64>(
        format!("{CAM}texture t {{ filename ok.ppm }}").as_bytes(),
        textures,
    )
    .unwrap();
    assert_eq!(
        (ok.textures()[0].width(), ok.textures()[0].texel(1, 0)),
        (2, [4, 5, 6])
    );
}

#[test]
fn block_structure() {
    assert_error(
        "camera { pixeldim 2 2 }",
        1,
        8,
        "expected a name after `camera`, found `{`",
    );
    assert_error(
        "camera",
        1,
        7,
        "expected a name after `camera`, found end of file",
    );
    assert_error(
        "camera c pixeldim 2 2",
        1,
        10,
        "expected `{` to open the camera block, found `pixeldim`",
    );
    assert_error(
        &scene("sphere s { center 0 0 -5 material m radius 1 }"),
        3,
        12,
        "expected `material` as the first attribute of sphere",
    );
    assert_error(
        &scene("sphere s { material m radius 1 radius 2 }"),
        3,
        32,
        "`radius` is given twice in this block",
    );
    assert_error(
        &scene("sphere s { material m radius 1 }"),
        3,
        1,
        "sphere is missing `center`",
    );
    assert_error(
        &scene("sphere s { material }"),
        3,
        21,
        "expected a name after `material`, found `}`",
    );
}

#[test]
fn characters_and_encoding() {
    assert_error(
        "camera c\x00 { }",
        1,
        9,
        "invalid character 0x00 (control characters are allowed only in comments)",
    );
    assert_error(
        &format!("{CAM}# comments may hold \x07 anything\nmaterial m {{ \x1b }}"),
        3,
        14,
        "invalid character 0x1b (control characters are allowed only in comments)",
    );
    let mut bytes = b"material caf".to_vec();
    bytes.extend_from_slice(b"\xe9 { }");
    let e = parse_scene::<f64, 1, 1, 1, 1, 64>(&bytes, no_textures).unwrap_err();
    assert_eq!(
        e.to_string(),
        "1:13: names and file names must be valid UTF-8"
    );
    // Columns count characters: the `é` before `sphear` is one column.
    assert_error(
        "# é\né sphear",
        2,
        1,
        "expected an entity (camera, material, light, spotlight, plane, sphere, fplane, tiled_plane, texture, texplane, projector, revsurf, animation, line, orbit, bounce), found `é`",
    );
}

#[test]
fn values_out_of_range() {
    assert_error(
        "material m { diffuse 1 1 1 transparency 1.5 }",
        1,
        28,
        "`transparency` must be between 0 and 1",
    );
    assert_error(
        "material m { shininess -3 }",
        1,
        14,
        "`shininess` must be 0 or more",
    );
    assert_error(
        "material m { transparency 0.5 }",
        1,
        14,
        "a transparent material needs a positive `diffuse` (it filters light by the diffuse colour)",
    );
    assert_error(
        "spotlight s { location 0 0 0 emissivity 1 1 1 point 0 -1 0 theta 200 }",
        1,
        60,
        "`theta` must be between 0 and 180 degrees",
    );
    assert_error(
        &format!(
            "{CAM}{MAT}texture t {{ filename ok.ppm }}\ntexplane p {{ material m normal 0 0 1 point 0 0 -5 xdir 1 0 0 dimensions 2 2 texname t mode 2 }}"
        ),
        4,
        87,
        "`mode` must be 0 or 1",
    );
}

#[test]
fn duplicate_names() {
    assert_error(
        &format!("{MAT}{MAT}"),
        2,
        10,
        "a material named `m` is already defined",
    );
    // Objects may share names (the course's spec1 has a sphere and an fplane called `left`).
    let text = scene(
        "sphere a { material m center 0 0 -5 radius 1 }\nsphere a { material m center 0 0 -9 radius 1 }",
    );
    assert!(parse_scene::<f64, 32, 16, 8, 16, 1024>(text.as_bytes(), no_textures).is_ok());
}

#[test]
fn hostile_input_fails_fast_without_panicking() {
    // 20,000 nested braces: the parser does not recurse; the first brace is not an entity.
    let braces = "{".repeat(20_000);
    assert_eq!(
        error_of(&braces).position.map(|p| (p.line, p.column)),
        Some((1, 1))
    );
    // 5,000 objects: the 33rd is a capacity error, in the default build and the host's.
    let many: String = (0..5000)
        .map(|i| format!("sphere s{i} {{ material m center 0 0 -5 radius 1 }}\n"))
        .collect();
    assert_eq!(
        error_of(&scene(&many)).to_string(),
        "35:1: too many objects: this build holds 32"
    );
    let host = parse_scene::<f64, 256, 64, 32, 16, 8192>(scene(&many).as_bytes(), no_textures)
        .unwrap_err();
    assert_eq!(
        host.to_string(),
        "259:1: too many objects: this build holds 256"
    );
    // Binary garbage.
    let garbage: Vec<u8> = (0..10_000u32)
        .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
        .collect();
    assert!(parse_scene::<f64, 32, 16, 8, 16, 1024>(&garbage, no_textures).is_err());
    let _: Result<HostScene<'_, f32>, _> = parse_scene(&garbage, no_textures);
}

#[test]
fn the_same_scene_in_every_number_type() {
    let text = scene("sphere s { material m center 0 0 -5 radius 1 }");
    let a: Scene<'_, f64> = parse_scene(text.as_bytes(), no_textures).unwrap();
    let b: Scene<'_, f32> = parse_scene(text.as_bytes(), no_textures).unwrap();
    assert_eq!(a.objects()[0].name(), b.objects()[0].name());
}

#[test]
fn values_beyond_the_number_type() {
    // Used as written, a radius of 1e39 does not fit f32 ...
    let text = scene("sphere s { material m center 0 0 -5 radius 1e39 }");
    let e = parse_scene_with_scale::<f32, 32, 16, 8, 16, 1024>(text.as_bytes(), no_textures, 1.0)
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "3:37: `radius` is beyond the range of f32, the number type of this build"
    );
    // ... and neither does the square of 1e20, computed at load.
    let text20 = scene("sphere s { material m center 0 0 -5 radius 1e20 }");
    let e = parse_scene_with_scale::<f32, 32, 16, 8, 16, 1024>(text20.as_bytes(), no_textures, 1.0)
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "3:37: `radius` is beyond the range of f32, the number type of this build"
    );
    // parse_scene scales such scenes into range (by a power of two: the image is the same).
    let text25 = scene("sphere s { material m center 0 0 -5 radius 1e25 }");
    let scaled = parse_scene::<f32, 32, 16, 8, 16, 1024>(text25.as_bytes(), no_textures).unwrap();
    assert!(
        scaled.scale() < 1e-7 && scaled.scale().log2().fract() == 0.0,
        "{}",
        scaled.scale()
    );
    // With 1e39 the camera's world window would fall below f32's resolution: the error
    // names the radius that made the scene be scaled so far.
    let e = parse_scene::<f32, 32, 16, 8, 16, 1024>(text.as_bytes(), no_textures).unwrap_err();
    assert_eq!(
        e.to_string(),
        "1:27: the scene reaches over 10^19 from the origin (its `radius`), beyond f32's range of 2^30: scaled by 2^-100 to fit, its `worlddim` falls below f32's resolution (bring the scene nearer the origin, make it smaller, or use a wider number type)"
    );
    // What scaling cannot save: a range of sizes wider than the type's.
    let wide = scene(
        "sphere big { material m center 0 0 -5 radius 1e20 }\nsphere small { material m center 0 0 -5 radius 1e-10 }",
    );
    let e = parse_scene::<f32, 32, 16, 8, 16, 1024>(wide.as_bytes(), no_textures).unwrap_err();
    assert_eq!(
        e.to_string(),
        "4:41: the scene reaches over 10^19 from the origin (its `radius`), beyond f32's range of 2^30: scaled by 2^-37 to fit, its `radius` falls below f32's resolution (bring the scene nearer the origin, make it smaller, or use a wider number type)"
    );
    assert!(parse_scene::<f64, 32, 16, 8, 16, 1024>(wide.as_bytes(), no_textures).is_ok());
}

#[test]
fn pixels_closer_than_the_type_resolves() {
    // A window 0.006 high over 120 rows, 6 away: neighbouring rows 8e-6 radians apart.
    let text = "camera c { pixeldim 160 120 worlddim 8 0.006 viewpoint 4 0.001 6 }\n\
                material m { diffuse 1 1 1 }\nplane p { material m normal 0 1 0 point 0 0 0 }";
    let e =
        parse_scene::<microray::scalar::I16F16, 32, 16, 8, 16, 1024>(text.as_bytes(), no_textures)
            .unwrap_err();
    assert_eq!(
        e.to_string(),
        "1:12: neighbouring pixels are closer in direction than i16f16 can tell apart (at least 16 steps of its resolution are needed: use fewer pixels or a larger `worlddim`)"
    );
    // f32 resolves 2^-23: the same camera is fine.
    assert!(parse_scene::<f32, 32, 16, 8, 16, 1024>(text.as_bytes(), no_textures).is_ok());
    // Fewer rows are far enough apart for Q16.16 too, and a later resolution change is
    // checked the same way.
    let coarse = text.replace("pixeldim 160 120", "pixeldim 160 2");
    let mut scene = parse_scene::<microray::scalar::I16F16, 32, 16, 8, 16, 1024>(
        coarse.as_bytes(),
        no_textures,
    )
    .unwrap();
    assert_eq!(
        scene.set_resolution(160, 120),
        Err(microray::ErrorKind::PixelsTooFine {
            number_type: "i16f16",
            steps: microray::camera::MIN_PIXEL_STEPS,
        })
    );
}

/// A `texplane` block naming its image with `texname FILE` (as the course's later scenes do).
fn texplane(texname: &str) -> String {
    format!(
        "texplane t {{ material m normal 0 0 1 point 0 0 -5 xdir 1 0 0 dimensions 2 2 \
         texname {texname} mode 0 }}\n"
    )
}

#[test]
fn texname_names_a_file_when_no_texture_block_has_that_name() {
    // Read as if a `texture ok.ppm { filename ok.ppm }` block came first: the same scene.
    let direct = format!("{CAM}{MAT}{}", texplane("ok.ppm"));
    let block = format!(
        "{CAM}{MAT}texture ok.ppm {{ filename ok.ppm }}\n{}",
        texplane("ok.ppm")
    );
    let read =
        |text: &str| -> HostScene<'_, f64> { parse_scene(text.as_bytes(), textures).unwrap() };
    assert_eq!(read(&direct), read(&block));
    assert_eq!(read(&direct).textures().len(), 1);
    // Twice the same file: one texture.
    let twice = format!(
        "{CAM}{MAT}{}{}",
        texplane("ok.ppm"),
        texplane("ok.ppm").replace(" t ", " u ")
    );
    assert_eq!(read(&twice).textures().len(), 1);
    // A texture block's name wins over a file of that name.
    let named = format!(
        "{CAM}{MAT}texture ok.ppm {{ filename p3.ppm }}\n{}",
        texplane("ok.ppm")
    );
    assert!(error_of(&named).kind.to_string().contains("p3.ppm"));
}

#[test]
fn texname_that_is_neither_a_texture_nor_a_file() {
    // Line 3 (camera, material, texplane), at the texname's value.
    let text = format!("{CAM}{MAT}{}", texplane("nothing"));
    let column = texplane("nothing").find("nothing").unwrap() as u32 + 1;
    assert_error(
        &text,
        3,
        column,
        "undefined texture `nothing` (textures must be defined before the planes and projectors that use them)",
    );
    // A file that is there but not an image: the texture error, at the same place.
    let text = format!("{CAM}{MAT}{}", texplane("p3.ppm"));
    let column = texplane("p3.ppm").find("p3.ppm").unwrap() as u32 + 1;
    let e = error_of(&text);
    let p = e.position.unwrap();
    assert_eq!((p.line, p.column), (3, column));
    assert!(
        e.kind.to_string().starts_with("texture file `p3.ppm`"),
        "{}",
        e.kind
    );
}

/// A `revsurf` block with `attributes` after its material.
fn revsurf(attributes: &str) -> String {
    format!("{CAM}{MAT}revsurf v {{ material m {attributes} }}")
}

#[test]
fn revsurf_errors() {
    // Line 3, at the attribute (the column counts `revsurf v { material m `: 25).
    assert_error(
        &revsurf("surfer 4 base 0 0 -4 direction 0 1 0 height 6"),
        3,
        24,
        "`surfer` must be 1, 2 or 3",
    );
    assert_error(
        &revsurf("surfer 1.5 base 0 0 -4 direction 0 1 0 height 6"),
        3,
        31,
        "`surfer` takes whole numbers, found `1.5`",
    );
    assert_error(
        &revsurf("surfer 2 base 0 0 -4 direction 0 0 0 height 6"),
        3,
        45,
        "`direction` must not be the zero vector",
    );
    assert_error(
        &revsurf("surfer 2 base 0 0 -4 direction 0 1 0 height 0"),
        3,
        61,
        "`height` must be greater than 0",
    );
    assert_error(
        &revsurf("surfer 2 base 0 0 -4 direction 0 1 0 height -2"),
        3,
        61,
        "`height` must be greater than 0",
    );
    assert_error(
        &revsurf("surfer 3 direction 0 1 0 height 6"),
        3,
        1,
        "revsurf is missing `base`",
    );
}

/// A `projector` block with `attributes` after its light's.
fn projector(attributes: &str) -> String {
    format!(
        "{CAM}texture t {{ filename ok.ppm }}\nprojector p {{ emissivity 1 1 1 location 4 3 2 \
         normal 0 0 1 point 2 1 0 xdir 1 0 0 dimensions 4 3 {attributes} }}"
    )
}

#[test]
fn projector_errors() {
    // Without a texture, with a texture that is neither a block nor a file, with a bad
    // mode, with its slide's x axis along its normal.
    assert_error(&projector("mode 0"), 3, 1, "projector is missing `texname`");
    assert_error(
        &projector("texname nowhere.ppm mode 0"),
        3,
        106,
        "undefined texture `nowhere.ppm` (textures must be defined before the planes and projectors that use them)",
    );
    assert_error(
        &projector("texname t mode 3"),
        3,
        108,
        "`mode` must be 0 or 1",
    );
    assert_error(
        &projector("texname t mode 0").replace("xdir 1 0 0", "xdir 0 0 2"),
        3,
        72,
        "`xdir` is parallel to the normal, so it gives no direction in the plane",
    );
    // A file named directly is read, as for a texplane.
    let text = projector("texname ok.ppm mode 1");
    let scene = parse_scene::<f64, 32, 16, 8, 16, 1024>(text.as_bytes(), textures).unwrap();
    assert_eq!(scene.textures()[1].name(), "ok.ppm");
    assert!(scene.lights()[0].slide.is_some());
}
