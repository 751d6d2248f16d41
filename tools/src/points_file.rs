//! The files of `penumbra points`: sensor points read from a NumPy `.npy` array or a CSV file
//! (`x,y,z,nx,ny,nz` per point, or `x,y,z` with one normal for all), and their visibility
//! written as a float32 `.npy` array or a CSV file, one column per light. A bad file is an error
//! naming it and where in it (a CSV line and column, a point's index), found before any point
//! is rendered.

use std::fmt;
use std::io::{BufRead, BufReader, Read, Write};
use std::path::Path;

use anyhow::{Context, Result, anyhow, bail};
use glam::DVec3;
use penumbra::geom::ImageError;

use crate::npy;

/// The bytes a point takes in memory with one light: its position and normal (48), its
/// result (4) and room for the work (8). Each further light adds a result of 4.
const BYTES_PER_POINT: u64 = 60;

/// The longest line read from a CSV file: a row of six numbers at full precision is about 150
/// bytes, so a longer one is not a row of points.
const MAX_CSV_LINE: u64 = 1 << 16;

/// The names of a row's columns, in messages.
const COLUMNS: [&str; 6] = ["x", "y", "z", "nx", "ny", "nz"];

/// A file format of the command, by its extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Format {
    /// NumPy's `.npy`.
    Npy,
    /// Comma-separated values.
    Csv,
}

impl Format {
    /// The format named by `path`'s extension (in any case), `None` for any other.
    pub(crate) fn of(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_string_lossy().to_ascii_lowercase();
        match ext.as_str() {
            "npy" => Some(Format::Npy),
            "csv" => Some(Format::Csv),
            _ => None,
        }
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Format::Npy => ".npy",
            Format::Csv => ".csv",
        })
    }
}

/// The sensors of a points file, in its order.
#[derive(Debug, Default)]
pub(crate) struct Points {
    pub(crate) positions: Vec<DVec3>,
    pub(crate) normals: Vec<DVec3>,
}

impl Points {
    pub(crate) fn len(&self) -> usize {
        self.positions.len()
    }
}

/// `Err` with a message when `n` points with results for `lights` lights would not fit in the
/// memory available ([`penumbra::geom::available_memory`]).
fn fits(n: u64, lights: usize) -> Result<(), String> {
    let per_point = BYTES_PER_POINT + 4 * (lights.max(1) as u64 - 1);
    let needed = n.saturating_mul(per_point);
    match penumbra::geom::available_memory() {
        Some(a) if needed > a => Err(format!(
            "{n} points take {:.1} GB with their results, more than the memory available ({:.1} GB)",
            needed as f64 / 1e9,
            a as f64 / 1e9
        )),
        _ => Ok(()),
    }
}

/// Opens the regular file at `path` (or the one a link there points to), with its length;
/// anything else (a folder, a FIFO, a device) is refused before it is opened.
fn open_regular(path: &Path) -> Result<(std::fs::File, u64)> {
    let m = std::fs::metadata(path).with_context(|| format!("{}", path.display()))?;
    if !m.is_file() {
        let what = if m.is_dir() {
            "a folder"
        } else {
            "a special file (FIFO, device or socket)"
        };
        bail!("{}: {what}, not a regular file", path.display());
    }
    let file = std::fs::File::open(path).with_context(|| format!("{}", path.display()))?;
    Ok((file, m.len()))
}

/// Reads the sensor points of `path` in `format`. A file of positions only (shape (n, 3), three
/// columns) takes `normal` for every point, and without it is refused; a file with normals
/// refuses `normal`. The points are checked finite and their normals non-zero, and their count
/// against the memory available for the results of `lights` lights.
pub(crate) fn read_points(
    path: &Path,
    format: Format,
    normal: Option<DVec3>,
    lights: usize,
) -> Result<Points> {
    let points = match format {
        Format::Npy => read_npy(path, normal, lights)?,
        Format::Csv => read_csv(path, normal, lights)?,
    };
    if points.len() == 0 {
        bail!("{}: the file holds no points", path.display());
    }
    Ok(points)
}

/// What a file of positions only lacks, for its message.
fn no_normals(normal_flag: &str) -> String {
    format!(
        "the file has positions only and no normals; --normal X,Y,Z supplies one normal for every point{normal_flag}"
    )
}

/// Checks the values of point `index` (a position and a normal); the error names the column.
fn check_point(values: &[f64; 6]) -> Result<(), String> {
    if let Some(c) = (0..6).find(|&c| !values[c].is_finite()) {
        return Err(format!(
            "{} = {} is not a finite number",
            COLUMNS[c], values[c]
        ));
    }
    if values[3..].iter().all(|&v| v == 0.0) {
        return Err("the normal (0, 0, 0) is zero: a sensor's normal needs a direction".into());
    }
    Ok(())
}

