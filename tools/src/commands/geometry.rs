//! `penumbra geometry`: the volume geometry of a scene.

use std::path::Path;

use anyhow::Result;
use penumbra::Scene;

/// Volume geometry counts of a scene, as `fixtures/expected/*.json` records them.
pub(crate) fn geometry(scene_path: &Path, json: bool) -> Result<()> {
    let scene = Scene::load(scene_path)?;
    let v = penumbra_volumes::Volumes::build(&scene);
    let g = penumbra_volumes::GeometryCounts::of(&v);
    if json {
        println!("{}", serde_json::to_string_pretty(&g)?);
    } else {
        println!(
            "{}: {} silhouette edges (multiplicity summed: {}), {} loops, {} wedges, {} volume triangles",
            scene_path.display(),
            g.silhouette_edges,
            g.silhouette_multiplicity,
            g.loops,
            g.wedges,
            g.volume_triangles
        );
        // What loading dropped, per mesh that dropped any.
        for m in &scene.meshes {
            let (zero, repeated) = (m.mesh.dropped_degenerate, m.mesh.dropped_duplicate);
            if zero + repeated > 0 {
                println!(
                    "  {}: {} triangles kept; dropped {zero} of zero area, {repeated} repeating another",
                    m.source.display(),
                    m.mesh.triangles.len()
                );
            }
        }
    }
    Ok(())
}
