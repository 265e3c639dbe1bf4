//! HDF5 trajectories (feature `hdf5`: the system libhdf5; with `hdf5-static`, the default
//! of the CLI and the Python package, the HDF5 C library built from source and linked in).
//!
//! Layout, readable by h5py without special knowledge:
//! ```text
//! /t, /x, …, /work      float64 datasets, one per numeric column, attribute `units`
//!                       (a body with contact spheres adds its per-surface columns)
//! /mode                 fixed-length ASCII strings (h5py: numpy bytes, e.g. b"sliding";
//!                       12 bytes, 64 for a body with contact spheres)
//! root attributes       version, scenario (the TOML text), scenario_path, status,
//!                       message, columns (comma-separated, file order), summary (JSON),
//!                       stats_accepted, stats_rejected, stats_rhs_evals, stats_events,
//!                       drift_<invariant> (only for the invariants that are conserved)
//! ```
//! Samples are buffered in memory, a row of f64 each (27, plus five per surface of a body
//! with contact spheres) and a byte for the mode, and written column by column when the
//! run ends, to a temporary file renamed into place.

use std::borrow::Cow;
use std::path::{Path, PathBuf};

use ellipsoid_core::simulate::{Mode, Sample};
use h5::types::{FixedAscii, VarLenUnicode};
use hdf5_metno as h5;
use tempfile::TempPath;

use crate::atomic;
use crate::columns::{self, Layout, NUMERIC_COLUMNS};
use crate::{Metadata, OutputError};

/// Turns off HDF5's plugin loading for the whole process, before any file is opened: with
/// it on, reading a dataset whose filter is not built in makes HDF5 `dlopen` every library
/// in its plugin directories (by default a path inside the build tree, then
/// `/usr/local/hdf5/lib/plugin`), so whoever can write there runs code in this process.
/// Also empties the plugin search path, so that no error names it. Idempotent; called at
/// start-up by the CLI and the Python module, and again by every function here that opens
/// a file (so library users are covered too).
pub fn forbid_plugins() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        h5::sync::sync(|| {
            // SAFETY: plain calls into the HDF5 library, serialised by its lock; the
            // library is initialised by `sync`.
            unsafe {
                let off = plugin_ffi::H5PLset_loading_state(0);
                assert!(off >= 0, "HDF5 refused to turn plugin loading off");
                let mut paths: std::ffi::c_uint = 0;
                while plugin_ffi::H5PLsize(&mut paths) >= 0 && paths > 0 {
                    if plugin_ffi::H5PLremove(0) < 0 {
                        break;
                    }
                }
            }
        })
    });
}

/// Whether HDF5 may load plugins of any kind, and how many plugin directories it searches
/// (after [`forbid_plugins`]: `(false, 0)`).
pub fn plugin_state() -> (bool, u32) {
    h5::sync::sync(|| {
        let mut mask: std::ffi::c_uint = 0;
        let mut paths: std::ffi::c_uint = 0;
        // SAFETY: as in `forbid_plugins`; both write one integer through a valid pointer.
        unsafe {
            plugin_ffi::H5PLget_loading_state(&mut mask);
            plugin_ffi::H5PLsize(&mut paths);
        }
        (mask != 0, paths)
    })
}

/// The plugin controls of H5PLpublic.h, declared with their C signatures (the
/// `hdf5-metno-sys` declaration of `H5PLset_loading_state` takes a pointer where the C
/// function takes the mask by value).
mod plugin_ffi {
    use std::ffi::{c_int, c_uint};
    unsafe extern "C" {
        pub fn H5PLset_loading_state(plugin_control_mask: c_uint) -> c_int;
        pub fn H5PLget_loading_state(plugin_control_mask: *mut c_uint) -> c_int;
        pub fn H5PLsize(num_paths: *mut c_uint) -> c_int;
        pub fn H5PLremove(index: c_uint) -> c_int;
    }
}

