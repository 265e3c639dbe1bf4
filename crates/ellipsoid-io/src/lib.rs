//! Writers for simulation results, shared by the `ellipsoid` command-line tool and the
//! Python package: the trajectory as CSV or (feature `hdf5`) HDF5, the run summary as
//! JSON, every file written atomically (a temporary file in the target's directory,
//! renamed into place only when complete).
//!
//! Column names and units are declared once, in [`columns`]. Trajectories are read back by
//! [`table`]; `viewer` (feature `viewer`) makes the self-contained 3-D viewer page from one,
//! `animate` (feature `animate`) a GIF animation.

#[cfg(feature = "animate")]
pub mod animate;
pub mod atomic;
pub mod columns;
pub mod csv;
#[cfg(feature = "hdf5")]
pub mod hdf5;
pub mod panels;
pub mod restore;
pub mod run;
pub mod summary;
pub mod table;
#[cfg(feature = "viewer")]
pub mod viewer;

use std::path::{Path, PathBuf};

use ellipsoid_core::simulate::Sample;

pub use summary::Summary;

/// How to get a build that writes HDF5 (used in the error of a build without it).
pub const HDF5_HINT: &str = "this ellipsoid was built without HDF5 support; install the default \
build, which includes it: `cargo install --path crates/ellipsoid-cli` (the HDF5 C library is \
built from source; needs cmake >= 3.26), or write CSV with `-o FILE.csv`";

/// Why an output could not be written.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The file name's extension names no format we write.
    #[error("{path}: unknown output format {extension:?}; use .csv or .h5")]
    UnknownFormat { path: PathBuf, extension: String },
    /// `.h5` asked of a build without the `hdf5` feature.
    #[error("{path}: {HDF5_HINT}")]
    Hdf5Unavailable { path: PathBuf },
    /// The file system refused.
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// The HDF5 library refused.
    #[error("{path}: HDF5: {message}")]
    Hdf5 { path: PathBuf, message: String },
}

impl OutputError {
    pub(crate) fn io(path: &Path, source: std::io::Error) -> Self {
        OutputError::Io {
            path: path.to_owned(),
            source,
        }
    }
}

/// A trajectory file format, chosen by extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// `.csv`: one header line, one row per sample.
    Csv,
    /// `.h5` / `.hdf5`: one dataset per column.
    Hdf5,
}

impl Format {
    /// The format named by `path`'s extension (case-insensitive). `.h5` from a build
    /// without the `hdf5` feature is an error that says how to get one.
    pub fn from_path(path: &Path) -> Result<Format, OutputError> {
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_lowercase())
            .unwrap_or_default();
        match ext.as_str() {
            "csv" => Ok(Format::Csv),
            "h5" | "hdf5" if cfg!(feature = "hdf5") => Ok(Format::Hdf5),
            "h5" | "hdf5" => Err(OutputError::Hdf5Unavailable {
                path: path.to_owned(),
            }),
            _ => Err(OutputError::UnknownFormat {
                path: path.to_owned(),
                extension: ext,
            }),
        }
    }
}

/// What a trajectory file records besides the samples.
#[derive(Debug, Clone, Copy)]
pub struct Metadata<'a> {
    /// The scenario's TOML text.
    pub scenario_text: &'a str,
    /// The run summary (its JSON is stored whole in HDF5 files).
    pub summary: &'a Summary,
}

/// A trajectory being written: samples stream in, then [`TrajectoryWriter::finish`]
/// puts the file in place. Dropped unfinished, it leaves nothing behind.
pub enum TrajectoryWriter {
    Csv(csv::CsvFile),
    #[cfg(feature = "hdf5")]
    Hdf5(hdf5::Hdf5File),
}

impl TrajectoryWriter {
    /// Starts a trajectory file at `path` (its directory must exist), format by extension,
    /// with the fixed columns (a one-surface body's).
    pub fn create(path: &Path) -> Result<Self, OutputError> {
        Self::start(path, None, columns::Layout::fixed())
    }

