//! The silhouettes' products of a [`super::GpuScene`] for its current light and transforms: the
//! shadow volumes' and wedges' vertex data, uploaded, and what groups the occluders.

use std::ops::Range;

use glam::DVec3;
use penumbra_geom::RectLight;
use penumbra_volumes::Volumes;

use super::meshes::StoredMesh;
use crate::blend_units::BlendUnits;
use crate::passes::buffer;
use crate::passes::wedge::WedgeInstance;
use crate::scene_data::{ReceiverClusters, nearest_edges, volume_vertices, wedge_instances};

/// The silhouettes' products for the current light and transforms.
pub(super) struct Shadows {
    /// Shadow-volume vertices ([`volume_vertices`]) and each blending unit's mesh and range.
    pub(super) volume: wgpu::Buffer,
    pub(super) volume_ranges: Vec<(u32, Range<u32>)>,
    /// Wedge instances, on both sides, and each blending unit's range of them.
    pub(super) instances: Vec<WedgeInstance>,
    pub(super) instance_buffer: wgpu::Buffer,
    pub(super) instance_ranges: Vec<Range<u32>>,
    /// Draw arguments whose word 5 is the number of instances (the tiled wedge pass reads it),
    /// and a buffer of one instance for the second part of their binding.
    pub(super) args: wgpu::Buffer,
    pub(super) spare: wgpu::Buffer,
    /// Each unit's nearest silhouette edge (light space), and the receivers' clusters.
    pub(super) nearest: Vec<f64>,
    pub(super) clusters: ReceiverClusters,
    /// Silhouette edges, for reports.
    pub(super) wedges: usize,
    /// The blending units' items for the tiled blend, their side quads uploaded, and their
    /// casters for the counts at the eye.
    pub(super) units: BlendUnits,
    pub(super) items: wgpu::Buffer,
    pub(super) quads: wgpu::Buffer,
    pub(super) triangle_units: wgpu::Buffer,
}

impl Shadows {
    /// The silhouettes' products of `volumes` (built for `light` and the meshes' current
    /// transforms; `world`: the scene's triangles), uploaded; and the bytes uploaded.
    pub(super) fn build(
        device: &wgpu::Device,
        meshes: &[StoredMesh],
        light: &RectLight,
        volumes: &Volumes,
        world: &[[DVec3; 3]],
    ) -> (Shadows, u64) {
        let stored: Vec<&[[f32; 3]]> = meshes.iter().map(|m| m.stored.as_slice()).collect();
        let (vol, ranges) = volume_vertices(volumes, &stored);
        let (instances, instance_ranges) = wedge_instances(light, world, volumes);
        let units = BlendUnits::new(volumes, &stored, &instance_ranges);
        let bytes = (std::mem::size_of_val(vol.as_slice())
            + std::mem::size_of_val(instances.as_slice())
            + std::mem::size_of_val(units.items.as_slice())
            + std::mem::size_of_val(units.quads.as_slice())
            + std::mem::size_of_val(units.triangle_units.as_slice())) as u64;
        let shadows = Shadows {
            volume: buffer(device, "volume triangles", &vol, wgpu::BufferUsages::VERTEX),
            volume_ranges: ranges,
            instance_buffer: buffer(
                device,
                "wedges",
                &instances,
                wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::STORAGE,
            ),
            args: buffer(
                device,
                "wedge count",
                &[0, 0, 0, 0, 36, instances.len() as u32, 0, 0],
                wgpu::BufferUsages::STORAGE,
            ),
            spare: buffer(
                device,
                "no more wedges",
                &[<WedgeInstance as bytemuck::Zeroable>::zeroed()],
                wgpu::BufferUsages::STORAGE,
            ),
            instances,
            instance_ranges,
            nearest: nearest_edges(volumes),
            clusters: ReceiverClusters::new(light, world),
            wedges: volumes.wedges.len(),
            // `buffer` gives an empty list the one element a binding needs.
            items: buffer(
                device,
                "blend items",
                &units.items,
                wgpu::BufferUsages::STORAGE,
            ),
            quads: buffer(
                device,
                "blend quads",
                &units.quads,
                wgpu::BufferUsages::STORAGE,
            ),
            triangle_units: buffer(
                device,
                "triangle units",
                &units.triangle_units,
                wgpu::BufferUsages::STORAGE,
            ),
            units,
        };
        (shadows, bytes)
    }
}
