//! Workspace-level tests, compiled as one binary through this module tree.

mod blending;
mod common;
mod depth_complexity;
mod distant_light;
mod extreme_extents;
mod far_light;
mod fixtures;
mod fuzz;
mod fuzz_exr;
mod interiors;
mod layout;
mod library_misuse;
mod light_inside;
mod light_plane;
mod mesh_files;
mod outside_crate;
mod quad_closed_form;
mod reference_vs_exact;
mod renderer;
mod repeated_faces;
mod scene_building;
mod sensors;
mod several_lights;
mod sun_hours;
mod volumes;
mod wedge_lookup;
