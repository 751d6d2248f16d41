//! `penumbra sun-hours`: the hours of direct sun at every pixel of a scene, or at sensor points,
//! from one time to another, the sun placed by NREL's Solar Position Algorithm (Reda and
//! Andreas 2004, as the crate `solar-positioning` implements it) at each step: to an EXR
//! (channel `hours`) and a colour map with its legend, or to a `.npy` or `.csv` file.

use std::path::Path;

use anyhow::{Context, Result, anyhow, bail};
use chrono::{DateTime, FixedOffset, NaiveDate, NaiveDateTime, TimeDelta, Utc};
use indicatif::{ProgressBar, ProgressStyle};
use penumbra::{Backend, RenderOptions, Renderer, Scene, SunStep, SunStudy, SunTarget, Technique};
use solar_positioning::{Location, RefractionCorrection, SolarPositions, delta_t};

use crate::outputs::{check_outputs, prepare};
use crate::points_file::{Format, read_points, sensor_error, write_values};
use crate::words::{InCommandWords, render_error};

/// Refraction at the standard atmosphere's pressure (hPa) and 12 degrees C, as pvlib's
/// defaults, so that the command and `penumbra.study` place the sun alike.
const PRESSURE_HPA: f64 = 1013.25;
const TEMPERATURE_C: f64 = 12.0;
/// The most steps a study may have: a year of minutes.
const MAX_STEPS: usize = 366 * 24 * 60;

/// What `penumbra sun-hours` was asked.
pub(crate) struct SunHoursArgs<'a> {
    pub(crate) scene: &'a Path,
    pub(crate) latitude: f64,
    pub(crate) longitude: f64,
    pub(crate) start: &'a str,
    pub(crate) end: &'a str,
    pub(crate) step: &'a str,
    pub(crate) out: &'a Path,
    pub(crate) png: Option<&'a Path>,
    pub(crate) technique: Technique,
    pub(crate) samples: usize,
    pub(crate) angular_size_deg: f64,
    pub(crate) backend: Backend,
    /// `--north` and `--up`, as given.
    pub(crate) frame: (&'a str, &'a str),
    /// `--points`: sensor points instead of the camera's pixels.
    pub(crate) points: Option<&'a Path>,
    /// `--normal X,Y,Z`: the normal of every point of a file of positions only.
    pub(crate) normal: Option<&'a str>,
}

/// A time: RFC 3339 with its offset (`2026-06-21T06:00:00+02:00`), or a date and time or a
/// date alone, taken in UTC (`2026-06-21T06:00`, `2026-06-21 06:00:00`, `2026-06-21`).
pub(crate) fn parse_time(flag: &str, text: &str) -> Result<DateTime<FixedOffset>> {
    if let Ok(t) = DateTime::parse_from_rfc3339(text) {
        return Ok(t);
    }
    let utc = FixedOffset::east_opt(0).expect("zero offset");
    for format in [
        "%Y-%m-%dT%H:%M:%S",
        "%Y-%m-%dT%H:%M",
        "%Y-%m-%d %H:%M:%S",
        "%Y-%m-%d %H:%M",
    ] {
        if let Ok(t) = NaiveDateTime::parse_from_str(text, format) {
            return Ok(t.and_utc().with_timezone(&utc));
        }
    }
    if let Ok(d) = NaiveDate::parse_from_str(text, "%Y-%m-%d") {
        let t = d.and_hms_opt(0, 0, 0).expect("midnight");
        return Ok(t.and_utc().with_timezone(&utc));
    }
    bail!(
        "{flag} {text:?}: expected a time such as 2026-06-21T06:00:00+02:00 (RFC 3339), or \
         2026-06-21T06:00 or 2026-06-21 in UTC"
    )
}

/// A step's length: minutes (`60`, `60m`, `15min`) or hours (`1h`), at least a minute.
pub(crate) fn parse_step(text: &str) -> Result<TimeDelta> {
    let bad = || anyhow!("--step {text:?}: expected a length such as 60m, 15m or 1h");
    let t = text.trim();
    let (number, minutes_per) = if let Some(n) = t.strip_suffix("min") {
        (n, 1)
    } else if let Some(n) = t.strip_suffix('m') {
        (n, 1)
    } else if let Some(n) = t.strip_suffix('h') {
        (n, 60)
    } else {
        (t, 1)
    };
    let n: i64 = number.trim().parse().map_err(|_| bad())?;
    if !(1..=366 * 24 * 60).contains(&n) {
        return Err(bad());
    }
    Ok(TimeDelta::minutes(n * minutes_per))
}

