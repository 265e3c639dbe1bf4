//! Atomic file creation: write to a temporary file in the target's directory, then
//! rename it over the target. A reader never sees a half-written file, and a run that
//! fails before [`AtomicFile::commit`] leaves nothing (the temporary is deleted on drop).

use std::fs::File;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

use tempfile::{NamedTempFile, TempPath};

use crate::OutputError;

/// A file that appears at its path only when committed.
pub struct AtomicFile {
    tmp: NamedTempFile,
    target: PathBuf,
}

impl AtomicFile {
    /// Opens a temporary file beside `target` (whose directory must exist).
    pub fn create(target: &Path) -> Result<Self, OutputError> {
        let tmp = temporary(target)?;
        Ok(AtomicFile { tmp, target: target.to_owned() })
    }

    /// The file being written.
    pub fn file(&mut self) -> &mut File {
        self.tmp.as_file_mut()
    }

    /// Flushes to disk and renames the file to its target.
    pub fn commit(self) -> Result<(), OutputError> {
        let target = self.target;
        self.tmp.as_file().sync_all().map_err(|e| OutputError::io(&target, e))?;
        commit_path(self.tmp.into_temp_path(), &target)
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.tmp.write(buf)
    }
    fn flush(&mut self) -> io::Result<()> {
        self.tmp.flush()
    }
}

/// A temporary file in `target`'s directory, named after it.
pub(crate) fn temporary(target: &Path) -> Result<NamedTempFile, OutputError> {
    let dir = match target.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let name = target.file_name().map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
    tempfile::Builder::new().prefix(&format!(".{name}.")).suffix(".tmp").tempfile_in(dir).map_err(|e| OutputError::io(target, e))
}

/// Gives the temporary the permissions of an ordinary new file and renames it to `target`.
pub(crate) fn commit_path(tmp: TempPath, target: &Path) -> Result<(), OutputError> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        // tempfile creates 0600; results are meant to be shared like any output file.
        std::fs::set_permissions(&tmp, std::fs::Permissions::from_mode(0o644)).map_err(|e| OutputError::io(target, e))?;
    }
    tmp.persist(target).map_err(|e| OutputError::io(target, e.error))
}

/// Writes `bytes` to `target` atomically.
pub fn write(target: &Path, bytes: &[u8]) -> Result<(), OutputError> {
    let mut f = AtomicFile::create(target)?;
    f.write_all(bytes).map_err(|e| OutputError::io(target, e))?;
    f.commit()
}
