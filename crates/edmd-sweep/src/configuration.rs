//! A configuration to start from (`init.from`): positions, velocities and, where given, radii,
//! masses and spins, read from an edmd replica file (or any H5MD file of the same layout) or a plain-text file.

use std::path::Path;

use crate::spec::FromSpec;

/// Particles read from a file, row-major N × D.
#[derive(Debug, Clone, PartialEq)]
pub struct Configuration {
    /// The dimension.
    pub dim: usize,
    /// Positions, N × D.
    pub position: Vec<f64>,
    /// Velocities, N × D.
    pub velocity: Vec<f64>,
    /// Radii, if the file gives them.
    pub radius: Option<Vec<f64>>,
    /// Masses, if the file gives them.
    pub mass: Option<Vec<f64>>,
    /// The box's sides, if the file gives them.
    pub box_len: Option<Vec<f64>>,
    /// Angular velocities, N × 1 (2D: z) or N × 3, if the file gives them.
    pub spin: Option<Vec<f64>>,
}

/// Components of an angular velocity: z alone in 2D, all three in 3D.
pub fn spin_width(dim: usize) -> usize {
    if dim == 2 {
        1
    } else {
        3
    }
}

impl Configuration {
    /// Particles.
    pub fn n(&self) -> usize {
        self.position.len() / self.dim
    }
}

/// Reads `from` for a replica of dimension `dim` (a text file does not say it); the error says
/// what is wrong with the file, in a line.
pub fn load(from: &FromSpec, dim: usize) -> Result<Configuration, String> {
    let path = Path::new(&from.file);
    let c = if path.extension().is_some_and(|e| e == "h5" || e == "hdf5") {
        load_h5(path, from.tau)?
    } else {
        load_text(path, dim)?
    };
    if c.dim != dim {
        return Err(format!("{}D particles, the grid's dim is {dim}", c.dim));
    }
    let finite = |name: &str, v: &[f64]| {
        v.iter().position(|x| !x.is_finite()).map_or(Ok(()), |k| {
            Err(format!("particle {}: {name} = {}", k / c.dim, v[k]))
        })
    };
    finite("position", &c.position)?;
    finite("velocity", &c.velocity)?;
    if let Some(w) = &c.spin {
        let width = spin_width(dim);
        if let Some(k) = w.iter().position(|x| !x.is_finite()) {
            return Err(format!(
                "particle {}: angular velocity = {}",
                k / width,
                w[k]
            ));
        }
        if w.len() != c.n() * width {
            return Err(format!(
                "{} angular velocities for {} particles",
                w.len() / width,
                c.n()
            ));
        }
    }
    Ok(c)
}

/// The snapshot of an H5MD file nearest `tau` (by pair collisions per particle), or its last.
fn load_h5(path: &Path, tau: Option<f64>) -> Result<Configuration, String> {
    let read = || -> hdf5::Result<Configuration> {
        let gas = hdf5::File::open(path)?.group("particles/gas")?;
        let pos = gas.dataset("position/value")?;
        let shape = pos.shape();
        let [k, n, dim] = shape[..] else {
            return Err(hdf5::Error::from("position/value is not frames × N × D"));
        };
        let steps: Vec<i64> = gas.dataset("position/step")?.read_raw()?;
        let frame = match tau {
            None => k - 1,
            Some(t) => (0..k)
                .min_by(|&a, &b| {
                    let d = |j: usize| (steps[j] as f64 / n as f64 - t).abs();
                    d(a).total_cmp(&d(b))
                })
                .unwrap_or(k - 1),
        };
        let frame_of = |name: &str| -> hdf5::Result<Vec<f64>> {
            let data = gas.dataset(name)?;
            let width = data.shape().last().copied().unwrap_or(dim);
            let all: Vec<f64> = data.read_raw()?;
            Ok(all[frame * n * width..(frame + 1) * n * width].to_vec())
        };
        let per_particle = |name: &str| gas.dataset(name).and_then(|d| d.read_raw::<f64>()).ok();
        let box_len = gas
            .dataset("box/edges")
            .and_then(|d| d.read_raw::<f64>())
            .ok();
        Ok(Configuration {
            dim,
            position: frame_of("position/value")?,
            velocity: frame_of("velocity/value")?,
            radius: per_particle("radius"),
            mass: per_particle("mass"),
            box_len,
            spin: gas
                .link_exists("angular_velocity")
                .then(|| frame_of("angular_velocity/value"))
                .transpose()?,
        })
    };
    if !path.exists() {
        return Err("no such file".into());
    }
    read().map_err(|e| e.to_string())
}

/// Lines of D positions, D velocities, then optionally a radius and a mass, then optionally the
/// angular velocity (z in 2D, three components in 3D); `#` starts a comment.
fn load_text(path: &Path, dim: usize) -> Result<Configuration, String> {
    let text = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
    let mut rows: Vec<Vec<f64>> = Vec::new();
    for (k, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let row: Result<Vec<f64>, _> = line.split_whitespace().map(str::parse::<f64>).collect();
        let row = row.map_err(|e| format!("line {}: {e}", k + 1))?;
        if rows.first().is_some_and(|r| r.len() != row.len()) {
            return Err(format!(
                "line {}: {} columns, the first row has {}",
                k + 1,
                row.len(),
                rows[0].len()
            ));
        }
        let with_spin = 2 * dim + 2 + spin_width(dim);
        if !(2 * dim..=2 * dim + 2).contains(&row.len()) && row.len() != with_spin {
            return Err(format!(
                "line {}: {} columns; {dim}D needs {} (positions, velocities), then optionally a radius and a mass, then optionally {} of angular velocity",
                k + 1,
                row.len(),
                2 * dim,
                spin_width(dim)
            ));
        }
        rows.push(row);
    }
    let cols = rows.first().map_or(2 * dim, Vec::len);
    let column = |j: usize| (cols > j).then(|| rows.iter().map(|r| r[j]).collect::<Vec<f64>>());
    Ok(Configuration {
        dim,
        position: rows.iter().flat_map(|r| r[..dim].to_vec()).collect(),
        velocity: rows.iter().flat_map(|r| r[dim..2 * dim].to_vec()).collect(),
        radius: column(2 * dim),
        mass: column(2 * dim + 1),
        box_len: None,
        spin: (cols > 2 * dim + 2).then(|| {
            rows.iter()
                .flat_map(|r| r[2 * dim + 2..].to_vec())
                .collect()
        }),
    })
}
