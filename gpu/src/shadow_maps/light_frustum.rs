//! The light map's frustum of the shadow-map techniques: a perspective from the light's centre
//! along its normal, fitted to the part of the scene that can shadow what the camera sees.

use glam::{DVec2, DVec3};
use penumbra_geom::{Camera, RectLight};

/// The light map's frustum: a perspective from the light's centre along its normal, in light
/// space (world units along the tangent, the bitangent and the normal).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightFrustum {
    /// Smallest slopes (x/z, y/z).
    pub lo: DVec2,
    /// Largest slopes.
    pub hi: DVec2,
    /// Projection near plane: geometry nearer to the light's plane is not in the map.
    pub near: f64,
    /// Nearest light depth of the scene in front of the near plane.
    pub z_min: f64,
    /// Farthest light depth of the scene.
    pub z_max: f64,
}

/// Largest slope of a frustum, |x/z| and |y/z| (about 89.1 degrees off the normal): beyond lies
/// a sliver along the light's plane. A frustum that reaches past [`super::windows::CORE_SLOPE`]
/// is rendered as several maps ([`super::windows`]).
pub const MAX_SLOPE: f64 = 64.0;

/// Light-space coordinates of world point `p`: along the tangent, the bitangent and the normal,
/// in world units.
fn light_coords(light: &RectLight, p: DVec3) -> DVec3 {
    let d = p - light.center;
    DVec3::new(
        d.dot(light.tangent),
        d.dot(light.bitangent),
        d.dot(light.normal),
    )
}

/// `triangles` (world space) in light coordinates.
fn in_light_space(light: &RectLight, triangles: &[[DVec3; 3]]) -> Vec<[DVec3; 3]> {
    triangles
        .iter()
        .map(|t| t.map(|p| light_coords(light, p)))
        .collect()
}

/// Slope bounds of points being gathered.
#[derive(Clone, Copy)]
struct Slopes {
    lo: DVec2,
    hi: DVec2,
}

impl Slopes {
    const EMPTY: Slopes = Slopes {
        lo: DVec2::INFINITY,
        hi: DVec2::NEG_INFINITY,
    };

    /// Takes in light-space point `l` (in front of the light), its slopes capped at
    /// [`MAX_SLOPE`].
    fn add(&mut self, l: DVec3) {
        let s = (l.truncate() / l.z).clamp(DVec2::splat(-MAX_SLOPE), DVec2::splat(MAX_SLOPE));
        self.lo = self.lo.min(s);
        self.hi = self.hi.max(s);
    }

    fn is_empty(&self) -> bool {
        !self.hi.cmpge(self.lo).all()
    }
}

impl LightFrustum {
    /// The frustum that holds every part of `triangles` (world space) at least `near` in front
    /// of the light's plane, `near` being 1e-3 of the scene's depth, slopes capped at
    /// [`MAX_SLOPE`]. `None` when nothing lies in front of the light.
    pub fn fit(light: &RectLight, triangles: &[[DVec3; 3]]) -> Option<LightFrustum> {
        LightFrustum::fit_light_space(&in_light_space(light, triangles))
    }

    /// [`LightFrustum::fit`] of triangles already in light coordinates.
    fn fit_light_space(triangles: &[[DVec3; 3]]) -> Option<LightFrustum> {
        let z_max = triangles
            .iter()
            .flatten()
            .map(|p| p.z)
            .fold(f64::NEG_INFINITY, f64::max);
        if !(z_max > 0.0) {
            return None;
        }
        let near = z_max * 1e-3;
        let mut slopes = Slopes::EMPTY;
        let mut z_min = f64::INFINITY;
        for l in triangles {
            for i in 0..3 {
                let (a, b) = (l[i], l[(i + 1) % 3]);
                if a.z >= near {
                    slopes.add(a);
                    z_min = z_min.min(a.z);
                }
                // Where the edge crosses the near plane.
                if (a.z - near) * (b.z - near) < 0.0 {
                    slopes.add(a + (b - a) * ((near - a.z) / (b.z - a.z)));
                    z_min = z_min.min(near);
                }
            }
        }
        Some(LightFrustum {
            near,
            z_min,
            z_max,
            ..padded(slopes)
        })
    }

