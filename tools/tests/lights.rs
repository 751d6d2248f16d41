//! Scenes of several lights from the command line: a channel `<name>.V` and a PNG per light,
//! each the image of the scene with that light alone; `probe`, `compare` and `bench` of them;
//! and bad light arrays refused with their file and line, leaving no output.

mod common;
use common::{
    GOOD_OBJ, GOOD_SCENE, assert_refused, files_in, no_adapter_here, penumbra, render_case_with,
    scratch, stdout_of,
};
use penumbra_geom::{VisibilityChannels, VisibilityImage};

/// The light table of [`GOOD_SCENE`].
const LIGHT: &str = "[light]\ncenter = [0.0, 4.0, 0.0]\nnormal = [0.0, -1.0, 0.0]\n\
    tangent = [1.0, 0.0, 0.0]\nsize = [1.0, 1.0]\n";

/// A light as an entry of `[[light]]`, with extra lines (a name), its centre at `x`.
fn entry(extra: &str, x: f64) -> String {
    format!(
        "[[light]]\n{extra}center = [{x:?}, 4.0, 0.0]\nnormal = [0.0, -1.0, 0.0]\n\
         tangent = [1.0, 0.0, 0.0]\nsize = [1.0, 1.0]\n"
    )
}

/// [`GOOD_SCENE`] with `lights` in place of its `[light]`.
fn scene_with(lights: &str) -> String {
    assert!(GOOD_SCENE.contains(LIGHT));
    GOOD_SCENE.replace(LIGHT, lights)
}

/// [`GOOD_SCENE`] with the one light at `x`.
fn single_at(x: f64) -> String {
    scene_with(&entry("", x).replace("[[light]]", "[light]"))
}

#[test]
fn each_light_gets_a_channel_and_a_png_equal_to_that_light_alone() {
    let two = scene_with(&format!(
        "{}\n{}",
        entry("name = \"key\"\n", -0.8),
        entry("", 0.9)
    ));
    for technique in ["reference", "depth-complexity", "wedges-blend"] {
        let args = ["--technique", technique];
        let (d, out) = render_case_with(&format!("two-{technique}"), &two, GOOD_OBJ, &args);
        stdout_of(&out);
        assert_eq!(
            files_in(&d),
            ["m.obj", "s.toml", "v.exr", "v.key.png", "v.light1.png"]
        );
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("2 lights"), "{err}");
        let channels = VisibilityChannels::read_exr(&d.join("v.exr")).unwrap();
        assert_eq!(channels.names(), ["key.V", "light1.V"]);
        // A single-image reader finds no `V` and says which channels there are.
        let e = VisibilityImage::read_exr(&d.join("v.exr")).unwrap_err();
        assert!(e.to_string().contains("key.V"), "{e}");
        for (k, (x, name)) in [(-0.8, "key"), (0.9, "light1")].into_iter().enumerate() {
            let (alone, out) = render_case_with(
                &format!("alone-{technique}-{k}"),
                &single_at(x),
                GOOD_OBJ,
                &args,
            );
            stdout_of(&out);
            let v = VisibilityImage::read_exr(&alone.join("v.exr")).unwrap();
            let c = &channels.channels()[k].image;
            assert!(
                c.data
                    .iter()
                    .zip(&v.data)
                    .all(|(a, b)| a.to_bits() == b.to_bits()),
                "{technique}: light {name}"
            );
            assert_eq!(
                std::fs::read(d.join(format!("v.{name}.png"))).unwrap(),
                std::fs::read(alone.join("v.png")).unwrap(),
                "{technique}: light {name}"
            );
            let _ = std::fs::remove_dir_all(&alone);
        }
        assert_ne!(
            channels.channels()[0],
            channels.channels()[1],
            "{technique}"
        );
        let _ = std::fs::remove_dir_all(&d);
    }
}

#[test]
fn bad_light_arrays_name_file_and_line_and_write_nothing() {
    let dup = scene_with(&format!(
        "{}\n{}",
        entry("name = \"a\"\n", 0.0),
        entry("name = \"a\"\n", 1.0)
    ));
    assert_refused(
        "dup",
        &dup,
        GOOD_OBJ,
        &["s.toml:18", "light[1].name", "\"a\"", "light[0]"],
    );
    // A default name counts.
    let dup = scene_with(&format!(
        "{}\n{}",
        entry("", 0.0),
        entry("name = \"light0\"\n", 1.0)
    ));
    assert_refused("default-dup", &dup, GOOD_OBJ, &["s.toml:17", "\"light0\""]);
    let bad = scene_with(&entry("name = \"key.1\"\n", 0.0));
    assert_refused(
        "bad-name",
        &bad,
        GOOD_OBJ,
        &["s.toml:11", "\"key.1\"", "'.'"],
    );
    let empty = scene_with(&entry("name = \"\"\n", 0.0));
    assert_refused("empty-name", &empty, GOOD_OBJ, &["s.toml:11", "empty"]);
    let both = scene_with(&format!("{LIGHT}\n{}", entry("", 1.0)));
    assert_refused(
        "both",
        &both,
        GOOD_OBJ,
        &["s.toml:16", "`[light]` and `[[light]]` in one file"],
    );
    let none = format!("light = []\n{}", scene_with(""));
    assert_refused("empty-array", &none, GOOD_OBJ, &["s.toml:1", "empty array"]);
    let late = scene_with(&format!(
        "{}\n{}",
        entry("", 0.0),
        entry("", 1.0).replace("size = [1.0, 1.0]", "size = [1.0, -1.0]")
    ));
    assert_refused("late-bad", &late, GOOD_OBJ, &["s.toml:20", "light[1].size"]);
}

