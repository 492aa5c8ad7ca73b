//! The panels' colour formats as levels per channel: what the dithers quantize to.
//!
//! A format is one grey channel (`BinaryColor`, `Gray2`, `Gray4`, `Gray8`) or three (red,
//! green, blue). Grey comes from the tracer's colour by ITU-R BT.601 luma with 8-bit weights,
//! `Y = (77 R + 150 G + 29 B) / 256` (embedded-graphics' own rule, kept to its 1/256 steps
//! instead of rounded to a byte). A level `q` of `max` shows as `round(255 q / max)`, as
//! embedded-graphics expands colours.
//!
//! embedded-graphics 0.8 has no 8- or 12-bit RGB type, so [`Rgb332`] and [`Rgb444`] are
//! defined here, stored as their panels take them (`RRRGGGBB`, `0000RRRRGGGGBBBB`).

use embedded_graphics::pixelcolor::raw::{RawU8, RawU16};
use embedded_graphics::pixelcolor::{
    BinaryColor, Gray2, Gray4, Gray8, GrayColor, PixelColor, Rgb555, Rgb565, Rgb666, Rgb888,
    RgbColor,
};

/// A panel's colour, as levels `0..=MAX[k]` of its channels.
pub trait PanelColor: PixelColor {
    /// The largest level of each channel: red, green, blue; a grey format's in `MAX[0]`.
    const MAX: [u8; 3];
    /// One grey channel (luma) instead of three.
    const GREY: bool;
    /// The format's name on the command line (`binary`, `gray4`, `rgb565`, ...).
    const NAME: &'static str;
    /// The colour of these levels (each at most its `MAX`).
    fn from_levels(levels: [u8; 3]) -> Self;
    /// This colour's levels.
    fn levels(self) -> [u8; 3];
}

/// The number of channels a format quantizes: 1 (grey) or 3.
pub const fn channels<C: PanelColor>() -> usize {
    if C::GREY { 1 } else { 3 }
}

/// `c`'s channels in 256ths of an 8-bit step (`0..=65280`): red, green and blue, or the
/// luma alone for a grey format (exact: the weights sum to 256).
#[inline(always)]
pub fn fine_values<C: PanelColor>(c: Rgb888) -> [u32; 3] {
    let (r, g, b) = (u32::from(c.r()), u32::from(c.g()), u32::from(c.b()));
    if C::GREY {
        [77 * r + 150 * g + 29 * b, 0, 0]
    } else {
        [r << 8, g << 8, b << 8]
    }
}

/// Level `q` of `max` as 8 bits, `round(255 q / max)`, in embedded-graphics' fixed-point
/// form (so the expansion is exactly its conversion to `Rgb888`).
#[inline(always)]
pub const fn expand(q: u8, max: u8) -> u8 {
    expand_by(q, expand_scale(max))
}

/// `255 / max` in 24 fractional bits (0 for a channel a format lacks): one division per
/// channel, not per pixel (the Cortex-M0 has no divider).
pub(crate) const fn expand_scale(max: u8) -> u32 {
    if max == 0 {
        0
    } else {
        (255u32 << 24) / max as u32
    }
}

/// [`expand`] with the channel's [`expand_scale`] (exact for `q <= max`).
#[inline(always)]
pub(crate) const fn expand_by(q: u8, scale: u32) -> u8 {
    ((q as u32 * scale + (1 << 23)) >> 24) as u8
}

/// A panel colour as the 8-bit colour it shows (grey on all three channels).
pub fn shown<C: PanelColor>(c: C) -> Rgb888 {
    let [a, b, d] = c.levels();
    let [ma, mb, md] = C::MAX;
    if C::GREY {
        let y = expand(a, ma);
        Rgb888::new(y, y, y)
    } else {
        Rgb888::new(expand(a, ma), expand(b, mb), expand(d, md))
    }
}

/// `c` with each channel cut to its top bits: what a panel shows without a dither (the
/// cheap conversion of panel drivers). Grey formats cut the luma (`floor(Y)` for `Gray8`).
pub fn truncate<C: PanelColor>(c: Rgb888) -> C {
    let cut = |v: u8, max: u8| v >> (8 - bits(max));
    if C::GREY {
        let [y, _, _] = fine_values::<C>(c);
        let y = (y >> 8).min(255) as u8;
        C::from_levels([cut(y, C::MAX[0]), 0, 0])
    } else {
        C::from_levels([
            cut(c.r(), C::MAX[0]),
            cut(c.g(), C::MAX[1]),
            cut(c.b(), C::MAX[2]),
        ])
    }
}

