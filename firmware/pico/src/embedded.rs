//! The scene build.rs embeds (the project's showcase, or the file `MICRORAY_PICO_SCENE`
//! names) with its textures and its `Scene` type, and its loading in place.

use microray::error::TextureError;
use microray::parse::parse_scene_into;

mod generated {
    include!(concat!(env!("OUT_DIR"), "/scene.rs"));
}
pub use generated::PicoScene;

/// Parses the embedded scene into `scene` and sets it to `width` x `height`: false if it
/// does not load (a capacity, a texture, the size).
pub fn load(scene: &mut PicoScene, width: u16, height: u16) -> bool {
    let textures = |name: &str| {
        generated::TEXTURES
            .iter()
            .find(|(written, _)| *written == name)
            .map(|(_, bytes)| *bytes)
            .ok_or(TextureError::NotFound)
    };
    parse_scene_into(generated::TEXT.as_bytes(), textures, scene).is_ok()
        && scene.set_resolution(width, height).is_ok()
}
