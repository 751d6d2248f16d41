//! The area of a union of convex polygons in the light square, exactly enough for the exact
//! evaluator (`exact_visibility`, whose documentation gives the method): the polygons'
//! edges snap rounded to a grid of spacing 2^-40, a constrained Delaunay triangulation of the
//! fragments, and the covered faces' areas summed.

use std::cmp::Ordering;
use std::collections::{HashMap, HashSet};
use std::hash::{BuildHasherDefault, Hasher};

use glam::DVec2;
use spade::handles::FixedVertexHandle;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

/// Area of the light square `[-1, 1]^2` in light-space units.
pub const LIGHT_SQUARE_AREA: f64 = 4.0;

/// Signed area of the closed polygon `poly` by the shoelace formula,
/// `A = 1/2 * sum_i (x_i * y_{i+1} - x_{i+1} * y_i)`: positive when counter-clockwise.
pub fn polygon_area(poly: &[DVec2]) -> f64 {
    let n = poly.len();
    if n < 3 {
        return 0.0;
    }
    let o = poly[0];
    let mut twice = 0.0;
    for i in 1..n - 1 {
        twice += (poly[i] - o).perp_dot(poly[i + 1] - o);
    }
    0.5 * twice
}

/// A union area and how often the triangulation had to split a constraint after all.
#[derive(Clone, Copy, Debug)]
pub(crate) struct UnionArea {
    pub(crate) area: f64,
    /// Snap-rounded fragments that still crossed an existing constraint and went through
    /// spade's splitting insertion. Zero unless snap rounding broke its guarantee.
    #[cfg_attr(
        not(test),
        allow(dead_code, reason = "read by the tests, which check it stays zero")
    )]
    pub(crate) split_fallbacks: usize,
}

