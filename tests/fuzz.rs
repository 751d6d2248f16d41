//! Mutational fuzzing of the scene loader and the OBJ loader, a bounded number of inputs per
//! target (`PENUMBRA_FUZZ_INPUTS`, default 200,000, or as many as `PENUMBRA_FUZZ_SECONDS`
//! allow): inputs grown from the fixtures by byte and token mutations, every one that loads
//! then rendered small by the CPU volume techniques and depth-complexity. Any panic fails the test, after the input is saved under
//! `target/fuzz-crashes/`; a crash found is kept in `tests/fuzz/` (a scene as `*.toml`, an OBJ as
//! `*.obj`), which every run replays first.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use glam::{DMat4, DVec2, DVec3};
use penumbra::Technique;
use penumbra::geom::Camera;
use penumbra::geom::{RectLight, Rng, Scene, TriangleMesh};
use penumbra::volumes::CpuRenderer;
use penumbra::volumes::{DepthComplexity, SamplePattern};
use penumbra::{Backend, RenderOptions, Renderer};

/// Numbers a user or a generator can produce that sit on some boundary.
const NUMBERS: [&str; 24] = [
    "0",
    "-0",
    "1",
    "-1",
    "0.5",
    "1e-45",
    "1e-300",
    "1e15",
    "1e16",
    "1e20",
    "1e38",
    "3.4e38",
    "1e39",
    "-1e39",
    "1e300",
    "nan",
    "inf",
    "-inf",
    "4294967296",
    "-2147483649",
    "179.999",
    "0.001",
    "65536",
    "1e7",
];

/// Lines worth inserting into either format.
const LINES: [&str; 22] = [
    "[[mesh]]",
    "[camera]",
    "[light]",
    "obj = \"m.obj\"",
    "scale = [1, 2]",
    "scale = 0",
    "translate = [1e30, 0, 0]",
    "rotate_axis_angle = [0, 0, 0, 90]",
    "width = 0",
    "size = [0, 1]",
    "f 1 1 1",
    "f 1 2",
    "f -1 -2 -3",
    "f 0 0 0",
    "f 1 2 3 4 5 6",
    "f 1/1/1 2/2/2 3/3/3",
    "v 1 2",
    "v 1 2 3 4 5 6 7",
    "vt 0 0",
    "vn 0 0 0",
    "o x",
    "f 9999999 1 2",
];

/// How much each target runs: a number of inputs, or for as long as asked.
enum Budget {
    Inputs(u64),
    Time(Duration),
}

impl Budget {
    /// `PENUMBRA_FUZZ_SECONDS` where it is set (a longer session), else `PENUMBRA_FUZZ_INPUTS`
    /// inputs, 200,000 by default (seconds on two cores: most mutants fail to load).
    fn from_env() -> Budget {
        let var = |name| std::env::var(name).ok().and_then(|v| v.parse::<f64>().ok());
        match (var("PENUMBRA_FUZZ_SECONDS"), var("PENUMBRA_FUZZ_INPUTS")) {
            (Some(s), _) => Budget::Time(Duration::from_secs_f64(s)),
            (None, n) => Budget::Inputs(n.map_or(200_000, |n| n as u64)),
        }
    }

    /// Whether another input is due after `runs` inputs since `start`.
    fn more(&self, runs: u64, start: Instant) -> bool {
        match *self {
            Budget::Inputs(n) => runs < n,
            Budget::Time(d) => start.elapsed() < d,
        }
    }
}

fn mutate(rng: &mut Rng, input: &str, corpus: &[String]) -> String {
    let mut lines: Vec<String> = input.lines().map(str::to_owned).collect();
    for _ in 0..1 + rng.below(4) {
        if lines.is_empty() {
            lines.push(String::new());
        }
        let i = rng.below(lines.len());
        match rng.below(8) {
            // A number replaced by a boundary value.
            0 | 1 => {
                let words: Vec<(usize, usize)> = number_spans(&lines[i]);
                if let Some(&(a, b)) = words.get(rng.below(words.len().max(1))) {
                    lines[i].replace_range(a..b, NUMBERS[rng.below(NUMBERS.len())]);
                }
            }
            2 => lines.insert(i, LINES[rng.below(LINES.len())].to_owned()),
            3 => {
                lines.remove(i);
            }
            4 => {
                let l = lines[i].clone();
                lines.insert(i, l);
            }
            5 => {
                // A line from another input.
                let other = &corpus[rng.below(corpus.len())];
                if let Some(l) = other.lines().nth(rng.below(other.lines().count().max(1))) {
                    lines.insert(i, l.to_owned());
                }
            }
            6 => {
                // One byte changed, kept valid UTF-8.
                let mut b = lines[i].clone().into_bytes();
                if !b.is_empty() {
                    let k = rng.below(b.len());
                    let set = b" ,.[]=\"-e0123456789#\t/";
                    b[k] = set[rng.below(set.len())];
                }
                lines[i] = String::from_utf8_lossy(&b).into_owned();
            }
            _ => {
                // Truncated mid-line.
                let l = &lines[i];
                let cut = l.char_indices().map(|(k, _)| k).nth(rng.below(l.len() + 1));
                lines[i] = l[..cut.unwrap_or(l.len())].to_owned();
            }
        }
    }
    lines.join("\n")
}

