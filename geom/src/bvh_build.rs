//! A top-down binned-SAH builder for obvhs' binary BVH ([`Bvh2`]), whose set-up time is
//! O(N log N) on any input.
//!
//! obvhs' own builder, PLOC, merges only mutual nearest neighbours along the Morton order in each
//! pass. When those merge costs are tied (many identical boxes: coincident faces given as separate
//! meshes) or monotone (nested slivers: a large convex polygon fan-triangulated from one vertex),
//! about one pair merges per pass, and the build takes O(N²): 50,000 slivers took 19 s. A top-down
//! build splits every node in time linear in its size, so each level of the tree costs O(N); the
//! depth stays O(log N) because binned SAH is used only for the top `SAH_DEPTH` (48) levels (it may
//! peel off one primitive at a time on adversarial inputs) and object-median splits, which halve
//! the set, take over below that or wherever the centroids coincide.
//!
//! The result has one primitive per leaf and siblings stored next to each other, as PLOC's has,
//! so obvhs' reinsertion optimizer and its conversion to a compressed wide BVH apply unchanged.

use glam::Vec3A;
use obvhs::{
    aabb::Aabb,
    bvh2::{Bvh2, DEFAULT_MAX_STACK_DEPTH, node::Bvh2Node},
};

/// Bins per axis of the SAH split search.
const BINS: usize = 32;

/// Nodes of this many items or more are partitioned by one coordinate ([`first_of_bin`]), which
/// costs some thirty bins to find, rather than by each item's bin.
const SPLIT_BY_COORDINATE_FROM: usize = 128;

/// Levels below which only object-median splits are made. Ordinary meshes rarely need SAH splits
/// this deep; the bound keeps the whole tree within `SAH_DEPTH + log2 N` levels, which both caps
/// the build at O(N log N) and keeps the wide BVH's depth well inside obvhs' fixed traversal
/// stack of 32 node groups.
const SAH_DEPTH: usize = 48;

/// A node still to be built by [`build_serial`]: the primitives `items[start..end]` of its
/// subtree, to be stored at index `node` of the whole array.
struct Task {
    node: usize,
    start: usize,
    end: usize,
    depth: usize,
}

/// A primitive as the build moves it: its box next to its index, so that every pass over a
/// node's primitives reads one contiguous run of memory rather than gathering from the whole
/// scene's arrays. Its centroid is computed where needed, the same `f32` values every time.
#[derive(Clone, Copy)]
struct Item {
    bounds: Aabb,
    index: u32,
}

/// Subtrees of this many primitives or more build their two halves on two threads. The tree
/// is the same on any number of threads: each node's split depends only on its primitives, and
/// each subtree's nodes have their place in the array before it is built ([`build_subtree`]).
const PARALLEL_FROM: usize = 4096;

/// Builds a binary BVH over `boxes` (primitive `i` has the `i`-th box): one primitive per leaf,
/// the root at index 0, both children of an inner node adjacent and after their parent.
pub fn build_bvh2(boxes: impl IntoIterator<Item = Aabb>) -> Bvh2 {
    build_bvh2_from(boxes, PARALLEL_FROM)
}

/// [`build_bvh2`], splitting subtrees of `parallel_from` primitives or more over threads.
fn build_bvh2_from(boxes: impl IntoIterator<Item = Aabb>, parallel_from: usize) -> Bvh2 {
    let mut items: Vec<Item> = boxes
        .into_iter()
        .zip(0u32..)
        .map(|(bounds, index)| Item { bounds, index })
        .collect();
    let n = items.len();
    if n == 0 {
        return Bvh2::default();
    }
    let mut nodes = vec![Bvh2Node::default(); 2 * n - 1];
    let (root, below) = nodes.split_first_mut().expect("n > 0");
    let max_depth = build_subtree(
        Subtree {
            items: &mut items,
            first_item: 0,
            node: root,
            below,
            first_below: 1,
            depth: 0,
        },
        parallel_from,
    );
    Bvh2 {
        nodes,
        primitive_indices: items.iter().map(|i| i.index).collect(),
        children_are_ordered_after_parents: true,
        max_depth: DEFAULT_MAX_STACK_DEPTH.max(max_depth + 1),
        ..Bvh2::default()
    }
}

