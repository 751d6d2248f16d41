//! Parameters of the shadow-map techniques (`pcf`, `pcss`, `fractional-disk`, `mdsm`,
//! `gaussian`): the optional tables `[shadow_map]`, `[pcf]`, `[pcss]`, `[fractional_disk]`,
//! `[mdsm]` and `[gaussian]` of a scene file (see `docs/scene-format.md`), each key optional with
//! its paper's default. The `penumbra render` flags of the same names override them.

use serde::Deserialize;

/// The light-centre shadow map every shadow-map technique starts from.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ShadowMapParams {
    /// Texels per side of the (square) shadow map.
    pub resolution: u32,
    /// Constant depth bias, as a fraction of the receiver's light depth.
    pub depth_bias: f64,
    /// Slope bias in shadow-map texels: the depth change across this many texels of the
    /// receiver's own plane is tolerated.
    pub slope_bias: f64,
}

impl Default for ShadowMapParams {
    fn default() -> Self {
        ShadowMapParams {
            resolution: 2048,
            depth_bias: 1e-3,
            slope_bias: 1.0,
        }
    }
}

/// `pcf`: Reeves, Salesin & Cook 1987, a fixed box of `kernel x kernel` texels.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PcfParams {
    /// Kernel side in texels: 3, 4 or 5.
    pub kernel: u32,
}

impl Default for PcfParams {
    fn default() -> Self {
        PcfParams { kernel: 3 }
    }
}

/// `pcss`: Fernando 2005 as Shinde 2022 describes it.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PcssParams {
    /// Blocker-search taps per side (a `search x search` grid over the search region).
    pub search: u32,
    /// Most filter taps per side of the variable PCF.
    pub filter_max: u32,
    /// Shinde 2022, section 4.4: four of a 4x4 lattice of taps per pixel, chosen by the pixel's
    /// position in its 2x2 screen quad.
    pub dither: bool,
}

impl Default for PcssParams {
    fn default() -> Self {
        PcssParams {
            search: 8,
            filter_max: 16,
            dither: false,
        }
    }
}

/// `fractional-disk`: Valient & de Boer (2004).
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct FractionalDiskParams {
    /// Eq. 2's ratio `a` between the disk's area in texels and the sample count.
    pub a: f64,
    /// Most PCF samples per pixel.
    pub max_samples: u32,
    /// Largest disk radius, in shadow-map texels.
    pub max_radius: f64,
    /// Distance-propagation passes after the edge pass (at least `max_radius`).
    pub passes: u32,
    /// Edge detection: relative depth jump between neighbouring texels.
    pub edge_threshold: f64,
    /// The disk re-test against false self-occlusion ("Stochastic sampled PCF", Fig. 3b).
    pub retest: bool,
}

impl Default for FractionalDiskParams {
    fn default() -> Self {
        FractionalDiskParams {
            a: 2.0,
            max_samples: 50,
            max_radius: 16.0,
            passes: 16,
            edge_threshold: 0.05,
            retest: true,
        }
    }
}

/// Which extra depth a 2-depth MDSM keeps besides the base map's.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MdsmExtra {
    /// The neighbourhood's maximum (Pagot et al. 2004, section 5).
    Max,
    /// The neighbourhood's minimum.
    Min,
}

/// `mdsm`: Pagot, Comba & Oliveira (2004).
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MdsmParams {
    /// Depths per texel, n: 1, 2 or 3.
    pub depths: u32,
    /// PCF side: k = kernel² samples (2 to 5).
    pub kernel: u32,
    /// Neighbourhood radius of the extra depths, in texels.
    pub radius: u32,
    /// The extra depth of a 2-depth map.
    pub extra: MdsmExtra,
}

impl Default for MdsmParams {
    fn default() -> Self {
        MdsmParams {
            depths: 3,
            kernel: 3,
            radius: 1,
            extra: MdsmExtra::Max,
        }
    }
}

/// The three filters of Cherry & Kooima 2015.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum GaussianVariant {
    /// PCF of the hard-shadow bit, kernel size from D.
    Pcf,
    /// One separable Gaussian, size from D.
    Single,
    /// Several Poisson-tap Gaussian passes, D decremented per pass.
    Multi,
}

