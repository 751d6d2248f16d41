//! `pcf`: Reeves, Salesin & Cook 1987's percentage-closer filtering, a `kernel x kernel` box of
//! depth tests around the receiver's texel of the light map (`shaders/pcf.wgsl`).

use penumbra_params::TechniqueParams;

use super::inputs::TechniqueLanes;
use super::pipelines::TechniquePasses;
use super::resources::ShadowFrame;
use crate::counters::Pass;
use crate::passes::VISIBILITY_FORMAT;

/// Its shader and its one pass.
pub(super) const PASSES: TechniquePasses = TechniquePasses {
    source: include_str!("../shaders/pcf.wgsl"),
    passes: &[("fs_pcf", VISIBILITY_FORMAT)],
};

/// Its lanes of the uniforms: the kernel side.
pub(super) fn lanes(params: &TechniqueParams) -> TechniqueLanes {
    TechniqueLanes {
        iparams: [params.pcf.kernel, 0, 0, 0],
        ..Default::default()
    }
}

/// Records the filter pass: V from the light map.
pub(super) fn record(f: &ShadowFrame<'_>, encoder: &mut wgpu::CommandEncoder) {
    f.run(
        encoder,
        "fs_pcf",
        (&f.base_buf, &[&f.map]),
        &f.visibility_view,
        Pass::Filter,
    );
}