/// The bits of a channel whose largest level is `max` (`2^bits - 1`).
const fn bits(max: u8) -> u32 {
    8 - max.leading_zeros()
}

macro_rules! rgb_panel {
    ($type:ty, $name:literal) => {
        impl PanelColor for $type {
            const MAX: [u8; 3] = [<$type>::MAX_R, <$type>::MAX_G, <$type>::MAX_B];
            const GREY: bool = false;
            const NAME: &'static str = $name;
            #[inline(always)]
            fn from_levels([r, g, b]: [u8; 3]) -> Self {
                <$type>::new(r, g, b)
            }
            fn levels(self) -> [u8; 3] {
                [self.r(), self.g(), self.b()]
            }
        }
    };
}

macro_rules! grey_panel {
    ($type:ty, $max:literal, $name:literal) => {
        impl PanelColor for $type {
            const MAX: [u8; 3] = [$max, 0, 0];
            const GREY: bool = true;
            const NAME: &'static str = $name;
            #[inline(always)]
            fn from_levels([y, _, _]: [u8; 3]) -> Self {
                <$type>::new(y)
            }
            fn levels(self) -> [u8; 3] {
                [self.luma(), 0, 0]
            }
        }
    };
}

rgb_panel!(Rgb332, "rgb332");
rgb_panel!(Rgb444, "rgb444");
rgb_panel!(Rgb555, "rgb555");
rgb_panel!(Rgb565, "rgb565");
rgb_panel!(Rgb666, "rgb666");
grey_panel!(Gray2, 3, "gray2");
grey_panel!(Gray4, 15, "gray4");
grey_panel!(Gray8, 255, "gray8");

impl PanelColor for BinaryColor {
    const MAX: [u8; 3] = [1, 0, 0];
    const GREY: bool = true;
    const NAME: &'static str = "binary";
    #[inline(always)]
    fn from_levels([y, _, _]: [u8; 3]) -> Self {
        BinaryColor::from(y != 0)
    }
    fn levels(self) -> [u8; 3] {
        [u8::from(self.is_on()), 0, 0]
    }
}