/// Byte spans of the number-like words of `line`.
fn number_spans(line: &str) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = None;
    for (k, ch) in line
        .char_indices()
        .chain(std::iter::once((line.len(), ' ')))
    {
        let numeric = ch.is_ascii_digit() || "+-.eE".contains(ch);
        match (start, numeric) {
            (None, true) => start = Some(k),
            (Some(s), false) => {
                if line[s..k].bytes().any(|b| b.is_ascii_digit()) {
                    out.push((s, k));
                }
                start = None;
            }
            _ => {}
        }
    }
    out
}

/// Renders `scene` at 8 x 6 with the CPU volume techniques and depth-complexity, as a user's
/// first look would; checks that every value is in [0, 1].
fn render_small(scene: &Scene) {
    let mut s = scene.clone();
    s.camera.width = 8;
    s.camera.height = 6;
    if s.triangle_count() > 20_000 {
        return;
    }
    // Each light of a scene of several alone, every one a channel, or refused as out of range.
    if !s.single_channel() {
        let all = Renderer::new(Backend::Cpu).render_lights(
            &s,
            Technique::Hard,
            &RenderOptions::default(),
        );
        match all {
            Ok(v) => {
                assert_eq!(v.channels().len(), s.lights.len());
                assert!(
                    v.channels().iter().all(|c| c
                        .image
                        .data
                        .iter()
                        .all(|v| (0.0..=1.0).contains(v)))
                );
            }
            Err(e) => assert!(
                (0..s.light_count()).any(|k| s.for_light(k).out_of_range().is_some()),
                "several lights, all in range, refused: {e}"
            ),
        }
    }
    // The front door refuses what is out of range; the rest it renders.
    let front = Renderer::new(Backend::Cpu).render(&s, Technique::Hard, &RenderOptions::default());
    if scene.out_of_range().is_some() {
        assert!(front.is_err(), "out of range, and rendered");
        return;
    }
    let r = CpuRenderer::new(&s.lit(0));
    for t in [Technique::Hard, Technique::WedgesBlend] {
        let img = r.render(t, &|_| {});
        assert!(
            img.data.iter().all(|v| (0.0..=1.0).contains(v)),
            "{t}: V out of [0, 1]"
        );
    }
    let dc = DepthComplexity::new(&s.lit(0));
    let img = dc.render(
        SamplePattern {
            per_axis: 2,
            jitter: false,
        },
        &|_| {},
    );
    assert!(
        img.data.iter().all(|v| (0.0..=1.0).contains(v)),
        "depth-complexity: V out of [0, 1]"
    );
}

/// A folder holding the fixture meshes that the corpus's scenes name, as `m.obj` too.
fn workspace() -> PathBuf {
    let d = std::env::temp_dir().join(format!("penumbra-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(d.join("meshes")).unwrap();
    std::fs::create_dir_all(d.join("scenes")).unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for m in ["quad.obj", "sphere.obj", "book.obj"] {
        std::fs::copy(
            root.join("fixtures/meshes").join(m),
            d.join("meshes").join(m),
        )
        .unwrap();
    }
    std::fs::copy(
        root.join("fixtures/meshes/quad.obj"),
        d.join("scenes/m.obj"),
    )
    .unwrap();
    d
}

/// The seed inputs: the fixtures' scenes that name generated meshes, or the small meshes, and
/// the hostile inputs kept as seeds.
fn seeds(ext: &str) -> Vec<String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut out = Vec::new();
    let dir = if ext == "toml" {
        "fixtures/scenes"
    } else {
        "fixtures/meshes"
    };
    for e in std::fs::read_dir(root.join(dir)).unwrap() {
        let p = e.unwrap().path();
        // A binary mesh (the PLY scan of the scale scenes) is no text seed.
        let Ok(text) = std::fs::read_to_string(&p) else {
            continue;
        };
        let small = if ext == "toml" {
            !["beetle", "cheburashka", "fandisk", "spot", "woody"]
                .iter()
                .any(|r| text.contains(&format!("{r}.obj")))
        } else {
            ["quad.obj", "sphere.obj", "book.obj"]
                .iter()
                .any(|m| p.ends_with(m))
        };
        if small {
            out.push(text);
        }
    }
    // And the hostile inputs of `tests/fuzz/seeds/`: a byte-order mark, repeated faces, a
    // sheet with two sides, a mesh wound inwards, a mirrored mesh under a far light, a ring of
    // vertices on the light's plane, a huge triangle, an eye just above the ground, a low sun
    // and a sun with a lamp.
    for e in std::fs::read_dir(root.join("tests/fuzz/seeds")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == ext) {
            out.push(std::fs::read_to_string(&p).unwrap());
        }
    }
    assert!(!out.is_empty());
    out
}

