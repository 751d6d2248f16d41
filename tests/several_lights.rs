//! Scenes of several lights: each light's channel is, pixel for pixel, the image of the same
//! scene file written with that light alone as its one `[light]`, for every back end's
//! techniques.

use std::path::Path;

use penumbra::{Backend, RenderOptions, Renderer, Runs, Scene, Technique};

use crate::common::{differing_pixels, gpu_renderer, scene_path};

/// The text of a scene file of several lights (`[[light]]`) with its light `k` alone, written
/// as a single `[light]` (its `name` dropped).
fn with_light_alone(text: &str, k: usize) -> String {
    let mut out = String::new();
    let mut light = None;
    let mut in_light = false;
    for line in text.lines() {
        if line.starts_with('[') {
            in_light = line == "[[light]]";
            if in_light {
                light = Some(light.map_or(0, |n: usize| n + 1));
                if light == Some(k) {
                    out.push_str("[light]\n");
                }
                continue;
            }
        }
        if in_light && (light != Some(k) || line.starts_with("name =")) {
            continue;
        }
        out.push_str(line);
        out.push('\n');
    }
    assert!(light.is_some_and(|n| n >= k), "no light {k}");
    out
}

/// The fixture two-lights, or with `sun` its fill light turned into a distant light from the
/// same side (its direction the fill light's `-normal`, full angles 9 x 30 degrees, about what
/// the fill light spans from the casters), and each of its lights alone, read from scene-file
/// text.
fn scene_and_singles(sun: bool) -> (Scene, Vec<Scene>) {
    let path = scene_path("two-lights");
    let mut text = std::fs::read_to_string(&path).unwrap();
    if sun {
        let fill = text.find("name = \"fill\"").unwrap();
        let end = fill + text[fill..].find("\n\n").unwrap();
        text.replace_range(
            fill..end,
            "name = \"fill\"\ndistant = true\n\
             direction = [0.6556100681071858, 0.7492686492653552, -0.0936585811581694]\n\
             tangent = [-0.12079677321987342, 0.226508373301436, 0.9664895738723741]\n\
             angular_size = [9.0, 30.0]",
        );
    }
    let scene = Scene::from_toml(&text, &path).unwrap();
    assert_eq!(scene.channel_names(), ["key.V", "fill.V"]);
    let singles = (0..scene.light_count())
        .map(|k| {
            let alone = Scene::from_toml(&with_light_alone(&text, k), &path).unwrap();
            assert!(alone.lights.len() == 1 && !alone.named_channels);
            assert_eq!(scene.lights[k].light, alone.lights[0].light);
            alone
        })
        .collect();
    assert_eq!(scene.lights[1].light.as_distant().is_some(), sun);
    (scene, singles)
}

/// Renders `techniques` of two-lights with one renderer of `backend` and asserts each channel
/// equal to its light alone's image, made by a renderer of its own (so that nothing one light
/// leaves in a renderer reaches the other's image unseen), and the two lights' images
/// different.
fn assert_channels_are_lights_alone(backend: Backend, techniques: &[Technique], sun: bool) {
    let renderer = &mut Renderer::new(backend);
    let (scene, singles) = scene_and_singles(sun);
    let options = RenderOptions {
        samples: 16,
        jitter: false,
    };
    for &t in techniques {
        let channels = renderer.render_lights(&scene, t, &options).unwrap();
        assert_eq!(channels.names(), ["key.V", "fill.V"], "{t}");
        // The last light first.
        for (k, (c, alone)) in channels.channels().iter().zip(&singles).enumerate().rev() {
            let image = Renderer::new(backend).render(alone, t, &options).unwrap();
            assert_eq!(c.image.data.len(), 160 * 120, "{t}");
            let differ = differing_pixels(&c.image.data, &image.data);
            assert_eq!(differ, 0, "{t}: light {k}: {differ} pixels differ");
        }
        // The two lights cast different shadows, both in view.
        let [a, b] = [0, 1].map(|k| &channels.channels()[k].image.data);
        assert!(a != b, "{t}");
        for v in [a, b] {
            assert!(v.iter().filter(|&&x| x < 0.5).count() > 100, "{t}");
        }
    }
}

/// Every technique the CPU renders (six).
fn cpu_techniques() -> Vec<Technique> {
    let cpu: Vec<Technique> = Technique::ALL
        .into_iter()
        .filter(|&t| Runs::of(t) != Runs::GpuOnly)
        .collect();
    assert_eq!(cpu.len(), 6);
    cpu
}

#[test]
fn each_light_s_channel_is_that_light_alone_on_the_cpu() {
    assert_channels_are_lights_alone(Backend::Cpu, &cpu_techniques(), false);
}

#[test]
fn a_distant_light_s_channel_is_that_light_alone_on_the_cpu() {
    assert_channels_are_lights_alone(Backend::Cpu, &cpu_techniques(), true);
}

#[test]
fn each_light_s_channel_is_that_light_alone_on_the_gpu() {
    let Some(mut gpu) = gpu_renderer() else {
        return;
    };
    // Every technique the GPU renders, each on the GPU.
    let techniques: Vec<Technique> = Technique::ALL
        .into_iter()
        .filter(|&t| Runs::of(t) != Runs::CpuOnly)
        .collect();
    assert_eq!(techniques.len(), 9);
    for &t in &techniques {
        let frame = gpu
            .render_frame(
                &(scene_and_singles(false).1[0]).lit(0),
                t,
                &RenderOptions {
                    samples: 16,
                    jitter: false,
                },
                None,
                &|_| {},
            )
            .unwrap();
        assert!(frame.detail.starts_with("gpu: "), "{t}: {}", frame.detail);
    }
    assert_channels_are_lights_alone(Backend::Gpu, &techniques, false);
    assert_channels_are_lights_alone(Backend::Gpu, &techniques, true);
}

#[test]
fn one_light_of_an_array_is_still_a_named_channel() {
    let path = scene_path("two-lights");
    let text = std::fs::read_to_string(&path).unwrap();
    // The first light kept as the array's one entry.
    let second = text.match_indices("[[light]]").nth(1).unwrap().0;
    let end = second + text[second..].find("\n\n").unwrap();
    let one = format!("{}{}", &text[..second], &text[end..]);
    let scene = Scene::from_toml(&one, Path::new(&path)).unwrap();
    assert_eq!(scene.channel_names(), ["key.V"]);
    let options = RenderOptions::default();
    let v = Renderer::new(Backend::Cpu)
        .render_lights(&scene, Technique::Hard, &options)
        .unwrap();
    assert!(!v.is_single());
    assert_eq!(v.names(), ["key.V"]);
}
