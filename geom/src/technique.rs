//! Every technique that renders a visibility image, by the name the command line and the scene
//! tables use.

use std::fmt;
use std::str::FromStr;

/// A way to compute the visibility image. Parsed from and printed as its command-line name
/// (`wedges-blend`, `depth-complexity`, ...).
///
/// ```
/// use penumbra::geom::Technique;
///
/// let t: Technique = "depth-complexity".parse().unwrap();
/// assert_eq!(t, Technique::DepthComplexity);
/// assert_eq!(t.to_string(), "depth-complexity");
/// assert!(!t.is_shadow_map() && t.takes_samples());
/// assert!(Technique::Pcss.is_shadow_map());
/// assert!("wedge-blend".parse::<Technique>().is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Technique {
    /// Ray-cast reference: N stratified-jittered light samples per pixel.
    Reference,
    /// Ray-cast hard shadow of a point light at the light's centre.
    HardReference,
    /// Exact for its N light samples: depth-complexity sampling over the potential silhouette
    /// edges (Laine et al. 2005; Forest, Barthe & Paulin 2008).
    DepthComplexity,
    /// Hard shadow of the light's centre by shadow volumes (the stencil answer).
    Hard,
    /// Additive penumbra wedges (Akenine-Möller & Assarsson 2002).
    Wedges,
    /// Penumbra-wedges blending (Forest, Barthe & Paulin 2006).
    WedgesBlend,
    /// Percentage-closer filtering of a light-centre shadow map (Reeves et al. 1987).
    Pcf,
    /// Percentage-closer soft shadows (Fernando 2005, as Shinde 2022 analyses it).
    Pcss,
    /// Fractional-disk soft shadows (Valient & de Boer 2004).
    FractionalDisk,
    /// Multiple-depth shadow maps (Pagot, Comba & Oliveira 2004).
    Mdsm,
    /// Multi-pass Gaussian contact-hardening shadows (Cherry & Kooima 2015).
    Gaussian,
}

impl Technique {
    /// Every technique, in the order of the command's help.
    pub const ALL: [Technique; 11] = [
        Technique::Reference,
        Technique::HardReference,
        Technique::DepthComplexity,
        Technique::Hard,
        Technique::Wedges,
        Technique::WedgesBlend,
        Technique::Pcf,
        Technique::Pcss,
        Technique::FractionalDisk,
        Technique::Mdsm,
        Technique::Gaussian,
    ];

    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Technique::Reference => "reference",
            Technique::HardReference => "hard-reference",
            Technique::DepthComplexity => "depth-complexity",
            Technique::Hard => "hard",
            Technique::Wedges => "wedges",
            Technique::WedgesBlend => "wedges-blend",
            Technique::Pcf => "pcf",
            Technique::Pcss => "pcss",
            Technique::FractionalDisk => "fractional-disk",
            Technique::Mdsm => "mdsm",
            Technique::Gaussian => "gaussian",
        }
    }

    /// One line on what it is, with its source.
    pub fn description(self) -> &'static str {
        match self {
            Technique::Reference => {
                "Ray-cast reference: N stratified-jittered light samples per pixel"
            }
            Technique::HardReference => {
                "Ray-cast hard shadow of a point light at the light's centre"
            }
            Technique::DepthComplexity => {
                "Exact for its N light samples: depth-complexity sampling (Laine et al. 2005; Forest, Barthe & Paulin 2008; GPU up to 1024 samples, CPU otherwise)"
            }
            Technique::Hard => "Hard shadow of the light's centre by shadow volumes",
            Technique::Wedges => "Additive penumbra wedges (Akenine-Möller & Assarsson 2002)",
            Technique::WedgesBlend => "Penumbra-wedges blending (Forest, Barthe & Paulin 2006)",
            Technique::Pcf => {
                "Percentage-closer filtering of a light-centre shadow map (Reeves et al. 1987; GPU)"
            }
            Technique::Pcss => {
                "Percentage-closer soft shadows (Fernando 2005, as Shinde 2022 analyses it; GPU)"
            }
            Technique::FractionalDisk => {
                "Fractional-disk soft shadows (Valient & de Boer 2004; GPU)"
            }
            Technique::Mdsm => "Multiple-depth shadow maps (Pagot, Comba & Oliveira 2004; GPU)",
            Technique::Gaussian => {
                "Multi-pass Gaussian contact-hardening shadows (Cherry & Kooima 2015; GPU)"
            }
        }
    }

    /// The shadow-map techniques (`docs/shadow-maps.md`): filters of a light-centre shadow map.
    pub fn is_shadow_map(self) -> bool {
        matches!(
            self,
            Technique::Pcf
                | Technique::Pcss
                | Technique::FractionalDisk
                | Technique::Mdsm
                | Technique::Gaussian
        )
    }

    /// The volume techniques: shadow volumes and penumbra wedges.
    pub fn is_volume(self) -> bool {
        matches!(
            self,
            Technique::Hard | Technique::Wedges | Technique::WedgesBlend
        )
    }

    /// The ray-cast references.
    pub fn is_reference(self) -> bool {
        matches!(self, Technique::Reference | Technique::HardReference)
    }

    /// Whether it evaluates N light samples per pixel (`--samples`).
    pub fn takes_samples(self) -> bool {
        matches!(self, Technique::Reference | Technique::DepthComplexity)
    }
}

impl fmt::Display for Technique {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A name that is no technique's.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown technique {name:?} (one of: {})", Technique::ALL.map(Technique::name).join(", "))]
pub struct UnknownTechnique {
    /// The name given.
    pub name: String,
}

impl FromStr for Technique {
    type Err = UnknownTechnique;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Technique::ALL
            .into_iter()
            .find(|t| t.name() == s)
            .ok_or_else(|| UnknownTechnique {
                name: s.to_string(),
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_parses_back_and_the_families_partition_the_techniques() {
        for t in Technique::ALL {
            assert_eq!(t.name().parse::<Technique>(), Ok(t));
            assert_eq!(t.to_string(), t.name());
            let families = [
                t.is_shadow_map(),
                t.is_volume(),
                t.is_reference(),
                t == Technique::DepthComplexity,
            ];
            assert_eq!(families.iter().filter(|&&k| k).count(), 1, "{t}");
        }
        let err = "wedge".parse::<Technique>().unwrap_err().to_string();
        assert!(
            err.contains("\"wedge\"") && err.contains("wedges-blend"),
            "{err}"
        );
    }
}