    /// Starts the trajectory file of a run of `scenario`, with its body's columns
    /// ([`columns::Layout`]): a CSV file begins with the comment line naming the scenario
    /// and its body ([`csv::comment`]; an HDF5 file stores the scenario at the end).
    pub fn for_scenario(
        path: &Path,
        scenario: &ellipsoid_core::scenario::Scenario,
    ) -> Result<Self, OutputError> {
        let layout = columns::Layout::of(&scenario.scene.body);
        Self::start(path, Some(&csv::comment(scenario)), layout)
    }

    fn start(
        path: &Path,
        comment: Option<&str>,
        layout: columns::Layout,
    ) -> Result<Self, OutputError> {
        match Format::from_path(path)? {
            Format::Csv => Ok(TrajectoryWriter::Csv(csv::CsvFile::create(
                path, comment, layout,
            )?)),
            #[cfg(feature = "hdf5")]
            Format::Hdf5 => Ok(TrajectoryWriter::Hdf5(hdf5::Hdf5File::create(
                path, layout,
            )?)),
            #[cfg(not(feature = "hdf5"))]
            Format::Hdf5 => unreachable!("Format::from_path refuses HDF5 without the feature"),
        }
    }

    /// Appends one sample (finite: the core stops a run at a non-finite one).
    pub fn write(&mut self, sample: &Sample) -> Result<(), OutputError> {
        match self {
            TrajectoryWriter::Csv(w) => w.write(sample),
            #[cfg(feature = "hdf5")]
            TrajectoryWriter::Hdf5(w) => {
                w.write(sample);
                Ok(())
            }
        }
    }

    /// Samples written so far.
    pub fn rows(&self) -> u64 {
        match self {
            TrajectoryWriter::Csv(w) => w.rows(),
            #[cfg(feature = "hdf5")]
            TrajectoryWriter::Hdf5(w) => w.rows(),
        }
    }

    /// Completes the file (CSV has no room for `meta`) and renames it into place.
    pub fn finish(self, meta: &Metadata<'_>) -> Result<(), OutputError> {
        self.prepare(meta)?.commit()
    }

