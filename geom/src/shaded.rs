//! The shaded preview: a simple diffuse picture of a scene lit by its lights, each light's
//! cosine term times its visibility V, so that one sees what is lit and where.
//!
//! For the pixel `(x, y)`, P is the first hit of the camera ray (the surface point of the
//! reference, [`Tracer::surface_point`]) and `n` its triangle's geometric normal, turned to face
//! the camera. Of the scene's `K` lights, with `ω_k` the unit direction from P to the centre of
//! light `k` (a distant light's direction `D`, every point on its emitting side) and `V_k` that
//! light's visibility image at the pixel,
//!
//! ```text
//! L = A + (1 - A) · (1/K) · Σ_k max(0, n · ω_k) · [P on light k's emitting side] · V_k
//! ```
//!
//! with the ambient term `A` = [`SHADED_AMBIENT`]. `L` is in `[0, 1]`, written as grey
//! (`R = G = B`) after sRGB encoding. A pixel whose ray hits nothing is the flat blue-grey
//! [`SHADED_BACKGROUND`], which no surface colour equals.

use glam::DVec3;
use rayon::prelude::*;

use crate::channels::VisibilityChannels;
use crate::image::{ImageError, io_err};
use crate::image_files::{PngColor, write_png_bytes};
use crate::lights::Light;
use crate::raycast::Rays;
use crate::scene::Scene;
use crate::tracer::TracerGeometry;

/// The ambient term `A` of the shaded preview: the linear value of a surface no light reaches.
pub const SHADED_AMBIENT: f64 = 0.1;

/// The sRGB colour of the shaded preview where the camera ray hits nothing: a blue-grey, never
/// the grey of a surface.
pub const SHADED_BACKGROUND: [u8; 3] = [72, 86, 110];

/// The linear value `L` of a surface point from its lights' terms `(n · ω_k, V_k)`: the ambient
/// [`SHADED_AMBIENT`] plus the rest times the mean over the lights of `max(0, n · ω_k) · V_k`
/// (each clamped to `[0, 1]`). A point of no light is the ambient.
///
/// ```
/// use penumbra_geom::{SHADED_AMBIENT, shaded_value};
/// assert_eq!(shaded_value(&[(1.0, 1.0)]), 1.0);
/// assert_eq!(shaded_value(&[(1.0, 0.0)]), SHADED_AMBIENT);
/// assert!(shaded_value(&[(0.5, 1.0), (0.5, 1.0)]) > shaded_value(&[(0.5, 1.0), (0.5, 0.0)]));
/// ```
pub fn shaded_value(terms: &[(f64, f64)]) -> f64 {
    if terms.is_empty() {
        return SHADED_AMBIENT;
    }
    let sum: f64 = terms
        .iter()
        .map(|&(cos, v)| cos.clamp(0.0, 1.0) * v.clamp(0.0, 1.0))
        .sum();
    SHADED_AMBIENT + (1.0 - SHADED_AMBIENT) * sum / terms.len() as f64
}

/// sRGB encoding of a linear value in `[0, 1]` as a byte.
pub fn srgb_byte(linear: f64) -> u8 {
    let c = linear.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0 + 0.5) as u8
}

