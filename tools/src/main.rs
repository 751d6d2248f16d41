//! `penumbra`: render visibility images, probe single pixels, compare images, and generate the
//! fixtures.

mod cli;
mod commands;
mod fixtures;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Result, bail};
use clap::Parser;
use penumbra::RenderOptions;
use penumbra::geom::Scene;

use cli::{Cli, Command};
use commands::{accuracy, bench, compare, geometry, probe, render};

fn main() -> ExitCode {
    quiet_device_select();
    remove_temporaries_on_signal();
    quiet_on_closed_stdout();
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

/// A reader that closes the output early (`penumbra compare A B | head -1`) ends the command
/// quietly, with the status of a process ended by SIGPIPE (141), as other tools do: `println!`
/// panics on a closed pipe, since Rust ignores SIGPIPE.
fn quiet_on_closed_stdout() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let message = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        if message.starts_with("failed printing to stdout") && message.contains("Broken pipe") {
            std::process::exit(141);
        }
        default(info);
    }));
}

/// On SIGINT, SIGTERM or SIGHUP, removes the temporary files of the outputs being written (their
/// previous content stays) and exits with 130, as an interrupted command does.
fn remove_temporaries_on_signal() {
    // Without a handler the signal ends the process as before; a temporary file it leaves is
    // then removed by the next run writing the same output.
    let _ = ctrlc::set_handler(|| {
        penumbra::geom::remove_temporaries_in_progress();
        std::process::exit(130);
    });
}

/// Turns off Mesa's device-select layer, an implicit Vulkan layer that connects to a Wayland or
/// X11 display to choose a default GPU and, on a machine without one, prints "XDG_RUNTIME_DIR is
/// invalid or not set" twice per instance. The command chooses its adapter itself
/// (`penumbra_gpu::GpuContext`), so the layer has nothing to add. A value the user set is kept.
fn quiet_device_select() {
    if std::env::var_os("NODEVICE_SELECT").is_none() {
        // Safe: no other thread exists yet to read the environment concurrently.
        #[allow(unsafe_code)] // `set_var` is unsafe since edition 2024; see the line above.
        unsafe {
            std::env::set_var("NODEVICE_SELECT", "1")
        };
    }
}

fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Render {
            scene,
            technique,
            out,
            samples,
            jitter,
            png,
            backend,
            params,
        } => render::render(
            &scene,
            technique,
            &out,
            Sampling { samples, jitter },
            png.as_deref(),
            backend,
            &params,
        ),
        Command::Probe {
            scene,
            pixel,
            samples,
        } => probe::probe(&scene, &pixel, samples),
        Command::Compare {
            a,
            b,
            heatmap,
            json,
        } => compare::compare(&a, &b, heatmap.as_deref(), json),
        Command::Geometry { scene, json } => geometry::geometry(&scene, json),
        Command::Bench {
            scene,
            technique,
            frames,
            rounds,
            backend,
            samples,
            jitter,
            json,
            params,
        } => bench::bench(
            &scene,
            &technique,
            bench::Timing { frames, rounds },
            backend,
            Sampling { samples, jitter },
            json,
            &params,
        ),
        Command::Accuracy {
            scenes,
            samples,
            technique_samples,
            jitter,
            techniques,
            backend,
            params,
        } => accuracy::accuracy(
            &scenes,
            samples,
            Sampling {
                samples: technique_samples,
                jitter,
            },
            &techniques,
            backend,
            &params,
        ),
        Command::GenFixtures { out } => {
            for f in fixtures::generate(&out)? {
                println!("wrote {f}");
            }
            Ok(())
        }
    }
}

/// `n` where `samples = n * n` (the library's check, [`RenderOptions::pattern`]), or an error
/// naming the flag.
fn samples_per_axis(samples: usize) -> Result<usize> {
    let options = RenderOptions {
        samples,
        jitter: false,
    };
    match options.pattern() {
        Ok(p) => Ok(p.per_axis),
        Err(_) => {
            bail!(
                "--samples {samples} must be a positive perfect square (64, 256, 1024, ...) up to {}",
                penumbra::MAX_SAMPLES
            )
        }
    }
}

/// The same file, whether or not it exists yet. Two existing paths are the same file when they
/// reach the same inode: through a symbolic link (the image writers write through links) or as
/// two hard links of one file. A path that does not exist yet is compared by its canonical folder
/// and name.
fn same_file(a: &Path, b: &Path) -> bool {
    if let (Some(x), Some(y)) = (identity(a), identity(b)) {
        return x == y;
    }
    let canon = |p: &Path| -> Option<PathBuf> {
        let parent = match p.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        Some(parent.canonicalize().ok()?.join(p.file_name()?))
    };
    match (canon(a), canon(b)) {
        (Some(x), Some(y)) => x == y,
        _ => a == b,
    }
}

/// The device and inode of the file a path reaches, following symbolic links; `None` where
/// nothing is there (or the platform has no inodes: then the canonical path stands for it).
fn identity(p: &Path) -> Option<(u64, u64)> {
    let m = std::fs::metadata(p).ok()?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        Some((m.dev(), m.ino()))
    }
    #[cfg(not(unix))]
    {
        let _ = m;
        None
    }
}

/// Refuses outputs that would overwrite an input or each other, or that are not regular files
/// (or links to one).
fn check_outputs(inputs: &[PathBuf], outputs: &[&Path]) -> Result<()> {
    for (k, out) in outputs.iter().enumerate() {
        // Before any work: a directory, device, FIFO or socket is refused, not replaced.
        penumbra::geom::output_target(out)?;
        if let Some(i) = inputs.iter().find(|i| same_file(i, out)) {
            bail!(
                "output {} is an input of this run ({}); refusing to overwrite it",
                out.display(),
                i.display()
            );
        }
        if outputs[..k].iter().any(|o| same_file(o, out)) {
            bail!("output {} is named twice", out.display());
        }
    }
    Ok(())
}

fn load_scene(path: &Path) -> Result<Scene> {
    Ok(Scene::load(path)?)
}

/// Light samples per pixel of the sampled techniques, and whether `depth-complexity` jitters
/// them as the reference does.
#[derive(Clone, Copy, Debug)]
struct Sampling {
    samples: usize,
    jitter: bool,
}
