//! Where the wedges are: a uniform grid over the receivers' box listing the wedges that may
//! hold each point, each binned into the cells its frustum (`wedge_reach.rs`) meets.

use glam::DVec3;

use crate::wedge::Wedge;
use crate::wedge_reach::{WedgeFrustum, padded, wedge_frustum};

/// A uniform grid over the scene's bounding box listing, per cell, the wedges whose bounding
/// box meets it: in every cell, or ([`WedgeGrid::build_for`]) only in the runs of cells that
/// hold given receivers.
pub struct WedgeGrid {
    lo: DVec3,
    cell: DVec3,
    dims: [usize; 3],
    start: Vec<u32>,
    items: Vec<u32>,
    /// Per row of cells along `x` (index `z * dims[1] + y`), the cells `x0..x1` that are
    /// filled; `None` when all are.
    rows: Option<Vec<(u32, u32)>>,
}

/// Upper bound on grid cells: this many cubed.
const GRID_CELLS_PER_AXIS: f64 = 48.0;

/// The cells per axis [`WedgeGrid::build_within`] tries, finest first, until the grid holds few
/// enough entries: each halving of the cells per axis divides the entries by about four.
const COARSER: [f64; 6] = [GRID_CELLS_PER_AXIS, 24.0, 12.0, 6.0, 3.0, 1.0];

/// The cells of the grid over a receivers' box that hold given light-space points, kept per row
/// of cells along `x` as the run from the first to the last: what [`WedgeGrid::build_for`]
/// fills. Points are added one at a time, so that no list of them is kept; two sets of the same
/// box merge.
#[derive(Clone, Debug)]
pub struct ReceiverCells {
    lo: DVec3,
    hi: DVec3,
    cell: DVec3,
    dims: [usize; 3],
    rows: Vec<(u32, u32)>,
    /// The bounding box of the points added, empty (`min > max`) before the first.
    seen: (DVec3, DVec3),
}

/// [`ReceiverCells::tighter`] offers the box of the points seen when it is smaller than the
/// grid's box this many times over (its cells twice as fine on each axis or more).
const TIGHTER_FROM: f64 = 8.0;

impl ReceiverCells {
    /// No cell yet, of the grid over the light-space box `[lo, hi]`.
    pub fn new(lo: DVec3, hi: DVec3) -> Self {
        let (cell, dims) = WedgeGrid::cells(lo, hi, GRID_CELLS_PER_AXIS);
        ReceiverCells {
            lo,
            hi,
            cell,
            dims,
            rows: vec![(u32::MAX, 0); dims[1] * dims[2]],
            seen: (DVec3::INFINITY, DVec3::NEG_INFINITY),
        }
    }

    /// Adds the cell of the light-space point `p` (nothing for a point outside the box).
    pub fn add(&mut self, p: DVec3) {
        if let Some([x, y, z]) = cell_of(self.lo, self.cell, self.dims, p) {
            let r = &mut self.rows[z * self.dims[1] + y];
            *r = (r.0.min(x as u32), r.1.max(x as u32 + 1));
            self.seen = (self.seen.0.min(p), self.seen.1.max(p));
        }
    }

    /// The cells of both (of the same box).
    pub fn merge(mut self, other: ReceiverCells) -> Self {
        for (r, o) in self.rows.iter_mut().zip(&other.rows) {
            *r = (r.0.min(o.0), r.1.max(o.1));
        }
        self.seen = (self.seen.0.min(other.seen.0), self.seen.1.max(other.seen.1));
        self
    }

    /// The box of the points added, padded as [`receiver_box`](crate::receiver_box) pads, when
    /// it is far smaller than the grid's (the camera sees a small part of the receivers: a
    /// ground reaching far beyond the view, or behind the light); `None` otherwise, or without a
    /// point. A grid over it gives every one of those points fewer candidates, in finer cells.
    pub fn tighter(&self) -> Option<(DVec3, DVec3)> {
        let (lo, hi) = self.seen;
        if !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z) {
            return None;
        }
        let (lo, hi) = padded(lo, hi);
        let (lo, hi) = (lo.max(self.lo), hi.min(self.hi));
        let volume = |d: DVec3| d.x * d.y * d.z;
        (volume(hi - lo) * TIGHTER_FROM < volume(self.hi - self.lo)).then_some((lo, hi))
    }
}

impl WedgeGrid {
    /// Bins `wedges` (light space) over the light-space box `[lo, hi]` holding every receiver.
    pub fn build(wedges: &[Wedge], lo: DVec3, hi: DVec3) -> Self {
        Self::build_rows(wedges, Slabs::new(lo, hi, GRID_CELLS_PER_AXIS), None)
    }