/// Refuses a dataset whose filter pipeline needs a filter this build lacks (with plugins
/// off, any filter that is not built in: this build has shuffle, Fletcher32, N-bit and
/// scale-offset, not deflate/gzip, szip or third-party compressors), before reading it.
pub fn check_filters(ds: &h5::Dataset, name: &str) -> Result<(), String> {
    forbid_plugins();
    for filter in ds.filters() {
        if !filter.is_available() {
            let id = filter.id();
            let what = match id {
                1 => "deflate (gzip)".to_owned(),
                4 => "szip".to_owned(),
                _ => format!("filter {id}"),
            };
            return Err(format!(
                "the dataset `{name}` is compressed with a filter this build lacks ({what}); \
                 write it uncompressed (h5py: no `compression=`), or as written by `ellipsoid run`"
            ));
        }
    }
    Ok(())
}

/// Opens an HDF5 file for reading, plugins off ([`forbid_plugins`]).
pub fn open(path: &Path) -> h5::Result<h5::File> {
    forbid_plugins();
    h5::File::open(path)
}

/// Creates (truncates) an HDF5 file, plugins off ([`forbid_plugins`]).
fn create(path: &Path) -> h5::Result<h5::File> {
    forbid_plugins();
    h5::File::create(path)
}

/// Longest mode name ("frictionless").
const MODE_LEN: usize = 12;

/// Longest mode label of a body with contact spheres ("two_contacts@" and two names of
/// at most `body::MAX_NAME` bytes joined by "+").
pub(crate) const LABEL_LEN: usize = 64;

/// A `mode` column: a code per row into the labels met, in order of first appearance.
#[derive(Default)]
struct Modes {
    codes: Vec<u8>,
    labels: Vec<String>,
}

impl Modes {
    fn push(&mut self, label: &str) {
        let code = match self.labels.iter().position(|l| l == label) {
            Some(k) => k,
            None => {
                self.labels.push(label.to_owned());
                self.labels.len() - 1
            }
        };
        self.codes
            .push(u8::try_from(code).expect("fewer than 256 mode labels"));
    }

    /// Writes the column as the dataset `mode`: fixed-length ASCII strings of
    /// [`MODE_LEN`] bytes, or [`LABEL_LEN`] when a label is longer.
    fn write(&self, loc: &h5::Group) -> h5::Result<h5::Dataset> {
        fn fixed<const N: usize>(m: &Modes, loc: &h5::Group) -> h5::Result<h5::Dataset> {
            let labels: Vec<FixedAscii<N>> = m
                .labels
                .iter()
                .map(|l| FixedAscii::from_ascii(l.as_bytes()).expect("mode labels are ASCII"))
                .collect();
            let rows: Vec<FixedAscii<N>> =
                m.codes.iter().map(|&c| labels[usize::from(c)]).collect();
            loc.new_dataset_builder()
                .with_data(&rows)
                .create(columns::MODE)
        }
        if self.labels.iter().all(|l| l.len() <= MODE_LEN) {
            fixed::<MODE_LEN>(self, loc)
        } else {
            fixed::<LABEL_LEN>(self, loc)
        }
    }
}

/// An HDF5 trajectory being collected.
pub struct Hdf5File {
    path: PathBuf,
    tmp: TempPath,
    layout: Layout,
    /// The numeric values, a row of `layout.numeric()` per sample.
    rows: Vec<f64>,
    modes: Modes,
}

impl Hdf5File {
    /// Reserves a temporary file beside `path` (so an unwritable directory fails early),
    /// for the columns of `layout`.
    pub fn create(path: &Path, layout: Layout) -> Result<Self, OutputError> {
        let tmp = atomic::temporary(path)?.into_temp_path();
        Ok(Hdf5File {
            path: path.to_owned(),
            tmp,
            layout,
            rows: Vec::new(),
            modes: Modes::default(),
        })
    }

