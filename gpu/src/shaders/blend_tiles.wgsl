// Tiled penumbra-wedges blending (`wedges-blend`, Forest, Barthe & Paulin 2006): one compute
// workgroup per screen tile of WEDGE_TILE x WEDGE_TILE pixels, one invocation per pixel, in
// place of a stencil, a wedge and a blend pass per group of silhouettes.
//
// The items come in the blend's order, unit after unit (`blend_units.rs`): the unit's count at
// the eye, the side quads of its shadow volume, then its wedges. The workgroup keeps, a round at
// a time and in order, those that can reach its tile: a count that is not zero, a quad that
// meets the tile's view frustum short of its farthest receiver, a wedge whose solid meets its
// receivers' light-space box (as tiled shading culls lights: Olsson and Assarsson 2011; Harada,
// McKee and Yang 2012). Each pixel then walks them with one unit's state at a time:
//
// - the unit's z-fail count at its receiver P: its count at the eye plus, for each side quad the
//   segment from the eye to P crosses, the quad's multiplicity, positive where the segment
//   enters the volume (the eye on the quad's outer side) and negative where it leaves. The
//   segment from the eye to the point it sees crosses no caster before P, so its caps add
//   nothing: the z-pass count (Heidmann 1991) of the volumes the stencil pass counts by z-fail,
//   computed exactly per pixel instead of rasterised. It is the count just in front of P; where
//   P's own triangle casts for the unit and the eye sees its side away from the light, that
//   point lies behind the triangle, which the count at P itself leaves out (as the CPU oracle
//   counts the casters between P and the light, and the stencil pass's depth test leaves out the
//   cap at P's depth): one less;
// - the silhouette buffer of its wedges, as the rasterised `fs_silhouette` accumulates it (areas
//   in f32, the inner half-wedges' cover rounded to f16 and the rectangles to 8 bits, as their
//   targets store them);
// - when the next unit starts, the unit's silhouette buffer blended into the pixel's final one
//   (`blend_parts.wgsl`), rounded as the final buffer stores it.
//
// Every pixel's final buffer is written once, at the end; the resolve reads it as it reads the
// rasterised passes'.

// The receivers (the depth pre-pass's eye-relative positions, `w` non-zero where hit).
@group(1) @binding(0) var position: texture_2d<f32>;
// The items: (unit, kind | index), kinds in the top two bits (`blend_units::EYE_ITEM`, ...).
@group(1) @binding(3) var<storage, read> items: array<vec2<u32>>;
// Each unit's z-fail count at the eye.
@group(1) @binding(4) var<storage, read> eye_counts: array<i32>;
// The side quads (`blend_units::BlendQuad`): the edge's start `from` (xyz, w the mesh) and end
// `to` (xyz, w the multiplicity), as the mesh's vertex buffer stores them.
struct Quad {
    start: vec4<f32>,
    end: vec4<f32>,
}
@group(1) @binding(5) var<storage, read> quads: array<Quad>;
// The final buffer, `FINAL_WORDS` words per pixel (`final_index`), written whole.
@group(1) @binding(6) var<storage, read_write> final_buffer: array<u32>;
// The receivers' normals (any orientation), and the unit each scene triangle casts for
// (`blend_units::NO_UNIT` for none).
@group(1) @binding(7) var normal: texture_2d<f32>;
@group(1) @binding(8) var<storage, read> triangle_units: array<u32>;

const QUAD_ITEM: u32 = 0x40000000u;
const WEDGE_ITEM: u32 = 0x80000000u;
const KIND: u32 = 0xc0000000u;
const NO_UNIT: u32 = 0xffffffffu;

// The tile's farthest receiver's view depth (clip w), as an `ordered` key, and as read.
var<workgroup> depth_key: atomic<u32>;
var<workgroup> depth_far: f32;

// A quad's corners, eye-relative.
struct Corners {
    a: vec3<f32>,
    b: vec3<f32>,
}

// Quad q's silhouette edge, from and to, eye-relative, placed as the depth pre-pass places the
// mesh's vertices.
fn corners(q: Quad) -> Corners {
    let mesh = u32(q.start.w);
    return Corners(eye_relative(mesh, q.start.xyz).xyz, eye_relative(mesh, q.end.xyz).xyz);
}

// Whether all four of a quad's homogeneous corners (two finite, two at infinity) lie strictly
// outside one half-space g >= 0: then so does the whole quad.
fn outside(g: vec4<f32>) -> bool {
    return g.x < 0.0 && g.y < 0.0 && g.z <= 0.0 && g.w <= 0.0;
}