    /// [`WedgeGrid::build`] in coarser cells where it would hold more than `max_entries`
    /// entries ([`WedgeGrid::entries`]): its memory stays near `4 max_entries` bytes however
    /// large the wedges (a light larger than the scene), at the cost of more candidates per
    /// point. At its coarsest, about one cell, it holds each wedge that reaches a receiver about
    /// once.
    pub fn build_within(wedges: &[Wedge], lo: DVec3, hi: DVec3, max_entries: u64) -> Self {
        let per_axis = COARSER
            .into_iter()
            .find(|&n| {
                Slabs::new(lo, hi, n).entries(wedges, max_entries.saturating_add(1)) <= max_entries
            })
            .unwrap_or(1.0);
        Self::build_rows(wedges, Slabs::new(lo, hi, per_axis), None)
    }

    /// [`WedgeGrid::build`] filling only, in each row of cells along `x`, the run from the
    /// first to the last cell holding one of the receivers `cells` has seen (a camera's surface
    /// points, which lie on surfaces, not throughout the box): the same candidates, in the same
    /// order, at those points; every wedge elsewhere. Filling every cell spent most of the time
    /// and memory on cells no pixel reads.
    pub fn build_for(wedges: &[Wedge], cells: ReceiverCells) -> Self {
        let slabs = Slabs::new(cells.lo, cells.hi, GRID_CELLS_PER_AXIS);
        Self::build_rows(wedges, slabs, Some(cells.rows))
    }

    /// The cell size and the cells per axis of the grid over `[lo, hi]` of at most about
    /// `per_axis` cubed cells.
    fn cells(lo: DVec3, hi: DVec3, per_axis: f64) -> (DVec3, [usize; 3]) {
        let ext = (hi - lo).max(DVec3::splat(1e-9));
        let k = (per_axis.powi(3) / (ext.x * ext.y * ext.z)).cbrt();
        let dims = [0, 1, 2].map(|a| ((ext[a] * k).ceil() as usize).clamp(1, 256));
        let cell = DVec3::new(
            ext.x / dims[0] as f64,
            ext.y / dims[1] as f64,
            ext.z / dims[2] as f64,
        );
        (cell, dims)
    }

    /// How many (wedge, cell) entries [`WedgeGrid::build`] makes over `[lo, hi]`, counted slab
    /// by slab without filling any: what its time and memory grow with (large lights give
    /// large wedges, each in many cells).
    pub fn entries(wedges: &[Wedge], lo: DVec3, hi: DVec3) -> u64 {
        Self::entries_up_to(wedges, lo, hi, u64::MAX)
    }

    /// [`WedgeGrid::entries`] counted up to `cap`, which it returns once there are that many:
    /// whether a grid is small enough is told without counting a large one through.
    pub fn entries_up_to(wedges: &[Wedge], lo: DVec3, hi: DVec3, cap: u64) -> u64 {
        Slabs::new(lo, hi, GRID_CELLS_PER_AXIS).entries(wedges, cap)
    }

    fn build_rows(wedges: &[Wedge], slabs: Slabs, rows: Option<Vec<(u32, u32)>>) -> Self {
        let (lo, hi) = (slabs.lo, slabs.hi);
        let (cell, dims) = (slabs.cell, slabs.dims);
        // Each wedge goes into the cells its frustum meets: per slab of cells in depth, those
        // under the hull of its sections at the slab's two depths (sections are linear in
        // depth), which for a slanted wedge is far fewer than its bounding box's.
        let frusta: Vec<Option<WedgeFrustum>> =
            wedges.iter().map(|w| wedge_frustum(w, lo, hi)).collect();
        let n = dims[0] * dims[1] * dims[2];
        let flat = |x: usize, y: usize, z: usize| (z * dims[1] + y) * dims[0] + x;
        let each = |f: &WedgeFrustum, out: &mut dyn FnMut(usize)| {
            slabs.each_slab(f, |z, [x0, x1], [y0, y1]| {
                for y in y0..y1 {
                    let (mut x0, mut x1) = (x0, x1);
                    if let Some(rows) = &rows {
                        let (r0, r1) = rows[z * dims[1] + y];
                        (x0, x1) = (x0.max(r0 as usize), x1.min(r1 as usize));
                    }
                    for x in x0..x1 {
                        out(flat(x, y, z));
                    }
                }
            });
        };
        let mut count = vec![0u32; n + 1];
        for f in frusta.iter().flatten() {
            each(f, &mut |c| count[c + 1] += 1);
        }
        for i in 0..n {
            count[i + 1] += count[i];
        }
        let mut fill = count.clone();
        let mut items = vec![0u32; count[n] as usize];
        for (wi, f) in frusta.iter().enumerate() {
            if let Some(f) = f {
                each(f, &mut |c| {
                    items[fill[c] as usize] = wi as u32;
                    fill[c] += 1;
                });
            }
        }
        WedgeGrid {
            lo,
            cell,
            dims,
            start: count,
            items,
            rows,
        }
    }