/// `gaussian`: multi-pass Gaussian contact-hardening shadows (Cherry & Kooima 2015).
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct GaussianParams {
    /// The filter.
    pub variant: GaussianVariant,
    /// Distance power Dp; the paper's value for the variant when absent (3, 1.9, 3).
    pub dp: Option<f64>,
    /// Distance multiplier Dm (the occluder distance is a fraction of the light's depth range).
    pub dm: f64,
    /// Largest kernel side in pixels (odd).
    pub max_kernel: u32,
    /// `multi`: number of Gaussian passes.
    pub passes: u32,
    /// `multi`: Poisson taps per pass (at most 64).
    pub taps: u32,
    /// Gaussian dilation of D before filtering, this many pixels wide (odd); 0 turns it off.
    pub dilation: u32,
}

impl Default for GaussianParams {
    fn default() -> Self {
        GaussianParams {
            variant: GaussianVariant::Multi,
            dp: None,
            dm: 200.0,
            max_kernel: 19,
            passes: 10,
            taps: 20,
            dilation: 0,
        }
    }
}

impl GaussianParams {
    /// Dp, or the paper's value for the variant (Fig. 5: pcf 3, single 1.9, multi 3).
    pub fn distance_power(&self) -> f64 {
        self.dp.unwrap_or(match self.variant {
            GaussianVariant::Single => 1.9,
            _ => 3.0,
        })
    }
}

/// Every shadow-map technique's parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TechniqueParams {
    /// `[shadow_map]`.
    pub shadow_map: ShadowMapParams,
    /// `[pcf]`.
    pub pcf: PcfParams,
    /// `[pcss]`.
    pub pcss: PcssParams,
    /// `[fractional_disk]`.
    pub fractional_disk: FractionalDiskParams,
    /// `[mdsm]`.
    pub mdsm: MdsmParams,
    /// `[gaussian]`.
    pub gaussian: GaussianParams,
}

/// A parameter out of its range: the table, the key and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParamError {
    /// The table (`pcf`, `shadow_map`, ...).
    pub table: &'static str,
    /// The key.
    pub key: &'static str,
    /// What is wrong, with the value.
    pub message: String,
}

impl std::fmt::Display for ParamError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}.{}: {}", self.table, self.key, self.message)
    }
}

impl std::error::Error for ParamError {}

fn check(
    ok: bool,
    table: &'static str,
    key: &'static str,
    message: impl FnOnce() -> String,
) -> Result<(), ParamError> {
    if ok {
        Ok(())
    } else {
        Err(ParamError {
            table,
            key,
            message: message(),
        })
    }
}

