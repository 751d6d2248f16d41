//! A bounding-volume hierarchy over axis-aligned boxes, for the queries that ray casting does
//! not answer: every item near a point, every item that may meet a convex polyhedron.
//!
//! Binary, split at the median of the boxes' centres along their widest axis, four items per
//! leaf at most. Queries are conservative: they report every item whose box meets the query
//! region, and possibly some whose box does not meet it exactly (a box outside a polyhedron but
//! not outside any one of its planes).

use glam::DVec3;

/// A half-space `n . x + d >= 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// Normal (need not be unit).
    pub n: DVec3,
    /// Offset.
    pub d: f64,
}

impl Plane {
    /// Signed value at `p`; non-negative inside.
    pub fn eval(&self, p: DVec3) -> f64 {
        self.n.dot(p) + self.d
    }
}

/// The hierarchy.
#[derive(Clone, Debug, Default)]
pub struct BoxTree {
    nodes: Vec<Node>,
    /// Item indices in leaf order.
    order: Vec<u32>,
}

#[derive(Clone, Copy, Debug)]
struct Node {
    lo: DVec3,
    hi: DVec3,
    /// Leaf: first index into `order`; inner node: index of the first child (the second follows).
    start: u32,
    /// Leaf: number of items; inner node: 0.
    count: u32,
}

/// Most items in a leaf.
const LEAF_ITEMS: usize = 4;

impl BoxTree {
    /// Builds the hierarchy over `boxes` (`(min, max)` each); items are their indices.
    pub fn build(boxes: &[(DVec3, DVec3)]) -> Self {
        let mut order: Vec<u32> = (0..boxes.len() as u32).collect();
        let mut nodes = Vec::with_capacity(2 * boxes.len() / LEAF_ITEMS + 1);
        if boxes.is_empty() {
            return BoxTree { nodes, order };
        }
        let blank = Node {
            lo: DVec3::ZERO,
            hi: DVec3::ZERO,
            start: 0,
            count: 0,
        };
        nodes.push(blank);
        let mut stack = vec![(0usize, 0usize, boxes.len())];
        // A node's items with their keys: the median is selected on this copy, in one run of
        // memory, rather than by reading each compared item's box from the whole array.
        let mut keyed: Vec<(f64, u32)> = Vec::with_capacity(boxes.len());
        while let Some((at, first, len)) = stack.pop() {
            let items = &mut order[first..first + len];
            let mut lo = DVec3::splat(f64::INFINITY);
            let mut hi = DVec3::splat(f64::NEG_INFINITY);
            let (mut clo, mut chi) = (lo, hi);
            for &i in items.iter() {
                let (a, b) = boxes[i as usize];
                lo = lo.min(a);
                hi = hi.max(b);
                clo = clo.min(a + b);
                chi = chi.max(a + b);
            }
            if len <= LEAF_ITEMS {
                nodes[at] = Node {
                    lo,
                    hi,
                    start: first as u32,
                    count: len as u32,
                };
                continue;
            }
            let ext = chi - clo;
            let axis = if ext.x >= ext.y && ext.x >= ext.z {
                0
            } else if ext.y >= ext.z {
                1
            } else {
                2
            };
            keyed.clear();
            keyed.extend(items.iter().map(|&i| {
                let (a, b) = boxes[i as usize];
                (a[axis] + b[axis], i)
            }));
            let mid = len / 2;
            keyed.select_nth_unstable_by(mid, |x, y| x.0.total_cmp(&y.0));
            for (item, &(_, i)) in items.iter_mut().zip(&keyed) {
                *item = i;
            }
            let child = nodes.len();
            nodes.push(blank);
            nodes.push(blank);
            nodes[at] = Node {
                lo,
                hi,
                start: child as u32,
                count: 0,
            };
            stack.push((child, first, mid));
            stack.push((child + 1, first + mid, len - mid));
        }
        BoxTree { nodes, order }
    }

    /// The items in leaf order: reordering one's items by it (item `k` becoming the old item
    /// `order()[k]`) and then calling [`BoxTree::renumber`] puts each leaf's items next to each
    /// other in memory.
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// Makes the tree's items `0, 1, 2, ...` in leaf order, after the caller has reordered its
    /// items by [`BoxTree::order`].
    pub fn renumber(&mut self) {
        for (k, i) in self.order.iter_mut().enumerate() {
            *i = k as u32;
        }
    }

    /// Calls `f` with every item in a leaf whose box no plane of `planes` leaves wholly outside.
    pub fn query_planes(&self, planes: &[Plane], f: &mut impl FnMut(u32)) {
        self.query_planes_while(planes, &mut |i| {
            f(i);
            true
        });
    }

