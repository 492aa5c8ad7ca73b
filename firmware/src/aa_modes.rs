//! The anti-aliased frames of `cargo xtask qemu --antialias`, by the suffix of each frame's
//! file: the firmware renders them, the xtask renders the same on the host to compare.

use microray::render::Antialias;

/// Each mode and the suffix of its frame: the library's measured modes.
pub const MODES: [(&str, Antialias); 4] = [
    ("+aa4", Antialias::MEASURED[0].1),
    ("+aa9", Antialias::MEASURED[1].1),
    ("+aa16", Antialias::MEASURED[2].1),
    ("+adaptive", Antialias::MEASURED[3].1),
];
