//! The CPU back end: the references, depth-complexity sampling and the volume techniques'
//! CPU renderers.

use penumbra_geom::{LightSamples, Reference};
use penumbra_geom::{LitScene, Technique, TracerGeometry};
use penumbra_volumes::{CpuRenderer, DepthComplexity, SamplePattern};

use crate::rendered_frame::Frame;

/// Renders a technique that runs on the CPU, taking the ray-casting hierarchy from `kept`
/// where it serves the scene and keeping the one it builds there otherwise.
pub(crate) fn render(
    scene: &LitScene,
    technique: Technique,
    pattern: SamplePattern,
    progress: &(dyn Fn(u64) + Sync),
    kept: &mut Option<TracerGeometry>,
) -> Frame {
    let (image, detail) = match technique {
        Technique::Reference | Technique::HardReference => {
            let (samples, detail) = match technique {
                Technique::Reference => (
                    LightSamples::Stratified {
                        per_axis: pattern.per_axis,
                    },
                    format!("cpu, {} samples", pattern.per_axis * pattern.per_axis),
                ),
                _ => (LightSamples::Centre, "cpu".to_string()),
            };
            (
                Reference::new_reusing(scene, kept).render(samples, progress),
                detail,
            )
        }
        Technique::DepthComplexity => {
            let r = DepthComplexity::new_reusing(scene, kept);
            let image = r.render(pattern, progress);
            let mut detail = format!(
                "cpu, {} {} samples, {} potential silhouette edges of {}",
                pattern.per_axis * pattern.per_axis,
                if pattern.jitter {
                    "jittered"
                } else {
                    "multi-jittered"
                },
                r.edges.edges.len(),
                r.edges.all_edges
            );
            if r.cast_pixels() > 0 {
                let share = r.cast_pixels() as f64 / image.data.len() as f64;
                detail += &format!(", {:.1}% of pixels by rays", 100.0 * share);
            }
            (image, detail)
        }
        _ => {
            let r = CpuRenderer::new_reusing(scene, kept);
            let detail = format!("cpu, {} wedges", r.volumes.wedges.len());
            (r.render(technique, progress), detail)
        }
    };
    Frame {
        image,
        times: None,
        counters: None,
        detail,
        warnings: Vec::new(),
    }
}