    /// [`LightFrustum::fit`] narrowed to the part of the scene that can shadow what the camera
    /// sees, so that the texels are spent there and not on a ground reaching far beyond the
    /// shadows. A receiver outside the map is lit, so the map must hold every visible receiver
    /// that something can shadow, and what can shadow it.
    ///
    /// In light space (slopes `s = xy / z`, light half sides `h`), a point B at depth `d` on the
    /// way from a receiver P at slope `s_P` and depth `z_P` to a point of the light lies at a
    /// slope within `h (1/d - 1/z_P) < h / d` of `s_P`. So:
    /// - the visible receivers are the parts of `triangles` inside the camera's view pyramid:
    ///   slopes `[lo, hi]`, depths up to `z_far`;
    /// - whatever shadows them lies where `lo z - h <= xy <= hi z + h` and `z <= z_far`: each
    ///   triangle is clipped to that region (and to the near plane);
    /// - a triangle shadows only points on the far side of its plane from part of the light,
    ///   so one with no visible receiver there shadows nothing in view and is left out: tested
    ///   against every corner of the visible parts for the largest triangles (a ground under
    ///   everything, for one), against their bounding box in light space for the others;
    /// - each remaining part, of slopes `S` and nearest depth `d`, shadows receivers only within
    ///   `S` widened by `h / d`.
    ///
    /// The frustum holds those parts and their widened reach within the visible slopes, within
    /// the scene's fit. It is the scene's fit where the camera sees nothing of the scene or
    /// nothing in view can be shadowed.
    pub fn fit_view(
        light: &RectLight,
        triangles: &[[DVec3; 3]],
        camera: &Camera,
    ) -> Option<LightFrustum> {
        let triangles = in_light_space(light, triangles);
        let scene = LightFrustum::fit_light_space(&triangles)?;
        let in_front = Plane {
            n: DVec3::Z,
            d: -scene.near,
        };
        let in_view = view_planes(camera).map(|n| Plane::of_world(light, n, camera.eye));
        let mut seen = Slopes::EMPTY;
        let mut z_far = 0.0f64;
        let mut receivers = Receivers::new(&triangles);
        for &t in &triangles {
            let mut part = Polygon::of(t);
            part.clip(&in_view);
            if part.len == 0 {
                continue;
            }
            for &l in part.points() {
                receivers.add(l);
            }
            part.clip(&[in_front]);
            for &l in part.points() {
                seen.add(l);
                z_far = z_far.max(l.z);
            }
        }
        if seen.is_empty() {
            return Some(scene);
        }
        let h = light.half_size();
        let lights = [-1.0, 1.0].map(|u| [-1.0, 1.0].map(|v| DVec3::new(u * h.x, v * h.y, 0.0)));
        let tolerance = 1e-9 * receivers.extent().max(scene.z_max);
        let (lo, hi) = (seen.lo, seen.hi);
        // lo z - h <= xy <= hi z + h, z <= z_far, z >= near.
        let on_the_way = [
            Plane {
                n: DVec3::new(1.0, 0.0, -lo.x),
                d: h.x,
            },
            Plane {
                n: DVec3::new(-1.0, 0.0, hi.x),
                d: h.x,
            },
            Plane {
                n: DVec3::new(0.0, 1.0, -lo.y),
                d: h.y,
            },
            Plane {
                n: DVec3::new(0.0, -1.0, hi.y),
                d: h.y,
            },
            Plane {
                n: DVec3::NEG_Z,
                d: z_far,
            },
            in_front,
        ];
        let mut fit = Slopes::EMPTY;
        for (i, &t) in triangles.iter().enumerate() {
            let normal = (t[1] - t[0]).cross(t[2] - t[0]);
            let side = |p: DVec3| normal.dot(p - t[0]);
            let margin = tolerance * normal.length();
            // The visible receivers' extent along the normal, relative to the plane.
            let (below, above) = receivers.span(i, normal);
            let (below, above) = (below - normal.dot(t[0]), above - normal.dot(t[0]));
            let lit_above = lights.iter().flatten().any(|&q| side(q) > 0.0);
            let lit_below = lights.iter().flatten().any(|&q| side(q) < 0.0);
            if !((lit_above && below < -margin) || (lit_below && above > margin)) {
                continue;
            }
            let mut part = Polygon::of(t);
            part.clip(&on_the_way);
            if part.len == 0 {
                continue;
            }
            let mut s = Slopes::EMPTY;
            let mut d = f64::INFINITY;
            for &l in part.points() {
                s.add(l);
                d = d.min(l.z);
            }
            let reach = h / d;
            fit.lo = fit.lo.min(s.lo.min((s.lo - reach).max(lo)));
            fit.hi = fit.hi.max(s.hi.max((s.hi + reach).min(hi)));
        }
        if fit.is_empty() {
            return Some(scene);
        }
        let fit = padded(Slopes {
            lo: fit.lo.max(scene.lo),
            hi: fit.hi.min(scene.hi),
        });
        Some(LightFrustum {
            lo: fit.lo,
            hi: fit.hi,
            ..scene
        })
    }
}

