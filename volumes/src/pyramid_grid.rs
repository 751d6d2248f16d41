//! A grid over the light's view of the receivers, listing in each cell the potential
//! silhouette edges that a receiver there may see between itself and the light: under a small
//! light (the sun) a point reads its few edges in one cell instead of querying the edge
//! hierarchy.
//!
//! Seen from the light's centre (light space's origin), a point `X` in front of the light
//! (`X.z > 0`) lies along `u(X) = X.xy / X.z`, at `w(X) = 1 / X.z`. A point `Q` of the pyramid
//! from a receiver `P` to the light rectangle `[-1, 1]^2` is `(1 - t) P + t L` for a light
//! point `L`, and
//!
//! ```text
//! u(Q) - u(P) = L.xy (P.z - Q.z) / (Q.z P.z),    so    |u(Q) - u(P)|∞ <= w(Q) - w(P)
//! ```
//!
//! A central projection keeps segments, so an edge `a b` in front of the light meets `P`'s
//! pyramid only where `u(P)` lies within `w_e - w(P)` of the box of the segment `u(a) u(b)`, `w_e`
//! the larger of `w(a)` and `w(b)`. The grid's cells cover the receivers' `u`, about four
//! receivers to a cell; each cell keeps the smallest `w` of its receivers (the farthest from the
//! light) and lists every edge whose box lies within `w_e` less that of it. A point reads its
//! own cell: a superset of the edges its pyramid meets, which [`crate::DepthComplexity`]
//! pre-tests and then tests exactly, as it does those a query of the edge hierarchy finds. The
//! same edges change the same counts: the image is the same, bit for bit.
//!
//! Under the sun an edge's reach is the width of the penumbra it casts on the receivers just
//! behind it, and a cell lists a few edges; under a light as large as the scene a cell would
//! list most of them, and the renderer keeps the hierarchy's queries there.

use glam::{DVec2, DVec3};

use crate::candidates::{Candidates, Lanes};
use crate::potential::PotentialEdges;

/// The grid: for each cell, the potential silhouette edges (indices into
/// [`PotentialEdges::edges`]) that a receiver in it may see between itself and the light.
pub(crate) struct PyramidGrid {
    /// `u` of the first cell's low corner.
    origin: DVec2,
    /// Cells per unit of `u`.
    per_unit: f64,
    /// Cells along `x` and `y`.
    size: [usize; 2],
    /// For each cell, row by row, the start of its edges in `edges`; one more at the end.
    starts: Vec<u32>,
    /// The cells' edges, cell after cell, each cell's in increasing order.
    edges: Vec<u32>,
    /// What the pre-test reads of each of `edges`, in their order.
    lanes: Lanes,
}

/// The most cells along a side.
const MOST_CELLS: usize = 1024;

/// The most listings a grid holds, per edge and receiver: beyond it the light is too large for
/// a grid to help (a cell would list most edges), and the renderer queries the hierarchy.
const MOST_LISTED: usize = 16;

/// About this many receivers to a cell.
const RECEIVERS_PER_CELL: f64 = 4.0;

impl PyramidGrid {
    /// The grid of `edges` for the light-space `receivers` (each `z > 0`), the only points it
    /// answers for; `None` where a part of the scene touches or crosses the light's plane (its
    /// `u` is unbounded) or there is no edge or no receiver.
    pub(crate) fn build(edges: &PotentialEdges, receivers: &[DVec3]) -> Option<PyramidGrid> {
        if !edges.crossings.is_empty() {
            return None;
        }
        let mut grid = Self::over(edges.edges.iter().map(|e| (e.a, e.b)), receivers)?;
        for &ei in &grid.edges {
            grid.lanes.push_edge(edges, ei);
        }
        Some(grid)
    }