// Whether the side quad of edge a b (eye-relative; the volume's side beyond it from the light's
// centre c) may meet the segments from the eye to the tile's receivers: not wholly outside one
// side of the tile's frustum, behind the eye or beyond `far` (clip w). `ndc`: the tile's
// rectangle (min x, min y, max x, max y) in normalised device coordinates.
fn quad_meets_tile(k: Corners, ndc: vec4<f32>, far: f32) -> bool {
    let c = frame.light_center.xyz;
    let m = frame.view_proj;
    let pa = m * vec4<f32>(k.a, 1.0);
    let pb = m * vec4<f32>(k.b, 1.0);
    let da = m * vec4<f32>(k.a - c, 0.0);
    let db = m * vec4<f32>(k.b - c, 0.0);
    let x = vec4<f32>(pa.x, pb.x, da.x, db.x);
    let y = vec4<f32>(pa.y, pb.y, da.y, db.y);
    let w = vec4<f32>(pa.w, pb.w, da.w, db.w);
    let finite = vec4<f32>(1.0, 1.0, 0.0, 0.0);
    return !(outside(x - ndc.x * w) || outside(ndc.z * w - x) || outside(y - ndc.y * w)
        || outside(ndc.w * w - y) || outside(w) || outside(far * finite - w));
}

// The change in a unit's z-fail count across its side quad of edge a b (`from`, `to`; `m`
// times) along the segment from the eye (the origin) to the receiver p: 0 where the segment
// does not cross it. The quad is the part of the plane through c, a and b beyond the edge from
// c. The segment's line meets it where the line passes the same way around c a, around the
// cone's far side and around b c, and the other way around a b; each turn is the sign of
// p . (x × y), computed for the rays c a and b c exactly as the neighbouring quads compute them
// (the cross product is antisymmetric in f32 too), so that a segment through a shared ray is
// counted by one quad or none, never two.
fn side_crossing(k: Corners, p: vec3<f32>, m: f32) -> f32 {
    let c = frame.light_center.xyz;
    let a = k.a;
    let b = k.b;
    // The side `to, from, from∞`: its outer normal.
    let n = cross(a - b, a - c);
    let at_eye = -dot(n, b);
    let at_p = dot(n, p - b);
    if (!(at_eye * at_p < 0.0)) {
        return 0.0;
    }
    let ca = dot(p, cross(c, a));
    let bc = dot(p, cross(b, c));
    let cone = dot(p, cross(a - c, b - c));
    let ab = dot(p, cross(a, b));
    let ahead = ca > 0.0 && bc > 0.0 && cone > 0.0 && ab < 0.0;
    let behind = ca < 0.0 && bc < 0.0 && cone < 0.0 && ab > 0.0;
    if (!(ahead || behind)) {
        return 0.0;
    }
    return select(-m, m, at_eye > 0.0);
}

// One unit's silhouette buffer at a pixel, as `fs_silhouette` adds it up.
struct Silhouette {
    count: f32,
    area: vec4<f32>,
    cover: vec4<f32>,
    rect0: vec4<f32>,
    rect1: vec4<f32>,
    rect2: vec4<f32>,
    rect3: vec4<f32>,
}

fn empty_silhouette() -> Silhouette {
    return Silhouette(0.0, vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(1.0), vec4<f32>(1.0),
        vec4<f32>(1.0), vec4<f32>(1.0));
}

// A value as an 8-bit unorm target stores it, and as an f16 one does.
fn unorm8(v: vec4<f32>) -> vec4<f32> {
    return unpack4x8unorm(pack4x8unorm(v));
}

fn half(v: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(unpack2x16float(pack2x16float(v.xy)), unpack2x16float(pack2x16float(v.zw)));
}

// The pixel's final buffer: occluded area per part and encoded rectangles, as stored.
struct Final {
    area: vec4<f32>,
    rect0: vec4<f32>,
    rect1: vec4<f32>,
    rect2: vec4<f32>,
    rect3: vec4<f32>,
}

// `s` blended into `f`, as `blend.wgsl` blends a silhouette buffer into the final buffer.
fn blend_into(f: Final, s: Silhouette) -> Final {
    // A negative count (rasterisation's, at a caster's outline) is none (`casters`).
    let n = max(s.count, 0.0);
    let s_areas = clamp(vec4<f32>(n) + s.area, vec4<f32>(0.0), vec4<f32>(1.0));
    var out = f;
    for (var k = 0u; k < 4u; k++) {
        if (s_areas[k] <= 0.0) {
            continue;
        }
        let e = select(select(select(s.rect3, s.rect2, k == 2u), s.rect1, k == 1u), s.rect0, k == 0u);
        let r = select(select(select(f.rect3, f.rect2, k == 2u), f.rect1, k == 1u), f.rect0, k == 0u);
        let part = blend_part(k, n, s_areas[k], s.cover[k], e, f.area[k], r);
        out.area[k] = part.area;
        let stored = unorm8(part.rect);
        switch k {
            case 0u: { out.rect0 = stored; }
            case 1u: { out.rect1 = stored; }
            case 2u: { out.rect2 = stored; }
            default: { out.rect3 = stored; }
        }
    }
    out.area = vec4<f32>(unpack2x16unorm(pack2x16unorm(out.area.xy)),
        unpack2x16unorm(pack2x16unorm(out.area.zw)));
    return out;
}

