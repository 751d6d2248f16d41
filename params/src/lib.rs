//! The parameters of the shadow-map techniques (`pcf`, `pcss`, `fractional-disk`, `mdsm`,
//! `gaussian`): typed, one struct per scene table, and described once in [`PARAMS`], the table
//! of every key with its type, range, default and meaning. That table is the one source of the
//! scene files' optional tables `[shadow_map]`, `[pcf]`, `[pcss]`, `[fractional_disk]`,
//! `[mdsm]` and `[gaussian]` ([`TechniqueParams::read_table`]), of the defaults
//! ([`TechniqueParams::default`]), of the range checks ([`TechniqueParams::validate`]), of the
//! `penumbra render` flags that override them, and of the reference in `docs/scene-format.md`
//! ([`toml_reference`], which a test keeps equal to the docs).
//!
//! ```
//! use penumbra::params::{PARAMS, TechniqueParams, Value};
//!
//! let mut p = TechniqueParams::default();
//! assert_eq!(p.pcf.kernel, 3);
//! let table: toml::Table = toml::from_str("kernel = 5").unwrap();
//! p.read_table("pcf", &table)?;
//! assert_eq!(p.pcf.kernel, 5);
//! // Out of range: named by table and key.
//! let kernel = PARAMS.iter().find(|q| q.flag == "pcf-kernel").unwrap();
//! p.set(kernel, Value::Int(9));
//! assert_eq!(p.validate().unwrap_err().to_string(), "pcf.kernel: 9 is not in 3..=5");
//! # Ok::<(), penumbra::params::ParamError>(())
//! ```
#![warn(missing_docs)]
#![warn(unnameable_types)]

mod kind;
mod table;

pub use kind::{Kind, Value};
pub use table::{PARAMS, Param, TABLES, toml_reference};

/// The light-centre shadow map every shadow-map technique starts from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowMapParams {
    /// Texels per side of the (square) shadow map.
    pub resolution: u32,
    /// Constant depth bias, as a fraction of the receiver's light depth.
    pub depth_bias: f64,
    /// Slope bias in shadow-map texels: the depth change across this many texels of the
    /// receiver's own plane is tolerated.
    pub slope_bias: f64,
}

/// `pcf`: Reeves, Salesin & Cook 1987, a fixed box of `kernel x kernel` texels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PcfParams {
    /// Kernel side in texels: 3, 4 or 5.
    pub kernel: u32,
}

/// `pcss`: Fernando 2005 as Shinde 2022 describes it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PcssParams {
    /// Blocker-search taps per side (a `search x search` grid over the search region).
    pub search: u32,
    /// Most filter taps per side of the variable PCF.
    pub filter_max: u32,
    /// Shinde 2022, section 4.4: four of a 4x4 lattice of taps per pixel, chosen by the pixel's
    /// position in its 2x2 screen quad.
    pub dither: bool,
}

/// `fractional-disk`: Valient & de Boer (2004).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FractionalDiskParams {
    /// Eq. 2's ratio `a` between the disk's area in grid cells and the sample count.
    pub a: f64,
    /// Most PCF samples per pixel.
    pub max_samples: u32,
    /// Largest disk radius, in cells of the 256² preprocessing grid (the paper's map size).
    pub max_radius: f64,
    /// Distance-propagation passes over the preprocessing grid after the edge pass (at least
    /// `max_radius`).
    pub passes: u32,
    /// Edge detection: relative depth jump between neighbouring texels.
    pub edge_threshold: f64,
    /// The disk re-test against false self-occlusion ("Stochastic sampled PCF", Fig. 3b).
    pub retest: bool,
}

/// Which extra depth a 2-depth MDSM keeps besides the base map's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MdsmExtra {
    /// The neighbourhood's maximum (Pagot et al. 2004, section 5).
    Max,
    /// The neighbourhood's minimum.
    Min,
}

/// `mdsm`: Pagot, Comba & Oliveira (2004).
#[derive(Clone, Copy, Debug, PartialEq)]
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

/// The three filters of Cherry & Kooima 2015.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GaussianVariant {
    /// PCF of the hard-shadow bit, kernel size from D.
    Pcf,
    /// One separable Gaussian, size from D.
    Single,
    /// Several Poisson-tap Gaussian passes, D decremented per pass.
    Multi,
}

/// `gaussian`: multi-pass Gaussian contact-hardening shadows (Cherry & Kooima 2015).
#[derive(Clone, Copy, Debug, PartialEq)]
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
#[derive(Clone, Copy, Debug, PartialEq)]
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