    pub fn write(&mut self, s: &Sample) {
        self.rows.extend(columns::values(s));
        self.layout.surface_values(s, &mut self.rows);
        self.modes.push(&self.layout.mode(s));
    }

    pub fn rows(&self) -> u64 {
        self.modes.codes.len() as u64
    }

    /// Writes the datasets and attributes, without putting the file in place.
    pub fn prepare(self, meta: &Metadata<'_>) -> Result<atomic::Prepared, OutputError> {
        let fail = |e: h5::Error| OutputError::Hdf5 {
            path: self.path.clone(),
            message: e.to_string(),
        };
        {
            let file = create(&self.tmp).map_err(fail)?;
            let width = self.layout.numeric();
            let column =
                |k: usize| Cow::Owned(self.rows.iter().skip(k).step_by(width).copied().collect());
            write_columns(&file, &self.layout.numeric_columns(), column, &self.modes)
                .map_err(fail)?;

            let summary = meta.summary;
            str_attr(&file, "version", &summary.version).map_err(fail)?;
            str_attr(&file, "scenario", meta.scenario_text).map_err(fail)?;
            str_attr(&file, "scenario_path", &summary.scenario).map_err(fail)?;
            str_attr(&file, "status", summary.status.name()).map_err(fail)?;
            str_attr(&file, "message", &summary.message).map_err(fail)?;
            str_attr(&file, "columns", &self.layout.names().join(",")).map_err(fail)?;
            str_attr(&file, "summary", &summary.to_json()).map_err(fail)?;
            let st = &summary.stats;
            for (name, v) in [
                ("stats_accepted", st.accepted),
                ("stats_rejected", st.rejected),
                ("stats_rhs_evals", st.rhs_evals),
                ("stats_events", st.events),
            ] {
                file.new_attr::<u64>()
                    .create(name)
                    .and_then(|a| a.write_scalar(&v))
                    .map_err(fail)?;
            }
            let drifts = summary
                .drift
                .iter()
                .map(|(which, v)| (format!("drift_{}", which.name()), v));
            for (name, v) in drifts {
                if let Some(v) = v {
                    file.new_attr::<f64>()
                        .create(name.as_str())
                        .and_then(|a| a.write_scalar(&v))
                        .map_err(fail)?;
                }
            }
            file.close().map_err(fail)?;
        }
        Ok(atomic::Prepared::new(self.tmp, &self.path))
    }
}

/// The numeric datasets (attribute `units`) and `mode` of one trajectory in `loc`;
/// `column(k)` is the data of the `k`-th of the numeric columns `names` (name, unit; a
/// [`Layout::numeric_columns`]), made one at a time, so a row-major buffer needs one
/// column's worth of memory more, not a copy of itself.
fn write_columns<'c>(
    loc: &h5::Group,
    names: &[(Cow<'static, str>, &'static str)],
    column: impl Fn(usize) -> Cow<'c, [f64]>,
    modes: &Modes,
) -> h5::Result<()> {
    for (k, (name, unit)) in names.iter().enumerate() {
        let ds = loc
            .new_dataset_builder()
            .with_data(&*column(k))
            .create(&**name)?;
        str_attr(&ds, "units", unit)?;
    }
    let ds = modes.write(loc)?;
    str_attr(&ds, "units", "1")?;
    let names: Vec<&str> = Mode::ALL.iter().map(|m| m.name()).collect();
    str_attr(&ds, "values", &names.join(", "))
}

/// Many trajectories in one HDF5 file (a parameter study's runs): a group per run at the
/// root, each laid out like a single trajectory file's root (`t`, …, `gap` with `units`,
/// `mode`), with the group's own string and number attributes, plus root string
/// attributes. Each group is written when added (so only the file, not memory, grows),
/// to a temporary beside `path` that [`Hdf5Groups::commit`] renames into place; dropped
/// uncommitted, the temporary is removed.
pub struct Hdf5Groups {
    path: PathBuf,
    file: Option<h5::File>,
    tmp: TempPath,
    groups: u64,
    rows: u64,
}

