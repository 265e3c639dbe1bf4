//! CSV trajectories: a comment line naming the scenario and its body (see [`comment`];
//! readers skip it: `pandas.read_csv(path, comment="#")`, `numpy.loadtxt`), a header line
//! of column names, then one row per sample; numbers in the shortest form that reads back
//! to the same f64 (`zmij`, Schubfach's shortest round-trip digits: `0.025`, `-1.5e-7`,
//! `60.0`), `mode` by name.

use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, SyncSender, sync_channel};
use std::thread::JoinHandle;

use ellipsoid_core::scenario::Scenario;
use ellipsoid_core::simulate::Sample;

use crate::OutputError;
use crate::atomic::{AtomicFile, Prepared};
use crate::columns::{self, Layout, MODE_POSITION};

/// Formats samples as CSV rows onto any writer.
pub struct CsvWriter<W: Write> {
    out: W,
    layout: Layout,
    rows: u64,
    line: Vec<u8>,
    /// The per-surface values of the row being written.
    extra: Vec<f64>,
    digits: zmij::Buffer,
}

/// How the comment line of a CSV trajectory starts; JSON follows.
pub const COMMENT: &str = "# ellipsoid ";

/// The comment line of a run of `scenario` (without its newline): the scenario's file name
/// (never its directories) and its body's shape, so that `ellipsoid view`, `plot` and
/// `animate` draw the body from the CSV alone, e.g.
/// `# ellipsoid {"scenario":"tippe-top.toml","semi_axes":[0.015,0.015,0.015],"com_offset":[0.0,0.0,-0.003]}`;
/// a body with contact spheres adds them (body axes, from the ellipsoid's centre, m):
/// `…,"spheres":[{"name":"stem","center":[0.0,0.0,0.013],"radius":0.005}]}`.
pub fn comment(scenario: &Scenario) -> String {
    let name = Path::new(&scenario.source).file_name().map_or_else(
        || scenario.source.clone(),
        |n| n.to_string_lossy().into_owned(),
    );
    let body = &scenario.scene.body;
    let (a, g) = (body.semi_axes(), body.com_offset());
    let mut json = serde_json::json!({
        "scenario": name,
        "semi_axes": [a.x, a.y, a.z],
        "com_offset": [g.x, g.y, g.z],
    });
    if !body.spheres().is_empty() {
        let spheres: Vec<serde_json::Value> = body
            .spheres()
            .iter()
            .map(|s| {
                let c = s.center;
                serde_json::json!({ "name": s.name, "center": [c.x, c.y, c.z], "radius": s.radius })
            })
            .collect();
        json["spheres"] = spheres.into();
    }
    if !body.rims().is_empty() {
        let rims: Vec<serde_json::Value> = (body.rims().iter())
            .map(|r| {
                let c = r.center;
                serde_json::json!({ "name": r.name, "center": [c.x, c.y, c.z], "radius": r.radius, "edge": r.edge })
            })
            .collect();
        json["rims"] = rims.into();
    }
    if !body.ellipsoid_contact() {
        json["ellipsoid_contact"] = false.into();
    }
    format!("{COMMENT}{json}")
}

impl<W: Write> CsvWriter<W> {
    /// Writes the header of the fixed columns (a one-surface body's).
    pub fn new(out: W) -> std::io::Result<Self> {
        Self::with_comment(out, None, Layout::fixed())
    }

    /// Writes the comment line, if any (see [`comment`]), then the header of `layout`.
    pub fn with_comment(
        mut out: W,
        comment: Option<&str>,
        layout: Layout,
    ) -> std::io::Result<Self> {
        if let Some(c) = comment {
            writeln!(out, "{c}")?;
        }
        writeln!(out, "{}", layout.names().join(","))?;
        Ok(CsvWriter {
            out,
            extra: Vec::with_capacity(layout.extra()),
            layout,
            rows: 0,
            line: Vec::with_capacity(1024),
            digits: zmij::Buffer::new(),
        })
    }

