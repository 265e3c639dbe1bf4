//! The journal: every finished row, appended as it finishes, so an interrupted study
//! (Ctrl-C, SIGKILL, power loss) loses at most the runs in flight, and a rerun skips
//! what is done.
//!
//! ```text
//! ellipsoid-study-journal 1 <outcome fingerprint>
//! <key>\t<cell>\t<cell>…\t<crc32>          one line per finished row
//! ```
//! A cell is `~` (no value), `i<integer>`, `f<float>` (Rust's `{:e}`, which reads back
//! to the same f64) or `s<JSON string>`; the CRC-32 (hexadecimal) covers the line before
//! its last tab. Each line goes to the file in one `write` call, so after a SIGKILL the
//! file holds whole lines and at most one torn last line; a torn or corrupt line ends the
//! journal when it is read (it and anything after it are cut off before appending). The
//! file is flushed to disk (fsync) at most once a second and when the study ends, so a
//! power cut loses at most about a second of rows as well.

use std::collections::HashMap;
use std::fs::{File, OpenOptions};
use std::io::{BufRead, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use super::plan::Cell;
use super::run::PointResult;

const MAGIC: &str = "ellipsoid-study-journal 1";
/// Longest time between two flushes to disk.
const SYNC_EVERY: Duration = Duration::from_secs(1);

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
        "{path}: not a study journal (its first line is not `{MAGIC} …`); refusing to overwrite it"
    )]
    NotAJournal { path: PathBuf },
    /// A pipe, device or directory where the journal goes (a FIFO would block).
    #[error(
        "{path}: the journal is not a regular file (a pipe, device or directory); remove it or write the table elsewhere"
    )]
    NotAFile { path: PathBuf },
}

/// An open journal, positioned to append.
pub struct Journal {
    file: File,
    path: PathBuf,
    synced: Instant,
    dirty: bool,
    line: String,
}

/// Rows read back, by key: the outcome cells.
pub type Done = HashMap<String, Vec<Cell>>;

impl Journal {
    /// Opens (or creates) the journal at `path` for a study whose outcome columns have
    /// `fingerprint` and `cells` cells per row; returns the rows already in it.
    pub fn open(
        path: &Path,
        fingerprint: &str,
        cells: usize,
    ) -> Result<(Journal, Done), JournalError> {
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
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(path)
            .map_err(io)?;
        let header = format!("{MAGIC} {fingerprint}\n");
        let len = file.metadata().map_err(io)?.len();
        let mut done = Done::new();
        if len == 0 {
            file.write_all(header.as_bytes()).map_err(io)?;
            file.sync_all().map_err(io)?;
        } else {
            // Line by line: a journal of millions of rows is never held whole.
            let mut reader = std::io::BufReader::new(&mut file);
            let mut line = Vec::new();
            reader.read_until(b'\n', &mut line).map_err(io)?;
            let first = String::from_utf8_lossy(&line);
            let Some(found) = first.trim_end().strip_prefix(MAGIC).map(str::trim) else {
                return Err(JournalError::NotAJournal {
                    path: path.to_owned(),
                });
            };
            if found != fingerprint {
                return Err(JournalError::Mismatch {
                    path: path.to_owned(),
                    found: found.to_owned(),
                    expected: fingerprint.to_owned(),
                });
            }
            let mut good = line.len() as u64;
            loop {
                line.clear();
                if reader.read_until(b'\n', &mut line).map_err(io)? == 0 {
                    break;
                }
                let Some((key, row)) = line
                    .strip_suffix(b"\n") // none: a torn last line
                    .and_then(|l| std::str::from_utf8(l).ok())
                    .and_then(|l| decode(l, cells))
                else {
                    break;
                };
                done.insert(key, row);
                good += line.len() as u64;
            }
            drop(reader);
            if good < len {
                file.set_len(good).map_err(io)?;
                file.sync_all().map_err(io)?;
            }
            file.seek(SeekFrom::Start(good)).map_err(io)?;
        }
        Ok((
            Journal {
                file,
                path: path.to_owned(),
                synced: Instant::now(),
                dirty: false,
                line: String::new(),
            },
            done,
        ))
    }

    /// Appends one row (one `write` call); flushes to disk if the last flush is more
    /// than a second old. Rows without a key (their scenario could not be resolved)
    /// are not kept.
    pub fn append(&mut self, r: &PointResult) -> Result<(), JournalError> {
        if r.key.is_empty() {
            return Ok(());
        }
        encode(&mut self.line, &r.key, &r.cells);
        self.file
            .write_all(self.line.as_bytes())
            .map_err(|source| JournalError::Io {
                path: self.path.clone(),
                source,
            })?;
        self.dirty = true;
        if self.synced.elapsed() >= SYNC_EVERY {
            self.sync()?;
        }
        Ok(())
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

/// One journal line (with its newline) into `line`.
pub fn encode(line: &mut String, key: &str, cells: &[Cell]) {
    use std::fmt::Write as _;
    line.clear();
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

/// A journal line (without its newline) back into its key and cells; `None` if torn or
/// corrupt.
pub fn decode(line: &str, cells: usize) -> Option<(String, Vec<Cell>)> {
    let (body, crc) = line.rsplit_once('\t')?;
    if u32::from_str_radix(crc, 16).ok()? != crc32fast::hash(body.as_bytes()) {
        return None;
    }
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

    #[test]
    fn rows_read_back_exactly_and_a_torn_tail_is_cut_off() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("j");
        let (mut j, done) = Journal::open(&path, "fp", 6).unwrap();
        assert!(done.is_empty());
        for i in 0..3 {
            j.append(&row(i)).unwrap();
        }
        drop(j);
        // A kill in the middle of the fourth line's write.
        let mut line = String::new();
        encode(&mut line, &row(3).key, &row(3).cells);
        let mut f = OpenOptions::new().append(true).open(&path).unwrap();
        f.write_all(&line.as_bytes()[..20]).unwrap();
        drop(f);
        let (mut j, done) = Journal::open(&path, "fp", 6).unwrap();
        assert_eq!(done.len(), 3);
        assert_eq!(done[&row(1).key], row(1).cells);
        j.append(&row(3)).unwrap();
        drop(j);
        let (_, done) = Journal::open(&path, "fp", 6).unwrap();
        assert_eq!(done.len(), 4);
        assert_eq!(done[&row(3).key], row(3).cells);
    }

    #[test]
    fn a_corrupt_line_ends_the_journal_and_other_outcomes_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("j");
        let (mut j, _) = Journal::open(&path, "fp", 6).unwrap();
        j.append(&row(0)).unwrap();
        j.append(&row(1)).unwrap();
        drop(j);
        let text = std::fs::read_to_string(&path)
            .unwrap()
            .replacen("completed", "complete!", 1);
        std::fs::write(&path, text).unwrap();
        let (_, done) = Journal::open(&path, "fp", 6).unwrap();
        assert!(done.is_empty(), "the first row's CRC no longer matches");
        assert!(matches!(
            Journal::open(&path, "other", 6),
            Err(JournalError::Mismatch { .. })
        ));
        std::fs::write(&path, "x,y\n1,2\n").unwrap();
        assert!(matches!(
            Journal::open(&path, "fp", 6),
            Err(JournalError::NotAJournal { .. })
        ));
    }
}
