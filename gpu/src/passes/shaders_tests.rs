//! Every WGSL file parses and validates with naga, as the passes compile it.

use std::path::PathBuf;

use super::blend::BLEND_PARTS_WGSL;
use super::build::WORKGROUP_SCAN_WGSL;
use super::complexity::COMPLEXITY_WGSL;
use super::count::COUNT_WGSL;
use super::fullscreen::{SHADOW_MAP_SHADERS, SHADOW_WGSL};
use super::wedge::WEDGE_INTEGRAL_WGSL;
use super::wedge_tiles::TILE_WEDGES_WGSL;
use super::wgsl_source;

#[test]
fn every_wgsl_file_validates_with_naga() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src/shaders");
    let mut n = 0;
    for e in std::fs::read_dir(&dir).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_none_or(|x| x != "wgsl") {
            continue;
        }
        let stem = p.file_stem().unwrap().to_string_lossy().into_owned();
        // Declarations compiled ahead of the passes' shaders, and the counting pass's first
        // parts: each is validated in the shaders that take it.
        if [
            "common",
            "shadow",
            "complexity",
            "count_regions",
            "count_pattern",
            "count_receiver",
            "wedge_integral",
            "workgroup_scan",
            "tile_wedges",
            "blend_parts",
        ]
        .contains(&stem.as_str())
        {
            continue;
        }
        // Each pass's shader is compiled after the shared constants and common.wgsl
        // (`wgsl_source`), the shadow-map techniques' with shadow.wgsl too
        // (`fullscreen::shadow_shader`), depth-complexity sampling's passes (and its receiver
        // candidates) with complexity.wgsl, the counting pass from its four files
        // (`count::COUNT_WGSL`), and the tiled passes and the blends with the parts they share.
        let file = std::fs::read_to_string(&p).unwrap();
        let source = if SHADOW_MAP_SHADERS.contains(&stem.as_str()) {
            format!("{SHADOW_WGSL}\n{file}")
        } else if stem == "count" {
            format!("{COMPLEXITY_WGSL}\n{COUNT_WGSL}")
        } else if stem == "wedge" {
            format!("{WEDGE_INTEGRAL_WGSL}\n{file}")
        } else if stem == "wedge_tiles" {
            format!("{WEDGE_INTEGRAL_WGSL}\n{WORKGROUP_SCAN_WGSL}\n{TILE_WEDGES_WGSL}\n{file}")
        } else if stem == "blend_tiles" {
            format!(
                "{WEDGE_INTEGRAL_WGSL}\n{WORKGROUP_SCAN_WGSL}\n{TILE_WEDGES_WGSL}\n{BLEND_PARTS_WGSL}\n{file}"
            )
        } else if stem == "blend" {
            format!("{BLEND_PARTS_WGSL}\n{file}")
        } else if stem == "build" {
            format!("{WORKGROUP_SCAN_WGSL}\n{file}")
        } else if stem == "edge_lists" || stem == "candidates" {
            format!("{COMPLEXITY_WGSL}\n{file}")
        } else {
            file
        };
        let src = wgsl_source(&source);
        let module = naga::front::wgsl::parse_str(&src)
            .unwrap_or_else(|e| panic!("{}: {}", p.display(), e.emit_to_string(&src)));
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::all(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{}: {e:?}", p.display()));
        n += 1;
    }
    assert!(
        n >= 3,
        "expected the pass shaders in {}, found {n}",
        dir.display()
    );
}