    /// Writes one row: each number in its shortest round-trip form (the recorder hands
    /// on finite samples only), assembled in one buffer and written at once.
    pub fn write(&mut self, s: &Sample) -> std::io::Result<()> {
        self.line.clear();
        self.extra.clear();
        self.layout.surface_values(s, &mut self.extra);
        for (i, v) in columns::values(s).iter().chain(&self.extra).enumerate() {
            if i == MODE_POSITION {
                self.line.extend_from_slice(self.layout.mode(s).as_bytes());
                self.line.push(b',');
            }
            self.line
                .extend_from_slice(self.digits.format(*v).as_bytes());
            self.line.push(b',');
        }
        *self.line.last_mut().expect("a row has columns") = b'\n';
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

/// The Poincaré sections of a run (`outcome.sections`, in the scene's order) as one CSV
/// table: a comment line (the trajectory's, see [`comment`], with `"units"`: each column's
/// SI unit), the header `section,` and the trajectory's columns, then one row per point,
/// each starting with its section's name, sections in the scene's order, points in time
/// order.
pub fn sections_table(scenario: &Scenario, sections: &[Vec<Sample>]) -> Vec<u8> {
    let layout = Layout::of(&scenario.scene.body);
    let mut head: serde_json::Value =
        serde_json::from_str(&comment(scenario)[COMMENT.len()..]).expect("the comment is JSON");
    let mut units = serde_json::Map::new();
    units.insert("section".into(), "".into());
    for (name, unit) in layout.units() {
        units.insert(name.into_owned(), unit.into());
    }
    head["units"] = units.into();
    let mut out = format!("{COMMENT}{head}\nsection,{}\n", layout.names().join(",")).into_bytes();
    for (section, points) in scenario.scene.sections.iter().zip(sections) {
        let mut writer = CsvWriter {
            out: Vec::new(),
            extra: Vec::with_capacity(layout.extra()),
            layout: layout.clone(),
            rows: 0,
            line: Vec::with_capacity(1024),
            digits: zmij::Buffer::new(),
        };
        let name = &section.crossing.name;
        // A name with a comma, a quote or a line break is quoted (RFC 4180).
        let label = if name.contains([',', '"', '\n', '\r']) {
            format!("\"{}\",", name.replace('"', "\"\""))
        } else {
            format!("{name},")
        };
        for p in points {
            out.extend_from_slice(label.as_bytes());
            writer.write(p).expect("writing to memory");
            out.append(&mut writer.out);
        }
    }
    out
}

/// Rows handed to the formatting thread at a time.
const BATCH: usize = 512;

/// The file's writer, on its own thread: it formats batches of rows as they come and
/// hands each emptied batch back for reuse.
type Formatter = JoinHandle<std::io::Result<CsvWriter<BufWriter<AtomicFile>>>>;

/// A CSV file written atomically. Rows are formatted on a second thread while the run
/// goes on (formatting costs more than the physics of a sample: issue #18,
/// docs/performance.md), at most two batches behind; a write error there stops the run
/// at the next batch and is reported by [`CsvFile::write`] or [`CsvFile::prepare`].
pub struct CsvFile {
    path: PathBuf,
    rows: u64,
    batch: Vec<Sample>,
    /// Full batches to the formatter (`None` once the file is being completed).
    full: Option<SyncSender<Vec<Sample>>>,
    /// Emptied batches back from it.
    empty: Receiver<Vec<Sample>>,
    formatter: Option<Formatter>,
}

impl CsvFile {
    /// Starts the file at `path` with the columns of `layout`, its first line `comment`
    /// if given (see [`comment`]).
    pub fn create(path: &Path, comment: Option<&str>, layout: Layout) -> Result<Self, OutputError> {
        let file = AtomicFile::create(path)?;
        let mut writer =
            CsvWriter::with_comment(BufWriter::with_capacity(1 << 16, file), comment, layout)
                .map_err(|e| OutputError::io(path, e))?;
        let (full, batches) = sync_channel::<Vec<Sample>>(2);
        let (give_back, empty) = sync_channel::<Vec<Sample>>(3);
        let formatter = std::thread::Builder::new()
            .name("csv".into())
            .spawn(move || {
                for mut batch in batches {
                    for row in &batch {
                        writer.write(row)?;
                    }
                    batch.clear();
                    let _ = give_back.try_send(batch);
                }
                Ok(writer)
            })
            .map_err(|e| OutputError::io(path, e))?;
        Ok(CsvFile {
            path: path.to_owned(),
            rows: 0,
            batch: Vec::with_capacity(BATCH),
            full: Some(full),
            empty,
            formatter: Some(formatter),
        })
    }

    pub fn write(&mut self, s: &Sample) -> Result<(), OutputError> {
        self.batch.push(*s);
        self.rows += 1;
        if self.batch.len() == BATCH {
            let next = self
                .empty
                .try_recv()
                .unwrap_or_else(|_| Vec::with_capacity(BATCH));
            let full = std::mem::replace(&mut self.batch, next);
            let sent = self.full.as_ref().map(|tx| tx.send(full));
            if !matches!(sent, Some(Ok(()))) {
                // The formatter stopped: it failed; its error says why.
                return Err(self.finish().err().unwrap_or_else(|| {
                    OutputError::io(&self.path, std::io::ErrorKind::BrokenPipe.into())
                }));
            }
        }
        Ok(())
    }

    pub fn rows(&self) -> u64 {
        self.rows
    }

    /// Hands on the last batch, waits for the formatter and takes its writer back.
    fn finish(&mut self) -> Result<CsvWriter<BufWriter<AtomicFile>>, OutputError> {
        if let Some(tx) = self.full.take() {
            let last = std::mem::take(&mut self.batch);
            if !last.is_empty() {
                let _ = tx.send(last);
            }
        }
        let Some(formatter) = self.formatter.take() else {
            let gone = std::io::Error::other("the file was already completed, or failed");
            return Err(OutputError::io(&self.path, gone));
        };
        match formatter.join() {
            Ok(done) => done.map_err(|e| OutputError::io(&self.path, e)),
            Err(panic) => std::panic::resume_unwind(panic),
        }
    }

    /// Completes the file without putting it in place.
    pub fn prepare(mut self) -> Result<Prepared, OutputError> {
        let buffered = self
            .finish()?
            .into_inner()
            .map_err(|e| OutputError::io(&self.path, e))?;
        let file = buffered
            .into_inner()
            .map_err(|e| OutputError::io(&self.path, e.into_error()))?;
        file.prepare()
    }
}

impl Drop for CsvFile {
    /// An unfinished file: the formatter stops, and its temporary file is removed before
    /// this returns (so an interrupted run leaves nothing behind when it exits).
    fn drop(&mut self) {
        self.batch.clear();
        self.full = None;
        if let Some(formatter) = self.formatter.take() {
            let _ = formatter.join();
        }
    }
}
