//! The study's table, one row per point in point order, written atomically (a temporary
//! file beside the target, renamed into place when complete) as CSV, Parquet (feature
//! `parquet`) or HDF5 (feature `hdf5`), chosen by the extension.
//!
//! - **CSV**: a header of `name [unit]` cells, then one line per row; numbers in Rust's
//!   `{:e}` form (exact), empty cells where there is no value, text quoted as RFC 4180 asks.
//! - **Parquet**: one column per table column (INT64, DOUBLE or UTF-8 BYTE_ARRAY), named by
//!   the same headers, no value stored as null; key–value metadata `units` (JSON: header →
//!   unit) and `study` (the study's source). Uncompressed (no codec is built in).
//! - **HDF5**: one dataset per column at the root, named by the column's name without its
//!   unit (a `/` in a name would make a group), with a `units` attribute; root attributes
//!   `columns` (the dataset names), `headers` (`name [unit]`), `units` (JSON), `study`; text as variable-length UTF-8 strings; float cells without a value hold NaN
//!   and integer ones −1 (attribute `missing` says so), since HDF5 has no null.

use std::io::Write;
use std::path::Path;

use ellipsoid_io::OutputError;
use ellipsoid_io::atomic::AtomicFile;

#[cfg(any(feature = "parquet", feature = "hdf5"))]
use super::plan::Type;
use super::plan::{Cell, Column, Role, Study};
use super::run::PointResult;

/// The table formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TableFormat {
    Csv,
    Parquet,
    Hdf5,
}

/// The rule for an output name, in messages.
pub const FORMAT_RULE: &str = "the table is written as .csv, .parquet or .h5 (by extension)";

impl TableFormat {
    /// The format named by `path`'s extension; `Err` says why not (unknown, or not in this build).
    pub fn from_path(path: &Path) -> Result<TableFormat, String> {
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_lowercase())
            .unwrap_or_default();
        match ext.as_str() {
            "csv" => Ok(TableFormat::Csv),
            "parquet" | "pq" if cfg!(feature = "parquet") => Ok(TableFormat::Parquet),
            "parquet" | "pq" => Err(
                "this build cannot write Parquet (built without the `parquet` feature); write .csv"
                    .into(),
            ),
            "h5" | "hdf5" if cfg!(feature = "hdf5") => Ok(TableFormat::Hdf5),
            "h5" | "hdf5" => Err(ellipsoid_io::HDF5_HINT.into()),
            _ => Err(format!("unknown extension {ext:?}: {FORMAT_RULE}")),
        }
    }
}

impl Study {
    /// Every row of the table, in point order, from the results (one per point, any order).
    pub fn rows(&self, mut results: Vec<PointResult>) -> Vec<Vec<Cell>> {
        results.sort_by_key(|r| r.index);
        results
            .into_iter()
            .map(|r| {
                let mut row = Vec::with_capacity(self.columns.len());
                row.push(Cell::Int(r.index as i64));
                row.extend(self.axis_cells(r.index));
                row.extend(r.cells);
                row.push(Cell::Text(r.key));
                row
            })
            .collect()
    }
}

/// Writes `rows` (of `columns`) to `path`, format by extension, atomically.
pub fn write(
    path: &Path,
    columns: &[Column],
    rows: &[Vec<Cell>],
    source: &str,
) -> Result<(), OutputError> {
    let _ = source; // recorded by the Parquet and HDF5 writers only
    let io = |e| OutputError::Io {
        path: path.to_owned(),
        source: e,
    };
    match TableFormat::from_path(path) {
        Ok(TableFormat::Csv) => {
            let mut f = AtomicFile::create(path)?;
            // Streamed: the table's text is never held whole.
            let mut out = std::io::BufWriter::new(f.file());
            write_csv(&mut out, columns, rows)
                .and_then(|()| out.flush())
                .map_err(io)?;
            drop(out);
            f.commit()
        }
        #[cfg(feature = "parquet")]
        Ok(TableFormat::Parquet) => {
            let mut f = AtomicFile::create(path)?;
            parquet_table::write(f.file(), columns, rows, source).map_err(|e| OutputError::Io {
                path: path.to_owned(),
                source: std::io::Error::other(format!("Parquet: {e}")),
            })?;
            f.commit()
        }
        #[cfg(feature = "hdf5")]
        Ok(TableFormat::Hdf5) => {
            let headers: Vec<String> = columns.iter().map(Column::header).collect();
            let headers = serde_json::Value::from(headers).to_string();
            ellipsoid_io::hdf5::write_table(
                path,
                &hdf5_columns(columns, rows),
                &[
                    ("study", source),
                    ("headers", &headers),
                    ("units", &units_json(columns)),
                ],
            )
        }
        #[allow(unreachable_patterns)] // formats this build lacks are refused by from_path
        Ok(_) => unreachable!("TableFormat::from_path refuses formats this build lacks"),
        Err(rule) => Err(OutputError::Io {
            path: path.to_owned(),
            source: std::io::Error::new(std::io::ErrorKind::InvalidInput, rule),
        }),
    }
}

/// Writes the table as CSV text to `out`, row by row.
pub fn write_csv(
    out: &mut impl Write,
    columns: &[Column],
    rows: &[Vec<Cell>],
) -> std::io::Result<()> {
    let header: Vec<String> = columns.iter().map(|c| quote(&c.header())).collect();
    writeln!(out, "{}", header.join(","))?;
    for row in rows {
        for (i, c) in row.iter().enumerate() {
            if i > 0 {
                out.write_all(b",")?;
            }
            match c {
                Cell::Null => {}
                Cell::Int(v) => write!(out, "{v}")?,
                Cell::Float(v) => write!(out, "{v:e}")?,
                Cell::Text(s) => out.write_all(quote(s).as_bytes())?,
            }
        }
        out.write_all(b"\n")?;
    }
    Ok(())
}

