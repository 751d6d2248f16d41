//! [`PARAMS`]: every key of the shadow-map techniques' tables, with its kind, range, default
//! and meaning, and what is made from it (the docs' reference block, [`toml_reference`]).

use crate::kind::{Kind, Value};
use crate::{GaussianVariant, MdsmExtra, TechniqueParams};

/// One key of one table.
#[derive(Debug)]
pub struct Param {
    /// The scene table, `pcf`.
    pub table: &'static str,
    /// The key, `kernel`.
    pub key: &'static str,
    /// The `penumbra render` flag that overrides it, without its dashes: `pcf-kernel`.
    pub flag: &'static str,
    /// Its kind and range.
    pub kind: Kind,
    /// Its default; `None` for a key whose absence means something ([`Param::doc`] says what).
    pub default: Option<Value>,
    /// What it is, in a few words.
    pub doc: &'static str,
    pub(crate) get: fn(&TechniqueParams) -> Option<Value>,
    pub(crate) set: fn(&mut TechniqueParams, Value),
}

impl Param {
    /// One line for the command's help: the technique, the meaning, the range, the table key
    /// and the default.
    pub fn help(&self) -> String {
        let technique = match self.table {
            "shadow_map" => "shadow map".to_string(),
            t => t.replace('_', "-"),
        };
        let range = self.kind.range();
        let range = if range.is_empty() {
            String::new()
        } else {
            format!(", {range}")
        };
        let default = self
            .default
            .map_or_else(|| "unset".to_string(), |d| d.to_string());
        format!(
            "{technique}: {}{range} [{}.{}, {default}]",
            self.doc, self.table, self.key
        )
    }
}

/// The tables, in file order, with what each is.
const TABLE_DOCS: [(&str, &str); 6] = [
    ("shadow_map", "the light-centre map all five start from"),
    ("pcf", "Reeves, Salesin & Cook 1987"),
    ("pcss", "Fernando 2005; Shinde 2022"),
    ("fractional_disk", "Valient & de Boer 2004"),
    ("mdsm", "Pagot, Comba & Oliveira 2004"),
    (
        "gaussian",
        "multi-pass Gaussian contact hardening, Cherry & Kooima 2015",
    ),
];

/// The tables' names.
pub const TABLES: [&str; 6] = [
    TABLE_DOCS[0].0,
    TABLE_DOCS[1].0,
    TABLE_DOCS[2].0,
    TABLE_DOCS[3].0,
    TABLE_DOCS[4].0,
    TABLE_DOCS[5].0,
];

const fn int(min: u32, max: u32) -> Kind {
    Kind::Int { min, max }
}

const fn real(min: f64, max: f64) -> Kind {
    Kind::Real {
        min,
        max,
        above: false,
    }
}

const fn above(min: f64, max: f64) -> Kind {
    Kind::Real {
        min,
        max,
        above: true,
    }
}

const MDSM_EXTRA: [&str; 2] = ["max", "min"];
const GAUSSIAN_VARIANT: [&str; 3] = ["pcf", "single", "multi"];

