//! Mutational fuzzing of the EXR readers that `compare`, `probe` and Python's `read_exr` use
//! (`VisibilityChannels::read_exr`, `read_exr_names`, `read_exr_channel`,
//! `VisibilityImage::read_exr`): files the writers made (one channel `V`; several lights' with
//! the light-order attribute; other sizes) mutated byte by byte, by spans, by boundary values
//! written over 32-bit fields and by cuts and repeats, a bounded number of inputs
//! (`PENUMBRA_FUZZ_INPUTS`, default 3,000). Each reader returns an image of sound values or an
//! error; a panic fails the test after the input is saved under `target/fuzz-crashes/`.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};

use penumbra::geom::{Channel, Rng, VisibilityChannels, VisibilityImage};

/// Values worth writing over a 32-bit field: sizes, offsets and counts on some boundary.
const WORDS: [u32; 10] = [
    0,
    1,
    0x7fff_ffff,
    0x8000_0000,
    0xffff_ffff,
    0xffff,
    0x1_0000,
    65_535 * 2,
    3,
    0xffff_fffe,
];

/// The seeds: the files the writers make.
fn seeds(dir: &Path) -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    let image = |w: u32, h: u32| {
        let data = (0..w * h).map(|k| (k % 7) as f32 / 6.0).collect();
        VisibilityImage {
            width: w,
            height: h,
            data,
        }
    };
    let one = dir.join("seed-one.exr");
    image(5, 3).write_exr(&one).unwrap();
    out.push(std::fs::read(&one).unwrap());
    let wide = dir.join("seed-wide.exr");
    image(70, 2).write_exr(&wide).unwrap();
    out.push(std::fs::read(&wide).unwrap());
    let lights = dir.join("seed-lights.exr");
    VisibilityChannels::new(vec![
        Channel {
            name: "key.V".into(),
            image: image(4, 4),
        },
        Channel {
            name: "fill.V".into(),
            image: image(4, 4),
        },
    ])
    .unwrap()
    .write_exr(&lights)
    .unwrap();
    out.push(std::fs::read(&lights).unwrap());
    out
}

/// One mutation of `input`.
fn mutate(rng: &mut Rng, input: &[u8], seeds: &[Vec<u8>]) -> Vec<u8> {
    let mut b = input.to_vec();
    if b.is_empty() {
        return seeds[rng.below(seeds.len())].clone();
    }
    let at = rng.below(b.len());
    match rng.below(7) {
        0 => b[at] ^= 1 << rng.below(8),
        1 => b[at] = rng.next_u64() as u8,
        2 => {
            let w = WORDS[rng.below(WORDS.len())].to_le_bytes();
            for (k, x) in w.iter().enumerate() {
                if let Some(y) = b.get_mut(at + k) {
                    *y = *x;
                }
            }
        }
        3 => b.truncate(at),
        4 => {
            let end = (at + 1 + rng.below(32)).min(b.len());
            let span = b[at..end].to_vec();
            let to = rng.below(b.len());
            b.splice(to..to, span);
        }
        5 => {
            let end = (at + 1 + rng.below(16)).min(b.len());
            b.drain(at..end);
        }
        _ => {
            // Another seed's tail from the same offset: headers of one, data of another.
            let other = &seeds[rng.below(seeds.len())];
            if at < other.len() {
                b.truncate(at);
                b.extend_from_slice(&other[at..]);
            }
        }
    }
    b
}

/// Every reader on `path`: an image of sound values, or an error.
fn read_all(path: &Path) {
    if let Ok(c) = VisibilityChannels::read_exr(path) {
        for ch in c.channels() {
            assert!(
                ch.image.check().is_ok(),
                "{}: {:?}",
                ch.name,
                ch.image.check()
            );
        }
        for name in c.names() {
            assert!(VisibilityChannels::read_exr_channel(path, name).is_ok());
        }
    }
    let _ = VisibilityChannels::read_exr_names(path);
    if let Ok(i) = VisibilityImage::read_exr(path) {
        assert!(i.check().is_ok(), "{:?}", i.check());
    }
}

fn crashes_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target/fuzz-crashes")
}

#[test]
fn fuzz_the_exr_readers() {
    let dir = std::env::temp_dir().join(format!("penumbra-fuzz-exr-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let seeds = seeds(&dir);
    let inputs: u64 = std::env::var("PENUMBRA_FUZZ_INPUTS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(3_000);
    let mut rng = Rng::new(0xe8_2f);
    let path = dir.join("input.exr");
    let mut read = 0;
    for k in 0..inputs {
        let base = &seeds[rng.below(seeds.len())];
        let mut input = mutate(&mut rng, base, &seeds);
        for _ in 0..rng.below(4) {
            input = mutate(&mut rng, &input, &seeds);
        }
        std::fs::write(&path, &input).unwrap();
        if catch_unwind(AssertUnwindSafe(|| read_all(&path))).is_err() {
            let saved = crashes_dir().join(format!("exr-{k}.exr"));
            std::fs::create_dir_all(crashes_dir()).unwrap();
            std::fs::write(&saved, &input).unwrap();
            panic!("input {k} panicked a reader; saved as {}", saved.display());
        }
        read += u64::from(VisibilityChannels::read_exr(&path).is_ok());
    }
    // The mutations leave some files readable: the readers are reached, not only the header.
    assert!(read > inputs / 50, "{read} of {inputs} read");
    let _ = std::fs::remove_dir_all(&dir);
}
