//! CSV trajectories: a header line of column names, then one row per sample; numbers in
//! the shortest form that reads back to the same f64 (Rust's `{:e}`), `mode` by name.

use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use ellipsoid_core::simulate::Sample;

use crate::OutputError;
use crate::atomic::{AtomicFile, Prepared};
use crate::columns::{self, MODE_POSITION};

/// Formats samples as CSV rows onto any writer.
pub struct CsvWriter<W: Write> {
    out: W,
    rows: u64,
    line: String,
}

impl<W: Write> CsvWriter<W> {
    /// Writes the header.
    pub fn new(mut out: W) -> std::io::Result<Self> {
        writeln!(out, "{}", columns::names().join(","))?;
        Ok(CsvWriter {
            out,
            rows: 0,
            line: String::with_capacity(512),
        })
    }

    /// Writes one row.
    pub fn write(&mut self, s: &Sample) -> std::io::Result<()> {
        use std::fmt::Write as _;
        self.line.clear();
        for (i, v) in columns::values(s).iter().enumerate() {
            if i == MODE_POSITION {
                self.line.push_str(s.mode.name());
                self.line.push(',');
            }
            let _ = write!(self.line, "{v:e}");
            self.line
                .push(if i + 1 == columns::NUMERIC { '\n' } else { ',' });
        }
        self.rows += 1;
        self.out.write_all(self.line.as_bytes())
    }

    /// Rows written.
    pub fn rows(&self) -> u64 {
        self.rows
    }

    /// The underlying writer, flushed.
    pub fn into_inner(mut self) -> std::io::Result<W> {
        self.out.flush()?;
        Ok(self.out)
    }
}

/// A CSV file written atomically.
pub struct CsvFile {
    writer: CsvWriter<BufWriter<AtomicFile>>,
    path: PathBuf,
}

impl CsvFile {
    pub fn create(path: &Path) -> Result<Self, OutputError> {
        let file = AtomicFile::create(path)?;
        let writer = CsvWriter::new(BufWriter::with_capacity(1 << 16, file))
            .map_err(|e| OutputError::io(path, e))?;
        Ok(CsvFile {
            writer,
            path: path.to_owned(),
        })
    }

    pub fn write(&mut self, s: &Sample) -> Result<(), OutputError> {
        self.writer
            .write(s)
            .map_err(|e| OutputError::io(&self.path, e))
    }

    pub fn rows(&self) -> u64 {
        self.writer.rows()
    }

    /// Completes the file without putting it in place.
    pub fn prepare(self) -> Result<Prepared, OutputError> {
        let path = self.path;
        let buffered = self
            .writer
            .into_inner()
            .map_err(|e| OutputError::io(&path, e))?;
        let file = buffered
            .into_inner()
            .map_err(|e| OutputError::io(&path, e.into_error()))?;
        file.prepare()
    }
}