impl Hdf5Groups {
    /// Creates the temporary file with the root string attributes `attrs`.
    pub fn create(path: &Path, attrs: &[(&str, &str)]) -> Result<Self, OutputError> {
        let tmp = atomic::temporary(path)?.into_temp_path();
        let fail = |e: h5::Error| OutputError::Hdf5 {
            path: path.to_owned(),
            message: e.to_string(),
        };
        let file = create(&tmp).map_err(fail)?;
        for (k, v) in attrs {
            str_attr(&file, k, v).map_err(fail)?;
        }
        Ok(Hdf5Groups {
            path: path.to_owned(),
            file: Some(file),
            tmp,
            groups: 0,
            rows: 0,
        })
    }

    /// Adds the group `name` (no `/`) holding one trajectory: the numeric columns
    /// `names` (name, unit: a [`Layout::numeric_columns`]) with their data `columns` (all
    /// of one length), `modes` (mode labels) of the same length, and the group attributes
    /// `text` (strings) and `numbers` (float64), and the attribute `columns` (the column
    /// names in file order, `mode` included, comma-separated, as a trajectory file's).
    #[allow(clippy::too_many_arguments)]
    pub fn add(
        &mut self,
        name: &str,
        names: &[(Cow<'static, str>, &'static str)],
        columns: &[Vec<f64>],
        modes: &[Cow<'_, str>],
        text: &[(&str, &str)],
        numbers: &[(&str, f64)],
    ) -> Result<(), OutputError> {
        let fail = |e: h5::Error| OutputError::Hdf5 {
            path: self.path.clone(),
            message: format!("group {name}: {e}"),
        };
        let file = self.file.as_ref().expect("open until committed");
        let mut codes = Modes::default();
        for m in modes {
            codes.push(m);
        }
        let g = file.create_group(name).map_err(fail)?;
        write_columns(&g, names, |k| Cow::Borrowed(&columns[k]), &codes).map_err(fail)?;
        // The columns in file order, as a trajectory file's root lists them.
        let mut list: Vec<&str> = names.iter().map(|c| &*c.0).collect();
        list.insert(columns::MODE_POSITION.min(list.len()), columns::MODE);
        str_attr(&g, "columns", &list.join(",")).map_err(fail)?;
        for (k, v) in text {
            str_attr(&g, &k.replace('/', "∕"), v).map_err(fail)?;
        }
        for (k, v) in numbers {
            g.new_attr::<f64>()
                .create(k.replace('/', "∕").as_str())
                .and_then(|a| a.write_scalar(v))
                .map_err(fail)?;
        }
        self.groups += 1;
        self.rows += modes.len() as u64;
        Ok(())
    }

    /// Groups added so far.
    pub fn groups(&self) -> u64 {
        self.groups
    }

    /// Trajectory rows (samples) written so far, over all groups.
    pub fn rows(&self) -> u64 {
        self.rows
    }

    /// Closes the file and renames it into place.
    pub fn commit(mut self) -> Result<(), OutputError> {
        if let Some(f) = self.file.take() {
            f.close().map_err(|e| OutputError::Hdf5 {
                path: self.path.clone(),
                message: e.to_string(),
            })?;
        }
        atomic::Prepared::new(self.tmp, &self.path).commit()
    }
}

/// A scalar UTF-8 string attribute (h5py reads it as `str`).
fn str_attr(loc: &h5::Location, name: &str, value: &str) -> h5::Result<()> {
    // Interior NUL bytes cannot be stored in a C string; none of ours has one.
    let v: VarLenUnicode = value
        .replace('\0', "")
        .parse()
        .map_err(|e: h5::types::StringError| h5::Error::from(e.to_string()))?;
    loc.new_attr::<VarLenUnicode>()
        .create(name)?
        .write_scalar(&v)
}

/// A trajectory read back from an HDF5 file written by [`Hdf5File`].
#[derive(Debug, Clone, PartialEq)]
pub struct Hdf5Trajectory {
    /// Numeric columns in file order, with their `units` attribute.
    pub columns: Vec<(String, String, Vec<f64>)>,
    /// The `mode` column.
    pub modes: Vec<String>,
    /// The root's string attributes (version, scenario, status, summary, …).
    pub attributes: std::collections::BTreeMap<String, String>,
    /// The float64 scalar attributes (in a study's trajectory file: the axis values).
    pub numbers: std::collections::BTreeMap<String, f64>,
}

impl Hdf5Trajectory {
    /// The numeric column `name`.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.columns
            .iter()
            .find(|c| c.0 == name)
            .map(|c| c.2.as_slice())
    }
}

