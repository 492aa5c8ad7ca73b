//! The anti-aliased frames of `cargo xtask qemu --antialias`, by the suffix of each frame's
//! file: the firmware renders them, the xtask renders the same on the host to compare.

use microray::render::{Antialias, Samples};

const fn samples(count: u16) -> Samples {
    match Samples::rotated(count) {
        Some(samples) => samples,
        None => Samples::ONE,
    }
}

/// Each mode and the suffix of its frame.
pub const MODES: [(&str, Antialias); 4] = [
    ("+aa4", Antialias::Grid(samples(4))),
    ("+aa9", Antialias::Grid(samples(9))),
    ("+aa16", Antialias::Grid(samples(16))),
    (
        "+adaptive",
        Antialias::Adaptive {
            samples: samples(16),
            threshold: 8,
        },
    ),
];