/// A subtree to build: its primitives `items` (at `first_item` in the whole list), its root
/// `node` and the `2 n - 2` nodes below it, `below`, which are the array's from `first_below`.
///
/// Nodes are placed depth first, a node's two children side by side: below a node come its
/// children, then everything below the first child (`2 n_left - 2` nodes), then everything
/// below the second. So once a node is split, where each part of its subtree goes is known.
struct Subtree<'a> {
    items: &'a mut [Item],
    first_item: usize,
    node: &'a mut Bvh2Node,
    below: &'a mut [Bvh2Node],
    first_below: usize,
    depth: usize,
}

/// The split of a node of `depth`: binned SAH near the top, else (or without one) the median.
fn split(items: &mut [Item], centres: &Aabb, depth: usize, bins: &mut [[Bin; BINS]; 3]) -> usize {
    let sah = if depth < SAH_DEPTH {
        sah_split(items, centres, bins)
    } else {
        None
    };
    sah.unwrap_or_else(|| median_split(items, centres))
}

/// Builds `t`, the halves of subtrees of `parallel_from` primitives or more on two threads;
/// returns its depth below the tree's root.
fn build_subtree(t: Subtree, parallel_from: usize) -> usize {
    if t.items.len() < parallel_from {
        return build_serial(t);
    }
    let (bounds, centres) = bounds_of(t.items);
    let mid = split(
        t.items,
        &centres,
        t.depth,
        &mut [[(Aabb::empty(), 0u32); BINS]; 3],
    );
    *t.node = Bvh2Node::new(bounds, 0, t.first_below as u32);
    let (pair, rest) = t.below.split_at_mut(2);
    let (left_node, right_node) = pair.split_at_mut(1);
    let (left_below, right_below) = rest.split_at_mut(2 * mid - 2);
    let (left_items, right_items) = t.items.split_at_mut(mid);
    let (left, right) = rayon::join(
        || {
            build_subtree(
                Subtree {
                    items: left_items,
                    first_item: t.first_item,
                    node: &mut left_node[0],
                    below: left_below,
                    first_below: t.first_below + 2,
                    depth: t.depth + 1,
                },
                parallel_from,
            )
        },
        || {
            build_subtree(
                Subtree {
                    items: right_items,
                    first_item: t.first_item + mid,
                    node: &mut right_node[0],
                    below: right_below,
                    first_below: t.first_below + 2 * mid,
                    depth: t.depth + 1,
                },
                parallel_from,
            )
        },
    );
    left.max(right)
}

/// Builds `t` on this thread, a node at a time from a stack; returns its depth below the
/// tree's root.
fn build_serial(t: Subtree) -> usize {
    // The root's index, not in `below`: one before the first of those.
    let root = t.first_below - 1;
    let (node, below) = (t.node, t.below);
    let mut stack = vec![Task {
        node: root,
        start: 0,
        end: t.items.len(),
        depth: t.depth,
    }];
    let mut next = t.first_below;
    let mut max_depth = t.depth;
    let mut bins = [[(Aabb::empty(), 0u32); BINS]; 3];
    while let Some(task) = stack.pop() {
        max_depth = max_depth.max(task.depth);
        let items = &mut t.items[task.start..task.end];
        let (bounds, centres) = bounds_of(items);
        let built = if items.len() == 1 {
            Bvh2Node::new(bounds, 1, (t.first_item + task.start) as u32)
        } else {
            let mid = split(items, &centres, task.depth, &mut bins);
            let left = next;
            next += 2;
            stack.push(Task {
                node: left + 1,
                start: task.start + mid,
                end: task.end,
                depth: task.depth + 1,
            });
            stack.push(Task {
                node: left,
                start: task.start,
                end: task.start + mid,
                depth: task.depth + 1,
            });
            Bvh2Node::new(bounds, 0, left as u32)
        };
        if task.node == root {
            *node = built;
        } else {
            below[task.node - t.first_below] = built;
        }
    }
    max_depth
}