/// The steps from `start` (included) to `end` (excluded) every `step`, the sun at each step's
/// start by SPA at `(latitude, longitude)`, refraction included, each weighing the step's
/// hours.
pub(crate) fn sun_steps(
    (latitude, longitude): (f64, f64),
    start: DateTime<FixedOffset>,
    end: DateTime<FixedOffset>,
    step: TimeDelta,
) -> Result<Vec<SunStep>> {
    if !(-90.0..=90.0).contains(&latitude) {
        bail!("--lat {latitude}: give degrees in [-90, 90]");
    }
    if !(-180.0..=180.0).contains(&longitude) {
        bail!("--lon {longitude}: give degrees in [-180, 180], east positive");
    }
    if end <= start {
        bail!("--end {end} is not after --start {start}");
    }
    let count = ((end - start).num_seconds() as f64 / step.num_seconds() as f64).ceil() as usize;
    if count > MAX_STEPS {
        bail!("{count} steps: at most {MAX_STEPS} (a year of minutes); take a longer --step");
    }
    let positions = SolarPositions::new();
    let location = Location {
        latitude,
        longitude,
    };
    let refraction = RefractionCorrection::new(PRESSURE_HPA, TEMPERATURE_C)
        .map_err(|e| anyhow!("refraction: {e}"))?;
    let hours = step.num_seconds() as f64 / 3600.0;
    let mut steps = Vec::with_capacity(count);
    let mut t = start;
    while t < end {
        let dt = delta_t::estimate_from_date_like(&t.with_timezone(&Utc))
            .map_err(|e| anyhow!("delta T at {t}: {e}"))?;
        let p = positions
            .at(&t, location, 0.0, dt, Some(refraction))
            .map_err(|e| anyhow!("the sun's position at {t}: {e}"))?;
        steps.push(SunStep {
            azimuth_deg: p.azimuth(),
            elevation_deg: p.elevation_angle(),
            hours,
        });
        t += step;
    }
    Ok(steps)
}

/// The hours at the camera's pixels, `size` of them, to the EXR `out` (channel `hours`) and the
/// colour map `png`; neither is left if one cannot be written.
fn write_pixels(out: &Path, png: Option<&Path>, size: (u32, u32), hours: &[f32]) -> Result<()> {
    let (w, h) = size;
    penumbra::geom::write_exr_channel(out, size, "hours", hours)
        .with_context(|| format!("writing {}", out.display()))?;
    if let Some(png) = png {
        let (pw, ph, rgb) = penumbra::geom::colour_map(hours, w as usize, h as usize, 'h');
        let written = penumbra::geom::write_png_bytes(
            png,
            pw as u32,
            ph as u32,
            penumbra::geom::PngColor::Rgb,
            &rgb,
        );
        if let Err(e) = written {
            let _ = std::fs::remove_file(out);
            return Err(e).with_context(|| format!("writing {}", png.display()));
        }
    }
    Ok(())
}

