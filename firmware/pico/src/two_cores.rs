//! Both cores render (feature `two-cores`): core 1 the odd rows, each handed over in a small
//! queue, core 0 the even rows and every write to the panel, which belongs to it (the split
//! is `split.rs`'s, which the host's tests run with a thread as core 1). Each core has its
//! own `Renderer` of the one scene (the plan is worked out twice, the same both times). The
//! library itself knows nothing of cores: this is the split `host::render_parallel` makes on
//! a PC.

use embedded_graphics::pixelcolor::Rgb565;
use embedded_graphics::prelude::DrawTarget;
use microray::render::Renderer;
use rp_pico::hal::multicore::Multicore;

use crate::embedded::PicoScene;
use crate::split::{even_rows, odd_rows};

/// Renders the scene into `panel` with both cores; returns when every row is on the panel.
pub fn render<'p, D>(multicore: &'p mut Multicore<'p>, scene: &'static PicoScene, panel: &mut D)
where
    D: DrawTarget<Color = Rgb565>,
{
    let cores = multicore.cores();
    let started = match (
        cortex_m::singleton!(: [usize; 4096] = [0; 4096]),
        cores.get_mut(1),
    ) {
        (Some(stack), Some(core1)) => core1
            .spawn(stack, move || odd_rows(&Renderer::new(scene)))
            .is_ok(),
        _ => false,
    };
    // Without core 1, core 0 renders every row.
    even_rows(&Renderer::new(scene), panel, if started { 2 } else { 1 });
}
