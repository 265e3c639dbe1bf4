//! The study's table, one row per point in point order, written atomically (a temporary
//! file beside the target, renamed into place when complete) as CSV, Parquet (feature
//! `parquet`) or HDF5 (feature `hdf5`), chosen by the extension.
//!
//! - **CSV**: a header of `name [unit]` cells, then one line per row; numbers in the
//!   shortest form that reads back exactly ([`number`]: `60`, `1e-10`), empty cells where there is no value, text quoted as RFC 4180 asks.
//! - **Parquet**: one column per table column (INT64, DOUBLE or UTF-8 BYTE_ARRAY), named by
//!   the same headers, no value stored as null; key–value metadata `units` (JSON: header →
//!   unit) and `study` (the study's source). Uncompressed (no codec is built in).
//! - **HDF5**: one dataset per column at the root, named by the column's name without its
//!   unit (a `/` in a name would make a group), with a `units` attribute; root attributes
//!   `columns` (the dataset names), `headers` (`name [unit]`), `units` (JSON), `study`; text as variable-length UTF-8 strings; float cells without a value hold NaN
//!   and integer ones −1 (attribute `missing` says so), since HDF5 has no null.

use std::io::Write;
use std::path::Path;

use ellipsoid_core::error::number;
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
            .map(|r| self.row(r.index, r.key, r.cells))
            .collect()
    }

    /// The table row of point `index` with its key and outcome cells.
    pub fn row(&self, index: usize, key: String, cells: Vec<Cell>) -> Vec<Cell> {
        let mut row = Vec::with_capacity(self.columns.len());
        row.push(Cell::Int(index as i64));
        row.extend(self.axis_cells(index));
        row.extend(cells);
        row.push(Cell::Text(key));
        row
    }
}

/// Writes `rows` (of `columns`) to `path`, format by extension, atomically.
pub fn write(
    path: &Path,
    columns: &[Column],
    rows: &[Vec<Cell>],
    source: &str,
) -> Result<(), OutputError> {
    write_rows(path, columns, rows.iter().map(|r| Ok(r.clone())), source)
}

/// Writes the table of `columns` whose rows `rows` gives in order, a row at a time
/// (memory holds at most a Parquet row group or an HDF5 block of rows), to `path`,
/// format by extension, atomically; an error of `rows` stops the writing.
pub fn write_rows(
    path: &Path,
    columns: &[Column],
    rows: impl ExactSizeIterator<Item = Result<Vec<Cell>, OutputError>>,
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
            write_csv(&mut out, columns, rows, io)?;
            out.flush().map_err(io)?;
            drop(out);
            f.commit()
        }
        #[cfg(feature = "parquet")]
        Ok(TableFormat::Parquet) => {
            let mut f = AtomicFile::create(path)?;
            parquet_table::write(f.file(), columns, rows, source, path)?;
            f.commit()
        }
        #[cfg(feature = "hdf5")]
        Ok(TableFormat::Hdf5) => {
            let headers: Vec<String> = columns.iter().map(Column::header).collect();
            let headers = serde_json::Value::from(headers).to_string();
            let mut w = ellipsoid_io::hdf5::TableWriter::create(
                path,
                &hdf5_columns(columns),
                rows.len(),
                &[
                    ("study", source),
                    ("headers", &headers),
                    ("units", &units_json(columns)),
                ],
            )?;
            for row in rows {
                w.push(hdf5_row(columns, &row?))?;
            }
            w.commit()
        }
        #[allow(unreachable_patterns)] // formats this build lacks are refused by from_path
        Ok(_) => unreachable!("TableFormat::from_path refuses formats this build lacks"),
        Err(rule) => Err(OutputError::Io {
            path: path.to_owned(),
            source: std::io::Error::new(std::io::ErrorKind::InvalidInput, rule),
        }),
    }
}

/// Writes the table as CSV text to `out`, row by row (`io` makes a write error an
/// output error).
pub fn write_csv(
    out: &mut impl Write,
    columns: &[Column],
    rows: impl Iterator<Item = Result<Vec<Cell>, OutputError>>,
    io: impl Fn(std::io::Error) -> OutputError,
) -> Result<(), OutputError> {
    let header: Vec<String> = columns.iter().map(|c| quote(&c.header())).collect();
    writeln!(out, "{}", header.join(",")).map_err(&io)?;
    for row in rows {
        write_csv_row(out, &row?).map_err(&io)?;
    }
    Ok(())
}