/// The union of the items' boxes and the bounds of their centroids.
fn bounds_of(items: &[Item]) -> (Aabb, Aabb) {
    let mut bounds = Aabb::empty();
    let mut centres = Aabb::empty();
    for item in items {
        bounds = bounds.union(&item.bounds);
        centres.extend(item.bounds.center());
    }
    (bounds, centres)
}

/// A bin of the SAH sweep: the union of its items' boxes, and their number.
type Bin = (Aabb, u32);

/// Bin of centroid coordinate `c` on an axis starting at `lo`, `scale` bins per unit, of `bins`.
#[inline]
fn bin_of(c: f32, lo: f32, scale: f32, bins: usize) -> usize {
    // Through `i32`, whose conversion is one instruction (`usize`'s takes several): `c >= lo`
    // and the product is at most about `bins`, so the two agree.
    (((c - lo) * scale) as i32).clamp(0, bins as i32 - 1) as usize
}

/// [`bin_of`] on the three axes at once, in a quarter of the instructions: clamped before the
/// conversion rather than after, which gives the same bins (both truncate towards zero, and the
/// clamp's ends are whole numbers).
#[inline]
fn bins_of(c: Vec3A, lo: Vec3A, scale: Vec3A, bins: usize) -> glam::IVec3 {
    ((c - lo) * scale)
        .max(Vec3A::ZERO)
        .min(Vec3A::splat((bins - 1) as f32))
        .as_ivec3()
}

/// The least `f32` in `[lo, hi]` whose [`bin_of`] (on the axis from `lo`) is `split` or more,
/// where `lo`'s bin is less and `hi`'s is not: as a bin only grows with the coordinate (each
/// rounded step is monotone), a centroid goes left of the split exactly when it is less than
/// this, one comparison instead of a bin per item. Found by bisecting the floats between.
fn first_of_bin(lo: f32, hi: f32, scale: f32, bins: usize, split: usize) -> f32 {
    let (mut below, mut at) = (ordered(lo), ordered(hi));
    while at - below > 1 {
        let mid = below + (at - below) / 2;
        if bin_of(unordered(mid), lo, scale, bins) >= split {
            at = mid;
        } else {
            below = mid;
        }
    }
    unordered(at)
}

/// The floats (but NaN) in their order as integers: the negative ones reversed, below the
/// positive ones.
fn ordered(x: f32) -> u32 {
    let u = x.to_bits();
    if u >> 31 == 1 { !u } else { u | 0x8000_0000 }
}

/// The float of [`ordered`] value `k`.
fn unordered(k: u32) -> f32 {
    f32::from_bits(if k >> 31 == 1 { k & 0x7fff_ffff } else { !k })
}

