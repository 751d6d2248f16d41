//! `pcss`: Fernando 2005's percentage-closer soft shadows, a blocker search over the pyramid
//! from the receiver to the light, kept in depth layers, then a filter of the light's points
//! per layer (`shaders/pcss.wgsl`; `docs/shadow-maps.md` says how it departs from the paper).

use penumbra_params::TechniqueParams;

use super::inputs::TechniqueLanes;
use super::pipelines::TechniquePasses;
use super::resources::ShadowFrame;
use crate::counters::Pass;
use crate::passes::VISIBILITY_FORMAT;

/// Its shader and its one pass.
pub(super) const PASSES: TechniquePasses = TechniquePasses {
    source: include_str!("../shaders/pcss.wgsl"),
    passes: &[("fs_pcss", VISIBILITY_FORMAT)],
};

/// Its lanes of the uniforms: the search grid, the filter's largest side, dithering.
pub(super) fn lanes(params: &TechniqueParams) -> TechniqueLanes {
    let p = &params.pcss;
    TechniqueLanes {
        iparams: [p.search, p.filter_max, p.dither as u32, 0],
        ..Default::default()
    }
}

/// Records the search-and-filter pass: V from the light map.
pub(super) fn record(f: &ShadowFrame<'_>, encoder: &mut wgpu::CommandEncoder) {
    f.run(
        encoder,
        "fs_pcss",
        (&f.base_buf, &[&f.map]),
        &f.visibility_view,
        Pass::Filter,
    );
}