/// A CSV field, quoted when it must be (RFC 4180).
fn quote(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) || s.starts_with(' ') || s.ends_with(' ') {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_owned()
    }
}

/// Column → unit, for file metadata.
pub fn units_json(columns: &[Column]) -> String {
    let map: serde_json::Map<String, serde_json::Value> = columns
        .iter()
        .map(|c| {
            (
                c.header(),
                c.unit
                    .clone()
                    .map_or(serde_json::Value::Null, serde_json::Value::from),
            )
        })
        .collect();
    serde_json::Value::Object(map).to_string()
}

#[cfg(feature = "hdf5")]
fn hdf5_columns(columns: &[Column], rows: &[Vec<Cell>]) -> Vec<ellipsoid_io::hdf5::TableColumn> {
    use ellipsoid_io::hdf5::{TableColumn, TableData};
    columns
        .iter()
        .enumerate()
        .map(|(j, c)| {
            let data = match c.ty {
                Type::Float => TableData::F64(
                    rows.iter()
                        .map(|r| match r[j] {
                            Cell::Float(v) => v,
                            _ => f64::NAN,
                        })
                        .collect(),
                ),
                Type::Int => TableData::I64(
                    rows.iter()
                        .map(|r| match r[j] {
                            Cell::Int(v) => v,
                            _ => -1,
                        })
                        .collect(),
                ),
                Type::Text => TableData::Text(
                    rows.iter()
                        .map(|r| match &r[j] {
                            Cell::Text(s) => s.clone(),
                            _ => String::new(),
                        })
                        .collect(),
                ),
            };
            TableColumn {
                name: c.name.clone(),
                unit: c.unit.clone().unwrap_or_else(|| "1".into()),
                missing: c.nullable.then(|| match c.ty {
                    Type::Float => "NaN: no value (the run failed before, or never reached it, or the invariant is not conserved)".into(),
                    Type::Int => "-1: no value (the run failed before it started)".into(),
                    Type::Text => "empty string: no value".into(),
                }),
                data,
            }
        })
        .collect()
}

#[cfg(feature = "parquet")]
mod parquet_table {
    use std::sync::Arc;

    use parquet::basic::{LogicalType, Repetition, Type as Physical};
    use parquet::data_type::{ByteArray, ByteArrayType, DoubleType, Int64Type};
    use parquet::file::metadata::KeyValue;
    use parquet::file::properties::WriterProperties;
    use parquet::file::writer::SerializedFileWriter;
    use parquet::schema::types::Type as Schema;

    use super::*;

    /// Rows per row group.
    const GROUP: usize = 65_536;

    pub fn write(
        file: &mut std::fs::File,
        columns: &[Column],
        rows: &[Vec<Cell>],
        source: &str,
    ) -> parquet::errors::Result<()> {
        let fields = columns
            .iter()
            .map(|c| {
                let (physical, logical) = match c.ty {
                    Type::Int => (Physical::INT64, None),
                    Type::Float => (Physical::DOUBLE, None),
                    Type::Text => (Physical::BYTE_ARRAY, Some(LogicalType::String)),
                };
                Schema::primitive_type_builder(&c.header(), physical)
                    .with_logical_type(logical)
                    .with_repetition(if c.nullable {
                        Repetition::OPTIONAL
                    } else {
                        Repetition::REQUIRED
                    })
                    .build()
                    .map(Arc::new)
            })
            .collect::<parquet::errors::Result<Vec<_>>>()?;
        let schema = Arc::new(
            Schema::group_type_builder("study")
                .with_fields(fields)
                .build()?,
        );
        let props = Arc::new(
            WriterProperties::builder()
                .set_key_value_metadata(Some(vec![
                    KeyValue::new("units".into(), units_json(columns)),
                    KeyValue::new("study".into(), source.to_owned()),
                    KeyValue::new("ellipsoid.version".into(), crate::study::VERSION.to_owned()),
                ]))
                .build(),
        );
        let mut w = SerializedFileWriter::new(file.try_clone()?, schema, props)?;
        for group in rows.chunks(GROUP) {
            let mut rg = w.next_row_group()?;
            for (j, c) in columns.iter().enumerate() {
                let mut col = rg.next_column()?.expect("one writer per schema column");
                let defs: Vec<i16> = group
                    .iter()
                    .map(|r| i16::from(r[j] != Cell::Null))
                    .collect();
                let defs = c.nullable.then_some(defs.as_slice());
                match c.ty {
                    Type::Int => {
                        let v: Vec<i64> = group
                            .iter()
                            .filter_map(|r| match r[j] {
                                Cell::Int(v) => Some(v),
                                _ => None,
                            })
                            .collect();
                        col.typed::<Int64Type>().write_batch(&v, defs, None)?;
                    }
                    Type::Float => {
                        let v: Vec<f64> = group
                            .iter()
                            .filter_map(|r| match r[j] {
                                Cell::Float(v) => Some(v),
                                _ => None,
                            })
                            .collect();
                        col.typed::<DoubleType>().write_batch(&v, defs, None)?;
                    }
                    Type::Text => {
                        let v: Vec<ByteArray> = group
                            .iter()
                            .filter_map(|r| match &r[j] {
                                Cell::Text(s) => Some(ByteArray::from(s.as_str())),
                                _ => None,
                            })
                            .collect();
                        col.typed::<ByteArrayType>().write_batch(&v, defs, None)?;
                    }
                }
                col.close()?;
            }
            rg.close()?;
        }
        w.close()?;
        Ok(())
    }
}

/// Whether a column holds axis values (for readers that split the table).
pub fn is_axis(c: &Column) -> bool {
    matches!(c.role, Role::Axis { .. })
}