/// Where the visible receivers lie (light space), for the test of which side of a triangle's
/// plane they reach: exactly, over every corner of the visible parts, for the largest
/// triangles (a ground under everything is one), and by their bounding box for the others. Both
/// are unchanged when the scene and its light move, turn and scale together.
struct Receivers {
    lo: DVec3,
    hi: DVec3,
    /// The largest triangles, their light-space normals and the least and greatest
    /// `normal . p` over the corners seen so far.
    exact: Vec<(usize, DVec3, f64, f64)>,
}

/// How many of the largest triangles are tested against every visible corner.
const EXACT_TRIANGLES: usize = 16;

impl Receivers {
    /// `triangles` in light coordinates.
    fn new(triangles: &[[DVec3; 3]]) -> Receivers {
        let area = |t: &[DVec3; 3]| (t[1] - t[0]).cross(t[2] - t[0]).length_squared();
        let mut order: Vec<usize> = (0..triangles.len()).collect();
        let k = EXACT_TRIANGLES.min(order.len());
        if k > 0 && k < order.len() {
            order.select_nth_unstable_by(k - 1, |&a, &b| {
                area(&triangles[b]).total_cmp(&area(&triangles[a]))
            });
        }
        let exact = order[..k]
            .iter()
            .map(|&i| {
                let t = triangles[i];
                let n = (t[1] - t[0]).cross(t[2] - t[0]);
                (i, n, f64::INFINITY, f64::NEG_INFINITY)
            })
            .collect();
        Receivers {
            lo: DVec3::INFINITY,
            hi: DVec3::NEG_INFINITY,
            exact,
        }
    }

    /// Takes in a corner of a visible part.
    fn add(&mut self, p: DVec3) {
        (self.lo, self.hi) = (self.lo.min(p), self.hi.max(p));
        for (_, n, lo, hi) in &mut self.exact {
            let v = n.dot(p);
            (*lo, *hi) = (lo.min(v), hi.max(v));
        }
    }

    /// The largest side of the corners' bounding box.
    fn extent(&self) -> f64 {
        (self.hi - self.lo).max_element()
    }

    /// The least and greatest `normal . p` over the visible receivers, for triangle `i` of
    /// light-space normal `normal`: exact for the largest triangles, else over the bounding box
    /// (wider).
    fn span(&self, i: usize, normal: DVec3) -> (f64, f64) {
        if let Some(&(_, n, lo, hi)) = self.exact.iter().find(|e| e.0 == i) {
            // The same corners give the same normal.
            debug_assert!((n - normal).length() <= 1e-9 * n.length());
            return (lo, hi);
        }
        let centre = (self.lo + self.hi) * 0.5;
        let reach = normal.abs().dot((self.hi - self.lo) * 0.5);
        let mid = normal.dot(centre);
        (mid - reach, mid + reach)
    }
}

/// A plane of light space: `n . l + d`, at least 0 on the kept side.
#[derive(Clone, Copy)]
struct Plane {
    n: DVec3,
    d: f64,
}

impl Plane {
    /// The plane of world space through `point` with normal `normal`, in light coordinates.
    fn of_world(light: &RectLight, normal: DVec3, point: DVec3) -> Plane {
        Plane {
            n: DVec3::new(
                normal.dot(light.tangent),
                normal.dot(light.bitangent),
                normal.dot(light.normal),
            ),
            d: normal.dot(light.center - point),
        }
    }

    fn at(&self, l: DVec3) -> f64 {
        self.n.dot(l) + self.d
    }
}

/// A convex polygon of at most `MAX_CORNERS` corners: a triangle clipped by at most ten planes
/// gains at most one corner per plane.
struct Polygon {
    corners: [DVec3; MAX_CORNERS],
    len: usize,
}

const MAX_CORNERS: usize = 16;

