//! Atomic file creation: write to a temporary file in the target's directory, then
//! rename it over the target. A reader never sees a half-written file, and a run that
//! fails before [`AtomicFile::commit`] leaves nothing (the temporary is deleted on drop).
//!
//! Several files that belong together (a trajectory and its summary) are first
//! [prepared](AtomicFile::prepare), then put in place by [`commit_all`]: either all of
//! them appear, or none does and the targets are as they were.

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
        Ok(AtomicFile {
            tmp,
            target: target.to_owned(),
        })
    }

    /// The file being written.
    pub fn file(&mut self) -> &mut File {
        self.tmp.as_file_mut()
    }

    /// Flushes to disk and renames the file to its target.
    pub fn commit(self) -> Result<(), OutputError> {
        self.prepare()?.commit()
    }

    /// Flushes to disk: the file is complete, waiting to be renamed to its target.
    pub fn prepare(self) -> Result<Prepared, OutputError> {
        let target = self.target;
        self.tmp
            .as_file()
            .sync_all()
            .map_err(|e| OutputError::io(&target, e))?;
        Ok(Prepared {
            tmp: self.tmp.into_temp_path(),
            target,
        })
    }
}

/// A complete file in a temporary beside its target, not yet in place (dropped, it is
/// deleted).
pub struct Prepared {
    tmp: TempPath,
    target: PathBuf,
}

impl Prepared {
    #[cfg_attr(not(feature = "hdf5"), allow(dead_code))] // the HDF5 writer makes its own temporary
    pub(crate) fn new(tmp: TempPath, target: &Path) -> Self {
        Prepared {
            tmp,
            target: target.to_owned(),
        }
    }

    /// Where the file goes.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Renames the file to its target.
    pub fn commit(self) -> Result<(), OutputError> {
        commit_path(self.tmp, &self.target)
    }
}

/// Puts every prepared file in place, or none: a target that is a directory is refused
/// before anything is renamed, and if a rename still fails, the files already renamed
/// are taken back (a new file is removed, a replaced one restored from a hard link made
/// beforehand).
pub fn commit_all(files: Vec<Prepared>) -> Result<(), OutputError> {
    for f in &files {
        check_target(&f.target)?;
    }
    // What to do to undo each rename made so far: restore the old file or remove the new.
    let mut undo: Vec<(PathBuf, Option<TempPath>)> = Vec::new();
    for f in files {
        let backup = backup_of(&f.target);
        let target = f.target.clone();
        if let Err(e) = f.commit() {
            for (target, backup) in undo.into_iter().rev() {
                match backup {
                    Some(b) => {
                        let _ = b.persist(&target);
                    }
                    None => {
                        let _ = std::fs::remove_file(&target);
                    }
                }
            }
            return Err(e);
        }
        undo.push((target, backup));
    }
    Ok(())
}

/// Refuses a target that exists and is not a regular file: a directory (renaming over it
/// fails), a symbolic link (the rename would replace the link, not the file it names) or
/// a device, pipe or socket such as /dev/stdout (the rename would replace the special
/// file itself).
pub fn check_target(target: &Path) -> Result<(), OutputError> {
    let Ok(meta) = std::fs::symlink_metadata(target) else {
        return Ok(());
    };
    let why = if meta.is_dir() {
        (io::ErrorKind::IsADirectory, "is a directory, not a file")
    } else if meta.file_type().is_symlink() {
        (
            io::ErrorKind::InvalidInput,
            "is a symbolic link; give the path of the file itself",
        )
    } else if !meta.is_file() {
        (
            io::ErrorKind::InvalidInput,
            "is a device, pipe or socket, not a regular file (for standard output give -)",
        )
    } else {
        return Ok(());
    };
    Err(OutputError::io(target, io::Error::new(why.0, why.1)))
}

/// A hard link to the existing file at `target` (deleted on drop), to restore it with;
/// None if there is no file there (or the file system cannot link, then it cannot be restored).
fn backup_of(target: &Path) -> Option<TempPath> {
    if !target.is_file() {
        return None;
    }
    let dir = match target.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    // Reserve a unique name, then link the old file under it.
    let path = tempfile::Builder::new()
        .prefix(".backup.")
        .suffix(".tmp")
        .tempfile_in(dir)
        .ok()?
        .into_temp_path();
    std::fs::remove_file(&path).ok()?;
    match std::fs::hard_link(target, &path) {
        Ok(()) => Some(path),
        Err(_) => {
            // Nothing at `path` now; keep TempPath from deleting a later file there.
            let _ = path.keep();
            None
        }
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

/// A temporary file in `target`'s directory, named after it; the target must pass
/// [`check_target`].
pub(crate) fn temporary(target: &Path) -> Result<NamedTempFile, OutputError> {
    check_target(target)?;
    let dir = match target.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let name = target
        .file_name()
        .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
    tempfile::Builder::new()
        .prefix(&format!(".{name}."))
        .suffix(".tmp")
        .tempfile_in(dir)
        .map_err(|e| OutputError::io(target, e))
}

/// Gives the temporary the permissions of an ordinary new file and renames it to `target`.
pub(crate) fn commit_path(tmp: TempPath, target: &Path) -> Result<(), OutputError> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        // tempfile creates 0600; results are meant to be shared like any output file.
        std::fs::set_permissions(&tmp, std::fs::Permissions::from_mode(0o644))
            .map_err(|e| OutputError::io(target, e))?;
    }
    tmp.persist(target)
        .map_err(|e| OutputError::io(target, e.error))
}