/// A parameter that cannot be taken: the table, the key and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParamError {
    /// The table (`pcf`, `shadow_map`, ...).
    pub table: String,
    /// The key.
    pub key: String,
    /// What is wrong, with the value.
    pub message: String,
}

impl std::fmt::Display for ParamError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}.{}: {}", self.table, self.key, self.message)
    }
}

impl std::error::Error for ParamError {}

impl Default for TechniqueParams {
    /// Every key's default from [`PARAMS`]: the papers' values where they give one.
    fn default() -> Self {
        let mut p = TechniqueParams {
            shadow_map: ShadowMapParams {
                resolution: 0,
                depth_bias: 0.0,
                slope_bias: 0.0,
            },
            pcf: PcfParams { kernel: 0 },
            pcss: PcssParams {
                search: 0,
                filter_max: 0,
                dither: false,
            },
            fractional_disk: FractionalDiskParams {
                a: 0.0,
                max_samples: 0,
                max_radius: 0.0,
                passes: 0,
                edge_threshold: 0.0,
                retest: false,
            },
            mdsm: MdsmParams {
                depths: 0,
                kernel: 0,
                radius: 0,
                extra: MdsmExtra::Max,
            },
            gaussian: GaussianParams {
                variant: GaussianVariant::Multi,
                dp: None,
                dm: 0.0,
                max_kernel: 0,
                passes: 0,
                taps: 0,
                dilation: 0,
            },
        };
        for param in &PARAMS {
            if let Some(v) = param.default {
                p.set(param, v);
            }
        }
        p
    }
}

impl TechniqueParams {
    /// Sets `param` to `value` (of `param`'s kind; [`TechniqueParams::validate`] checks the
    /// range).
    ///
    /// # Panics
    ///
    /// If `value` is not of `param`'s kind.
    pub fn set(&mut self, param: &Param, value: Value) {
        (param.set)(self, value);
    }

    /// The value of `param`: `None` for an unset optional key (`gaussian.dp`).
    pub fn get(&self, param: &Param) -> Option<Value> {
        (param.get)(self)
    }

    /// Reads the scene file's table `[name]`: every key must be one of [`PARAMS`]' for that
    /// table, with a value of its kind. Ranges are checked by [`TechniqueParams::validate`].
    pub fn read_table(&mut self, name: &str, entries: &toml::Table) -> Result<(), ParamError> {
        let error = |key: &str, message: String| ParamError {
            table: name.to_string(),
            key: key.to_string(),
            message,
        };
        let known: Vec<&Param> = PARAMS.iter().filter(|p| p.table == name).collect();
        if known.is_empty() {
            return Err(error(
                "",
                format!("no such table (the tables: {})", TABLES.join(", ")),
            ));
        }
        for (key, value) in entries {
            let Some(param) = known.iter().find(|p| p.key == key) else {
                let keys: Vec<&str> = known.iter().map(|p| p.key).collect();
                return Err(error(
                    key,
                    format!("unknown key (the keys of [{name}]: {})", keys.join(", ")),
                ));
            };
            let v = param
                .kind
                .from_toml(value)
                .ok_or_else(|| error(key, format!("{value} is not {}", param.kind.expected())))?;
            self.set(param, v);
        }
        Ok(())
    }