impl Polygon {
    fn of(t: [DVec3; 3]) -> Polygon {
        let mut corners = [DVec3::ZERO; MAX_CORNERS];
        corners[..3].copy_from_slice(&t);
        Polygon { corners, len: 3 }
    }

    fn points(&self) -> &[DVec3] {
        &self.corners[..self.len]
    }

    /// Keeps the part where every plane is at least 0 (Sutherland and Hodgman).
    fn clip(&mut self, planes: &[Plane]) {
        for plane in planes {
            if self.len == 0 {
                return;
            }
            if self.points().iter().all(|&l| plane.at(l) >= 0.0) {
                continue;
            }
            let mut out = [DVec3::ZERO; MAX_CORNERS];
            let mut n = 0;
            for i in 0..self.len {
                let (a, b) = (self.corners[i], self.corners[(i + 1) % self.len]);
                let (sa, sb) = (plane.at(a), plane.at(b));
                if sa >= 0.0 {
                    out[n] = a;
                    n += 1;
                }
                if (sa >= 0.0) != (sb >= 0.0) {
                    out[n] = a + (b - a) * (sa / (sa - sb));
                    n += 1;
                }
            }
            debug_assert!(n <= MAX_CORNERS);
            (self.corners, self.len) = (out, n);
        }
    }
}

/// `slopes` with half a percent of margin, so that nothing falls on the border texels' far edge.
fn padded(slopes: Slopes) -> LightFrustum {
    let pad = (slopes.hi - slopes.lo).max(DVec2::splat(1e-6)) * 0.005;
    LightFrustum {
        lo: slopes.lo - pad,
        hi: slopes.hi + pad,
        near: 0.0,
        z_min: 0.0,
        z_max: 0.0,
    }
}