    /// The grid of the light-space segments `edges` for `receivers`, without the pre-test's
    /// lanes.
    fn over(
        edges: impl ExactSizeIterator<Item = (DVec3, DVec3)>,
        receivers: &[DVec3],
    ) -> Option<PyramidGrid> {
        if edges.len() == 0 || receivers.is_empty() {
            return None;
        }
        let u_of = |p: DVec3| p.truncate() / p.z;
        // The receivers' box in `u`, and the least `w` of any (the farthest from the light).
        let (lo, hi, least_w) = receivers.iter().fold(
            (
                DVec2::splat(f64::INFINITY),
                DVec2::splat(f64::NEG_INFINITY),
                f64::INFINITY,
            ),
            |(lo, hi, w), &p| (lo.min(u_of(p)), hi.max(u_of(p)), w.min(1.0 / p.z)),
        );
        let span = hi - lo;
        if !(span.is_finite() && least_w.is_finite()) {
            return None;
        }
        // Square cells, about `RECEIVERS_PER_CELL` receivers to each were they spread evenly.
        let target = (receivers.len() as f64 / RECEIVERS_PER_CELL).max(1.0);
        let cell = (span.x * span.y / target)
            .sqrt()
            .max(span.max_element() / MOST_CELLS as f64);
        let per_unit = match cell > 0.0 {
            true => 1.0 / cell,
            false => 1.0,
        };
        let size = [
            ((span.x * per_unit).ceil() as usize).clamp(1, MOST_CELLS),
            ((span.y * per_unit).ceil() as usize).clamp(1, MOST_CELLS),
        ];
        let mut grid = PyramidGrid {
            origin: lo,
            per_unit,
            size,
            starts: vec![0; size[0] * size[1] + 1],
            edges: Vec::new(),
            lanes: Lanes::default(),
        };
        // Each cell's smallest `w = 1 / z` among its receivers: the farthest from the light.
        let mut farthest = vec![f64::INFINITY; size[0] * size[1]];
        for &p in receivers {
            let [x, y] = grid.cell_of(u_of(p));
            let w = &mut farthest[y * size[0] + x];
            *w = w.min(1.0 / p.z);
        }
        // (cell, edge) for every cell an edge may reach a receiver of, edges in order.
        let mut listed: Vec<(u32, u32)> = Vec::new();
        let most = MOST_LISTED * (edges.len() + receivers.len());
        for (ei, (a, b)) in edges.enumerate() {
            let near = a.z.min(b.z);
            if !(near > 0.0) {
                return None;
            }
            let (ua, ub) = (u_of(a), u_of(b));
            let (elo, ehi) = (ua.min(ub), ua.max(ub));
            // The edge's largest `w`, at its end nearer the light, and the rounding of `u` and
            // `w`, far below any reach that matters.
            let w = 1.0 / near;
            let slack = 1e-9 * w + 1e-12 * ua.abs().max(ub.abs()).max_element();
            let widest = w - least_w + slack;
            if widest < 0.0 {
                continue;
            }
            let ([x0, y0], [x1, y1]) = (grid.cell_of(elo - widest), grid.cell_of(ehi + widest));
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let c = y * size[0] + x;
                    let reach = w - farthest[c] + slack;
                    if !(reach >= 0.0) {
                        continue;
                    }
                    // The L-infinity distance from the edge's box to the cell's.
                    let clo = lo + DVec2::new(x as f64, y as f64) * cell;
                    // A hair wide of the cell: a receiver at the grid's far side is clamped into it.
                    let gap = (clo - ehi).max(elo - (clo + cell)).max_element() - 1e-6 * cell;
                    if gap <= reach {
                        listed.push((c as u32, ei as u32));
                    }
                }
            }
            if listed.len() > most {
                return None;
            }
        }
        // Counted, then placed in order: each cell's edges in increasing order.
        for &(c, _) in &listed {
            grid.starts[c as usize + 1] += 1;
        }
        for k in 1..grid.starts.len() {
            grid.starts[k] += grid.starts[k - 1];
        }
        let mut next = grid.starts.clone();
        grid.edges = vec![0; listed.len()];
        for (c, ei) in listed {
            let at = &mut next[c as usize];
            grid.edges[*at as usize] = ei;
            *at += 1;
        }
        Some(grid)
    }

    /// The cell that holds `u`, the outermost for a `u` outside the grid.
    fn cell_of(&self, u: DVec2) -> [usize; 2] {
        let at = (u - self.origin) * self.per_unit;
        let clamp = |v: f64, n: usize| v.floor().clamp(0.0, (n - 1) as f64) as usize;
        [clamp(at.x, self.size[0]), clamp(at.y, self.size[1])]
    }

    /// Where in the grid's lists the edges lie, in increasing order, whose reach covers the
    /// cell of the light-space point `p` (`p.z > 0`): every edge that may meet `p`'s pyramid
    /// to the light, and none for a point outside every edge's reach.
    fn near(&self, p: DVec3) -> std::ops::Range<usize> {
        let [x, y] = self.cell_of(p.truncate() / p.z);
        let cell = y * self.size[0] + x;
        self.starts[cell] as usize..self.starts[cell + 1] as usize
    }

    /// How many edges the cell of `p` lists.
    pub(crate) fn count_near(&self, p: DVec3) -> usize {
        self.near(p).len()
    }

    /// Into `candidates`, the edges of `p`'s cell that the pre-test with the pyramid keeps at
    /// `p` (`r2`: `R^2`), every one kept.
    pub(crate) fn candidates(
        &self,
        edges: &PotentialEdges,
        p: DVec3,
        r2: f32,
        candidates: &mut Candidates,
    ) {
        candidates.pretested_from(edges, &self.edges, &self.lanes, self.near(p), p, r2);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::potential::pyramid_planes;
    use penumbra_geom::Rng;

    /// Every segment that meets a receiver's pyramid to the light (found by points along it) is
    /// listed in the receiver's cell, and a cell lists few of the segments.
    #[test]
    fn a_cell_lists_every_edge_its_receivers_pyramids_meet() {
        let mut rng = Rng::new(7);
        let mut r = |lo: f64, hi: f64| rng.range(lo, hi);
        // Light space of a small light: receivers 200 to 300 from it, spread 60 across.
        let receivers: Vec<DVec3> = (0..600)
            .map(|_| DVec3::new(r(-30.0, 30.0), r(-30.0, 30.0), r(200.0, 300.0)))
            .collect();
        let edges: Vec<(DVec3, DVec3)> = (0..1500)
            .map(|_| {
                let a = DVec3::new(r(-32.0, 32.0), r(-32.0, 32.0), r(150.0, 300.0));
                (a, a + DVec3::new(r(-4.0, 4.0), r(-4.0, 4.0), r(-8.0, 8.0)))
            })
            .collect();
        let grid = PyramidGrid::over(edges.iter().copied(), &receivers).unwrap();
        let (mut meeting, mut listed) = (0, 0);
        for &p in &receivers {
            let planes = pyramid_planes(p);
            let cell = &grid.edges[grid.near(p)];
            listed += cell.len();
            for (ei, &(a, b)) in edges.iter().enumerate() {
                let meets = (0..=200).any(|k| {
                    let q = a.lerp(b, k as f64 / 200.0);
                    q.z < p.z && planes.iter().all(|s| s.eval(q) >= 0.0)
                });
                if meets {
                    meeting += 1;
                    assert!(cell.contains(&(ei as u32)), "edge {ei} not listed for {p}");
                }
            }
        }
        // The pyramids are about a fifth of a unit wide where the edges are: some edges meet
        // them, and a cell lists a few times as many, far fewer than all.
        println!("{listed} listed for {meeting} meeting");
        assert!(meeting > 100, "{meeting}");
        assert!(
            listed < 40 * meeting && listed < receivers.len() * edges.len() / 50,
            "{listed} listed for {meeting} meeting"
        );
    }
}