macro_rules! small_rgb {
    ($(#[$doc:meta])* $type:ident, $raw:ty, $store:ty, ($r:expr, $g:expr, $b:expr)) => {
        $(#[$doc])*
        #[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Debug, Default)]
        pub struct $type($store);

        impl $type {
            const B_SHIFT: u32 = 0;
            const G_SHIFT: u32 = $b;
            const R_SHIFT: u32 = $g + $b;

            /// The colour of these levels (each masked to its bits).
            pub const fn new(r: u8, g: u8, b: u8) -> Self {
                let r = (r as $store) & ((1 << $r) - 1);
                let g = (g as $store) & ((1 << $g) - 1);
                let b = (b as $store) & ((1 << $b) - 1);
                Self((r << Self::R_SHIFT) | (g << Self::G_SHIFT) | (b << Self::B_SHIFT))
            }

            /// The stored bits, as a panel takes them.
            pub const fn into_storage(self) -> $store {
                self.0
            }
        }

        impl PixelColor for $type {
            type Raw = $raw;
        }

        impl RgbColor for $type {
            const MAX_R: u8 = (1 << $r) - 1;
            const MAX_G: u8 = (1 << $g) - 1;
            const MAX_B: u8 = (1 << $b) - 1;
            const BLACK: Self = Self::new(0, 0, 0);
            const RED: Self = Self::new(Self::MAX_R, 0, 0);
            const GREEN: Self = Self::new(0, Self::MAX_G, 0);
            const BLUE: Self = Self::new(0, 0, Self::MAX_B);
            const YELLOW: Self = Self::new(Self::MAX_R, Self::MAX_G, 0);
            const MAGENTA: Self = Self::new(Self::MAX_R, 0, Self::MAX_B);
            const CYAN: Self = Self::new(0, Self::MAX_G, Self::MAX_B);
            const WHITE: Self = Self::new(Self::MAX_R, Self::MAX_G, Self::MAX_B);

            fn r(&self) -> u8 {
                ((self.0 >> Self::R_SHIFT) as u8) & Self::MAX_R
            }
            fn g(&self) -> u8 {
                ((self.0 >> Self::G_SHIFT) as u8) & Self::MAX_G
            }
            fn b(&self) -> u8 {
                ((self.0 >> Self::B_SHIFT) as u8) & Self::MAX_B
            }
        }

        impl From<$raw> for $type {
            fn from(raw: $raw) -> Self {
                Self(embedded_graphics::pixelcolor::raw::RawData::into_inner(raw) & (<$store>::MAX >> (<$store>::BITS - ($r + $g + $b))))
            }
        }

        impl From<$type> for $raw {
            fn from(c: $type) -> Self {
                <$raw>::new(c.0)
            }
        }

        impl From<$type> for Rgb888 {
            /// Each channel expanded to 8 bits, `round(255 q / max)`.
            fn from(c: $type) -> Self {
                shown(c)
            }
        }

        impl From<Rgb888> for $type {
            /// Each channel rounded to its nearest level (embedded-graphics' rule).
            fn from(c: Rgb888) -> Self {
                let near = |v: u8, max: u8| ((u32::from(v) * u32::from(max) + 127) / 255) as u8;
                Self::new(
                    near(c.r(), Self::MAX_R),
                    near(c.g(), Self::MAX_G),
                    near(c.b(), Self::MAX_B),
                )
            }
        }
    };
}

small_rgb!(
    /// 8-bit colour, 3-3-2 bits (`RRRGGGBB`): panels and buses that move a byte a pixel.
    Rgb332,
    RawU8,
    u8,
    (3, 3, 2)
);
small_rgb!(
    /// 12-bit colour, 4-4-4 bits (`0000RRRRGGGGBBBB`): the 12-bit mode of ST7735, ST7789
    /// and ILI9341 panels.
    Rgb444,
    RawU16,
    u16,
    (4, 4, 4)
);

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trip<C: PanelColor + core::fmt::Debug>() {
        let [r, g, b] = C::MAX;
        for l0 in 0..=r {
            for l1 in 0..=g {
                for l2 in [0, b] {
                    let levels = [l0, l1, l2];
                    assert_eq!(C::from_levels(levels).levels(), levels, "{}", C::NAME);
                }
            }
        }
    }

    #[test]
    fn levels_round_trip_in_every_format() {
        round_trip::<BinaryColor>();
        round_trip::<Gray2>();
        round_trip::<Gray4>();
        round_trip::<Gray8>();
        round_trip::<Rgb332>();
        round_trip::<Rgb444>();
        round_trip::<Rgb555>();
        round_trip::<Rgb565>();
        round_trip::<Rgb666>();
    }

    #[test]
    fn the_expansion_is_embedded_graphics_own() {
        for q in 0..=31 {
            let ours = shown(Rgb565::new(q, q * 2, q));
            assert_eq!(ours, Rgb888::from(Rgb565::new(q, q * 2, q)));
        }
        for q in 0..=15 {
            assert_eq!(shown(Gray4::new(q)), Rgb888::from(Gray4::new(q)));
        }
        for q in 0..=63 {
            assert_eq!(
                shown(Rgb666::new(q, q, q)),
                Rgb888::from(Rgb666::new(q, q, q))
            );
        }
        assert_eq!(shown(BinaryColor::On), Rgb888::WHITE);
        assert_eq!(shown(Rgb332::new(7, 7, 3)), Rgb888::WHITE);
        assert_eq!(shown(Rgb444::new(8, 0, 15)), Rgb888::new(136, 0, 255));
    }

    #[test]
    fn small_rgb_stores_as_panels_take_it() {
        assert_eq!(Rgb332::new(0b101, 0b010, 0b11).into_storage(), 0b1010_1011);
        assert_eq!(Rgb444::new(0xa, 0x5, 0xc).into_storage(), 0x0a5c);
        let c = Rgb444::new(0xa, 0x5, 0xc);
        assert_eq!((c.r(), c.g(), c.b()), (0xa, 0x5, 0xc));
        assert_eq!(Rgb332::from(RawU8::new(0xff)), Rgb332::WHITE);
    }

    #[test]
    fn truncation_keeps_the_top_bits() {
        let c = Rgb888::new(0b1011_0110, 0b0110_1101, 0b1111_0000);
        assert_eq!(
            truncate::<Rgb565>(c),
            Rgb565::new(0b10110, 0b011011, 0b11110)
        );
        assert_eq!(truncate::<Rgb332>(c), Rgb332::new(0b101, 0b011, 0b11));
        // luma 127.41 is cut to 127.
        let grey = Rgb888::new(128, 127, 128);
        assert_eq!(
            fine_values::<Gray8>(grey)[0],
            77 * 128 + 150 * 127 + 29 * 128
        );
        assert_eq!(truncate::<Gray8>(grey), Gray8::new(127));
        assert_eq!(
            truncate::<BinaryColor>(Rgb888::new(128, 128, 128)),
            BinaryColor::On
        );
        assert_eq!(
            truncate::<BinaryColor>(Rgb888::new(127, 127, 127)),
            BinaryColor::Off
        );
        assert_eq!(truncate::<Gray2>(Rgb888::new(200, 200, 200)), Gray2::new(3));
    }
}
