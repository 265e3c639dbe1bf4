//! The journal: every finished row, appended as it finishes, so an interrupted study
//! (Ctrl-C, SIGKILL, power loss) loses at most the runs in flight, and a rerun skips
//! what is done.
//!
//! ```text
//! ellipsoid-study-journal 2 <outcome fingerprint> <plan fingerprint>
//! <point>\t<key>\t<cell>\t<cell>…\t<crc32>          one line per finished row
//! ```
//! `<point>` is the row's point index, or `-` for a row known by its key only (kept from
//! a journal of an edited study, or of the first format); `<key>` is the row's key (empty
//! for a point whose scenario could not be resolved). A cell is `~` (no value),
//! `i<integer>`, `f<float>` (Rust's `{:e}`, which reads back to the same f64) or `s<JSON
//! string>`; the CRC-32 (hexadecimal) covers the line before its last tab. Each line
//! goes to the file in one `write` call, so after a SIGKILL the file holds whole lines and
//! at most one torn last line; a torn or corrupt line ends the journal when it is read (it
//! and anything after it are cut off before appending). The file is flushed to disk
//! (fsync) at most once a second and when the study ends, so a power cut loses at most
//! about a second of rows as well.
//!
//! **Resuming.** The plan fingerprint is a hash of the study as data (its canonical
//! [`Plan`](super::Plan)): when it is this study's, a row's point index is trusted and the
//! point is skipped without being resolved (10⁶ rows of a 10⁷-point study: half a second).
//! Otherwise (the study file was edited, or the journal is of the first format, which
//! had no indexes) the rows are matched by key, which resolves every point (tens of
//! microseconds each), and the journal is rewritten in this format with its rows as
//! key-only lines, each matched point adding its indexed line.
//!
//! **Reading the table back.** The journal knows where each point's line is
//! ([`Journal::row`]), so the table is written from it in point order, a row at a
//! time, whatever the order the rows finished in.

use std::collections::HashMap;
use std::fs::{File, OpenOptions};
use std::io::{BufRead, BufReader, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use super::plan::Cell;
use super::run::{PointResult, RowStatus};

const MAGIC: &str = "ellipsoid-study-journal";
/// The format written.
const VERSION: u32 = 2;
/// Longest time between two flushes to disk.
const SYNC_EVERY: Duration = Duration::from_secs(1);
/// Lines read between two looks at the cancel flag.
const CANCEL_EVERY: usize = 4096;

/// Why a journal cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum JournalError {
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// The journal was written for a study recording other outcomes.
    #[error(
        "{path}: this journal holds rows of a study with other outcomes (fingerprint {found}, this study's {expected}); delete it to start over, or write the table elsewhere"
    )]
    Mismatch {
        path: PathBuf,
        found: String,
        expected: String,
    },
    /// Not a journal at all.
    #[error(
        "{path}: not a study journal (its first line is not `{MAGIC} 1|2 …`); refusing to overwrite it"
    )]
    NotAJournal { path: PathBuf },
    /// A pipe, device or directory where the journal goes (a FIFO would block).
    #[error(
        "{path}: the journal is not a regular file (a pipe, device or directory); remove it or write the table elsewhere"
    )]
    NotAFile { path: PathBuf },
    /// A row whose `status` cell names no status (the journal was edited, or written by
    /// another version).
    #[error(
        "{path}:{line}: the row's status {value} is not one of {}; the journal was edited or written by another version: delete it to start over, or write the table elsewhere",
        RowStatus::names().collect::<Vec<_>>().join(", ")
    )]
    UnknownStatus {
        path: PathBuf,
        /// 1-based, the header being line 1.
        line: usize,
        /// The cell as written (a string quoted, `~` for no value).
        value: String,
    },
    /// The cancel flag was set while the journal was read; it is unchanged.
    #[error("{path}: interrupted while reading the journal")]
    Interrupted { path: PathBuf },
}

/// Whom a journal is for: the study's fingerprints, its outcome cells per row and its
/// number of points.
#[derive(Debug, Clone, Copy)]
pub struct For<'a> {
    /// [`Study::outcome_fingerprint`](super::Study::outcome_fingerprint): rows of other
    /// outcomes are refused.
    pub outcomes: &'a str,
    /// [`Study::plan_fingerprint`](super::Study::plan_fingerprint): rows of another plan
    /// are matched by key.
    pub plan: &'a str,
    pub cells: usize,
    pub points: usize,
}