fn read_npy(path: &Path, normal: Option<DVec3>, lights: usize) -> Result<Points> {
    let at = path.display();
    let (file, len) = open_regular(path)?;
    let mut r = BufReader::new(file);
    let header = npy::read_header(&mut r).map_err(|e| anyhow!("{at}: {e}"))?;
    let shape = header.shape_text();
    let (n, cols) = match header.shape[..] {
        [n, c @ (3 | 6)] => (n, c as usize),
        _ => bail!(
            "{at}: the array's shape is {shape}; the points are an array of shape (n, 6), a row x, y, z, nx, ny, nz per point, or (n, 3) of positions with --normal"
        ),
    };
    match (cols, normal) {
        (3, None) => bail!("{at}: shape {shape}: {}", no_normals("")),
        (6, Some(_)) => bail!(
            "{at}: shape {shape} holds a normal for each point; --normal is for files of positions only, shape (n, 3)"
        ),
        _ => {}
    }
    let declared = header
        .data_len()
        .ok_or_else(|| anyhow!("{at}: shape {shape} declares more bytes than a file can hold"))?;
    let held = len.saturating_sub(header.data_offset);
    if held < declared {
        bail!(
            "{at}: the data is truncated: shape {shape} of {} takes {declared} bytes and the file holds {held} after its header",
            header.dtype
        );
    }
    if held > declared {
        bail!(
            "{at}: the file holds {held} bytes after its header, more than the {declared} that shape {shape} of {} takes",
            header.dtype
        );
    }
    fits(n, lights).map_err(|e| anyhow!("{at}: {e}"))?;
    let n = n as usize;
    let mut points = Points {
        positions: Vec::with_capacity(n),
        normals: Vec::with_capacity(n),
    };
    let item = header.dtype.size();
    let row_bytes = cols * item;
    // A few thousand rows at a time.
    let rows_per_read = 4096;
    let mut buf = vec![0u8; row_bytes * rows_per_read];
    let mut index = 0usize;
    while index < n {
        let rows = rows_per_read.min(n - index);
        let chunk = &mut buf[..rows * row_bytes];
        r.read_exact(chunk)
            .with_context(|| format!("{at}: reading point {index}"))?;
        for row in chunk.chunks_exact(row_bytes) {
            let mut v = [0.0; 6];
            for (c, x) in row.chunks_exact(item).enumerate() {
                v[c] = header.dtype.value(x);
            }
            if let Some(nrm) = normal {
                v[3..].copy_from_slice(&nrm.to_array());
            }
            check_point(&v).map_err(|e| {
                anyhow!("{at}: point {index} (row {index} of the array, from 0): {e}")
            })?;
            points.positions.push(DVec3::new(v[0], v[1], v[2]));
            points.normals.push(DVec3::new(v[3], v[4], v[5]));
            index += 1;
        }
    }
    Ok(points)
}

/// Reads the rows of the CSV file at `path`, giving each to `row` with its line (from 1) and
/// its six values (the normal from `normal` in a file of positions only), checked. Blank lines
/// and lines beginning with `#` are skipped; the first other line is a header when none of its
/// fields is a number.
fn scan_csv(
    path: &Path,
    normal: Option<DVec3>,
    mut row: impl FnMut(u64, [f64; 6]) -> Result<()>,
) -> Result<()> {
    let at = path.display();
    let (file, _) = open_regular(path)?;
    let mut r = BufReader::new(file);
    let want = if normal.is_some() { 3 } else { 6 };
    let mut bytes = Vec::new();
    let mut line = 0u64;
    let mut first = true;
    loop {
        bytes.clear();
        line += 1;
        let got = (&mut r)
            .take(MAX_CSV_LINE)
            .read_until(b'\n', &mut bytes)
            .with_context(|| format!("{at}:{line}"))?;
        if got == 0 {
            return Ok(());
        }
        if bytes.len() as u64 == MAX_CSV_LINE && bytes.last() != Some(&b'\n') {
            bail!("{at}:{line}: the line is longer than {MAX_CSV_LINE} bytes");
        }
        let text = std::str::from_utf8(&bytes)
            .map_err(|_| anyhow!("{at}:{line}: the line is not UTF-8 text"))?
            // A byte-order mark, as spreadsheets write at the start of a UTF-8 file.
            .trim_start_matches('\u{feff}')
            .trim();
        if text.is_empty() || text.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = text.split(',').map(str::trim).collect();
        let header = first && fields.iter().all(|f| f.parse::<f64>().is_err());
        first = false;
        let what = if header {
            "the header names"
        } else {
            "the row has"
        };
        match (fields.len(), normal) {
            (k, _) if k == want => {}
            (3, None) => bail!(
                "{at}:{line}: {what} 3 columns (x, y, z): {}",
                no_normals(" (or give the columns nx, ny, nz)")
            ),
            (6, Some(_)) => bail!(
                "{at}:{line}: {what} 6 columns (x, y, z, nx, ny, nz); --normal is for files of positions only, 3 columns"
            ),
            (k, _) => bail!(
                "{at}:{line}: {what} {k} columns; a row is {} ({want} numbers separated by commas)",
                COLUMNS[..want].join(",")
            ),
        }
        if header {
            continue;
        }
        let mut v = [0.0; 6];
        for (c, f) in fields.iter().enumerate() {
            let name = COLUMNS[c];
            let column = c + 1;
            v[c] = f.parse::<f64>().map_err(|_| {
                anyhow!("{at}:{line}: column {column} ({name}): {f:?} is not a number")
            })?;
            if !v[c].is_finite() {
                bail!("{at}:{line}: column {column} ({name}): {f} is not a finite number");
            }
        }
        if let Some(nrm) = normal {
            v[3..].copy_from_slice(&nrm.to_array());
        }
        check_point(&v).map_err(|e| anyhow!("{at}:{line}: {e}"))?;
        row(line, v)?;
    }
}