/// The binned split of least surface-area cost over the three axes, applied to `items`
/// (partitioned in place); the size of the left part, or `None` when the centroids coincide on
/// every axis.
fn sah_split(items: &mut [Item], centres: &Aabb, bins: &mut [[Bin; BINS]; 3]) -> Option<usize> {
    let extent = centres.diagonal();
    // No more bins than items: most nodes are small, and sweeping 32 bins for 2 items made the
    // sweeps cost more than the binning.
    let n_bins = items.len().min(BINS);
    let spread: [bool; 3] = std::array::from_fn(|axis| extent[axis] > 0.0);
    if spread == [false; 3] {
        // Coincident centroids: no split on any axis, as the sweep below would find.
        return None;
    }
    let scale: [f32; 3] = std::array::from_fn(|axis| n_bins as f32 / extent[axis]);
    // The three axes' bins in one pass over the items; only the `n_bins` in use are cleared
    // (clearing all of them cost more than binning the many small nodes).
    for axis_bins in bins.iter_mut() {
        axis_bins[..n_bins].fill((Aabb::empty(), 0));
    }
    let scale3 = Vec3A::from(scale);
    for item in items.iter() {
        let at = bins_of(item.bounds.center(), centres.min, scale3, n_bins);
        for axis in 0..3 {
            if spread[axis] {
                let bin = &mut bins[axis][at[axis] as usize];
                bin.0 = bin.0.union(&item.bounds);
                bin.1 += 1;
            }
        }
    }
    // (cost, axis, first bin of the right part)
    let mut best: Option<(f32, usize, usize)> = None;
    for axis in 0..3 {
        if !spread[axis] {
            continue;
        }
        let bins = &bins[axis][..n_bins];
        // Cost of the right part when it starts at bin k (infinite when empty).
        let mut right_cost = [f32::INFINITY; BINS];
        let (mut acc, mut count) = (Aabb::empty(), 0u32);
        for k in (1..n_bins).rev() {
            acc = acc.union(&bins[k].0);
            count += bins[k].1;
            if count > 0 {
                right_cost[k] = acc.half_area() * count as f32;
            }
        }
        let (mut acc, mut count) = (Aabb::empty(), 0u32);
        for k in 0..n_bins - 1 {
            acc = acc.union(&bins[k].0);
            count += bins[k].1;
            if count == 0 || count as usize == items.len() {
                continue;
            }
            let cost = acc.half_area() * count as f32 + right_cost[k + 1];
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, k + 1));
            }
        }
    }
    let (_, axis, split) = best?;
    // For a large node, the least coordinate of the right part, found once, instead of each
    // item's bin.
    let first = (items.len() >= SPLIT_BY_COORDINATE_FROM).then(|| {
        first_of_bin(
            centres.min[axis],
            centres.max[axis],
            scale[axis],
            n_bins,
            split,
        )
    });
    let goes_left = |item: &Item| {
        let c = item.bounds.center_axis(axis);
        match first {
            Some(first) => c < first,
            None => bin_of(c, centres.min[axis], scale[axis], n_bins) < split,
        }
    };
    // In-place two-way partition.
    let (mut lo, mut hi) = (0, items.len());
    while lo < hi {
        if goes_left(&items[lo]) {
            lo += 1;
        } else {
            hi -= 1;
            items.swap(lo, hi);
        }
    }
    // Both parts are non-empty: the sweep only accepts splits with items on either side.
    debug_assert!(lo > 0 && lo < items.len());
    Some(lo)
}