/// An open journal, positioned to append, with where each point's row is.
pub struct Journal {
    file: File,
    path: PathBuf,
    synced: Instant,
    dirty: bool,
    line: String,
    /// Length of the file (where the next line goes).
    len: u64,
    /// Byte offset of each point's line, by point index; 0 where the point has none (the
    /// header is at 0). Zeroed pages cost nothing until written.
    at: Vec<u64>,
    /// Points with a line.
    indexed: usize,
    /// Of those read when the journal was opened, the failed ones (status other than
    /// completed or observed).
    failed: usize,
    /// Rows known by key only (from a journal of another plan or format): key → status
    /// and cells.
    by_key: HashMap<String, (RowStatus, Vec<Cell>)>,
    cells: usize,
    /// Reads rows back ([`Journal::row`]): a second handle with its position.
    reader: Option<(BufReader<File>, u64)>,
}

impl Journal {
    /// Opens (or creates) the journal at `path` for the study `whom`; reads the rows
    /// already in it, looking at `cancel` every few thousand lines.
    pub fn open(path: &Path, whom: For<'_>, cancel: &AtomicBool) -> Result<Journal, JournalError> {
        let io = |source| JournalError::Io {
            path: path.to_owned(),
            source,
        };
        // Checked before opening: reading a FIFO waits for a writer, for ever.
        if std::fs::metadata(path).is_ok_and(|m| !m.is_file()) {
            return Err(JournalError::NotAFile {
                path: path.to_owned(),
            });
        }
        let file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(path)
            .map_err(io)?;
        let header = format!("{MAGIC} {VERSION} {} {}\n", whom.outcomes, whom.plan);
        let len = file.metadata().map_err(io)?.len();
        let mut j = Journal {
            file,
            path: path.to_owned(),
            synced: Instant::now(),
            dirty: false,
            line: String::new(),
            len: header.len() as u64,
            at: vec![0; whom.points],
            indexed: 0,
            failed: 0,
            by_key: HashMap::new(),
            cells: whom.cells,
            reader: None,
        };
        if len == 0 {
            j.file.write_all(header.as_bytes()).map_err(io)?;
            j.file.sync_all().map_err(io)?;
            return Ok(j);
        }
        // Line by line: a journal of millions of rows is never held whole.
        let mut reader = BufReader::with_capacity(1 << 16, &mut j.file);
        let mut line = Vec::new();
        reader.read_until(b'\n', &mut line).map_err(io)?;
        let first = String::from_utf8_lossy(&line);
        let mut words = first.trim_end().split(' ');
        let (version, outcomes, plan) = match (words.next(), words.next()) {
            (Some(MAGIC), Some("1")) => (1, words.next(), None),
            (Some(MAGIC), Some("2")) => (2, words.next(), words.next()),
            _ => (0, None, None),
        };
        let Some(outcomes) = outcomes.filter(|_| version > 0) else {
            return Err(JournalError::NotAJournal {
                path: path.to_owned(),
            });
        };
        if outcomes != whom.outcomes {
            return Err(JournalError::Mismatch {
                path: path.to_owned(),
                found: outcomes.to_owned(),
                expected: whom.outcomes.to_owned(),
            });
        }
        // Indexes are trusted only in a journal of this very plan.
        let trusted = plan == Some(whom.plan);
        let mut good = line.len() as u64;
        let mut by_key = HashMap::new();
        let mut at = std::mem::take(&mut j.at);
        let (mut indexed, mut failed) = (0, 0);
        for n in 0.. {
            if n % CANCEL_EVERY == 0 && cancel.load(Ordering::Relaxed) {
                return Err(JournalError::Interrupted {
                    path: path.to_owned(),
                });
            }
            line.clear();
            if reader.read_until(b'\n', &mut line).map_err(io)? == 0 {
                break;
            }
            let row = line
                .strip_suffix(b"\n") // none: a torn last line
                .and_then(|l| std::str::from_utf8(l).ok())
                .and_then(|l| {
                    if version == 1 {
                        decode_v1(l, whom.cells).map(|(k, c)| (None, k, c))
                    } else {
                        decode(l, whom.cells)
                    }
                });
            let Some((point, key, cells)) = row else {
                break;
            };
            if point.is_some_and(|i| i >= whom.points) {
                break; // not of this study: corrupt
            }
            // Parsed here, once: the tally and the rows handed on carry it typed.
            let status = RowStatus::of(&cells).map_err(|value| JournalError::UnknownStatus {
                path: path.to_owned(),
                line: n + 2,
                value,
            })?;
            match point {
                Some(i) if trusted => {
                    if at[i] == 0 {
                        indexed += 1;
                        failed += usize::from(status.failed());
                    }
                    at[i] = good;
                }
                _ if !key.is_empty() => {
                    by_key.insert(key, (status, cells));
                }
                _ => {}
            }
            good += line.len() as u64;
        }
        drop(reader);
        j.at = at;
        j.indexed = indexed;
        j.failed = failed;
        j.by_key = by_key;
        if !trusted {
            // Rewritten in this format for this plan: its rows as key-only lines.
            j.rewrite(&header)?;
        } else {
            if good < len {
                j.file.set_len(good).map_err(io)?;
                j.file.sync_all().map_err(io)?;
            }
            j.file.seek(SeekFrom::Start(good)).map_err(io)?;
            j.len = good;
        }
        Ok(j)
    }

