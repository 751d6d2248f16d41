//! `penumbra geometry`: the volume geometry of a scene (of each light of a scene of several).

use std::path::Path;

use anyhow::Result;
use penumbra::Scene;
use penumbra_volumes::GeometryCounts;

/// Volume geometry counts of a scene, as `fixtures/expected/*.json` records them: of its one
/// light, or of each light alone of a scene of several (`"lights"`, a list in the scene's
/// order, each entry with its `name`).
pub(crate) fn geometry(scene_path: &Path, json: bool) -> Result<()> {
    let scene = Scene::load(scene_path)?;
    let counts = |s: &Scene| {
        penumbra_volumes::GeometryCounts::of(&penumbra_volumes::Volumes::build(&s.lit(0)))
    };
    if scene.single_channel() {
        let g = counts(&scene);
        if json {
            println!("{}", serde_json::to_string_pretty(&g)?);
        } else {
            println!("{}: {}", scene_path.display(), describe(&g));
        }
    } else {
        let each: Vec<(String, GeometryCounts)> = (0..scene.light_count())
            .map(|k| (scene.lights[k].name.clone(), counts(&scene.for_light(k))))
            .collect();
        if json {
            let mut lights = Vec::with_capacity(each.len());
            for (name, g) in &each {
                let mut v = serde_json::json!({ "name": name });
                if let (Some(o), serde_json::Value::Object(fields)) =
                    (v.as_object_mut(), serde_json::to_value(g)?)
                {
                    o.extend(fields);
                }
                lights.push(v);
            }
            println!(
                "{}",
                serde_json::to_string_pretty(&serde_json::json!({ "lights": lights }))?
            );
        } else {
            for (name, g) in &each {
                println!("{}, light {name}: {}", scene_path.display(), describe(g));
            }
        }
    }
    if !json {
        // What loading dropped, per mesh that dropped any.
        for m in scene.meshes.iter() {
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

/// The counts in words.
fn describe(g: &GeometryCounts) -> String {
    format!(
        "{} silhouette edges (multiplicity summed: {}), {} loops, {} wedges, {} volume triangles",
        g.silhouette_edges, g.silhouette_multiplicity, g.loops, g.wedges, g.volume_triangles
    )
}
