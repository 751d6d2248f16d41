//! `penumbra`: render visibility images, give the visibility at sensor points, probe single
//! pixels, compare images, and generate the fixtures.

mod cli;
mod commands;
mod fixtures;
mod npy;
mod outputs;
mod points_file;
mod words;

use std::process::ExitCode;

use anyhow::Result;
use clap::Parser;
use penumbra::RenderOptions;

use cli::{Cli, Command};
use commands::{accuracy, bench, compare, counters, geometry, points, probe, render, sun_hours};

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
/// previous content stays) and the folders made for them, and exits with 130, as an
/// interrupted command does.
fn remove_temporaries_on_signal() {
    // Without a handler the signal ends the process as before; a temporary file it leaves is
    // then removed by the next run writing the same output.
    let _ = ctrlc::set_handler(|| {
        penumbra::geom::remove_temporaries_in_progress();
        outputs::remove_folders_in_progress();
        std::process::exit(130);
    });
}

/// Turns off Mesa's device-select layer, an implicit Vulkan layer that connects to a Wayland or
/// X11 display to choose a default GPU and, on a machine without one, prints "XDG_RUNTIME_DIR is
/// invalid or not set" twice per instance. The command chooses its adapter itself
/// (`penumbra_gpu::GpuContext`), so the layer has nothing to add. The library sets the same
/// when it creates its wgpu instance with the variable unset; the command sets it first, while
/// it has one thread, so that the library finds it set. A value the user set is kept.
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
            shaded,
            backend,
            params,
        } => render::render(
            &scene,
            technique,
            render::RenderOutputs {
                out: &out,
                png: png.as_deref(),
                shaded: shaded.as_deref(),
            },
            RenderOptions { samples, jitter },
            backend,
            &params,
        ),
        Command::Points {
            scene,
            points,
            out,
            light,
            normal,
            samples,
            technique,
            jitter,
        } => points::points(points::PointsArgs {
            scene: &scene,
            points: &points,
            out: &out,
            light: light.as_deref(),
            normal: normal.as_deref(),
            technique,
            options: RenderOptions { samples, jitter },
        }),
        Command::SunHours {
            scene,
            lat,
            lon,
            start,
            end,
            step,
            out,
            png,
            points,
            normal,
            technique,
            samples,
            angular_size,
            backend,
            north,
            up,
        } => sun_hours::sun_hours(sun_hours::SunHoursArgs {
            scene: &scene,
            latitude: lat,
            longitude: lon,
            start: &start,
            end: &end,
            step: &step,
            out: &out,
            png: png.as_deref(),
            technique,
            samples,
            angular_size_deg: angular_size,
            backend,
            frame: (&north, &up),
            points: points.as_deref(),
            normal: normal.as_deref(),
        }),
        Command::Probe {
            scene,
            pixel,
            samples,
        } => probe::probe(&scene, &pixel, samples),
        Command::Compare {
            a,
            b,
            channel,
            heatmap,
            json,
        } => compare::compare(&a, &b, channel.as_deref(), heatmap.as_deref(), json),
        Command::Geometry { scene, json } => geometry::geometry(&scene, json),
        Command::Bench {
            scene,
            technique,
            frames: _,
            rounds: _,
            backend,
            samples,
            jitter,
            counters: true,
            wedge_pass,
            json,
            params,
        } => counters::counters(
            &scene,
            &technique,
            (backend, wedge_pass),
            RenderOptions { samples, jitter },
            json,
            &params,
        ),
        Command::Bench {
            scene,
            technique,
            frames,
            rounds,
            backend,
            samples,
            jitter,
            counters: false,
            wedge_pass,
            json,
            params,
        } => bench::bench(
            &scene,
            &technique,
            bench::Timing { frames, rounds },
            (backend, wedge_pass),
            RenderOptions { samples, jitter },
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
            wedge_pass,
            params,
        } => accuracy::accuracy(
            &scenes,
            samples,
            (&technique_samples, jitter),
            &techniques,
            (backend, wedge_pass),
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