/// [`union_area`] of polygons already clipped and cleaned by [`finish_polygon`].
pub(crate) fn union_area_of_clean(polys: &[Vec<DVec2>]) -> UnionArea {
    let done = |area| UnionArea {
        area,
        split_fallbacks: 0,
    };
    // A polygon that fills the square (up to rounding) leaves nothing to triangulate.
    if polys
        .iter()
        .any(|p| polygon_area(p).abs() >= LIGHT_SQUARE_AREA * (1.0 - 1e-12))
    {
        return done(LIGHT_SQUARE_AREA);
    }
    match polys.len() {
        0 => return done(0.0),
        1 => return done(polygon_area(&polys[0]).abs()),
        _ => {}
    }

    // Polygons on the grid, and their unique undirected edges plus the square's boundary.
    let square = [
        [-GRID_ONE, -GRID_ONE],
        [GRID_ONE, -GRID_ONE],
        [GRID_ONE, GRID_ONE],
        [-GRID_ONE, GRID_ONE],
    ];
    let mut grid_polys: Vec<Vec<GridPoint>> = Vec::with_capacity(polys.len() + 1);
    grid_polys.push(square.to_vec());
    for poly in polys {
        let mut g: Vec<GridPoint> = poly.iter().map(|&v| to_grid(v)).collect();
        g.dedup();
        while g.len() > 1 && g.first() == g.last() {
            g.pop();
        }
        if g.len() >= 3 {
            grid_polys.push(g);
        }
    }
    let mut segment_of: FastMap<[GridPoint; 2], usize> = FastMap::default();
    let mut segments: Vec<[GridPoint; 2]> = Vec::new();
    for poly in &grid_polys {
        for (i, &a) in poly.iter().enumerate() {
            let b = poly[(i + 1) % poly.len()];
            segment_of.entry(ordered(a, b)).or_insert_with(|| {
                segments.push(ordered(a, b));
                segments.len() - 1
            });
        }
    }

    let arrangement = snap_round(&segments);

    // Every hot pixel is a vertex, every fragment between consecutive hot pixels of a route a
    // constraint. Grid points are exact in f64 and fragments do not cross, so the splitting
    // insertion is only a fallback.
    let vertices: Vec<Point2<f64>> = arrangement.hot.iter().map(|&h| from_grid(h)).collect();
    let mut cdt = ConstrainedDelaunayTriangulation::<Point2<f64>>::bulk_load_cdt(vertices, vec![])
        .expect("grid points in [-1, 1] are valid spade input");
    let mut fragments: HashSet<[u32; 2], FastHash> = HashSet::default();
    let mut split_fallbacks = 0;
    for route in &arrangement.routes {
        for w in route.windows(2) {
            let (a, b) = (w[0], w[1]);
            if a == b || !fragments.insert([a.min(b), a.max(b)]) {
                continue;
            }
            let (a, b) = (
                FixedVertexHandle::from_index(a as usize),
                FixedVertexHandle::from_index(b as usize),
            );
            if cdt.try_add_constraint(a, b).is_empty() {
                split_fallbacks += 1;
                cdt.add_constraint_and_split(a, b, |v| v);
            }
        }
    }

    // The snapped polygons: each edge replaced by its route through the hot pixels.
    let snapped: Vec<Vec<GridPoint>> = grid_polys[1..]
        .iter()
        .map(|poly| {
            let mut out: Vec<GridPoint> = Vec::new();
            for (i, &a) in poly.iter().enumerate() {
                let b = poly[(i + 1) % poly.len()];
                let route = &arrangement.routes[segment_of[&ordered(a, b)]];
                let forward = ordered(a, b)[0] == a;
                let mut push = |h: u32| {
                    let p = arrangement.hot[h as usize];
                    if out.last() != Some(&p) {
                        out.push(p);
                    }
                };
                if forward {
                    route.iter().for_each(|&h| push(h));
                } else {
                    route.iter().rev().for_each(|&h| push(h));
                }
            }
            while out.len() > 1 && out.first() == out.last() {
                out.pop();
            }
            out
        })
        .collect();

    let buckets = Buckets::new(&snapped);
    let mut area = 0.0;
    for face in cdt.inner_faces() {
        let [a, b, c] = face.positions().map(|q| DVec2::new(q.x, q.y));
        let face_area = 0.5 * (b - a).perp_dot(c - a);
        if face_area <= 0.0 {
            continue;
        }
        // Three times the centroid, exactly, on the grid.
        let [ga, gb, gc] = [a, b, c].map(to_grid);
        let q3 = [ga[0] + gb[0] + gc[0], ga[1] + gb[1] + gc[1]];
        if buckets
            .candidates(q3)
            .iter()
            .any(|&i| contains_thrice(&snapped[i as usize], q3))
        {
            area += face_area;
        }
    }
    UnionArea {
        area: area.min(LIGHT_SQUARE_AREA),
        split_fallbacks,
    }
}

/// The multiply-rotate hash of rustc's `FxHasher`: the keys here are small integer arrays from
/// one evaluation, not adversarial input, and SipHash cost a tenth of the running time.
#[derive(Clone, Copy, Default)]
struct FxHasher(u64);