/// One CSV line: floats as the shortest text that reads back exactly, plain from 1e-4 to
/// 1e15 (`60`, `0.25`) and in scientific notation beyond (`1e-10`).
fn write_csv_row(out: &mut impl Write, row: &[Cell]) -> std::io::Result<()> {
    for (i, c) in row.iter().enumerate() {
        if i > 0 {
            out.write_all(b",")?;
        }
        match c {
            Cell::Null => {}
            Cell::Int(v) => write!(out, "{v}")?,
            Cell::Float(v) => out.write_all(number(*v).as_bytes())?,
            Cell::Text(s) => out.write_all(quote(s).as_bytes())?,
        }
    }
    out.write_all(b"\n")
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

/// The HDF5 datasets of `columns`.
#[cfg(feature = "hdf5")]
fn hdf5_columns(columns: &[Column]) -> Vec<ellipsoid_io::hdf5::TableColumn> {
    use ellipsoid_io::hdf5::{TableColumn, TableType};
    columns
        .iter()
        .map(|c| TableColumn {
            name: c.name.clone(),
            unit: c.unit.clone().unwrap_or_else(|| "1".into()),
            missing: c.nullable.then(|| match c.ty {
                Type::Float => "NaN: no value (the run failed before, or never reached it, or the invariant is not conserved)".into(),
                Type::Int => "-1: no value (the run failed before it started)".into(),
                Type::Text => "empty string: no value".into(),
            }),
            ty: match c.ty {
                Type::Float => TableType::F64,
                Type::Int => TableType::I64,
                Type::Text => TableType::Text,
            },
        })
        .collect()
}

/// A row's HDF5 values: a cell without a value is NaN, −1 or the empty string by its
/// column's type (HDF5 has no null).
#[cfg(feature = "hdf5")]
fn hdf5_row<'a>(
    columns: &'a [Column],
    row: &'a [Cell],
) -> impl Iterator<Item = ellipsoid_io::hdf5::TableValue<'a>> {
    use ellipsoid_io::hdf5::TableValue;
    columns.iter().zip(row).map(|(c, cell)| match (c.ty, cell) {
        (Type::Float, Cell::Float(v)) => TableValue::F64(*v),
        (Type::Float, _) => TableValue::F64(f64::NAN),
        (Type::Int, Cell::Int(v)) => TableValue::I64(*v),
        (Type::Int, _) => TableValue::I64(-1),
        (Type::Text, Cell::Text(s)) => TableValue::Text(s),
        (Type::Text, _) => TableValue::Text(""),
    })
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
        mut rows: impl Iterator<Item = Result<Vec<Cell>, OutputError>>,
        source: &str,
        path: &Path,
    ) -> Result<(), OutputError> {
        let fail = |e: parquet::errors::ParquetError| OutputError::Io {
            path: path.to_owned(),
            source: std::io::Error::other(format!("Parquet: {e}")),
        };
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
            .collect::<parquet::errors::Result<Vec<_>>>()
            .map_err(fail)?;
        let schema = Arc::new(
            Schema::group_type_builder("study")
                .with_fields(fields)
                .build()
                .map_err(fail)?,
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
        let handle = file.try_clone().map_err(|e| OutputError::Io {
            path: path.to_owned(),
            source: e,
        })?;
        let mut w = SerializedFileWriter::new(handle, schema, props).map_err(fail)?;
        let mut group = Vec::with_capacity(GROUP);
        loop {
            group.clear();
            for row in rows.by_ref().take(GROUP) {
                group.push(row?);
            }
            if group.is_empty() {
                break;
            }
            write_group(&mut w, columns, &group).map_err(fail)?;
        }
        w.close().map_err(fail)?;
        Ok(())
    }

    /// One row group.
    fn write_group(
        w: &mut SerializedFileWriter<std::fs::File>,
        columns: &[Column],
        group: &[Vec<Cell>],
    ) -> parquet::errors::Result<()> {
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
        Ok(())
    }
}

/// Whether a column holds axis values (for readers that split the table).
pub fn is_axis(c: &Column) -> bool {
    matches!(c.role, Role::Axis { .. })
}