    /// Checks every parameter against its range in [`PARAMS`], and the constraints between
    /// keys: `fractional_disk.passes` must propagate `max_radius`; `gaussian.max_kernel` is odd
    /// and `gaussian.dilation` 0 or odd.
    pub fn validate(&self) -> Result<(), ParamError> {
        let error = |table: &str, key: &str, message: String| ParamError {
            table: table.to_string(),
            key: key.to_string(),
            message,
        };
        for param in &PARAMS {
            if let Some(v) = self.get(param)
                && let Some(why) = param.kind.out_of_range(v)
            {
                return Err(error(param.table, param.key, why));
            }
        }
        let f = &self.fractional_disk;
        if (f.passes as f64) < f.max_radius.ceil() {
            return Err(error(
                "fractional_disk",
                "passes",
                format!(
                    "{} passes cannot propagate max_radius = {} texels (need ceil(max_radius)..=64)",
                    f.passes, f.max_radius
                ),
            ));
        }
        let g = &self.gaussian;
        if g.max_kernel % 2 == 0 {
            return Err(error(
                "gaussian",
                "max_kernel",
                format!("{} is not an odd number up to 63", g.max_kernel),
            ));
        }
        if g.dilation != 0 && g.dilation % 2 == 0 {
            return Err(error(
                "gaussian",
                "dilation",
                format!("{} is not 0 or an odd number up to 63", g.dilation),
            ));
        }
        Ok(())
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
    fn defaults_are_the_papers_and_validate() {
        let p = TechniqueParams::default();
        assert_eq!(p.validate(), Ok(()));
        assert_eq!(
            (
                p.shadow_map.resolution,
                p.pcf.kernel,
                p.pcss.search,
                p.pcss.filter_max
            ),
            (2048, 3, 8, 16)
        );
        assert_eq!((p.fractional_disk.a, p.fractional_disk.passes), (2.0, 16));
        assert_eq!((p.mdsm.depths, p.mdsm.extra), (3, MdsmExtra::Max));
        assert_eq!(
            (p.gaussian.variant, p.gaussian.dp),
            (GaussianVariant::Multi, None)
        );
        assert_eq!(p.gaussian.distance_power(), 3.0);
        // Every key has a default but the optional distance power.
        for param in &PARAMS {
            assert_eq!(
                param.default.is_none(),
                param.flag == "gaussian-dp",
                "{}",
                param.flag
            );
            assert_eq!(p.get(param), param.default, "{}", param.flag);
        }
    }

    #[test]
    fn ranges_and_constraints_are_checked() {
        let mut p = TechniqueParams::default();
        p.pcf.kernel = 6;
        assert_eq!(p.validate().unwrap_err().key, "kernel");
        p = TechniqueParams::default();
        p.fractional_disk.passes = 3;
        assert_eq!(p.validate().unwrap_err().key, "passes");
        p = TechniqueParams::default();
        p.gaussian.max_kernel = 18;
        assert_eq!(p.validate().unwrap_err().key, "max_kernel");
        p = TechniqueParams::default();
        p.gaussian.dp = Some(0.0);
        assert_eq!(
            p.validate().unwrap_err().to_string(),
            "gaussian.dp: 0 is not in (0, 8]"
        );
        p = TechniqueParams::default();
        p.fractional_disk.a = f64::NAN;
        assert_eq!(p.validate().unwrap_err().key, "a");
        // Not finite, beyond 32-bit floats, or out of range once rounded to one.
        let message = |set: fn(&mut TechniqueParams)| {
            let mut p = TechniqueParams::default();
            set(&mut p);
            p.validate().unwrap_err().to_string()
        };
        assert_eq!(
            message(|p| p.gaussian.dm = f64::INFINITY),
            "gaussian.dm: inf is not finite"
        );
        assert_eq!(
            message(|p| p.fractional_disk.a = f64::NAN),
            "fractional_disk.a: NaN is not finite"
        );
        assert_eq!(
            message(|p| p.gaussian.dm = 1e39),
            "gaussian.dm: 1e39 does not fit in 32-bit floats (largest magnitude 3.4e38)"
        );
        assert_eq!(
            message(|p| p.gaussian.dp = Some(1e-50)),
            "gaussian.dp: 1e-50 is 0 in 32-bit floats, which is not in (0, 8]"
        );
    }

    #[test]
    fn tables_are_read_by_key_and_kind() {
        let mut p = TechniqueParams::default();
        let t: toml::Table =
            toml::from_str("variant = \"single\"\ndp = 2\nmax_kernel = 21\ndilation = 3").unwrap();
        p.read_table("gaussian", &t).unwrap();
        assert_eq!(p.gaussian.variant, GaussianVariant::Single);
        assert_eq!((p.gaussian.dp, p.gaussian.max_kernel), (Some(2.0), 21));
        let bad = |table: &str, text: &str| {
            let t: toml::Table = toml::from_str(text).unwrap();
            TechniqueParams::default()
                .read_table(table, &t)
                .unwrap_err()
                .to_string()
        };
        assert!(bad("pcf", "kernal = 3").contains("unknown key (the keys of [pcf]: kernel)"));
        assert!(bad("pcf", "kernel = 3.5").contains("is not an integer"));
        assert!(bad("pcf", "kernel = -1").contains("is not an integer"));
        assert!(bad("mdsm", "extra = \"median\"").contains("\"max\" or \"min\""));
        assert!(bad("pcss", "dither = 1").contains("is not true or false"));
        assert!(bad("pfc", "kernel = 3").contains("no such table"));
    }

    #[test]
    fn equal_area_disk() {
        let r = equal_area_radius(1.0, 1.0);
        assert!((std::f64::consts::PI * r * r - 4.0).abs() < 1e-12);
    }
}