    /// Candidate wedges for the light-space point `p` (a superset of those containing it), or
    /// `None` when `p` lies outside the grid or in a cell left empty by
    /// [`WedgeGrid::build_for`] (then every wedge is a candidate).
    pub fn candidates(&self, p: DVec3) -> Option<&[u32]> {
        let c = cell_of(self.lo, self.cell, self.dims, p)?;
        if let Some(rows) = &self.rows {
            let (x0, x1) = rows[c[2] * self.dims[1] + c[1]];
            if !(x0 as usize <= c[0] && c[0] < x1 as usize) {
                return None;
            }
        }
        let i = (c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0];
        Some(&self.items[self.start[i] as usize..self.start[i + 1] as usize])
    }
}

/// The grid's cells over `[lo, hi]`, walked a slab of cells in depth at a time.
struct Slabs {
    lo: DVec3,
    hi: DVec3,
    cell: DVec3,
    dims: [usize; 3],
}

impl Slabs {
    fn new(lo: DVec3, hi: DVec3, per_axis: f64) -> Self {
        let (cell, dims) = WedgeGrid::cells(lo, hi, per_axis);
        Slabs { lo, hi, cell, dims }
    }

    /// How many (wedge, cell) entries binning `wedges` into these cells makes, counted up to
    /// `cap`: once there are that many, the rest are not looked at and `cap` is returned.
    fn entries(&self, wedges: &[Wedge], cap: u64) -> u64 {
        let mut n = 0u64;
        for f in wedges
            .iter()
            .filter_map(|w| wedge_frustum(w, self.lo, self.hi))
        {
            self.each_slab(&f, |_, [x0, x1], [y0, y1]| {
                n += ((x1 - x0) * (y1 - y0)) as u64
            });
            if n >= cap {
                return cap;
            }
        }
        n
    }

    /// The cell index on axis `a` of the coordinate `v`, clamped to the grid.
    fn index(&self, v: f64, a: usize) -> usize {
        (((v - self.lo[a]) / self.cell[a]).max(0.0) as usize).min(self.dims[a] - 1)
    }

    /// For each slab `z` the frustum `f` meets, the cells `x0..x1` by `y0..y1` under the hull
    /// of its sections at the slab's two depths (sections are linear in depth).
    fn each_slab(&self, f: &WedgeFrustum, mut out: impl FnMut(usize, [usize; 2], [usize; 2])) {
        let (lo, cell) = (self.lo, self.cell);
        for z in self.index(f.z.0, 2)..=self.index(f.z.1, 2) {
            let za = (lo.z + z as f64 * cell.z).max(f.z.0);
            let zb = (lo.z + (z + 1) as f64 * cell.z).min(f.z.1);
            let (a, b) = (f.section(za), f.section(zb.max(za)));
            let (rlo, rhi) = (a.0.min(b.0), a.1.max(b.1));
            if !(rlo.x <= rhi.x && rlo.y <= rhi.y) {
                continue;
            }
            out(
                z,
                [self.index(rlo.x, 0), self.index(rhi.x, 0) + 1],
                [self.index(rlo.y, 1), self.index(rhi.y, 1) + 1],
            );
        }
    }
}