impl TechniqueParams {
    /// Checks every parameter's range.
    pub fn validate(&self) -> Result<(), ParamError> {
        let s = &self.shadow_map;
        check(
            (16..=8192).contains(&s.resolution),
            "shadow_map",
            "resolution",
            || format!("{} is not in 16..=8192", s.resolution),
        )?;
        check(
            (0.0..=0.5).contains(&s.depth_bias),
            "shadow_map",
            "depth_bias",
            || format!("{} is not in [0, 0.5]", s.depth_bias),
        )?;
        check(
            (0.0..=64.0).contains(&s.slope_bias),
            "shadow_map",
            "slope_bias",
            || format!("{} is not in [0, 64]", s.slope_bias),
        )?;
        let k = self.pcf.kernel;
        check((3..=5).contains(&k), "pcf", "kernel", || {
            format!("{k} is not 3, 4 or 5")
        })?;
        let p = &self.pcss;
        check((1..=16).contains(&p.search), "pcss", "search", || {
            format!("{} is not in 1..=16", p.search)
        })?;
        check(
            (1..=32).contains(&p.filter_max),
            "pcss",
            "filter_max",
            || format!("{} is not in 1..=32", p.filter_max),
        )?;
        let f = &self.fractional_disk;
        check(f.a > 0.0 && f.a.is_finite(), "fractional_disk", "a", || {
            format!("{} is not a positive number", f.a)
        })?;
        check(
            (1..=256).contains(&f.max_samples),
            "fractional_disk",
            "max_samples",
            || format!("{} is not in 1..=256", f.max_samples),
        )?;
        check(
            f.max_radius >= 1.0 && f.max_radius <= 64.0,
            "fractional_disk",
            "max_radius",
            || format!("{} texels is not in [1, 64]", f.max_radius),
        )?;
        check(
            f.passes as f64 >= f.max_radius.ceil() && f.passes <= 64,
            "fractional_disk",
            "passes",
            || {
                format!(
                    "{} passes cannot propagate max_radius = {} texels (need ceil(max_radius)..=64)",
                    f.passes, f.max_radius
                )
            },
        )?;
        check(
            f.edge_threshold > 0.0 && f.edge_threshold.is_finite(),
            "fractional_disk",
            "edge_threshold",
            || format!("{} is not a positive number", f.edge_threshold),
        )?;
        let m = &self.mdsm;
        check((1..=3).contains(&m.depths), "mdsm", "depths", || {
            format!("{} is not 1, 2 or 3", m.depths)
        })?;
        check((2..=5).contains(&m.kernel), "mdsm", "kernel", || {
            format!("{} is not in 2..=5", m.kernel)
        })?;
        check(m.radius <= 4, "mdsm", "radius", || {
            format!("{} is not in 0..=4", m.radius)
        })?;
        let g = &self.gaussian;
        let dp = g.distance_power();
        check(dp > 0.0 && dp <= 8.0, "gaussian", "dp", || {
            format!("{dp} is not in (0, 8]")
        })?;
        check(g.dm >= 0.0 && g.dm.is_finite(), "gaussian", "dm", || {
            format!("{} is not a non-negative number", g.dm)
        })?;
        check(
            g.max_kernel % 2 == 1 && g.max_kernel <= 63,
            "gaussian",
            "max_kernel",
            || format!("{} is not an odd number up to 63", g.max_kernel),
        )?;
        check((1..=32).contains(&g.passes), "gaussian", "passes", || {
            format!("{} is not in 1..=32", g.passes)
        })?;
        check((1..=64).contains(&g.taps), "gaussian", "taps", || {
            format!("{} is not in 1..=64", g.taps)
        })?;
        check(
            g.dilation == 0 || (g.dilation % 2 == 1 && g.dilation <= 63),
            "gaussian",
            "dilation",
            || format!("{} is not 0 or an odd number up to 63", g.dilation),
        )
    }
}

/// Valient & de Boer's Eq. 2: the number of PCF samples for a disk of radius `q` texels,
/// `f(q) = ceil(pi q² / a)`, capped at `max`.
pub fn fractional_disk_samples(q: f64, a: f64, max: u32) -> u32 {
    let f = (std::f64::consts::PI * q * q / a).ceil();
    if f <= 0.0 { 0 } else { (f as u32).min(max) }
}

/// The radius of the disk of the same area as a `2 hx x 2 hy` rectangle, `sqrt(4 hx hy / pi)`:
/// the light "size" of the papers that assume a disk light.
pub fn equal_area_radius(hx: f64, hy: f64) -> f64 {
    (4.0 * hx * hy / std::f64::consts::PI).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sample_count_follows_eq_2() {
        // Fig. 2 of Valient & de Boer 2004: q = 2 and q = 5 texels with a = 2.
        assert_eq!(fractional_disk_samples(2.0, 2.0, 1000), 7);
        assert_eq!(fractional_disk_samples(5.0, 2.0, 1000), 40);
        assert_eq!(fractional_disk_samples(16.0, 2.0, 50), 50);
        assert_eq!(fractional_disk_samples(0.0, 2.0, 50), 0);
    }

    #[test]
    fn defaults_validate_and_ranges_are_checked() {
        let mut p = TechniqueParams::default();
        assert_eq!(p.validate(), Ok(()));
        p.pcf.kernel = 6;
        assert_eq!(p.validate().unwrap_err().key, "kernel");
        p = TechniqueParams::default();
        p.fractional_disk.passes = 3;
        assert_eq!(p.validate().unwrap_err().key, "passes");
    }

    #[test]
    fn equal_area_disk() {
        let r = equal_area_radius(1.0, 1.0);
        assert!((std::f64::consts::PI * r * r - 4.0).abs() < 1e-12);
    }
}