    /// Replaces the file by one of this format with `header` and the rows known by key,
    /// atomically (a journal of another plan stays whole until the new one is in place).
    fn rewrite(&mut self, header: &str) -> Result<(), JournalError> {
        let io = |source| JournalError::Io {
            path: self.path.clone(),
            source,
        };
        let fail = |e: ellipsoid_io::OutputError| io(std::io::Error::other(e.to_string()));
        let mut tmp = ellipsoid_io::atomic::AtomicFile::create(&self.path).map_err(fail)?;
        {
            let mut out = std::io::BufWriter::new(tmp.file());
            out.write_all(header.as_bytes()).map_err(io)?;
            for (key, (_, cells)) in &self.by_key {
                encode(&mut self.line, None, key, cells);
                out.write_all(self.line.as_bytes()).map_err(io)?;
            }
            out.flush().map_err(io)?;
        }
        tmp.commit().map_err(fail)?;
        self.file = OpenOptions::new()
            .read(true)
            .write(true)
            .open(&self.path)
            .map_err(io)?;
        self.len = self.file.seek(SeekFrom::End(0)).map_err(io)?;
        Ok(())
    }

    /// Whether point `i` has its row.
    pub fn has(&self, i: usize) -> bool {
        self.at.get(i).is_some_and(|&a| a != 0)
    }

    /// Points with their row.
    pub fn indexed(&self) -> usize {
        self.indexed
    }

    /// Of the points whose rows were read when the journal was opened, those that failed.
    pub fn failed(&self) -> usize {
        self.failed
    }

    /// Rows known by key only (a journal of another plan or of the first format): their
    /// points must be resolved to be matched ([`Journal::by_key`]).
    pub fn keyed(&self) -> usize {
        self.by_key.len()
    }

    /// The status and cells of the row known by `key` only, if any.
    pub fn by_key(&self, key: &str) -> Option<&(RowStatus, Vec<Cell>)> {
        self.by_key.get(key)
    }

    /// Appends one row (one `write` call) and notes where it is; flushes to disk if the
    /// last flush is more than a second old.
    pub fn append(&mut self, r: &PointResult) -> Result<(), JournalError> {
        encode(&mut self.line, Some(r.index), &r.key, &r.cells);
        self.file
            .write_all(self.line.as_bytes())
            .map_err(|source| JournalError::Io {
                path: self.path.clone(),
                source,
            })?;
        if let Some(a) = self.at.get_mut(r.index) {
            if *a == 0 {
                self.indexed += 1;
            }
            *a = self.len;
        }
        self.len += self.line.len() as u64;
        self.dirty = true;
        if self.synced.elapsed() >= SYNC_EVERY {
            self.sync()?;
        }
        Ok(())
    }

    /// Point `i`'s row, read back from the file (without trajectory); `None` if it has
    /// none. Cheapest in point order (a buffered read when the lines follow each other).
    pub fn row(&mut self, i: usize) -> Result<Option<PointResult>, JournalError> {
        let io = |source| JournalError::Io {
            path: self.path.clone(),
            source,
        };
        let Some(&at) = self.at.get(i).filter(|&&a| a != 0) else {
            return Ok(None);
        };
        if self.reader.is_none() {
            let f = File::open(&self.path).map_err(io)?;
            self.reader = Some((BufReader::with_capacity(1 << 16, f), 0));
        }
        let (reader, pos) = self.reader.as_mut().expect("opened above");
        if *pos != at {
            let delta = i64::try_from(at).unwrap_or(i64::MAX) - i64::try_from(*pos).unwrap_or(0);
            reader.seek_relative(delta).map_err(io)?;
        }
        self.line.clear();
        let n = reader.read_line(&mut self.line).map_err(io)?;
        *pos = at + n as u64;
        let row = decode(self.line.trim_end_matches('\n'), self.cells)
            .filter(|(p, ..)| *p == Some(i))
            .and_then(|(_, key, cells)| Some((key, RowStatus::of(&cells).ok()?, cells)));
        match row {
            Some((key, status, cells)) => Ok(Some(PointResult {
                index: i,
                key,
                status,
                cells,
                trajectory: None,
            })),
            None => Err(io(std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                format!(
                    "the row of point {i} no longer reads back (the journal changed while the study ran)"
                ),
            ))),
        }
    }

    /// Flushes to disk.
    pub fn sync(&mut self) -> Result<(), JournalError> {
        if self.dirty {
            self.file.sync_data().map_err(|source| JournalError::Io {
                path: self.path.clone(),
                source,
            })?;
            self.dirty = false;
        }
        self.synced = Instant::now();
        Ok(())
    }
}