/// The cell of the grid from `lo` with cells of size `cell`, `dims` per axis, holding the
/// light-space point `p`, or `None` outside the grid.
fn cell_of(lo: DVec3, cell: DVec3, dims: [usize; 3], p: DVec3) -> Option<[usize; 3]> {
    let mut c = [0usize; 3];
    for a in 0..3 {
        let f = (p[a] - lo[a]) / cell[a];
        if !(f >= 0.0 && f < dims[a] as f64 + 1e-9) {
            return None;
        }
        c[a] = (f as usize).min(dims[a] - 1);
    }
    Some(c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wedge_reach::*;
    use penumbra_geom::Rng;

    /// The wedge of the edge `from -> to` of a mesh in front of the light.
    fn wedge(from: DVec3, to: DVec3) -> Wedge {
        Wedge {
            from,
            to,
            multiplicity: 1,
            occluder: 0,
            silhouette_loop: 0,
            unit: 0,
            caster: None,
        }
    }

    #[test]
    fn wedge_frustum_holds_every_point_of_its_wedge_in_the_receivers_box() {
        let mut rng = Rng::new(0x9e3779b97f4a7c15);
        let mut r = || rng.next_f64();
        let (lo, hi) = (DVec3::new(-6.0, -5.0, 0.5), DVec3::new(7.0, 6.0, 9.0));
        let mut frusta = 0;
        for _ in 0..300 {
            let mut point = || DVec3::new(8.0 * r() - 4.0, 8.0 * r() - 4.0, 0.2 + 9.5 * r());
            let (from, to) = (point(), point());
            let w = wedge(from, to);
            let Some(f) = wedge_frustum(&w, lo, hi) else {
                continue;
            };
            let (blo, bhi) = wedge_box(&w, lo, hi).unwrap();
            assert!(f.volume() <= (bhi - blo).element_product() * (1.0 + 1e-9));
            frusta += usize::from(f.near != f.far);
            for _ in 0..200 {
                // A point of the wedge: from a light point through an edge point, beyond it.
                let s = from.lerp(to, r());
                let l = DVec3::new(2.0 * r() - 1.0, 2.0 * r() - 1.0, 0.0);
                let p = s + (s - l) * (4.0 * r() * r());
                let inside = p.cmpge(lo).all() && p.cmple(hi).all();
                if inside && s.z > 0.0 {
                    assert!(f.holds(p, 1e-9), "{p} outside {f:?} (edge {from} {to})");
                }
            }
        }
        assert!(
            frusta > 100,
            "the frustum should usually beat the box: {frusta}"
        );
    }

    #[test]
    fn a_grid_for_receivers_lists_at_them_what_the_whole_grid_does() {
        let mut rng = Rng::new(7);
        let mut r = || rng.next_f64();
        let (lo, hi) = (DVec3::new(-6.0, -5.0, 0.5), DVec3::new(7.0, 6.0, 9.0));
        let wedges: Vec<Wedge> = (0..400)
            .map(|_| {
                let mut point = || DVec3::new(8.0 * r() - 4.0, 8.0 * r() - 4.0, 0.2 + 9.5 * r());
                wedge(point(), point())
            })
            .collect();
        // Receivers on a slanted plane, as a ground seen from a light is.
        let receivers: Vec<DVec3> = (0..2000)
            .map(|_| {
                let (x, y) = (12.0 * r() - 5.5, 10.0 * r() - 4.5);
                DVec3::new(x, y, 4.0 + 0.3 * x - 0.2 * y)
            })
            .collect();
        let whole = WedgeGrid::build(&wedges, lo, hi);
        // Added in two halves and merged, as the renderer's threads do.
        let (first, second) = receivers.split_at(receivers.len() / 3);
        let mut a = ReceiverCells::new(lo, hi);
        first.iter().for_each(|&p| a.add(p));
        let mut b = ReceiverCells::new(lo, hi);
        second.iter().for_each(|&p| b.add(p));
        let some = WedgeGrid::build_for(&wedges, a.merge(b));
        assert!(
            some.items.len() * 4 < whole.items.len(),
            "{} of {}",
            some.items.len(),
            whole.items.len()
        );
        for &p in &receivers {
            assert_eq!(some.candidates(p), whole.candidates(p), "at {p}");
            assert!(some.candidates(p).is_some());
        }
        // Elsewhere: the grid's cell where it was filled, every wedge (None) where not.
        let (mut filled, mut empty) = (0, 0);
        for _ in 0..2000 {
            let p = lo + (hi - lo) * DVec3::new(r(), r(), r());
            match some.candidates(p) {
                Some(c) => {
                    assert_eq!(Some(c), whole.candidates(p));
                    filled += 1;
                }
                None => empty += 1,
            }
        }
        assert!(filled > 0 && empty > 0, "{filled} {empty}");
    }

    #[test]
    fn entries_counts_what_the_whole_grid_holds() {
        let mut rng = Rng::new(0xe27);
        let (lo, hi) = (DVec3::new(-6.0, -5.0, 0.5), DVec3::new(7.0, 6.0, 9.0));
        // Short and long edges, near the light and near the receivers' far depth, and some
        // beyond it (no wedge reaches a receiver).
        let wedges: Vec<Wedge> = (0..400)
            .map(|i| {
                let z = |rng: &mut Rng| rng.range(0.1, if i % 5 == 0 { 12.0 } else { 8.0 });
                let from = DVec3::new(rng.range(-4.0, 4.0), rng.range(-4.0, 4.0), z(&mut rng));
                let reach = if i % 2 == 0 { 0.2 } else { 3.0 };
                let to = from
                    + DVec3::new(
                        rng.range(-reach, reach),
                        rng.range(-reach, reach),
                        rng.range(-reach, reach),
                    );
                wedge(from, to.with_z(to.z.max(0.05)))
            })
            .collect();
        for n in [1, 17, 400] {
            let grid = WedgeGrid::build(&wedges[..n], lo, hi);
            let entries = WedgeGrid::entries(&wedges[..n], lo, hi);
            assert_eq!(entries, grid.items.len() as u64, "{n} wedges");
            // Counted up to a cap: the cap once reached, else the whole count.
            for cap in [1, entries / 2, entries, entries + 1] {
                let capped = WedgeGrid::entries_up_to(&wedges[..n], lo, hi, cap);
                assert_eq!(capped, entries.min(cap), "{n} wedges up to {cap}");
            }
            assert!(
                n < 17 || entries > 10 * n as u64,
                "{entries} entries of {n} wedges"
            );
        }
    }

    #[test]
    fn a_grid_within_a_budget_is_coarser_and_still_lists_every_wedge_holding_a_point() {
        let mut rng = Rng::new(0xb0d6e7);
        let (lo, hi) = (DVec3::new(-6.0, -5.0, 0.5), DVec3::new(7.0, 6.0, 9.0));
        let point = |rng: &mut Rng, z: f64| {
            DVec3::new(
                rng.range(-4.0, 4.0),
                rng.range(-4.0, 4.0),
                rng.range(0.2, z),
            )
        };
        let wedges: Vec<Wedge> = (0..300)
            .map(|_| wedge(point(&mut rng, 4.0), point(&mut rng, 4.0)))
            .collect();
        let finest = WedgeGrid::entries(&wedges, lo, hi);
        let mut last = u64::MAX;
        for max in [u64::MAX, finest / 5, finest / 50, 0] {
            let grid = WedgeGrid::build_within(&wedges, lo, hi, max);
            let held = grid.items.len() as u64;
            // Within the budget, or in the coarsest cells (a few) when none fits it.
            assert!(
                held <= max || grid.start.len() <= 9,
                "{held} entries for {max}"
            );
            assert!(
                held <= last && (max < finest || held == finest),
                "{held} {last}"
            );
            last = held;
            for _ in 0..500 {
                let p = DVec3::new(
                    rng.range(-6.0, 7.0),
                    rng.range(-5.0, 6.0),
                    rng.range(0.5, 9.0),
                );
                let listed = grid.candidates(p).expect("inside the grid");
                for (wi, w) in wedges.iter().enumerate() {
                    if w.contains(p) {
                        assert!(
                            listed.contains(&(wi as u32)),
                            "wedge {wi} at {p}, budget {max}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn a_tighter_box_holds_every_point_and_only_where_it_is_far_smaller() {
        let (lo, hi) = (
            DVec3::new(-100.0, -100.0, 0.0),
            DVec3::new(100.0, 100.0, 200.0),
        );
        let mut cells = ReceiverCells::new(lo, hi);
        assert_eq!(cells.tighter(), None, "no point");
        let mut rng = Rng::new(0x7167);
        let mut points = Vec::new();
        for _ in 0..1000 {
            let p = DVec3::new(
                rng.range(-2.0, 3.0),
                rng.range(1.0, 2.0),
                rng.range(5.0, 9.0),
            );
            cells.add(p);
            points.push(p);
        }
        // A point outside the grid's box is no receiver of it.
        cells.add(DVec3::new(500.0, 0.0, 1.0));
        let (tlo, thi) = cells.tighter().expect("a box far smaller than the grid's");
        assert!(
            points
                .iter()
                .all(|p| p.cmpgt(tlo).all() && p.cmplt(thi).all())
        );
        assert!(
            thi.x < 3.1 && thi.y < 2.1 && thi.z < 9.1 && tlo.x > -2.1,
            "{tlo} {thi}"
        );
        // Points spread over more than an eighth of the box: no tighter one.
        for (a, b) in [(0.0, 0.0), (0.9, 0.9)] {
            cells.add(lo + (hi - lo) * DVec3::new(a, b, a));
        }
        assert_eq!(cells.tighter(), None);
    }
}