/// The shaded preview of a scene: 8-bit sRGB pixels, row by row from the top.
#[derive(Clone, Debug, PartialEq)]
pub struct ShadedImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` RGB triples.
    pub rgb: Vec<[u8; 3]>,
}

impl ShadedImage {
    /// The preview of `scene` from its lights' visibility images `images` (one channel per
    /// light, in the order of [`Scene::channel_names`], of the camera's size), by the formula
    /// of this module. Refused when `images` does not fit the scene.
    pub fn render(scene: &Scene, images: &VisibilityChannels) -> Result<ShadedImage, ImageError> {
        Self::render_reusing(scene, images, &mut None)
    }

    /// [`ShadedImage::render`], taking the ray-casting hierarchy from `kept` where it serves
    /// the scene's triangles, and keeping the one it builds there otherwise
    /// ([`TracerGeometry::reusing`]).
    pub fn render_reusing(
        scene: &Scene,
        images: &VisibilityChannels,
        kept: &mut Option<TracerGeometry>,
    ) -> Result<ShadedImage, ImageError> {
        let lights: Vec<Light> = scene.lights.iter().map(|l| l.light).collect();
        let cam = &scene.camera;
        let (w, h) = (cam.width, cam.height);
        let channels = images.channels();
        if channels.len() != lights.len() {
            return Err(bad_channels(
                "",
                format!(
                    "{} images for a scene of {} lights",
                    channels.len(),
                    lights.len()
                ),
            ));
        }
        if let Some(c) = channels
            .iter()
            .find(|c| (c.image.width, c.image.height) != (w, h))
        {
            return Err(bad_channels(
                &c.name,
                format!(
                    "{}x{} px, not the camera's {w}x{h}",
                    c.image.width, c.image.height
                ),
            ));
        }
        let tracer = TracerGeometry::reusing(scene.triangles(), Rays::Few, kept);
        let mut rgb = vec![SHADED_BACKGROUND; w as usize * h as usize];
        rgb.par_chunks_mut(w.max(1) as usize)
            .enumerate()
            .for_each(|(j, row)| {
                let mut terms = Vec::with_capacity(lights.len());
                for (i, out) in row.iter_mut().enumerate() {
                    let dir = cam.ray_dir(i as u32, j as u32);
                    let Some(p) = tracer.surface_point(cam.eye, dir) else {
                        continue;
                    };
                    let n = facing_normal(tracer.triangles()[p.triangle as usize], dir);
                    terms.clear();
                    for (light, c) in lights.iter().zip(channels) {
                        let (lit, omega) = match light {
                            Light::Rect(l) => (
                                l.is_lit_side(p.position),
                                (l.center - p.position).normalize_or_zero(),
                            ),
                            Light::Distant(l) => (true, l.direction),
                        };
                        let v = if lit {
                            c.image.get(i as u32, j as u32) as f64
                        } else {
                            0.0
                        };
                        terms.push((n.dot(omega), v));
                    }
                    *out = [srgb_byte(shaded_value(&terms)); 3];
                }
            });
        Ok(ShadedImage {
            width: w,
            height: h,
            rgb,
        })
    }

    /// The colour at column `x`, row `y`.
    pub fn get(&self, x: u32, y: u32) -> [u8; 3] {
        self.rgb[y as usize * self.width as usize + x as usize]
    }

    /// Writes the preview as an 8-bit RGB PNG (atomically).
    pub fn write_png(&self, path: &std::path::Path) -> Result<(), ImageError> {
        if self.width == 0 || self.height == 0 {
            return Err(io_err(path, "an image of no pixels"));
        }
        write_png_bytes(
            path,
            self.width,
            self.height,
            PngColor::Rgb,
            self.rgb.as_flattened(),
        )
    }
}

/// The unit geometric normal of a triangle, turned against the ray direction `dir` (towards
/// the camera); zero for a degenerate triangle.
fn facing_normal([a, b, c]: [DVec3; 3], dir: DVec3) -> DVec3 {
    let n = (b - a).cross(c - a).normalize_or_zero();
    if n.dot(dir) > 0.0 { -n } else { n }
}

fn bad_channels(channel: &str, problem: String) -> ImageError {
    ImageError::BadChannels {
        channel: channel.to_string(),
        problem,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Camera;
    use crate::channels::Channel;
    use crate::image::VisibilityImage;
    use crate::light::RectLight;
    use crate::lights::NamedLight;
    use crate::mesh::TriangleMesh;
    use glam::{DMat4, DVec2};

    #[test]
    fn the_formula() {
        // A surface facing a light it sees whole is white; one in shadow, the ambient.
        assert_eq!(shaded_value(&[(1.0, 1.0)]), 1.0);
        assert_eq!(shaded_value(&[(1.0, 0.0)]), SHADED_AMBIENT);
        // The cosine term scales the light; a light behind the surface adds nothing.
        let half = shaded_value(&[(0.5, 1.0)]);
        assert!((half - (SHADED_AMBIENT + (1.0 - SHADED_AMBIENT) * 0.5)).abs() < 1e-12);
        assert_eq!(shaded_value(&[(-0.7, 1.0)]), SHADED_AMBIENT);
        // V in between scales it too.
        assert_eq!(shaded_value(&[(1.0, 0.25)]), shaded_value(&[(0.25, 1.0)]));
        // Of several lights, the mean: two lights never exceed white, and both lighting a
        // point is brighter than one of them.
        assert_eq!(shaded_value(&[(1.0, 1.0), (1.0, 1.0)]), 1.0);
        let one = shaded_value(&[(0.8, 1.0), (0.8, 0.0)]);
        let both = shaded_value(&[(0.8, 1.0), (0.8, 1.0)]);
        assert!(both > one && one > SHADED_AMBIENT);
        assert_eq!(shaded_value(&[]), SHADED_AMBIENT);
    }

    #[test]
    fn srgb_encoding() {
        assert_eq!(srgb_byte(0.0), 0);
        assert_eq!(srgb_byte(1.0), 255);
        assert_eq!(srgb_byte(2.0), 255);
        assert_eq!(srgb_byte(-1.0), 0);
        // Middle grey (linear 0.214) is about half the bytes.
        assert_eq!(srgb_byte(0.2158), 128);
        // The ambient is visibly above black, the background no surface grey.
        assert!(srgb_byte(SHADED_AMBIENT) > 60);
        assert!(SHADED_BACKGROUND[0] != SHADED_BACKGROUND[2]);
    }

    /// A quad at height 1 over a ground plane, under a light at height 4 looking down.
    fn scene(lights: usize) -> Scene {
        let camera = Camera::look_at(
            DVec3::new(0.0, 6.0, 7.0),
            DVec3::ZERO,
            DVec3::Y,
            45.0,
            32,
            24,
        )
        .unwrap();
        let light = RectLight::new(
            DVec3::new(0.0, 4.0, 0.0),
            -DVec3::Y,
            DVec3::X,
            DVec2::splat(1.0),
        )
        .unwrap();
        let quad = TriangleMesh::quad();
        let s = Scene::new(camera)
            .with_light(light)
            .with_mesh("ground", &quad, DMat4::from_scale(DVec3::splat(20.0)))
            .with_mesh("quad", &quad, DMat4::from_translation(DVec3::Y));
        if lights < 2 {
            return s;
        }
        let named = (0..lights)
            .map(|k| NamedLight::new(&format!("l{k}"), light).unwrap())
            .collect();
        s.with_lights(named).unwrap()
    }

    #[test]
    fn lit_shadowed_and_background_pixels() {
        let s = scene(1);
        let (w, h) = (s.camera.width, s.camera.height);
        // V = 1 on the left half, 0 on the right.
        let mut v = VisibilityImage::filled(w, h, 1.0);
        for j in 0..h {
            for i in w / 2..w {
                v.data[(j * w + i) as usize] = 0.0;
            }
        }
        let img = ShadedImage::render(&s, &VisibilityChannels::single(v)).unwrap();
        assert_eq!(
            (img.width, img.height, img.rgb.len()),
            (w, h, (w * h) as usize)
        );
        // The ground below the camera's centre row: lit on the left, ambient on the right.
        let (lit, dark) = (img.get(w / 2 - 3, h - 2), img.get(w / 2 + 3, h - 2));
        assert!(lit[0] > dark[0], "{lit:?} {dark:?}");
        assert_eq!(dark, [srgb_byte(SHADED_AMBIENT); 3]);
        // The sky at the top row is the background.
        assert_eq!(img.get(0, 0), SHADED_BACKGROUND);
    }

    #[test]
    fn images_that_do_not_fit_the_scene_are_refused() {
        let s = scene(1);
        let small = VisibilityChannels::single(VisibilityImage::filled(3, 3, 1.0));
        let e = ShadedImage::render(&s, &small).unwrap_err().to_string();
        assert!(e.contains("not the camera's 32x24"), "{e}");
        let two = scene(2);
        let one = VisibilityChannels::new(vec![Channel {
            name: "a.V".into(),
            image: VisibilityImage::filled(32, 24, 1.0),
        }])
        .unwrap();
        let e = ShadedImage::render(&two, &one).unwrap_err().to_string();
        assert!(e.contains("1 images for a scene of 2 lights"), "{e}");
    }
}