/// One journal line (with its newline) into `line`: point `point` (`None`: known by key
/// only), its key and cells.
pub fn encode(line: &mut String, point: Option<usize>, key: &str, cells: &[Cell]) {
    use std::fmt::Write as _;
    line.clear();
    match point {
        Some(i) => {
            let _ = write!(line, "{i}");
        }
        None => line.push('-'),
    }
    line.push('\t');
    line.push_str(key);
    for c in cells {
        line.push('\t');
        match c {
            Cell::Null => line.push('~'),
            Cell::Int(i) => {
                let _ = write!(line, "i{i}");
            }
            Cell::Float(f) => {
                let _ = write!(line, "f{f:e}");
            }
            Cell::Text(s) => {
                line.push('s');
                line.push_str(&serde_json::to_string(s).unwrap_or_else(|_| "\"\"".into()));
            }
        }
    }
    let crc = crc32fast::hash(line.as_bytes());
    let _ = writeln!(line, "\t{crc:08x}");
}

/// A journal line (without its newline) back into its point (`None`: by key only), key
/// and cells; `None` if torn or corrupt.
pub fn decode(line: &str, cells: usize) -> Option<(Option<usize>, String, Vec<Cell>)> {
    let (point, rest) = line.split_once('\t')?;
    let point = match point {
        "-" => None,
        p => Some(p.parse().ok()?),
    };
    // The CRC covers the whole line before its last tab, the point included.
    let (body, crc) = line.rsplit_once('\t')?;
    if u32::from_str_radix(crc, 16).ok()? != crc32fast::hash(body.as_bytes()) {
        return None;
    }
    let (key, row) = cells_of(rest.strip_suffix(crc)?.strip_suffix('\t')?, cells)?;
    Some((point, key, row))
}

/// A line of the first format (`<key>\t<cell>…\t<crc32>`, no point) into its key and
/// cells.
fn decode_v1(line: &str, cells: usize) -> Option<(String, Vec<Cell>)> {
    let (body, crc) = line.rsplit_once('\t')?;
    if u32::from_str_radix(crc, 16).ok()? != crc32fast::hash(body.as_bytes()) {
        return None;
    }
    cells_of(body, cells)
}