/// The crashes kept as regressions, with the given extension.
fn regressions(ext: &str) -> Vec<(PathBuf, String)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz");
    let Ok(entries) = std::fs::read_dir(&dir) else {
        return Vec::new();
    };
    entries
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == ext))
        .map(|p| {
            let t = std::fs::read_to_string(&p).unwrap();
            (p, t)
        })
        .collect()
}

thread_local! {
    static QUIET: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Silences the panic messages of this thread (the fuzzing loop's expected catches) or not; other
/// threads' panics print as usual.
fn quiet_panics(quiet: bool) {
    static HOOK: std::sync::Once = std::sync::Once::new();
    HOOK.call_once(|| {
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !QUIET.with(|q| q.get()) {
                default(info);
            }
        }));
    });
    QUIET.with(|q| q.set(quiet));
}

/// Runs `check` on the regressions, then on mutants of the seeds until the budget is spent.
/// Returns the number of inputs tried.
fn fuzz(name: &str, ext: &str, seed: u64, check: impl Fn(&str) + std::panic::RefUnwindSafe) {
    for (p, text) in regressions(ext) {
        if std::panic::catch_unwind(|| check(&text)).is_err() {
            panic!("{name}: the kept crash {} panics again", p.display());
        }
    }
    let mut corpus = seeds(ext);
    let mut rng = Rng::new(seed ^ std::process::id() as u64);
    let budget = Budget::from_env();
    let start = Instant::now();
    let (mut runs, mut crashes) = (0u64, Vec::new());
    quiet_panics(true);
    while budget.more(runs, start) {
        let base = corpus[rng.below(corpus.len())].clone();
        let input = mutate(&mut rng, &base, &corpus);
        runs += 1;
        if std::panic::catch_unwind(|| check(&input)).is_err() {
            let out = Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("target/fuzz-crashes")
                .join(format!("{name}-{runs}.{ext}"));
            let _ = std::fs::create_dir_all(out.parent().unwrap());
            let _ = std::fs::write(&out, &input);
            crashes.push(out);
        } else if corpus.len() < 400 && rng.below(8) == 0 {
            // Keep some mutants as bases: deeper mutations later.
            corpus.push(input);
        }
    }
    quiet_panics(false);
    println!(
        "{name}: {runs} inputs in {:.0} s, {} crashes",
        start.elapsed().as_secs_f64(),
        crashes.len()
    );
    if let Some(first) = crashes.first() {
        // Replay it with the hook back, for its message.
        let text = std::fs::read_to_string(first).unwrap();
        check(&text);
        panic!(
            "{name}: {} crashing inputs, the first in {}",
            crashes.len(),
            first.display()
        );
    }
}

#[test]
fn fuzz_the_scene_loader() {
    let dir = workspace();
    let path = dir.join("scenes/s.toml");
    fuzz("scene", "toml", 0x5ce9e, |text| {
        if let Ok(scene) = Scene::from_toml(text, &path) {
            render_small(&scene);
        }
    });
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn fuzz_the_obj_loader() {
    let camera = Camera::look_at(DVec3::new(0., 3., 4.), DVec3::ZERO, DVec3::Y, 45., 8, 6).unwrap();
    let light = RectLight::new(
        DVec3::new(0., 5., 0.),
        DVec3::NEG_Y,
        DVec3::X,
        DVec2::new(1.0, 1.0),
    )
    .unwrap();
    fuzz("obj", "obj", 0x0b1, |text| {
        if let Ok(mesh) = TriangleMesh::parse_obj(Path::new("fuzz.obj"), text) {
            let scene =
                Scene::new(camera)
                    .with_light(light)
                    .with_mesh("fuzz", &mesh, DMat4::IDENTITY);
            // What a renderer refuses (`Renderer::render` asks the same) is not rendered.
            if scene.out_of_range().is_none() {
                render_small(&scene);
            }
        }
    });
}