/// The camera's view pyramid: the inward normals of its four side planes, which pass through
/// the eye. A point X is in view where `n . (X - eye) >= 0` for all four.
fn view_planes(camera: &Camera) -> [DVec3; 4] {
    let ty = (camera.fov_y_deg.to_radians() * 0.5).tan();
    let tx = ty * camera.width as f64 / camera.height as f64;
    let (f, r, u) = (camera.forward, camera.right, camera.true_up);
    let inward = |a: DVec3, b: DVec3| {
        let n = a.cross(b);
        if n.dot(f) < 0.0 { -n } else { n }
    };
    [
        inward(f + r * tx, u),
        inward(f - r * tx, u),
        inward(f + u * ty, r),
        inward(f - u * ty, r),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn light_frustum_holds_every_point_in_front_of_the_light() {
        let light = RectLight::new(
            DVec3::new(0.0, 5.0, 0.0),
            DVec3::NEG_Y,
            DVec3::X,
            DVec2::new(2.0, 1.0),
        )
        .unwrap();
        let tris = [
            [
                DVec3::new(-3.0, 0.0, -2.0),
                DVec3::new(4.0, 0.0, -2.0),
                DVec3::new(0.0, 0.0, 6.0),
            ],
            // Crosses the light's plane: clipped at the near plane.
            [
                DVec3::new(0.5, 4.0, 0.0),
                DVec3::new(1.0, 6.0, 0.0),
                DVec3::new(0.0, 4.0, 0.5),
            ],
        ];
        let f = LightFrustum::fit(&light, &tris).unwrap();
        assert!((f.z_max - 5.0).abs() < 1e-12);
        assert!(f.near > 0.0 && f.z_min >= f.near * (1.0 - 1e-9) && f.z_min < 1.0 + 1e-9);
        for p in tris.iter().flatten() {
            let l = light_coords(&light, *p);
            if l.z >= f.near {
                let s = l.truncate() / l.z;
                if s.abs().max_element() < MAX_SLOPE {
                    assert!(
                        s.cmpge(f.lo).all() && s.cmple(f.hi).all(),
                        "{p} at slope {s}"
                    );
                }
            }
        }
        assert!(LightFrustum::fit(&light, &[[DVec3::new(0.0, 9.0, 0.0); 3]]).is_none());
    }

    /// On `beetle` (a ground far larger than the view, a light near its plane at the far end)
    /// and `camera-in-shadow`: every visible receiver in shadow of some part of the light, and
    /// every point that shadows it, lies inside the view's frustum; and the view's frustum is
    /// several times narrower than the scene's.
    #[test]
    fn the_view_s_frustum_holds_every_shadowed_receiver_and_its_occluders() {
        use penumbra_geom::Scene;
        use penumbra_geom::SceneBvh;
        for (name, narrower) in [("beetle", 50.0), ("camera-in-shadow", 1.0)] {
            let path = format!(
                "{}/../fixtures/scenes/{name}.toml",
                env!("CARGO_MANIFEST_DIR")
            );
            let scene = Scene::load(std::path::Path::new(&path)).unwrap();
            let tris = scene.triangles();
            let bvh = SceneBvh::build(&tris);
            let light = &scene.lit(0).light;
            let whole = LightFrustum::fit(light, &tris).unwrap();
            let view = LightFrustum::fit_view(light, &tris, &scene.camera).unwrap();
            let area = |f: &LightFrustum| (f.hi - f.lo).x * (f.hi - f.lo).y;
            assert!(
                area(&whole) >= narrower * area(&view),
                "{name}: {whole:?} against {view:?}"
            );
            let inside = |p: DVec3| {
                let l = light_coords(light, p);
                let s = l.truncate() / l.z;
                s.cmpge(view.lo).all() && s.cmple(view.hi).all()
            };
            let cam = &scene.camera;
            let (mut rays, mut occluders) = (0, 0);
            for j in (0..cam.height).step_by(4) {
                for i in (0..cam.width).step_by(4) {
                    let d = cam.ray_dir(i, j);
                    let Some(hit) = bvh.closest_hit(cam.eye, d, 1e30) else {
                        continue;
                    };
                    let p = cam.eye + d * hit.t;
                    for k in 0..25 {
                        let uv = DVec2::new((k % 5) as f64, (k / 5) as f64) / 2.0 - 1.0;
                        let x = light.point(uv);
                        let to = x - p;
                        let len = to.length();
                        let dir = (to / len).as_vec3().into();
                        bvh.for_each_hit(p, dir, 1e-4, len as f32, hit.triangle, |t| {
                            let [a, b, c] = tris[t as usize];
                            let n = (b - a).cross(c - a);
                            let b_point = p + to * (n.dot(a - p) / n.dot(to));
                            assert!(inside(p), "{name}: receiver {p} (pixel {i},{j}) outside");
                            assert!(inside(b_point), "{name}: occluder {b_point} of {p} outside");
                            occluders += 1;
                        });
                        rays += 1;
                    }
                }
            }
            assert!(
                rays > 1000 && occluders > 1000,
                "{name}: {rays} {occluders}"
            );
        }
    }

    /// Moved, turned and scaled with its light, a scene keeps its frustum: the slopes are
    /// those of light space, and neither test of which triangles can shadow the view depends on
    /// the world's axes (a box in world space did: turned, its corners reached under the ground
    /// and took the ground in, widening `overlapping-quads`' frustum twice along each axis).
    #[test]
    fn the_view_s_frustum_moves_with_the_scene() {
        use penumbra_geom::Scene;
        let mut rng = penumbra_geom::Rng::new(5);
        for name in ["overlapping-quads", "beetle"] {
            let path = format!(
                "{}/../fixtures/scenes/{name}.toml",
                env!("CARGO_MANIFEST_DIR")
            );
            let scene = Scene::load(std::path::Path::new(&path)).unwrap();
            let fit =
                |s: &Scene| LightFrustum::fit_view(&s.lit(0).light, &s.triangles(), &s.camera);
            let base = fit(&scene).unwrap();
            for _ in 0..4 {
                let axis = DVec3::new(rng.range(-1., 1.), rng.range(-1., 1.), rng.range(-1., 1.));
                let scale = 10f64.powf(rng.range(-2.0, 2.0));
                let m = glam::DMat4::from_scale_rotation_translation(
                    DVec3::splat(scale),
                    glam::DQuat::from_axis_angle(
                        axis.normalize(),
                        rng.range(0.0, std::f64::consts::TAU),
                    ),
                    DVec3::new(
                        rng.range(-1e3, 1e3),
                        rng.range(-1e3, 1e3),
                        rng.range(-1e3, 1e3),
                    ),
                );
                let moved = fit(&scene.transformed(&m)).unwrap();
                let off = (moved.lo - base.lo).abs().max((moved.hi - base.hi).abs());
                assert!(
                    off.max_element() < 1e-9,
                    "{name}: {base:?} against {moved:?}"
                );
                assert!((moved.z_max / scale - base.z_max).abs() < 1e-9 * base.z_max);
            }
        }
    }
}
