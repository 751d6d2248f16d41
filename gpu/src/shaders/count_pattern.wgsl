// The counting pass's light samples: the correlated multi-jittered pattern of
// `penumbra_volumes::samples` (Kensler 2013), compiled with count_regions.wgsl ahead of
// count.wgsl (`passes::count::COUNT_WGSL`).

// The pattern's permutation of 0..l chosen by p (`penumbra_volumes::samples::permute`,
// Kensler 2013).
fn permute(index: u32, l: u32, p: u32) -> u32 {
    var w = l - 1u;
    w |= w >> 1u;
    w |= w >> 2u;
    w |= w >> 4u;
    w |= w >> 8u;
    w |= w >> 16u;
    var i = index;
    loop {
        spent++;
        i ^= p;
        i *= 0xe170893du;
        i ^= p >> 16u;
        i ^= (i & w) >> 4u;
        i ^= p >> 8u;
        i *= 0x0929eb3fu;
        i ^= p >> 23u;
        i ^= (i & w) >> 1u;
        i *= 1u | (p >> 27u);
        i *= 0x6935fa69u;
        i ^= (i & w) >> 11u;
        i *= 0x74dcb303u;
        i ^= (i & w) >> 2u;
        i *= 0x9e501cc3u;
        i ^= (i & w) >> 2u;
        i *= 0xc860a3dfu;
        i &= w;
        i ^= i >> 5u;
        if (i < l) {
            return (i + p) % l;
        }
    }
    return 0u;
}

// `penumbra_volumes::samples::hash` (Kensler 2013).
fn hash(index: u32, p: u32) -> u32 {
    var i = index ^ p;
    i ^= i >> 17u;
    i ^= i >> 10u;
    i *= 0xb36534e5u;
    i ^= i >> 12u;
    i ^= i >> 21u;
    i *= 0x93fc4795u;
    i ^= 0xdf6e307fu;
    i ^= i >> 17u;
    return i * (1u | (p >> 18u));
}

// A coordinate of the pattern: fine column (or row) `fine` of N² and its 16-bit jitter `jitter`,
// -1 + (fine + jitter / 65536) 2 / N², rounded once to f32 where N² 65536 <= 2^24.
fn pattern_coordinate(fine: u32, jitter: u32, nn: u32) -> f32 {
    let units = fine * 65536u + jitter;
    let total = nn * 65536u;
    return f32(i32(2u * units) - i32(total)) / f32(total);
}

// The permutation seeds of pixel `seed`'s pattern: its fine column per cell row, its fine row
// per cell column, and its jitters (`SamplePattern::points`).
fn column_seed(seed: u32) -> u32 {
    return seed * 0x63d83595u;
}

fn row_seed(seed: u32) -> u32 {
    return seed * 0xa511e9b3u;
}

fn jitter_seed_of(seed: u32) -> u32 {
    return seed * 0xa399d265u;
}

// The sample of cell (i, j) of N x N on the light's plane, given the cell row's fine column
// `column`, the cell column's fine row `row` and the pixel's jitter seed.
fn pattern_point(i: u32, j: u32, column: u32, row: u32, jitter: u32) -> vec2<f32> {
    let n = params.per_axis;
    let h = hash(j * n + i, jitter);
    return vec2<f32>(
        pattern_coordinate(i * n + column, h & 0xffffu, n * n),
        pattern_coordinate(j * n + row, h >> 16u, n * n),
    );
}
