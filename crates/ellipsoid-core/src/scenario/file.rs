//! Reading input files within bounds: only regular files (a FIFO, a device such as
//! /dev/zero or a directory is refused before it is opened, so nothing blocks or reads
//! without end), and never more than a limit of bytes actually read, whatever the file's
//! size metadata says.

use std::fs::File;
use std::io::Read;
use std::path::Path;

/// Largest scenario file read \[bytes\]: 8 MiB (a scenario is a few kB).
pub const MAX_SCENARIO_BYTES: u64 = 8 << 20;

/// Opens `path` for reading if it is a regular file (symbolic links followed). The error
/// is the rule broken or the system's message, without the path.
pub fn open_regular(path: &Path) -> Result<File, String> {
    let regular = |meta: std::fs::Metadata| {
        if meta.is_file() {
            Ok(())
        } else {
            Err("not a regular file (a pipe, device or directory is not read)".to_owned())
        }
    };
    // Checked before opening: opening a FIFO waits for a writer.
    regular(std::fs::metadata(path).map_err(|e| e.to_string())?)?;
    let file = File::open(path).map_err(|e| e.to_string())?;
    regular(file.metadata().map_err(|e| e.to_string())?)?;
    Ok(file)
}

/// The bytes of the regular file `path`, refused if it holds more than `limit`.
pub fn read_bounded(path: &Path, limit: u64) -> Result<Vec<u8>, String> {
    let file = open_regular(path)?;
    let mut bytes = Vec::new();
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| e.to_string())?;
    if bytes.len() as u64 > limit {
        return Err(format!("more than {limit} bytes; at most {limit} are read"));
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn endless_and_special_files_are_refused_before_reading() {
        for special in ["/dev/zero", "/dev/urandom", "/"] {
            let e = read_bounded(Path::new(special), 100).unwrap_err();
            assert!(e.starts_with("not a regular file"), "{special}: {e}");
        }
        let dir = std::env::temp_dir().join(format!("ellipsoid-file-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let big = dir.join("big");
        std::fs::write(&big, vec![b'#'; 101]).unwrap();
        assert_eq!(
            read_bounded(&big, 100).unwrap_err(),
            "more than 100 bytes; at most 100 are read"
        );
        assert_eq!(read_bounded(&big, 101).unwrap().len(), 101);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