    /// [`BoxTree::query_planes`] until `f` returns `false`; returns whether it never did (every
    /// item was visited).
    pub fn query_planes_while(&self, planes: &[Plane], f: &mut impl FnMut(u32) -> bool) -> bool {
        self.query(
            |lo, hi| {
                !planes.iter().any(|pl| {
                    // The box corner furthest along the plane's normal.
                    let far = DVec3::select(pl.n.cmpge(DVec3::ZERO), hi, lo);
                    pl.n.dot(far) + pl.d < 0.0
                })
            },
            f,
        )
    }

    /// Calls `f` with every item in a leaf whose box meets the box `[lo, hi]`: every item whose
    /// own box meets it, and possibly others of the same leaves.
    pub fn query_box(&self, lo: DVec3, hi: DVec3, f: &mut impl FnMut(u32)) {
        self.query(|a, b| a.cmple(hi).all() && b.cmpge(lo).all(), &mut |i| {
            f(i);
            true
        });
    }

    /// Calls `f` with the items of the leaves whose boxes `meets` accepts, until it returns
    /// `false`; returns whether it never did.
    fn query(&self, meets: impl Fn(DVec3, DVec3) -> bool, f: &mut impl FnMut(u32) -> bool) -> bool {
        if self.nodes.is_empty() {
            return true;
        }
        // The tree is balanced: its depth is about log2(items / 4), far below 64.
        let mut stack = [0u32; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let node = &self.nodes[stack[top] as usize];
            if !meets(node.lo, node.hi) {
                continue;
            }
            if node.count > 0 {
                let s = node.start as usize;
                for &i in &self.order[s..s + node.count as usize] {
                    if !f(i) {
                        return false;
                    }
                }
            } else {
                stack[top] = node.start;
                stack[top + 1] = node.start + 1;
                top += 2;
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Rng;

    #[test]
    fn box_queries_find_every_overlapping_box_and_few_others() {
        let mut rng = Rng::new(42);
        let mut r = || rng.range(-10.0, 10.0);
        let boxes: Vec<(DVec3, DVec3)> = (0..2000)
            .map(|_| {
                let a = DVec3::new(r(), r(), r());
                let d = DVec3::new(r().abs(), r().abs(), r().abs()) * 0.1;
                (a, a + d)
            })
            .collect();
        let tree = BoxTree::build(&boxes);
        let (mut reported, mut meeting) = (0, 0);
        for _ in 0..200 {
            let lo = DVec3::new(r(), r(), r());
            let hi = lo + DVec3::splat(1.5);
            let mut got = vec![false; boxes.len()];
            tree.query_box(lo, hi, &mut |i| {
                assert!(!got[i as usize], "item {i} reported twice");
                got[i as usize] = true;
            });
            for (i, (a, b)) in boxes.iter().enumerate() {
                let meets = a.cmple(hi).all() && b.cmpge(lo).all();
                assert!(
                    !meets || got[i],
                    "box {i} meets the query but was not reported"
                );
                meeting += usize::from(meets);
            }
            reported += got.iter().filter(|&&g| g).count();
        }
        // Leaves of four: a few more than meet, far fewer than all.
        assert!(
            meeting > 0 && reported <= 8 * meeting,
            "{reported} for {meeting}"
        );
    }

    #[test]
    fn plane_queries_never_miss_a_box_inside() {
        let mut rng = Rng::new(7);
        let mut r = || rng.range(-10.0, 10.0);
        let boxes: Vec<(DVec3, DVec3)> = (0..1000)
            .map(|_| {
                let a = DVec3::new(r(), r(), r());
                (a, a + DVec3::splat(0.2))
            })
            .collect();
        let tree = BoxTree::build(&boxes);
        let planes = [
            Plane {
                n: DVec3::new(1.0, 0.5, 0.0),
                d: 1.0,
            },
            Plane {
                n: DVec3::new(-0.3, 1.0, 0.2),
                d: 2.0,
            },
        ];
        let mut got = vec![false; boxes.len()];
        tree.query_planes(&planes, &mut |i| got[i as usize] = true);
        for (i, (a, b)) in boxes.iter().enumerate() {
            let centre = 0.5 * (*a + *b);
            let inside = planes.iter().all(|p| p.n.dot(centre) + p.d >= 0.0);
            assert!(!inside || got[i], "box {i} inside but not reported");
        }
        assert!(got.iter().any(|&g| !g), "some boxes should be culled");
    }

    #[test]
    fn an_empty_tree_reports_nothing() {
        let tree = BoxTree::build(&[]);
        tree.query_box(DVec3::splat(-1.0), DVec3::ONE, &mut |_| {
            panic!("nothing to report")
        });
    }
}