/// Reads a trajectory file written by [`Hdf5File`].
pub fn read(path: &Path) -> Result<Hdf5Trajectory, OutputError> {
    read_in(path, None)
}

/// The names of the groups at the root of a file written by [`Hdf5Groups`], sorted.
pub fn group_names(path: &Path) -> Result<Vec<String>, OutputError> {
    let fail = |e: h5::Error| OutputError::Hdf5 {
        path: path.to_owned(),
        message: e.to_string(),
    };
    let file = open(path).map_err(fail)?;
    let mut names: Vec<String> = file
        .groups()
        .map_err(fail)?
        .iter()
        .map(|g| g.name().trim_start_matches('/').to_owned())
        .collect();
    names.sort();
    Ok(names)
}

/// Reads the trajectory in group `group` of a file written by [`Hdf5Groups`] (its
/// attributes are the group's).
pub fn read_group(path: &Path, group: &str) -> Result<Hdf5Trajectory, OutputError> {
    read_in(path, Some(group))
}

fn read_in(path: &Path, group: Option<&str>) -> Result<Hdf5Trajectory, OutputError> {
    let fail = |e: h5::Error| OutputError::Hdf5 {
        path: path.to_owned(),
        message: e.to_string(),
    };
    let file = open(path).map_err(fail)?;
    let loc: h5::Group = match group {
        Some(g) => file.group(g).map_err(fail)?,
        None => file.group("/").map_err(fail)?,
    };
    // A trajectory file's `columns` attribute lists its columns, as does a study's group
    // (one without it holds the fixed ones).
    let listed: Option<VarLenUnicode> = loc.attr("columns").and_then(|a| a.read_scalar()).ok();
    let names: Vec<String> = match &listed {
        Some(list) => list
            .as_str()
            .split(',')
            .filter(|n| *n != columns::MODE)
            .map(str::to_owned)
            .collect(),
        None => NUMERIC_COLUMNS.iter().map(|c| c.0.to_owned()).collect(),
    };
    let mut columns = Vec::new();
    for name in &names {
        let name = name.as_str();
        let ds = loc.dataset(name).map_err(fail)?;
        check_filters(&ds, name)
            .map_err(h5::Error::from)
            .map_err(fail)?;
        let units: VarLenUnicode = ds
            .attr("units")
            .and_then(|a| a.read_scalar())
            .map_err(fail)?;
        columns.push((
            name.to_owned(),
            units.as_str().to_owned(),
            ds.read_raw::<f64>().map_err(fail)?,
        ));
    }
    let modes = loc.dataset(columns::MODE).map_err(fail)?;
    check_filters(&modes, columns::MODE)
        .map_err(h5::Error::from)
        .map_err(fail)?;
    let modes = modes.read_raw::<FixedAscii<LABEL_LEN>>().map_err(fail)?;
    let mut attributes = std::collections::BTreeMap::new();
    let mut numbers = std::collections::BTreeMap::new();
    for name in loc.attr_names().map_err(fail)? {
        let attr = loc.attr(&name).map_err(fail)?;
        if let Ok(v) = attr.read_scalar::<VarLenUnicode>() {
            attributes.insert(name, v.as_str().to_owned());
        } else if attr.dtype().is_ok_and(|t| t.is::<f64>()) {
            numbers.insert(name, attr.read_scalar::<f64>().map_err(fail)?);
        }
    }
    Ok(Hdf5Trajectory {
        columns,
        modes: modes.iter().map(|m| m.as_str().to_owned()).collect(),
        attributes,
        numbers,
    })
}