pub(crate) fn sun_hours(args: SunHoursArgs<'_>) -> Result<()> {
    let start = parse_time("--start", args.start)?;
    let end = parse_time("--end", args.end)?;
    let step = parse_step(args.step)?;
    let steps = sun_steps((args.latitude, args.longitude), start, end, step)?;
    let north = crate::cli::parse_direction("--north", args.frame.0)?;
    let up = crate::cli::parse_direction("--up", args.frame.1)?;
    if north.normalize().dot(up.normalize()).abs() > 1e-6 {
        bail!(
            "--north {} and --up {}: give two orthogonal directions",
            args.frame.0,
            args.frame.1
        );
    }
    let study = SunStudy {
        north,
        up,
        angular_size_deg: args.angular_size_deg,
        technique: args.technique,
        options: RenderOptions {
            samples: args.samples,
            jitter: false,
        },
    };
    study
        .options
        .pattern_for(args.technique)
        .in_command_words()?;
    if !(args.angular_size_deg > 0.0 && args.angular_size_deg <= 90.0) {
        bail!(
            "--angular-size {}: give the sun's full angle in degrees, in (0, 90]",
            args.angular_size_deg
        );
    }
    // Pixels to an EXR (and a PNG), or sensor points to a .npy or .csv file.
    let sensors = match args.points {
        None => {
            if args.out.extension().and_then(|e| e.to_str()) != Some("exr") {
                bail!(
                    "--out {}: the hours are written as an OpenEXR image (channel hours): name \
                     it .exr, or give --points for a .npy or .csv file of hours per point",
                    args.out.display()
                );
            }
            None
        }
        Some(points) => {
            if args.png.is_some() {
                bail!("--png draws the camera's pixels: it takes no --points");
            }
            let format = |path: &Path, flag: &str| {
                Format::of(path).ok_or_else(|| {
                    anyhow!(
                        "{flag} {}: with --points, name it .npy or .csv",
                        path.display()
                    )
                })
            };
            let normal = args
                .normal
                .map(|n| crate::cli::parse_direction("--normal", n))
                .transpose()?;
            Some((
                points,
                format(points, "--points")?,
                format(args.out, "--out")?,
                normal,
            ))
        }
    };
    let mut inputs = vec![args.scene.to_path_buf()];
    inputs.extend(args.points.map(Path::to_path_buf));
    let mut outputs = vec![args.out];
    outputs.extend(args.png);
    check_outputs(&inputs, &outputs)?;
    let scene = Scene::load(args.scene)?;
    inputs.extend(scene.input_files());
    check_outputs(&inputs, &outputs)?;
    let prepared = prepare(&outputs)?;
    let points = match &sensors {
        Some((path, format, _, normal)) => Some(read_points(path, *format, *normal, 1)?),
        None => None,
    };
    let daylight = steps.iter().filter(|s| study.is_day(s)).count();
    let bar = ProgressBar::new(steps.len() as u64);
    bar.set_style(
        ProgressStyle::with_template("sun steps [{bar:40}] {pos}/{len}, {elapsed} (eta {eta})")
            .expect("static template")
            .progress_chars("=> "),
    );
    let began = std::time::Instant::now();
    let mut renderer = Renderer::new(args.backend);
    let target = match &points {
        Some(p) => SunTarget::Points {
            points: &p.positions,
            normals: &p.normals,
        },
        None => SunTarget::Pixels,
    };
    let sum = renderer
        .sun_hours(&scene, &study, &steps, target, &|d| {
            bar.set_position(d as u64)
        })
        .map_err(|e| match &sensors {
            Some((path, format, _, normal)) => sensor_error(e, path, *format, *normal),
            None => render_error(e, "--samples"),
        })?;
    bar.finish_and_clear();
    let hours: Vec<f32> = sum.iter().map(|&v| v as f32).collect();
    let (w, h) = (scene.camera.width, scene.camera.height);
    let counted = match &sensors {
        Some((_, _, out_format, _)) => {
            write_values(
                args.out,
                *out_format,
                &[("hours".to_string(), hours.clone())],
            )?;
            format!("{} points", hours.len())
        }
        None => {
            write_pixels(args.out, args.png, (w, h), &hours)?;
            format!("{w}x{h} px")
        }
    };
    for d in prepared.keep() {
        eprintln!("created folder {}", d.display());
    }
    let max = hours.iter().copied().fold(0.0f32, f32::max);
    eprintln!(
        "{}: {counted}, {} steps of {} min ({daylight} in daylight), {} at {} samples, \
         up to {max:.2} h of sun, {:.2} s -> {}",
        args.scene.display(),
        steps.len(),
        step.num_minutes(),
        args.technique,
        args.samples,
        began.elapsed().as_secs_f64(),
        args.out.display()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_and_steps_as_users_write_them() {
        let t = parse_time("--start", "2026-06-21T06:00:00+02:00").unwrap();
        assert_eq!(
            t.with_timezone(&Utc).to_rfc3339(),
            "2026-06-21T04:00:00+00:00"
        );
        let u = parse_time("--start", "2026-06-21T04:00").unwrap();
        assert_eq!(t, u);
        assert_eq!(
            parse_time("--end", "2026-06-22").unwrap().to_rfc3339(),
            "2026-06-22T00:00:00+00:00"
        );
        let e = parse_time("--end", "June 22").unwrap_err().to_string();
        assert!(e.starts_with("--end \"June 22\": expected a time"), "{e}");
        assert_eq!(parse_step("60m").unwrap(), TimeDelta::minutes(60));
        assert_eq!(parse_step("1h").unwrap(), TimeDelta::minutes(60));
        assert_eq!(parse_step("15min").unwrap(), TimeDelta::minutes(15));
        assert_eq!(parse_step("30").unwrap(), TimeDelta::minutes(30));
        assert!(parse_step("0m").is_err() && parse_step("-5m").is_err());
        assert!(parse_step("fast").is_err());
    }

    #[test]
    fn the_sun_by_spa_against_its_published_example() {
        // Reda and Andreas (2004), Table A5.1 (Golden, Colorado, 17 October 2003 12:30:30
        // at UTC-7): azimuth 194.34024, topocentric zenith 50.11162 degrees, at 820 mbar and
        // 11 degrees C, 1830 m, delta T 67 s. Here: sea level, 1013 mbar, 12 degrees C and
        // delta T estimated, which move the zenith by about 0.006 degrees.
        let t = parse_time("--start", "2003-10-17T12:30:30-07:00").unwrap();
        let s = sun_steps(
            (39.742476, -105.1786),
            t,
            t + TimeDelta::minutes(1),
            TimeDelta::minutes(1),
        )
        .unwrap();
        assert_eq!(s.len(), 1);
        assert!((s[0].azimuth_deg - 194.34024).abs() < 0.01, "{:?}", s[0]);
        assert!(
            (90.0 - s[0].elevation_deg - 50.11162).abs() < 0.02,
            "{:?}",
            s[0]
        );
        assert_eq!(s[0].hours, 1.0 / 60.0);
        // A day of hours: 24 steps.
        let d = parse_time("--start", "2026-06-21").unwrap();
        let day = sun_steps(
            (48.85, 2.35),
            d,
            d + TimeDelta::days(1),
            TimeDelta::hours(1),
        )
        .unwrap();
        assert_eq!(day.len(), 24);
        assert!(day.iter().filter(|s| s.elevation_deg > 0.0).count() >= 15);
        let e = sun_steps((91.0, 0.0), d, d + TimeDelta::days(1), TimeDelta::hours(1));
        assert!(e.unwrap_err().to_string().contains("--lat 91"));
    }
}