    /// Completes the file in its temporary; [`atomic::Prepared::commit`] (or
    /// [`atomic::commit_all`], with other files) puts it in place.
    #[cfg_attr(not(feature = "hdf5"), allow(unused_variables))] // only HDF5 files store metadata
    pub fn prepare(self, meta: &Metadata<'_>) -> Result<atomic::Prepared, OutputError> {
        match self {
            TrajectoryWriter::Csv(w) => w.prepare(),
            #[cfg(feature = "hdf5")]
            TrajectoryWriter::Hdf5(w) => w.prepare(meta),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ellipsoid_core::simulate::Mode;
    use ellipsoid_core::state::EulerAngles;
    use nalgebra::Vector3;

    fn sample() -> Sample {
        Sample {
            t: 0.1,
            position: Vector3::new(1e-300, -0.0, 0.014818069210007943),
            angles: EulerAngles {
                theta: 0.1,
                phi: 1.0 / 3.0,
                ..Default::default()
            },
            omega: Vector3::new(0.0, 0.0, 60.0),
            omega_world: Vector3::new(0.0, 0.0, 60.0),
            velocity: Vector3::zeros(),
            contact: nalgebra::Vector2::new(0.5, -0.25),
            drift: -1.5e-13,
            energy: 2.9768262947508894e-2,
            work: 0.0,
            normal_force: 0.5,
            slip_speed: 0.0,
            gap: 0.0,
            mode: Mode::Sliding,
            touching: [None; ellipsoid_core::model::MOST_CONTACTS],
        }
    }

    #[test]
    fn csv_rows_round_trip_and_put_mode_before_work() {
        let mut w = csv::CsvWriter::new(Vec::new()).unwrap();
        w.write(&sample()).unwrap();
        let text = String::from_utf8(w.into_inner().unwrap()).unwrap();
        let mut lines = text.lines();
        assert_eq!(
            lines.next().unwrap(),
            "t,x,y,z,theta,phi,psi,theta_dot,phi_dot,psi_dot,omega_x,omega_y,omega_z,vx,vy,vz,energy,normal_force,slip_speed,mode,work,omega_world_x,omega_world_y,omega_world_z,contact_x,contact_y,drift,gap"
        );
        let row: Vec<&str> = lines.next().unwrap().split(',').collect();
        assert_eq!(row[19], "sliding");
        let numbers: Vec<f64> = row
            .iter()
            .enumerate()
            .filter(|(i, _)| *i != 19)
            .map(|(_, v)| v.parse().unwrap())
            .collect();
        assert_eq!(
            numbers.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            columns::values(&sample())
                .iter()
                .map(|v| v.to_bits())
                .collect::<Vec<_>>()
        );
        assert_eq!(row[1], "1e-300");
    }

    /// Every finite double reads back from the CSV to the same bits, over random bit
    /// patterns (all exponents, subnormals and signed zeros included).
    #[test]
    fn csv_numbers_round_trip_over_random_bit_patterns() {
        let mut bits = 0x9E37_79B9_7F4A_7C15_u64;
        let mut next = || loop {
            bits ^= bits << 13;
            bits ^= bits >> 7;
            bits ^= bits << 17;
            let v = f64::from_bits(bits);
            if v.is_finite() {
                return v;
            }
        };
        let mut w = csv::CsvWriter::new(Vec::new()).unwrap();
        let mut written = Vec::new();
        for _ in 0..20_000 {
            let mut s = sample();
            s.t = next();
            s.position = Vector3::new(next(), next(), next());
            s.omega = Vector3::new(next(), next(), next());
            s.energy = next();
            s.gap = next();
            written.push(columns::values(&s));
            w.write(&s).unwrap();
        }
        let text = String::from_utf8(w.into_inner().unwrap()).unwrap();
        for (line, want) in text.lines().skip(1).zip(&written) {
            let got: Vec<u64> = line
                .split(',')
                .enumerate()
                .filter(|(i, _)| *i != columns::MODE_POSITION)
                .map(|(_, v)| v.parse::<f64>().unwrap().to_bits())
                .collect();
            assert_eq!(got, want.map(f64::to_bits), "{line}");
        }
        assert_eq!(text.lines().count(), written.len() + 1);
    }

    /// The file written through the formatting thread holds exactly the text the
    /// writer makes on one thread, in order, for a row count that is no multiple of the
    /// batch; dropped unfinished after as many rows, it leaves nothing behind.
    #[test]
    fn csv_files_formatted_on_their_own_thread_keep_every_row_in_order() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.csv");
        let rows: Vec<Sample> = (0..2_777)
            .map(|k| {
                let mut s = sample();
                s.t = k as f64 * 1e-3;
                s.energy = (k as f64).sqrt();
                s
            })
            .collect();
        let mut w = TrajectoryWriter::create(&path).unwrap();
        let mut reference = csv::CsvWriter::new(Vec::new()).unwrap();
        for s in &rows {
            w.write(s).unwrap();
            reference.write(s).unwrap();
        }
        assert_eq!(w.rows(), 2_777);
        let TrajectoryWriter::Csv(file) = w else {
            unreachable!("a .csv path")
        };
        file.prepare().unwrap().commit().unwrap();
        assert_eq!(
            std::fs::read(&path).unwrap(),
            reference.into_inner().unwrap()
        );

        let other = dir.path().join("u.csv");
        let mut w = TrajectoryWriter::create(&other).unwrap();
        for s in &rows {
            w.write(s).unwrap();
        }
        drop(w);
        let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert_eq!(left.len(), 1, "only t.csv: {left:?}");
    }

    #[test]
    fn formats_by_extension() {
        assert_eq!(
            Format::from_path(Path::new("a/b.CSV")).unwrap(),
            Format::Csv
        );
        assert!(matches!(
            Format::from_path(Path::new("b.txt")),
            Err(OutputError::UnknownFormat { .. })
        ));
        let h5 = Format::from_path(Path::new("b.h5"));
        if cfg!(feature = "hdf5") {
            assert_eq!(h5.unwrap(), Format::Hdf5);
        } else {
            assert!(
                h5.unwrap_err()
                    .to_string()
                    .contains("built without HDF5 support")
            );
        }
    }

    #[test]
    fn an_unfinished_file_leaves_nothing_behind() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.csv");
        let mut w = TrajectoryWriter::create(&path).unwrap();
        w.write(&sample()).unwrap();
        drop(w);
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
        atomic::write(&path, b"x").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"x");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }
}
