//! Which back ends can run each technique: the rule the front door's choice of back end is built
//! on.

use penumbra_geom::Technique;

/// The back ends a technique can run on.
///
/// ```
/// use penumbra::{Runs, Technique};
///
/// assert_eq!(Runs::of(Technique::Pcss), Runs::GpuOnly);
/// assert_eq!(Runs::of(Technique::WedgesBlend), Runs::Either);
/// assert_eq!(Runs::of(Technique::Reference), Runs::CpuOnly);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Runs {
    /// The GPU only: the shadow-map techniques (Mesa's lavapipe serves without a GPU).
    GpuOnly,
    /// The GPU where there is one, the CPU otherwise: the volume techniques and depth-complexity
    /// sampling.
    Either,
    /// The CPU only: the ray-cast references.
    CpuOnly,
}

impl Runs {
    /// Where `technique` runs.
    pub fn of(technique: Technique) -> Runs {
        if technique.is_shadow_map() {
            Runs::GpuOnly
        } else if technique.is_reference() {
            Runs::CpuOnly
        } else {
            Runs::Either
        }
    }
}
