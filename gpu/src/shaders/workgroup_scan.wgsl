// The inclusive prefix sums over a workgroup of SCAN_GROUP invocations (Hillis and Steele 1986),
// of two counts at once. Declarations only, prepended to the passes that compact their output in
// order: the shadows' build (`build.wgsl`) and the tiled wedges (`wedge_tiles.wgsl`).

const SCAN_GROUP: u32 = 256u;

// The sums; after `workgroup_scan`, `scan_sums[SCAN_GROUP - 1u]` holds the workgroup's total.
var<workgroup> scan_sums: array<vec2<u32>, SCAN_GROUP>;

// The inclusive prefix sums of `mine` over the workgroup, in the order of `local`.
fn workgroup_scan(local: u32, mine: vec2<u32>) -> vec2<u32> {
    scan_sums[local] = mine;
    workgroupBarrier();
    for (var step = 1u; step < SCAN_GROUP; step <<= 1u) {
        var v = scan_sums[local];
        if (local >= step) {
            v += scan_sums[local - step];
        }
        workgroupBarrier();
        scan_sums[local] = v;
        workgroupBarrier();
    }
    return scan_sums[local];
}
