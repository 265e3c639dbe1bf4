//! CSV trajectories: a header line of column names, then one row per sample; numbers in
//! the shortest form that reads back to the same f64 (`zmij`, Schubfach's shortest
//! round-trip digits: `0.025`, `-1.5e-7`, `60.0`), `mode` by name.

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
    line: Vec<u8>,
    digits: zmij::Buffer,
}

impl<W: Write> CsvWriter<W> {
    /// Writes the header.
    pub fn new(mut out: W) -> std::io::Result<Self> {
        writeln!(out, "{}", columns::names().join(","))?;
        Ok(CsvWriter {
            out,
            rows: 0,
            line: Vec::with_capacity(1024),
            digits: zmij::Buffer::new(),
        })
    }

    /// Writes one row: each number in its shortest round-trip form (the recorder hands
    /// on finite samples only), assembled in one buffer and written at once.
    pub fn write(&mut self, s: &Sample) -> std::io::Result<()> {
        self.line.clear();
        for (i, v) in columns::values(s).into_iter().enumerate() {
            if i == MODE_POSITION {
                self.line.extend_from_slice(s.mode.name().as_bytes());
                self.line.push(b',');
            }
            self.line
                .extend_from_slice(self.digits.format(v).as_bytes());
            self.line.push(if i + 1 == columns::NUMERIC {
                b'\n'
            } else {
                b','
            });
        }
        self.rows += 1;
        self.out.write_all(&self.line)
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