/// Every key of every table, in the order of the docs.
pub static PARAMS: [Param; 24] = [
    Param {
        table: "shadow_map",
        key: "resolution",
        flag: "shadow-map-resolution",
        kind: int(16, 8192),
        default: Some(Value::Int(2048)),
        doc: "texels per side",
        get: |p| Some(Value::Int(p.shadow_map.resolution)),
        set: |p, v| p.shadow_map.resolution = v.int(),
    },
    Param {
        table: "shadow_map",
        key: "depth_bias",
        flag: "depth-bias",
        kind: real(0.0, 0.5),
        default: Some(Value::Real(1e-3)),
        doc: "constant bias, fraction of the receiver's light depth",
        get: |p| Some(Value::Real(p.shadow_map.depth_bias)),
        set: |p, v| p.shadow_map.depth_bias = v.real(),
    },
    Param {
        table: "shadow_map",
        key: "slope_bias",
        flag: "slope-bias",
        kind: real(0.0, 64.0),
        default: Some(Value::Real(1.0)),
        doc: "the receiver plane's depth change across this many texels",
        get: |p| Some(Value::Real(p.shadow_map.slope_bias)),
        set: |p, v| p.shadow_map.slope_bias = v.real(),
    },
    Param {
        table: "pcf",
        key: "kernel",
        flag: "pcf-kernel",
        kind: int(3, 5),
        default: Some(Value::Int(3)),
        doc: "a kernel x kernel box of texels",
        get: |p| Some(Value::Int(p.pcf.kernel)),
        set: |p, v| p.pcf.kernel = v.int(),
    },
    Param {
        table: "pcss",
        key: "search",
        flag: "pcss-search",
        kind: int(1, 16),
        default: Some(Value::Int(8)),
        doc: "blocker-search taps per side",
        get: |p| Some(Value::Int(p.pcss.search)),
        set: |p, v| p.pcss.search = v.int(),
    },
    Param {
        table: "pcss",
        key: "filter_max",
        flag: "pcss-filter-max",
        kind: int(1, 32),
        default: Some(Value::Int(16)),
        doc: "most PCF taps per side",
        get: |p| Some(Value::Int(p.pcss.filter_max)),
        set: |p, v| p.pcss.filter_max = v.int(),
    },
    Param {
        table: "pcss",
        key: "dither",
        flag: "pcss-dither",
        kind: Kind::Bool,
        default: Some(Value::Bool(false)),
        doc: "Shinde 2022, section 4.4: four of a 4x4 lattice per pixel",
        get: |p| Some(Value::Bool(p.pcss.dither)),
        set: |p, v| p.pcss.dither = v.bool(),
    },
    Param {
        table: "fractional_disk",
        key: "a",
        flag: "fd-a",
        kind: above(0.0, f64::INFINITY),
        default: Some(Value::Real(2.0)),
        doc: "Eq. 2: f(q) = ceil(pi q^2 / a)",
        get: |p| Some(Value::Real(p.fractional_disk.a)),
        set: |p, v| p.fractional_disk.a = v.real(),
    },
    Param {
        table: "fractional_disk",
        key: "max_samples",
        flag: "fd-max-samples",
        kind: int(1, 256),
        default: Some(Value::Int(50)),
        doc: "cap of f(q)",
        get: |p| Some(Value::Int(p.fractional_disk.max_samples)),
        set: |p, v| p.fractional_disk.max_samples = v.int(),
    },
    Param {
        table: "fractional_disk",
        key: "max_radius",
        flag: "fd-max-radius",
        kind: real(1.0, 64.0),
        default: Some(Value::Real(16.0)),
        doc: "largest disk radius, cells of the 256² preprocessing grid",
        get: |p| Some(Value::Real(p.fractional_disk.max_radius)),
        set: |p, v| p.fractional_disk.max_radius = v.real(),
    },
    Param {
        table: "fractional_disk",
        key: "passes",
        flag: "fd-passes",
        kind: int(1, 64),
        default: Some(Value::Int(16)),
        doc: "distance-propagation passes over the grid, at least ceil(max_radius)",
        get: |p| Some(Value::Int(p.fractional_disk.passes)),
        set: |p, v| p.fractional_disk.passes = v.int(),
    },
    Param {
        table: "fractional_disk",
        key: "edge_threshold",
        flag: "fd-edge-threshold",
        kind: above(0.0, f64::INFINITY),
        default: Some(Value::Real(0.05)),
        doc: "edge detection: relative depth jump",
        get: |p| Some(Value::Real(p.fractional_disk.edge_threshold)),
        set: |p, v| p.fractional_disk.edge_threshold = v.real(),
    },
    Param {
        table: "fractional_disk",
        key: "retest",
        flag: "fd-retest",
        kind: Kind::Bool,
        default: Some(Value::Bool(false)),
        doc: "the disk re-test against false self-occlusion (Fig. 3b)",
        get: |p| Some(Value::Bool(p.fractional_disk.retest)),
        set: |p, v| p.fractional_disk.retest = v.bool(),
    },
    Param {
        table: "mdsm",
        key: "depths",
        flag: "mdsm-depths",
        kind: int(1, 3),
        default: Some(Value::Int(3)),
        doc: "depths per texel, n",
        get: |p| Some(Value::Int(p.mdsm.depths)),
        set: |p, v| p.mdsm.depths = v.int(),
    },
    Param {
        table: "mdsm",
        key: "kernel",
        flag: "mdsm-kernel",
        kind: int(2, 5),
        default: Some(Value::Int(3)),
        doc: "PCF side, k = kernel^2",
        get: |p| Some(Value::Int(p.mdsm.kernel)),
        set: |p, v| p.mdsm.kernel = v.int(),
    },
    Param {
        table: "mdsm",
        key: "radius",
        flag: "mdsm-radius",
        kind: int(0, 4),
        default: Some(Value::Int(1)),
        doc: "neighbourhood radius of the extra depths, texels",
        get: |p| Some(Value::Int(p.mdsm.radius)),
        set: |p, v| p.mdsm.radius = v.int(),
    },
    Param {
        table: "mdsm",
        key: "extra",
        flag: "mdsm-extra",
        kind: Kind::Choice(&MDSM_EXTRA),
        default: Some(Value::Choice("max")),
        doc: "a 2-depth map's extra depth, the neighbourhood's \"max\" or \"min\"",
        get: |p| {
            Some(Value::Choice(match p.mdsm.extra {
                MdsmExtra::Max => "max",
                MdsmExtra::Min => "min",
            }))
        },
        set: |p, v| {
            p.mdsm.extra = match v.choice() {
                "min" => MdsmExtra::Min,
                _ => MdsmExtra::Max,
            }
        },
    },
    Param {
        table: "gaussian",
        key: "variant",
        flag: "gaussian-variant",
        kind: Kind::Choice(&GAUSSIAN_VARIANT),
        default: Some(Value::Choice("multi")),
        doc: "the filter, \"pcf\", \"single\" or \"multi\"",
        get: |p| {
            Some(Value::Choice(match p.gaussian.variant {
                GaussianVariant::Pcf => "pcf",
                GaussianVariant::Single => "single",
                GaussianVariant::Multi => "multi",
            }))
        },
        set: |p, v| {
            p.gaussian.variant = match v.choice() {
                "pcf" => GaussianVariant::Pcf,
                "single" => GaussianVariant::Single,
                _ => GaussianVariant::Multi,
            }
        },
    },
    Param {
        table: "gaussian",
        key: "dp",
        flag: "gaussian-dp",
        kind: above(0.0, 8.0),
        default: None,
        doc: "distance power (unset: 3 for pcf and multi, 1.9 for single)",
        get: |p| p.gaussian.dp.map(Value::Real),
        set: |p, v| p.gaussian.dp = Some(v.real()),
    },
    Param {
        table: "gaussian",
        key: "dm",
        flag: "gaussian-dm",
        kind: real(0.0, f64::INFINITY),
        default: Some(Value::Real(200.0)),
        doc: "distance multiplier (occluder distance as a fraction of the depth range)",
        get: |p| Some(Value::Real(p.gaussian.dm)),
        set: |p, v| p.gaussian.dm = v.real(),
    },
    Param {
        table: "gaussian",
        key: "max_kernel",
        flag: "gaussian-max-kernel",
        kind: int(1, 63),
        default: Some(Value::Int(19)),
        doc: "largest kernel, odd",
        get: |p| Some(Value::Int(p.gaussian.max_kernel)),
        set: |p, v| p.gaussian.max_kernel = v.int(),
    },
    Param {
        table: "gaussian",
        key: "passes",
        flag: "gaussian-passes",
        kind: int(1, 32),
        default: Some(Value::Int(10)),
        doc: "multi: passes",
        get: |p| Some(Value::Int(p.gaussian.passes)),
        set: |p, v| p.gaussian.passes = v.int(),
    },
    Param {
        table: "gaussian",
        key: "taps",
        flag: "gaussian-taps",
        kind: int(1, 64),
        default: Some(Value::Int(20)),
        doc: "multi: Poisson taps per pass",
        get: |p| Some(Value::Int(p.gaussian.taps)),
        set: |p, v| p.gaussian.taps = v.int(),
    },
    Param {
        table: "gaussian",
        key: "dilation",
        flag: "gaussian-dilation",
        kind: int(0, 63),
        default: Some(Value::Int(0)),
        doc: "Gaussian dilation of D, odd kernel; 0 = off",
        get: |p| Some(Value::Int(p.gaussian.dilation)),
        set: |p, v| p.gaussian.dilation = v.int(),
    },
];