/// `<key>\t<cell>…` into the key and `cells` cells.
fn cells_of(body: &str, cells: usize) -> Option<(String, Vec<Cell>)> {
    let mut parts = body.split('\t');
    let key = parts.next()?.to_owned();
    let row: Option<Vec<Cell>> = parts
        .map(|p| match p.split_at_checked(1)? {
            ("~", "") => Some(Cell::Null),
            ("i", v) => v.parse().ok().map(Cell::Int),
            ("f", v) => v.parse().ok().map(Cell::Float),
            ("s", v) => serde_json::from_str::<String>(v).ok().map(Cell::Text),
            _ => None,
        })
        .collect();
    let row = row?;
    (row.len() == cells).then_some((key, row))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(i: usize) -> PointResult {
        PointResult {
            index: i,
            key: format!("{i:032x}"),
            status: RowStatus::Ran(ellipsoid_core::simulate::StatusKind::Completed),
            cells: vec![
                Cell::Text("completed".into()),
                Cell::Text("a\tmessage, with \"quotes\"\nand a newline".into()),
                Cell::Float(0.1 + 0.2),
                Cell::Float(5e-324),
                Cell::Null,
                Cell::Int(-7),
            ],
            trajectory: None,
        }
    }

    const FOR: For<'static> = For {
        outcomes: "fp",
        plan: "plan",
        cells: 6,
        points: 10,
    };

    fn open(path: &Path, whom: For<'_>) -> Journal {
        Journal::open(path, whom, &AtomicBool::new(false)).unwrap()
    }

    #[test]
    fn rows_read_back_exactly_by_point_and_a_torn_tail_is_cut_off() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("j");
        let mut j = open(&path, FOR);
        assert_eq!(j.indexed(), 0);
        for i in [2, 0, 1] {
            j.append(&row(i)).unwrap();
        }
        drop(j);
        // A kill in the middle of the fourth line's write.
        let mut line = String::new();
        encode(&mut line, Some(3), &row(3).key, &row(3).cells);
        let mut f = OpenOptions::new().append(true).open(&path).unwrap();
        f.write_all(&line.as_bytes()[..20]).unwrap();
        drop(f);
        let mut j = open(&path, FOR);
        assert_eq!((j.indexed(), j.keyed()), (3, 0));
        assert!(!j.has(3));
        for i in 0..3 {
            assert_eq!(j.row(i).unwrap(), Some(row(i)));
        }
        assert_eq!(j.row(3).unwrap(), None);
        j.append(&row(3)).unwrap();
        assert_eq!(j.row(3).unwrap(), Some(row(3)));
        drop(j);
        let mut j = open(&path, FOR);
        assert_eq!(j.indexed(), 4);
        assert_eq!(j.row(3).unwrap(), Some(row(3)));
        assert_eq!(j.row(1).unwrap(), Some(row(1)));
    }

    #[test]
    fn another_plan_or_the_first_format_is_matched_by_key_only() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("j");
        let mut j = open(&path, FOR);
        j.append(&row(0)).unwrap();
        j.append(&row(1)).unwrap();
        drop(j);
        // The study was edited: its rows are known by key, no index is trusted.
        let edited = For {
            plan: "edited",
            ..FOR
        };
        let mut j = open(&path, edited);
        assert_eq!((j.indexed(), j.keyed()), (0, 2));
        assert_eq!(j.by_key(&row(1).key), Some(&(row(1).status, row(1).cells)));
        assert_eq!(j.row(0).unwrap(), None);
        j.append(&row(5)).unwrap();
        drop(j);
        // Rewritten for the edited plan: the key-only rows and the new indexed one.
        let mut j = open(&path, edited);
        assert_eq!((j.indexed(), j.keyed()), (1, 2));
        assert_eq!(j.row(5).unwrap(), Some(row(5)));
        // The first format: `<key>\t<cells>\t<crc>`, no point.
        let mut v1 = String::from("ellipsoid-study-journal 1 fp\n");
        for i in 0..3 {
            let mut line = String::new();
            encode(&mut line, None, &row(i).key, &row(i).cells);
            v1.push_str(line.strip_prefix("-\t").unwrap());
        }
        // The CRC of the first format covers the line without the point: recomputed.
        let v1: String = v1
            .lines()
            .enumerate()
            .map(|(n, l)| {
                if n == 0 {
                    return format!("{l}\n");
                }
                let body = l.rsplit_once('\t').unwrap().0;
                format!("{body}\t{:08x}\n", crc32fast::hash(body.as_bytes()))
            })
            .collect();
        std::fs::write(&path, v1).unwrap();
        let j = open(&path, FOR);
        assert_eq!((j.indexed(), j.keyed()), (0, 3));
        assert_eq!(j.by_key(&row(2).key), Some(&(row(2).status, row(2).cells)));
        drop(j);
        let first = std::fs::read_to_string(&path).unwrap();
        assert!(first.starts_with("ellipsoid-study-journal 2 fp plan\n"));
    }

    #[test]
    fn a_corrupt_line_ends_the_journal_and_other_outcomes_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("j");
        let mut j = open(&path, FOR);
        j.append(&row(0)).unwrap();
        j.append(&row(1)).unwrap();
        drop(j);
        let text = std::fs::read_to_string(&path)
            .unwrap()
            .replacen("completed", "complete!", 1);
        std::fs::write(&path, text).unwrap();
        assert_eq!(
            open(&path, FOR).indexed(),
            0,
            "the first row's CRC no longer matches"
        );
        let other = For {
            outcomes: "other",
            ..FOR
        };
        let cancel = AtomicBool::new(false);
        assert!(matches!(
            Journal::open(&path, other, &cancel),
            Err(JournalError::Mismatch { .. })
        ));
        // A point beyond the study's is corrupt too.
        let mut j = open(&path, FOR);
        j.append(&row(0)).unwrap();
        j.append(&row(1)).unwrap();
        drop(j);
        let fewer = For { points: 1, ..FOR };
        assert_eq!(open(&path, fewer).indexed(), 1);
        std::fs::write(&path, "x,y\n1,2\n").unwrap();
        assert!(matches!(
            Journal::open(&path, FOR, &cancel),
            Err(JournalError::NotAJournal { .. })
        ));
        std::fs::write(&path, "ellipsoid-study-journal 2 fp plan\n").unwrap();
        assert!(matches!(
            Journal::open(&path, FOR, &AtomicBool::new(true)),
            Err(JournalError::Interrupted { .. })
        ));
    }
}