/// Splits `items` in half at the median centroid along the axis of their widest centroid spread
/// (or as they stand when the centroids coincide); the size of the left part.
fn median_split(items: &mut [Item], centres: &Aabb) -> usize {
    let mid = items.len() / 2;
    let extent = centres.diagonal();
    if extent.max_element() > 0.0 {
        let axis = centres.largest_axis();
        items.select_nth_unstable_by(mid, |a, b| {
            a.bounds
                .center_axis(axis)
                .total_cmp(&b.bounds.center_axis(axis))
        });
    }
    mid
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3A;

    fn aabb(lo: [f32; 3], hi: [f32; 3]) -> Aabb {
        Aabb::new(Vec3A::from(lo), Vec3A::from(hi))
    }

    /// Checks the layout obvhs expects and returns the depth of the tree.
    fn check(bvh: &Bvh2, boxes: &[Aabb]) -> usize {
        let mut seen = vec![false; boxes.len()];
        let mut depth = 0;
        let mut stack = vec![(0usize, 0usize)];
        while let Some((i, d)) = stack.pop() {
            depth = depth.max(d);
            let node = &bvh.nodes[i];
            if node.is_leaf() {
                assert_eq!(node.prim_count, 1);
                let p = bvh.primitive_indices[node.first_index as usize] as usize;
                assert!(!seen[p], "primitive {p} in two leaves");
                seen[p] = true;
                assert_eq!(*node.aabb(), boxes[p]);
                continue;
            }
            let c = node.first_index as usize;
            assert!(c > i, "children stored after their parent");
            for child in [c, c + 1] {
                let b = bvh.nodes[child].aabb();
                assert!(node.aabb().min.cmple(b.min).all() && node.aabb().max.cmpge(b.max).all());
                stack.push((child, d + 1));
            }
        }
        assert!(seen.iter().all(|&s| s), "every primitive in a leaf");
        assert_eq!(bvh.nodes.len(), 2 * boxes.len() - 1);
        assert!(bvh.max_depth > depth);
        depth
    }

    /// Depth within SAH_DEPTH + log2 N + 1 however the boxes are arranged: PLOC's tree on these
    /// inputs was as deep as the inputs were many, and its build quadratic.
    fn assert_shallow(boxes: &[Aabb]) {
        let depth = check(&build_bvh2(boxes.iter().copied()), boxes);
        let bound = SAH_DEPTH + (boxes.len() as f64).log2().ceil() as usize + 1;
        assert!(
            depth <= bound,
            "depth {depth} over {bound} for {} boxes",
            boxes.len()
        );
    }

    #[test]
    fn a_split_s_first_coordinate_parts_centroids_as_their_bins_do() {
        let mut rng = crate::Rng::stream(12, 0);
        let mut u = |r: f32| (rng.next_f64() as f32 * 2.0 - 1.0) * r;
        let mut checked = 0;
        for bins in [2usize, 3, 7, 32] {
            for _ in 0..2_000 {
                // Ranges of either sign, across zero, and tiny ones.
                let lo = u(4.0) * [1.0, 1e-30, 0.0][checked % 3];
                let hi = lo + u(3.0).abs() * [1.0, 1e-6, 1e-36][checked % 3] + f32::MIN_POSITIVE;
                let scale = bins as f32 / (hi - lo);
                for split in 1..bins {
                    if bin_of(lo, lo, scale, bins) >= split || bin_of(hi, lo, scale, bins) < split {
                        continue;
                    }
                    let first = first_of_bin(lo, hi, scale, bins, split);
                    for _ in 0..20 {
                        let t = u(0.5) + 0.5;
                        let c = (lo + (hi - lo) * t).clamp(lo, hi);
                        let (before, after) =
                            (unordered(ordered(first) - 1), unordered(ordered(first) + 1));
                        for c in [c, first, before, after, lo, hi, -0.0, 0.0] {
                            if !(lo..=hi).contains(&c) {
                                continue;
                            }
                            assert_eq!(
                                c < first,
                                bin_of(c, lo, scale, bins) < split,
                                "{c} {lo} {hi} {bins} {split}"
                            );
                            checked += 1;
                        }
                    }
                }
            }
        }
        assert!(checked > 100_000, "{checked}");
    }

    #[test]
    fn three_axes_at_once_bin_as_one_at_a_time() {
        let mut rng = crate::Rng::stream(11, 0);
        let mut u = |r: f32| (rng.next_f64() as f32 * 2.0 - 1.0) * r;
        let mut checked = 0;
        for bins in [2usize, 3, 7, 31, 32] {
            for _ in 0..20_000 {
                let lo = Vec3A::new(u(5.0), u(5.0), u(5.0));
                let extent = Vec3A::new(u(3.0).abs(), u(3.0).abs(), u(3.0).abs());
                let scale = Vec3A::splat(bins as f32) / extent;
                // Inside the range, on its ends and beyond them (rounding puts a centroid there).
                let c = lo + extent * Vec3A::new(u(1.2) + 0.5, u(1.2) + 0.5, u(1.2) + 0.5);
                let ends = [
                    lo,
                    lo + extent,
                    lo + extent * (bins - 1) as f32 / bins as f32,
                ];
                for c in [c].into_iter().chain(ends) {
                    let all = bins_of(c, lo, scale, bins);
                    for axis in 0..3 {
                        let one = bin_of(c[axis], lo[axis], scale[axis], bins);
                        assert_eq!(all[axis] as usize, one, "{c} {lo} {scale} {bins}");
                        checked += 1;
                    }
                }
            }
        }
        assert!(checked > 1_000_000);
    }

    #[test]
    fn identical_boxes_give_a_balanced_tree() {
        let boxes = vec![aabb([0.0; 3], [1.0, 0.0, 1.0]); 10_000];
        let depth = check(&build_bvh2(boxes.iter().copied()), &boxes);
        assert_eq!(
            depth, 14,
            "a median split of 10,000 has depth ceil(log2) = 14"
        );
    }

    #[test]
    fn nested_and_fan_boxes_stay_shallow() {
        // Nested boxes with one common corner, growing geometrically: SAH would peel them off
        // one by one.
        let nested: Vec<Aabb> = (0..5000)
            .map(|i| aabb([0.0; 3], [1.001f32.powi(i), 1.0, 1.001f32.powi(i)]))
            .collect();
        assert_shallow(&nested);
        // The slivers of a fan-triangulated 20,000-gon: every box holds the first vertex.
        let m = 20_000;
        let ring = |i: usize| {
            let a = std::f32::consts::TAU * i as f32 / m as f32;
            Vec3A::new(a.cos(), 0.0, a.sin())
        };
        let fan: Vec<Aabb> = (1..m - 1)
            .map(|i| Aabb::from_points(&[ring(0), ring(i), ring(i + 1)]))
            .collect();
        assert_shallow(&fan);
        // Centroids spread over many octaves on one axis.
        let octaves: Vec<Aabb> = (0..4000)
            .map(|i| {
                let x = 0.99f32.powi(i);
                aabb([x, 0.0, 0.0], [x, 1.0, 1.0])
            })
            .collect();
        assert_shallow(&octaves);
    }

    #[test]
    fn threads_build_the_tree_one_thread_builds() {
        let mut rng = crate::Rng::stream(13, 0);
        let mut u = || rng.next_f64() as f32;
        let random: Vec<Aabb> = (0..20_000)
            .map(|_| {
                let lo = [u() * 10.0, u() * 10.0, u() * 10.0];
                aabb(lo, [lo[0] + u(), lo[1] + u() * 0.1, lo[2] + u()])
            })
            .collect();
        let same = vec![aabb([0.0; 3], [1.0, 0.0, 1.0]); 3000];
        let nested: Vec<Aabb> = (0..3000)
            .map(|i| aabb([0.0; 3], [1.001f32.powi(i), 1.0, 1.001f32.powi(i)]))
            .collect();
        for boxes in [random, same, nested] {
            let one = build_bvh2_from(boxes.iter().copied(), usize::MAX);
            check(&one, &boxes);
            for from in [2, 3, 100, 4096] {
                let many = build_bvh2_from(boxes.iter().copied(), from);
                let key = |b: &Bvh2| -> Vec<_> {
                    b.nodes
                        .iter()
                        .map(|n| (*n.aabb(), n.prim_count, n.first_index))
                        .collect()
                };
                assert!(key(&one) == key(&many), "nodes differ from {from}");
                assert_eq!(one.primitive_indices, many.primitive_indices);
                assert_eq!(one.max_depth, many.max_depth);
            }
        }
    }

    #[test]
    fn one_and_no_primitives() {
        assert!(build_bvh2([]).nodes.is_empty());
        let one = [aabb([0.0; 3], [1.0; 3])];
        assert_eq!(check(&build_bvh2(one), &one), 0);
    }
}