/// Writes `bytes` to `target` atomically.
pub fn write(target: &Path, bytes: &[u8]) -> Result<(), OutputError> {
    prepare(target, bytes)?.commit()
}

/// Writes `bytes` to a temporary beside `target`, to be put in place later.
pub fn prepare(target: &Path, bytes: &[u8]) -> Result<Prepared, OutputError> {
    let mut f = AtomicFile::create(target)?;
    f.write_all(bytes).map_err(|e| OutputError::io(target, e))?;
    f.prepare()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(dir: &Path) -> Vec<String> {
        let mut n: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        n.sort();
        n
    }

    #[cfg(unix)]
    #[test]
    fn special_files_and_symlinks_are_refused_before_anything_is_written() {
        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("real.csv");
        std::fs::write(&real, "keep").unwrap();
        let link = dir.path().join("link.csv");
        std::os::unix::fs::symlink(&real, &link).unwrap();
        let dangling = dir.path().join("dangling.csv");
        std::os::unix::fs::symlink(dir.path().join("nowhere"), &dangling).unwrap();
        for (target, why) in [
            (link.as_path(), "symbolic link"),
            (dangling.as_path(), "symbolic link"),
            (Path::new("/dev/null"), "device, pipe or socket"),
        ] {
            let err = AtomicFile::create(target).err().expect("refused");
            assert!(err.to_string().contains(why), "{}: {err}", target.display());
        }
        assert_eq!(std::fs::read_to_string(&real).unwrap(), "keep");
        assert!(
            std::fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(
            names(dir.path()),
            ["dangling.csv", "link.csv", "real.csv"],
            "no temporary left"
        );
    }

    #[test]
    fn commit_all_puts_every_file_in_place() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a.csv"), dir.path().join("b.json"));
        std::fs::write(&a, "old").unwrap();
        commit_all(vec![
            prepare(&a, b"new a").unwrap(),
            prepare(&b, b"new b").unwrap(),
        ])
        .unwrap();
        assert_eq!(std::fs::read_to_string(&a).unwrap(), "new a");
        assert_eq!(std::fs::read_to_string(&b).unwrap(), "new b");
        assert_eq!(
            names(dir.path()),
            ["a.csv", "b.json"],
            "no temporary or backup left"
        );
    }

    #[test]
    fn commit_all_refuses_a_directory_target_before_renaming_anything() {
        let dir = tempfile::tempdir().unwrap();
        let (a, d) = (dir.path().join("a.csv"), dir.path().join("d"));
        let files = vec![prepare(&a, b"a").unwrap(), prepare(&d, b"d").unwrap()];
        // the target became a directory after its file was prepared
        std::fs::create_dir(&d).unwrap();
        let err = commit_all(files).unwrap_err();
        assert!(
            err.to_string().ends_with("d: is a directory, not a file"),
            "{err}"
        );
        assert_eq!(names(dir.path()), ["d"]);
        assert_eq!(names(&d), Vec::<String>::new());
    }

    #[test]
    fn commit_all_takes_back_what_it_renamed_when_a_later_rename_fails() {
        let dir = tempfile::tempdir().unwrap();
        let (old, new) = (dir.path().join("old.csv"), dir.path().join("new.csv"));
        std::fs::write(&old, "keep").unwrap();
        let sub = dir.path().join("sub");
        std::fs::create_dir(&sub).unwrap();
        let doomed = prepare(&sub.join("s.json"), b"s").unwrap();
        std::fs::remove_dir_all(&sub).unwrap(); // its temporary goes with it: the rename fails
        assert!(
            commit_all(vec![
                prepare(&old, b"replaced").unwrap(),
                prepare(&new, b"n").unwrap(),
                doomed
            ])
            .is_err()
        );
        assert_eq!(
            std::fs::read_to_string(&old).unwrap(),
            "keep",
            "the replaced file is restored"
        );
        assert_eq!(
            names(dir.path()),
            ["old.csv"],
            "the new file is removed, no backup left"
        );
    }
}