fn read_csv(path: &Path, normal: Option<DVec3>, lights: usize) -> Result<Points> {
    let mut points = Points::default();
    scan_csv(path, normal, |line, v| {
        if points.positions.len() == points.positions.capacity() {
            // Before the vectors grow, the memory for as many points as they will hold.
            let more = points.positions.capacity().max(1024);
            let total = points.positions.len() + more;
            fits(total as u64, lights).map_err(|e| anyhow!("{}:{line}: {e}", path.display()))?;
            points.positions.reserve_exact(more);
            points.normals.reserve_exact(more);
        }
        points.positions.push(DVec3::new(v[0], v[1], v[2]));
        points.normals.push(DVec3::new(v[3], v[4], v[5]));
        Ok(())
    })?;
    Ok(points)
}

/// A render's error over the points of `path`: a bad sensor told by its place in the file
/// ([`point_place`]), the others in the command's words.
pub(crate) fn sensor_error(
    error: penumbra::RenderError,
    path: &Path,
    format: Format,
    normal: Option<DVec3>,
) -> anyhow::Error {
    match error {
        penumbra::RenderError::BadSensor { index, problem } => {
            anyhow!("{}: {problem}", point_place(path, format, normal, index))
        }
        e => crate::words::render_error(e, "--samples"),
    }
}

/// Where point `index` of a points file is, for a message: `FILE:LINE` in a CSV file,
/// `FILE: point INDEX` in a `.npy` file.
fn point_place(path: &Path, format: Format, normal: Option<DVec3>, index: u64) -> String {
    let at = path.display();
    if format == Format::Csv {
        let mut k = 0u64;
        let mut found = None;
        let _ = scan_csv(path, normal, |line, _| {
            if k == index {
                found = Some(line);
                // Stops the scan: the line is found.
                bail!("found");
            }
            k += 1;
            Ok(())
        });
        if let Some(line) = found {
            return format!("{at}:{line}: point {index}");
        }
    }
    format!("{at}: point {index} (from 0)")
}

/// Writes the visibility `columns` (a name and a value per point each, all as long) to `path`
/// in `format`, through a temporary file renamed into place: `.npy` a float32 array, shape
/// `(n,)` of one column and `(n, columns)` of several; `.csv` a header line of the columns'
/// names then a row per point.
pub(crate) fn write_values(
    path: &Path,
    format: Format,
    columns: &[(String, Vec<f32>)],
) -> Result<()> {
    let n = columns.first().map_or(0, |c| c.1.len());
    assert!(
        columns.iter().all(|c| c.1.len() == n),
        "columns of one length"
    );
    penumbra::geom::write_atomically(path, |tmp| {
        let io = |e: std::io::Error| ImageError::Io {
            path: tmp.to_path_buf(),
            message: e.to_string(),
        };
        let mut w = std::io::BufWriter::new(std::fs::File::create(tmp).map_err(io)?);
        match format {
            Format::Npy => {
                let shape: Vec<u64> = if columns.len() == 1 {
                    vec![n as u64]
                } else {
                    vec![n as u64, columns.len() as u64]
                };
                w.write_all(&npy::f4_preamble(&shape)).map_err(io)?;
                for i in 0..n {
                    for c in columns {
                        w.write_all(&c.1[i].to_le_bytes()).map_err(io)?;
                    }
                }
            }
            Format::Csv => {
                let names: Vec<&str> = columns.iter().map(|c| c.0.as_str()).collect();
                writeln!(w, "{}", names.join(",")).map_err(io)?;
                for i in 0..n {
                    for (k, c) in columns.iter().enumerate() {
                        let sep = if k + 1 == columns.len() { "\n" } else { "," };
                        write!(w, "{}{sep}", c.1[i]).map_err(io)?;
                    }
                }
            }
        }
        w.flush().map_err(io)
    })
    .with_context(|| format!("writing {}", path.display()))
}