/// The type of a column of a table written by [`TableWriter`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TableType {
    F64,
    I64,
    /// Variable-length UTF-8 strings (NUL bytes dropped).
    Text,
}

/// One column of a table written by [`TableWriter`].
pub struct TableColumn {
    /// Dataset name (any UTF-8 without `/`; `/` is replaced by `∕`).
    pub name: String,
    /// Its `units` attribute.
    pub unit: String,
    /// What marks a cell without a value, if some have none (its `missing` attribute).
    pub missing: Option<String>,
    pub ty: TableType,
}

/// A cell given to [`TableWriter::push`], of its column's type.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TableValue<'a> {
    F64(f64),
    I64(i64),
    Text(&'a str),
}

/// Rows buffered before they are written (a block of each column).
const TABLE_BLOCK: usize = 1 << 14;

/// A block of one column's values.
enum Block {
    F64(Vec<f64>),
    I64(Vec<i64>),
    Text(Vec<VarLenUnicode>),
}

/// A table (a parameter study's results) written a block of rows at a time: one
/// dataset per column at the root, of the table's number of rows (known when it is
/// created), each with a `units` attribute (and `missing` where some cells have no
/// value), plus root string attributes and `columns` (the dataset names in order, as a
/// JSON list); into a temporary beside the target that [`TableWriter::commit`] renames
/// into place once every row is written. Memory holds one block of rows, whatever the
/// table's length.
pub struct TableWriter {
    path: PathBuf,
    tmp: TempPath,
    file: Option<h5::File>,
    datasets: Vec<(h5::Dataset, Block)>,
    rows: usize,
    written: usize,
}

impl TableWriter {
    /// Creates the temporary with the datasets of `columns`, `rows` rows each, and the
    /// root string attributes `attrs`.
    pub fn create(
        path: &Path,
        columns: &[TableColumn],
        rows: usize,
        attrs: &[(&str, &str)],
    ) -> Result<Self, OutputError> {
        let tmp = atomic::temporary(path)?.into_temp_path();
        let fail = |e: h5::Error| OutputError::Hdf5 {
            path: path.to_owned(),
            message: e.to_string(),
        };
        let file = create(&tmp).map_err(fail)?;
        let mut names = Vec::new();
        let mut datasets = Vec::new();
        for c in columns {
            let name = c.name.replace('/', "∕");
            let (ds, block) = match c.ty {
                TableType::F64 => (
                    file.new_dataset::<f64>().shape(rows).create(name.as_str()),
                    Block::F64(Vec::new()),
                ),
                TableType::I64 => (
                    file.new_dataset::<i64>().shape(rows).create(name.as_str()),
                    Block::I64(Vec::new()),
                ),
                TableType::Text => (
                    file.new_dataset::<VarLenUnicode>()
                        .shape(rows)
                        .create(name.as_str()),
                    Block::Text(Vec::new()),
                ),
            };
            let ds = ds.map_err(fail)?;
            str_attr(&ds, "units", &c.unit).map_err(fail)?;
            if let Some(m) = &c.missing {
                str_attr(&ds, "missing", m).map_err(fail)?;
            }
            names.push(serde_json::Value::from(name));
            datasets.push((ds, block));
        }
        str_attr(
            &file,
            "columns",
            &serde_json::Value::Array(names).to_string(),
        )
        .map_err(fail)?;
        for (k, v) in attrs {
            str_attr(&file, k, v).map_err(fail)?;
        }
        Ok(TableWriter {
            path: path.to_owned(),
            tmp,
            file: Some(file),
            datasets,
            rows,
            written: 0,
        })
    }