impl Hasher for FxHasher {
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0u8; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.write_u64(u64::from_le_bytes(word));
        }
    }

    fn write_u64(&mut self, i: u64) {
        self.0 = (self.0.rotate_left(5) ^ i).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }

    fn write_u32(&mut self, i: u32) {
        self.write_u64(i as u64);
    }

    fn write_usize(&mut self, i: usize) {
        self.write_u64(i as u64);
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

type FastHash = BuildHasherDefault<FxHasher>;
type FastMap<K, V> = HashMap<K, V, FastHash>;

/// A point of the snapping grid: light-space coordinates times `2^GRID_BITS`.
type GridPoint = [i64; 2];

/// Bits of the fixed-point grid. With `|x| <= 2^40`, every orientation and every rounded
/// intersection below is exact in `i128` (the largest product is at most `2^125`).
const GRID_BITS: u32 = 40;

/// The square's half side on the grid.
const GRID_ONE: i64 = 1 << GRID_BITS;

fn to_grid(v: DVec2) -> GridPoint {
    let s = GRID_ONE as f64;
    [(v.x * s).round() as i64, (v.y * s).round() as i64]
}

fn from_grid(p: GridPoint) -> Point2<f64> {
    let s = 1.0 / GRID_ONE as f64;
    Point2::new(p[0] as f64 * s, p[1] as f64 * s)
}

fn ordered(a: GridPoint, b: GridPoint) -> [GridPoint; 2] {
    if a <= b { [a, b] } else { [b, a] }
}

/// `cross(b - a, c - a)`, exactly: positive when `a, b, c` turn counter-clockwise.
fn orient(a: GridPoint, b: GridPoint, c: GridPoint) -> i128 {
    let d = |p: GridPoint, q: GridPoint| [(q[0] - p[0]) as i128, (q[1] - p[1]) as i128];
    let (u, v) = (d(a, b), d(a, c));
    u[0] * v[1] - u[1] * v[0]
}

/// Segments snap-rounded to the grid: the hot pixels and, per segment, the hot pixels it passes
/// through in order from its first end to its second.
struct Arrangement {
    hot: Vec<GridPoint>,
    routes: Vec<Vec<u32>>,
}

/// Snap rounding (Hobby 1999, "Practical segment intersection with finite precision output",
/// CGTA 13(4); Guibas & Marimont 1998): a pixel (the half-open unit square `[c - 1/2,
/// c + 1/2)^2` around a grid point `c`) is hot when it holds an endpoint or a crossing of two
/// segments, and every segment is replaced by the polyline through the centres of the hot
/// pixels it meets, in the order it meets them. The resulting fragments meet only at hot pixel
/// centres, so they can be inserted as constraints without any splitting, and every coordinate
/// the triangulation sees is exact.
///
/// Segments (with distinct ends, on the grid) are bucketed in a uniform grid of cells; crossings
/// are only sought between segments sharing a cell, and hot pixels only in the cells a segment
/// runs through.
fn snap_round(segments: &[[GridPoint; 2]]) -> Arrangement {
    let mut hot_index: FastMap<GridPoint, u32> = FastMap::default();
    let mut hot: Vec<GridPoint> = Vec::new();
    let mut add_hot = |p: GridPoint, hot: &mut Vec<GridPoint>| {
        *hot_index.entry(p).or_insert_with(|| {
            hot.push(p);
            hot.len() as u32 - 1
        })
    };
    for s in segments {
        add_hot(s[0], &mut hot);
        add_hot(s[1], &mut hot);
    }

    let cells = CellGrid::for_count(segments.len());
    let mut seg_cells: Vec<Vec<u32>> = vec![Vec::new(); cells.n * cells.n];
    let mut scratch = Vec::new();
    for (i, s) in segments.iter().enumerate() {
        cells.along_segment(s[0], s[1], &mut scratch);
        for &c in &scratch {
            seg_cells[c].push(i as u32);
        }
    }
    for list in &seg_cells {
        for (k, &i) in list.iter().enumerate() {
            for &j in &list[k + 1..] {
                if let Some(p) = crossing(segments[i as usize], segments[j as usize]) {
                    add_hot(p, &mut hot);
                }
            }
        }
    }

    let mut hot_cells: Vec<Vec<u32>> = vec![Vec::new(); cells.n * cells.n];
    for (h, &p) in hot.iter().enumerate() {
        hot_cells[cells.cell_of(p)].push(h as u32);
    }
    let routes = segments
        .iter()
        .map(|&[a, b]| {
            cells.along_segment(a, b, &mut scratch);
            let mut on: Vec<(Bound, u32)> = scratch
                .iter()
                .flat_map(|&c| hot_cells[c].iter())
                .filter_map(|&h| pixel_entry(a, b, hot[h as usize]).map(|t| (t, h)))
                .collect();
            // A closed bound comes before an open one of equal value.
            on.sort_unstable_by(|x, y| x.0.value_cmp(&y.0).then(x.0.open.cmp(&y.0.open)));
            on.into_iter().map(|(_, h)| h).collect()
        })
        .collect();
    Arrangement { hot, routes }
}

/// The grid point nearest to the proper crossing of segments `s` and `t` (rounding halves up),
/// or `None` when they do not cross properly. Touching and overlapping segments meet at
/// endpoints, which are hot already.
fn crossing(s: [GridPoint; 2], t: [GridPoint; 2]) -> Option<GridPoint> {
    let (a, b, c, d) = (s[0], s[1], t[0], t[1]);
    let (o1, o2) = (orient(a, b, c), orient(a, b, d));
    let (o3, o4) = (orient(c, d, a), orient(c, d, b));
    if !((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) || !((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)) {
        return None;
    }
    // a + (b - a) * num / den with num / den = o3 / (o3 - o4) in (0, 1).
    let (mut num, mut den) = (o3, o3 - o4);
    if den < 0 {
        (num, den) = (-num, -den);
    }
    let round = |from: i64, delta: i64| -> i64 {
        // floor((2 * delta * num + den) / (2 * den)), with |2 * delta * num| <= 2^125.
        let q = (2 * delta as i128 * num + den).div_euclid(2 * den);
        from + q as i64
    };
    Some([round(a[0], b[0] - a[0]), round(a[1], b[1] - a[1])])
}

/// A bound `num / den` (`den > 0`) of an interval of the segment parameter `t`, and whether
/// the bound itself is excluded.
#[derive(Clone, Copy, Debug)]
struct Bound {
    num: i128,
    den: i128,
    open: bool,
}

impl Bound {
    /// Compares the values, exactly (numerators and denominators stay below `2^44`).
    fn value_cmp(&self, other: &Bound) -> Ordering {
        (self.num * other.den).cmp(&(other.num * self.den))
    }
}

/// Where the segment `a + t (b - a)`, `t` in `[0, 1]`, enters the half-open pixel
/// `[c - 1/2, c + 1/2)^2`, or `None` when it misses it. Exact, in doubled coordinates. Half-open
/// pixels partition the plane, so the pixels a segment meets occupy disjoint intervals of `t`
/// and their entry parameters order them along the segment.
fn pixel_entry(a: GridPoint, b: GridPoint, c: GridPoint) -> Option<Bound> {
    let mut lower = Bound {
        num: 0,
        den: 1,
        open: false,
    };
    let mut upper = Bound {
        num: 1,
        den: 1,
        open: false,
    };
    for k in 0..2 {
        let (a2, d2) = (2 * a[k] as i128, 2 * (b[k] - a[k]) as i128);
        let lo = 2 * c[k] as i128 - 1;
        let hi = lo + 2;
        let (l, u) = match d2.cmp(&0) {
            Ordering::Equal if lo <= a2 && a2 < hi => continue,
            Ordering::Equal => return None,
            // lo <= a2 + t d2 < hi.
            Ordering::Greater => (
                Bound {
                    num: lo - a2,
                    den: d2,
                    open: false,
                },
                Bound {
                    num: hi - a2,
                    den: d2,
                    open: true,
                },
            ),
            Ordering::Less => (
                Bound {
                    num: a2 - hi,
                    den: -d2,
                    open: true,
                },
                Bound {
                    num: a2 - lo,
                    den: -d2,
                    open: false,
                },
            ),
        };
        match l.value_cmp(&lower) {
            Ordering::Greater => lower = l,
            Ordering::Equal => lower.open |= l.open,
            Ordering::Less => {}
        }
        match u.value_cmp(&upper) {
            Ordering::Less => upper = u,
            Ordering::Equal => upper.open |= u.open,
            Ordering::Greater => {}
        }
    }
    match lower.value_cmp(&upper) {
        Ordering::Less => Some(lower),
        Ordering::Equal if !lower.open && !upper.open => Some(lower),
        _ => None,
    }
}

/// Even-odd test of the point `q3 / 3` against the closed polyline `poly`, exact: all
/// coordinates are scaled by 3 so the face centroid stays on an integer grid.
fn contains_thrice(poly: &[GridPoint], q3: GridPoint) -> bool {
    let mut inside = false;
    let n = poly.len();
    for i in 0..n {
        let (u, v) = (poly[i], poly[(i + 1) % n]);
        let (u, v) = ([3 * u[0], 3 * u[1]], [3 * v[0], 3 * v[1]]);
        if (u[1] > q3[1]) != (v[1] > q3[1]) && (orient(u, v, q3) > 0) == (v[1] > u[1]) {
            inside = !inside;
        }
    }
    inside
}

/// A uniform grid of `n x n` cells over the square `[-2^40, 2^40]^2` of grid points, `n` a
/// power of two.
struct CellGrid {
    n: usize,
    /// log2 of a cell's side in grid units.
    shift: u32,
}

impl CellGrid {
    /// About one item per cell, at most 256 x 256 cells.
    fn for_count(count: usize) -> Self {
        let n = ((count as f64).sqrt().ceil() as usize)
            .next_power_of_two()
            .clamp(1, 256);
        CellGrid {
            n,
            shift: GRID_BITS + 1 - n.trailing_zeros(),
        }
    }

    fn index(&self, s: i64) -> usize {
        (((s + GRID_ONE).max(0) >> self.shift) as usize).min(self.n - 1)
    }

    fn cell_of(&self, p: GridPoint) -> usize {
        self.index(p[1]) * self.n + self.index(p[0])
    }

    /// Every cell that comes within two grid units of the segment `a-b`, row by row: a superset
    /// of the cells holding the centre of a pixel the segment meets.
    fn along_segment(&self, a: GridPoint, b: GridPoint, out: &mut Vec<usize>) {
        out.clear();
        const MARGIN: i64 = 2;
        let (y_lo, y_hi) = (a[1].min(b[1]) - MARGIN, a[1].max(b[1]) + MARGIN);
        let (x_min, x_max) = (a[0].min(b[0]) - MARGIN, a[0].max(b[0]) + MARGIN);
        // The x-extent of the part of the segment within [y0, y1], up to f64 rounding.
        let x_span = |y0: i64, y1: i64| -> (f64, f64) {
            if a[1] == b[1] {
                return (a[0].min(b[0]) as f64, a[0].max(b[0]) as f64);
            }
            let x_at = |y: i64| {
                let t = ((y - a[1]) as f64 / (b[1] - a[1]) as f64).clamp(0.0, 1.0);
                a[0] as f64 + (b[0] - a[0]) as f64 * t
            };
            let (xa, xb) = (x_at(y0), x_at(y1));
            (xa.min(xb), xa.max(xb))
        };
        for row in self.index(y_lo)..=self.index(y_hi) {
            let row_lo = ((row as i64) << self.shift) - GRID_ONE;
            let row_hi = row_lo + (1 << self.shift);
            // A pixel centred in this row reaches half a unit into its neighbours.
            let (y0, y1) = (y_lo.max(row_lo - MARGIN), y_hi.min(row_hi + MARGIN));
            let (xa, xb) = x_span(y0, y1);
            // The f64 error is far below one grid unit; the margin covers it.
            let lo = ((xa.floor() as i64) - MARGIN).max(x_min);
            let hi = ((xb.ceil() as i64) + MARGIN).min(x_max);
            for col in self.index(lo)..=self.index(hi) {
                out.push(row * self.n + col);
            }
        }
    }
}

/// The snapped polygons whose bounding box meets each cell of a [`CellGrid`].
struct Buckets {
    cells: CellGrid,
    lists: Vec<Vec<u32>>,
}

impl Buckets {
    fn new(polys: &[Vec<GridPoint>]) -> Self {
        let cells = CellGrid::for_count(polys.len());
        let mut lists = vec![Vec::new(); cells.n * cells.n];
        for (i, poly) in polys.iter().enumerate() {
            if poly.is_empty() {
                continue;
            }
            let (mut lo, mut hi) = ([i64::MAX; 2], [i64::MIN; 2]);
            for p in poly {
                for k in 0..2 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
            for row in cells.index(lo[1])..=cells.index(hi[1]) {
                for col in cells.index(lo[0])..=cells.index(hi[0]) {
                    lists[row * cells.n + col].push(i as u32);
                }
            }
        }
        Buckets { cells, lists }
    }

    /// Polygons that may contain the point `q3 / 3`.
    fn candidates(&self, q3: GridPoint) -> &[u32] {
        // floor division keeps the cell consistent with the bounding boxes.
        let q = [q3[0].div_euclid(3), q3[1].div_euclid(3)];
        &self.lists[self.cells.cell_of(q)]
    }
}
