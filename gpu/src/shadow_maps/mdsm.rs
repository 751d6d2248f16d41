//! `mdsm`: Pagot, Comba & Oliveira 2004's multiple-depth shadow maps: a build pass keeps `n`
//! depths of each texel's neighbourhood, and PCF over them reaches `n k + 1` values
//! (`shaders/mdsm.wgsl`).

use penumbra_params::{MdsmExtra, TechniqueParams};

use super::inputs::TechniqueLanes;
use super::pipelines::TechniquePasses;
use super::resources::{RGBA, ShadowFrame};
use crate::counters::Pass;
use crate::passes::VISIBILITY_FORMAT;

/// Its shader and its passes: the build, the filter, and the probe of the tests
/// ([`super::ShadowMapRenderer::probe`]).
pub(super) const PASSES: TechniquePasses = TechniquePasses {
    source: include_str!("../shaders/mdsm.wgsl"),
    passes: &[
        ("fs_build", RGBA),
        ("fs_mdsm", VISIBILITY_FORMAT),
        ("fs_probe", VISIBILITY_FORMAT),
    ],
};

/// Its lanes of the uniforms: depths per texel, kernel side, neighbourhood radius, and whether
/// the extra depth of two is the maximum.
pub(super) fn lanes(params: &TechniqueParams) -> TechniqueLanes {
    let p = &params.mdsm;
    TechniqueLanes {
        iparams: [
            p.depths,
            p.kernel,
            p.radius,
            (p.extra == MdsmExtra::Max) as u32,
        ],
        ..Default::default()
    }
}

/// Records the build pass into a map of the neighbourhoods' depths, then the filter pass.
pub(super) fn record(f: &ShadowFrame<'_>, encoder: &mut wgpu::CommandEncoder) {
    let multi = f.image("mdsm", f.map_size, RGBA);
    f.run(
        encoder,
        "fs_build",
        (&f.base_buf, &[&f.map]),
        &multi,
        Pass::Preprocess,
    );
    f.run(
        encoder,
        "fs_mdsm",
        (&f.base_buf, &[&f.map, &multi]),
        &f.visibility_view,
        Pass::Filter,
    );
}