    /// Adds a row: one value per column, each of its column's type (a value of another
    /// type is an error).
    pub fn push<'a>(
        &mut self,
        row: impl IntoIterator<Item = TableValue<'a>>,
    ) -> Result<(), OutputError> {
        let buffered = self.buffered();
        if self.written + buffered >= self.rows {
            return Err(self.error(format!("more than the {} rows declared", self.rows)));
        }
        let row: Vec<TableValue<'a>> = row.into_iter().collect();
        let typed = row.len() == self.datasets.len()
            && self.datasets.iter().zip(&row).all(|((_, block), v)| {
                matches!(
                    (block, v),
                    (Block::F64(_), TableValue::F64(_))
                        | (Block::I64(_), TableValue::I64(_))
                        | (Block::Text(_), TableValue::Text(_))
                )
            });
        if !typed {
            return Err(self.error(format!(
                "row {}: not one value of its column's type per column",
                self.written + buffered
            )));
        }
        for ((_, block), v) in self.datasets.iter_mut().zip(row) {
            match (block, v) {
                (Block::F64(b), TableValue::F64(x)) => b.push(x),
                (Block::I64(b), TableValue::I64(x)) => b.push(x),
                (Block::Text(b), TableValue::Text(s)) => {
                    b.push(s.replace('\0', "").parse().unwrap_or_default())
                }
                _ => unreachable!("checked above"),
            }
        }
        if buffered + 1 == TABLE_BLOCK {
            self.flush()?;
        }
        Ok(())
    }

    /// Rows held in the blocks, not yet written.
    fn buffered(&self) -> usize {
        match self.datasets.first().map(|d| &d.1) {
            Some(Block::F64(b)) => b.len(),
            Some(Block::I64(b)) => b.len(),
            Some(Block::Text(b)) => b.len(),
            None => 0,
        }
    }

    fn error(&self, message: String) -> OutputError {
        OutputError::Hdf5 {
            path: self.path.clone(),
            message,
        }
    }

    /// Writes the blocks at their place in the datasets and empties them.
    fn flush(&mut self) -> Result<(), OutputError> {
        let n = self.buffered();
        if n == 0 {
            return Ok(());
        }
        let at = self.written..self.written + n;
        for (ds, block) in &mut self.datasets {
            match block {
                Block::F64(b) => ds.write_slice(b.as_slice(), at.clone()),
                Block::I64(b) => ds.write_slice(b.as_slice(), at.clone()),
                Block::Text(b) => ds.write_slice(b.as_slice(), at.clone()),
            }
            .map_err(|e| OutputError::Hdf5 {
                path: self.path.clone(),
                message: e.to_string(),
            })?;
            match block {
                Block::F64(b) => b.clear(),
                Block::I64(b) => b.clear(),
                Block::Text(b) => b.clear(),
            }
        }
        self.written += n;
        Ok(())
    }

    /// Writes the last block, closes the file and renames it into place; an error if
    /// fewer rows than declared were pushed.
    pub fn commit(mut self) -> Result<(), OutputError> {
        self.flush()?;
        if self.written != self.rows {
            return Err(self.error(format!(
                "{} rows written of the {} declared",
                self.written, self.rows
            )));
        }
        self.datasets.clear();
        if let Some(f) = self.file.take() {
            f.close().map_err(|e| OutputError::Hdf5 {
                path: self.path.clone(),
                message: e.to_string(),
            })?;
        }
        atomic::Prepared::new(self.tmp, &self.path).commit()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plugins_are_off_and_no_plugin_directory_is_searched() {
        forbid_plugins();
        assert_eq!(plugin_state(), (false, 0));
        // Opening a file goes through the same switch.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.h5");
        create(&path).unwrap().close().unwrap();
        open(&path).unwrap();
        assert_eq!(plugin_state(), (false, 0));
    }

    /// The HDF5 library linked in carries no path of the build machine: no default
    /// plugin directory (HDF5's default is a directory inside the build tree) and no
    /// configuration summary with the install prefix (scripts/cmake-hdf5 configures the
    /// build so). Read from this test's own executable, which links the same library;
    /// the needles are joined at run time so that they are not in it themselves.
    #[test]
    fn no_build_path_is_compiled_into_the_hdf5_library() {
        let exe = std::fs::read(std::env::current_exe().unwrap()).unwrap();
        for needle in [
            ["lib", "plugin"].join("/"),
            ["Installation", "point:"].join(" "),
        ] {
            assert!(
                !exe.windows(needle.len()).any(|w| w == needle.as_bytes()),
                "`{needle}` is compiled in: HDF5 was configured without scripts/cmake-hdf5 \
                 (set ELLIPSOID_CMAKE, not CMAKE, and rebuild it: cargo clean -p hdf5-metno-src)"
            );
        }
    }

    /// A table of several blocks reads back cell for cell (the last block partial), and
    /// a writer given more or fewer rows than declared leaves no file.
    #[test]
    fn a_table_is_written_a_block_at_a_time_and_reads_back_cell_for_cell() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.h5");
        let n = 2 * TABLE_BLOCK + 123;
        let columns = [
            ("x", TableType::F64),
            ("count", TableType::I64),
            ("a/b", TableType::Text),
        ]
        .map(|(name, ty)| TableColumn {
            name: name.into(),
            unit: "1".into(),
            missing: None,
            ty,
        });
        let x = |i: usize| (i as f64).sqrt() * 1e-300 + f64::from(i == 7) * f64::NAN;
        let text = |i: usize| format!("row {i}, \"quoted\"\0é");
        let mut w = TableWriter::create(&path, &columns, n, &[("study", "s")]).unwrap();
        for i in 0..n {
            let t = text(i);
            w.push([
                TableValue::F64(x(i)),
                TableValue::I64(i as i64 - 5),
                TableValue::Text(&t),
            ])
            .unwrap();
        }
        assert!(w.push([]).is_err(), "one row more than declared");
        w.commit().unwrap();
        let f = open(&path).unwrap();
        let xs: Vec<f64> = f.dataset("x").unwrap().read_raw().unwrap();
        let counts: Vec<i64> = f.dataset("count").unwrap().read_raw().unwrap();
        let texts: Vec<VarLenUnicode> = f.dataset("a∕b").unwrap().read_raw().unwrap();
        assert_eq!(xs.len(), n);
        for i in 0..n {
            assert_eq!(xs[i].to_bits(), x(i).to_bits(), "row {i}");
            assert_eq!(counts[i], i as i64 - 5);
            assert_eq!(texts[i].as_str(), text(i).replace('\0', ""));
        }
        let names: String = f
            .attr("columns")
            .unwrap()
            .read_scalar::<VarLenUnicode>()
            .unwrap()
            .to_string();
        assert_eq!(names, r#"["x","count","a∕b"]"#);
        drop(f);
        // Fewer rows than declared: refused, the old table kept, no temporary left.
        let before = std::fs::read(&path).unwrap();
        let mut w = TableWriter::create(&path, &columns, 3, &[]).unwrap();
        w.push([
            TableValue::F64(1.0),
            TableValue::I64(1),
            TableValue::Text(""),
        ])
        .unwrap();
        assert!(
            w.push([TableValue::I64(1), TableValue::I64(1), TableValue::Text("")])
                .is_err(),
            "a value of another type"
        );
        assert!(w.commit().is_err());
        assert_eq!(std::fs::read(&path).unwrap(), before);
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }
}