/// The reference block of `docs/scene-format.md`: every table with every key at its default,
/// each commented with its meaning and range (a key without a default commented out).
pub fn toml_reference() -> String {
    let mut out = String::new();
    for (i, (table, doc)) in TABLE_DOCS.iter().enumerate() {
        if i > 0 {
            out.push('\n');
        }
        out.push_str(&format!("{:<26}# {doc}\n", format!("[{table}]")));
        for p in PARAMS.iter().filter(|p| p.table == *table) {
            let left = match p.default {
                Some(v) => format!("{} = {v}", p.key),
                None => format!("# {} =", p.key),
            };
            let range = p.kind.range();
            let comment = if range.is_empty() {
                p.doc.to_string()
            } else {
                format!("{}, {range}", p.doc)
            };
            out.push_str(&format!("{left:<26}# {comment}\n"));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_param_belongs_to_a_table_and_has_a_unique_flag() {
        let mut flags: Vec<&str> = PARAMS.iter().map(|p| p.flag).collect();
        flags.sort_unstable();
        flags.dedup();
        assert_eq!(flags.len(), PARAMS.len());
        for p in &PARAMS {
            assert!(TABLES.contains(&p.table), "{}", p.table);
            if let Some(d) = p.default {
                assert_eq!(p.kind.out_of_range(d), None, "{}", p.flag);
            }
        }
    }

    #[test]
    fn the_reference_block_reads_back_as_the_defaults() {
        let text = toml_reference();
        let doc: toml::Table = toml::from_str(&text).unwrap();
        let mut p = TechniqueParams::default();
        for (name, table) in &doc {
            p.read_table(name, table.as_table().unwrap()).unwrap();
        }
        assert_eq!(p, TechniqueParams::default());
        assert!(
            text.contains("kernel = 3                # a kernel x kernel box of texels, 3..=5\n")
        );
        assert!(text.contains("# dp =                    # distance power (unset: 3"));
    }
}