#[test]
fn probe_compare_and_bench_take_each_light() {
    let d = scratch("lights-tools");
    let two = scene_with(&format!(
        "{}\n{}",
        entry("name = \"key\"\n", -0.8),
        entry("name = \"fill\"\n", 0.9)
    ));
    std::fs::write(d.join("s.toml"), &two).unwrap();
    std::fs::write(d.join("m.obj"), GOOD_OBJ).unwrap();
    let render = |technique: &str, out: &str| {
        stdout_of(
            &penumbra()
                .arg("render")
                .arg(d.join("s.toml"))
                .args(["--technique", technique, "--samples", "16", "--out"])
                .arg(d.join(out))
                .output()
                .unwrap(),
        );
    };
    render("hard-reference", "h.exr");
    render("reference", "r.exr");
    // Every channel in turn, each under its name.
    let text = stdout_of(
        &penumbra()
            .arg("compare")
            .arg(d.join("h.exr"))
            .arg(d.join("r.exr"))
            .arg("--heatmap")
            .arg(d.join("heat.png"))
            .output()
            .unwrap(),
    );
    let key = text.find("channel key.V").expect(&text);
    let fill = text.find("channel fill.V").expect(&text);
    assert!(key < fill, "{text}");
    assert_eq!(
        text.matches("penumbra mean signed error").count(),
        2,
        "{text}"
    );
    assert!(d.join("heat.key.png").exists() && d.join("heat.fill.png").exists());
    assert!(!d.join("heat.png").exists());
    // One channel, as JSON: the single-image form.
    let json = stdout_of(
        &penumbra()
            .arg("compare")
            .arg(d.join("h.exr"))
            .arg(d.join("r.exr"))
            .args(["--channel", "fill.V", "--json"])
            .output()
            .unwrap(),
    );
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert!(v["penumbra"]["mae"].as_f64().unwrap() > 0.05, "{json}");
    // Every channel as JSON: a list, each entry naming its channel.
    let json = stdout_of(
        &penumbra()
            .arg("compare")
            .arg(d.join("h.exr"))
            .arg(d.join("r.exr"))
            .arg("--json")
            .output()
            .unwrap(),
    );
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v[0]["channel"], "key.V");
    assert_eq!(v[1]["channel"], "fill.V");
    assert!(v[1]["all"]["mae"].as_f64().is_some());
    // A channel that is not there names the file and the channels it has.
    let out = penumbra()
        .arg("compare")
        .arg(d.join("h.exr"))
        .arg(d.join("r.exr"))
        .args(["--channel", "V"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("h.exr") && err.contains("key.V, fill.V"),
        "{err}"
    );
    // Images of different lights are compared channel by channel only when named.
    std::fs::write(d.join("one.toml"), single_at(0.0)).unwrap();
    stdout_of(
        &penumbra()
            .arg("render")
            .arg(d.join("one.toml"))
            .args(["--technique", "hard-reference", "--out"])
            .arg(d.join("one.exr"))
            .output()
            .unwrap(),
    );
    let out = penumbra()
        .arg("compare")
        .arg(d.join("one.exr"))
        .arg(d.join("r.exr"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("--channel"), "{err}");
    // The lights in the other order: the same images, compared in A's order.
    let swapped = scene_with(&format!(
        "{}\n{}",
        entry("name = \"fill\"\n", 0.9),
        entry("name = \"key\"\n", -0.8)
    ));
    std::fs::write(d.join("swapped.toml"), swapped).unwrap();
    stdout_of(
        &penumbra()
            .arg("render")
            .arg(d.join("swapped.toml"))
            .args(["--technique", "hard-reference", "--out"])
            .arg(d.join("swapped.exr"))
            .output()
            .unwrap(),
    );
    let json = stdout_of(
        &penumbra()
            .arg("compare")
            .arg(d.join("swapped.exr"))
            .arg(d.join("h.exr"))
            .arg("--json")
            .output()
            .unwrap(),
    );
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v[0]["channel"], "fill.V");
    for c in [&v[0], &v[1]] {
        assert_eq!(c["all"]["max"], 0.0, "{json}");
    }
    // probe: each light in turn.
    let text = stdout_of(
        &penumbra()
            .arg("probe")
            .arg(d.join("s.toml"))
            .args(["--pixel", "12,8", "--samples", "16"])
            .output()
            .unwrap(),
    );
    let key = text.find("light key (channel key.V)").expect(&text);
    let fill = text.find("light fill (channel fill.V)").expect(&text);
    assert!(key < fill, "{text}");
    assert_eq!(text.matches("V exact").count(), 2, "{text}");
    // bench: a frame renders both lights.
    let json = stdout_of(
        &penumbra()
            .arg("bench")
            .arg(d.join("s.toml"))
            .args([
                "--technique",
                "wedges-blend",
                "--backend",
                "cpu",
                "--frames",
                "1",
                "--json",
            ])
            .output()
            .unwrap(),
    );
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["lights"], 2, "{json}");
    // bench --counters: a frame, and a report, per light.
    let out = penumbra()
        .arg("bench")
        .arg(d.join("s.toml"))
        .args([
            "--technique",
            "hard",
            "--backend",
            "gpu",
            "--counters",
            "--json",
        ])
        .output()
        .unwrap();
    if !no_adapter_here(&out) {
        let v: serde_json::Value = serde_json::from_str(&stdout_of(&out)).unwrap();
        let lights: Vec<&str> = v
            .as_array()
            .expect("a report per light")
            .iter()
            .map(|r| r["light"].as_str().unwrap())
            .collect();
        assert_eq!(lights, ["key", "fill"]);
    }
    let _ = std::fs::remove_dir_all(&d);
}