@compute @workgroup_size(WEDGE_TILE, WEDGE_TILE)
fn tile(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let pixel = group.xy * WEDGE_TILE + lid.xy;
    let inside = all(vec2<f32>(pixel) < frame.size.xy);
    if (local == 0u) {
        atomicStore(&depth_key, 0u);
    }
    var rel = vec3<f32>(0.0);
    var p = vec3<f32>(0.0);
    var has = false;
    // The unit P's triangle casts for, where the eye sees its side away from the light.
    var own = NO_UNIT;
    if (inside) {
        let hit = textureLoad(position, vec2<i32>(pixel), 0);
        if (hit.w != 0.0) {
            rel = hit.xyz;
            p = to_light(rel);
            has = true;
            let n = textureLoad(normal, vec2<i32>(pixel), 0).xyz;
            let away = dot(n, -rel) * dot(n, frame.light_center.xyz - rel) < 0.0;
            let t = bitcast<u32>(hit.w) - TRIANGLE_BIAS;
            if (away && t < arrayLength(&triangle_units)) {
                own = triangle_units[t];
            }
        }
    }
    let any = receivers_box(local, has, p);
    if (has) {
        atomicMax(&depth_key, ordered((frame.view_proj * vec4<f32>(rel, 1.0)).w));
    }
    let lo = tile_box[0];
    let hi = tile_box[1];
    workgroupBarrier();
    if (local == 0u) {
        depth_far = unordered(atomicLoad(&depth_key));
    }
    let far = workgroupUniformLoad(&depth_far) * 1.001 + 1e-6;
    // The tile's pixels in normalised device coordinates, a pixel wider on each side.
    let size = frame.size.xy;
    let x0 = vec2<f32>(group.xy * WEDGE_TILE) - 1.0;
    let x1 = vec2<f32>(group.xy * WEDGE_TILE + WEDGE_TILE) + 1.0;
    let ndc = vec4<f32>(2.0 * x0.x / size.x - 1.0, 1.0 - 2.0 * x1.y / size.y,
        2.0 * x1.x / size.x - 1.0, 1.0 - 2.0 * x0.y / size.y);
    var f = Final(vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0));
    var s = empty_silhouette();
    var unit = NO_UNIT;
    let n = select(0u, arrayLength(&items), any);
    for (var first = 0u; first < n; first += ROUND) {
        // This invocation's run of items, in order, tested against the tile.
        let start = first + local * PER_INVOCATION;
        var keep = 0u;
        var kept_here = 0u;
        for (var j = 0u; j < PER_INVOCATION; j++) {
            if (start + j >= n) {
                break;
            }
            let item = items[start + j];
            let index = item.y & ~KIND;
            var meets = false;
            switch item.y & KIND {
                case 0u: { meets = eye_counts[item.x] != 0; }
                case QUAD_ITEM: { meets = quad_meets_tile(corners(quads[index]), ndc, far); }
                default: { meets = meets_box(solid_of(index), lo, hi); }
            }
            if (meets) {
                keep |= 1u << j;
                kept_here++;
            }
        }
        let count = keep_in_order(local, start, keep, kept_here);
        for (var k = 0u; k < count; k++) {
            let item = items[kept[k]];
            if (item.x != unit) {
                if (unit != NO_UNIT) {
                    f = blend_into(f, s);
                }
                unit = item.x;
                s = empty_silhouette();
                s.count = select(0.0, -1.0, unit == own);
            }
            if (!has) {
                continue;
            }
            let index = item.y & ~KIND;
            switch item.y & KIND {
                case 0u: { s.count += f32(eye_counts[unit]); }
                case QUAD_ITEM: {
                    let q = quads[index];
                    s.count += side_crossing(corners(q), rel, q.end.w);
                }
                default: {
                    let solid = solid_of(index);
                    if (holds(solid, p)) {
                        let w = tile_wedge(index);
                        let hard = s.count > 0.0;
                        let e = integral(w.edge_from, w.edge_to, w.caster, p, select(RECTS_OUTER, RECTS_INNER, hard));
                        if (e.valid) {
                            s.area += e.area * e.sign;
                            s.cover = half(s.cover + e.cover);
                            s.rect0 = min(s.rect0, unorm8(encode_rect(e.rect0, 0u)));
                            s.rect1 = min(s.rect1, unorm8(encode_rect(e.rect1, 1u)));
                            s.rect2 = min(s.rect2, unorm8(encode_rect(e.rect2, 2u)));
                            s.rect3 = min(s.rect3, unorm8(encode_rect(e.rect3, 3u)));
                        }
                    }
                }
            }
        }
        workgroupBarrier();
    }
    if (unit != NO_UNIT) {
        f = blend_into(f, s);
    }
    if (inside) {
        let i = final_index(pixel);
        final_buffer[i] = pack2x16unorm(f.area.xy);
        final_buffer[i + 1u] = pack2x16unorm(f.area.zw);
        final_buffer[i + 2u] = pack4x8unorm(f.rect0);
        final_buffer[i + 3u] = pack4x8unorm(f.rect1);
        final_buffer[i + 4u] = pack4x8unorm(f.rect2);
        final_buffer[i + 5u] = pack4x8unorm(f.rect3);
    }
}
