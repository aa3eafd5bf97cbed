//! The error type of the library: every message names the field, value or path at fault, and I/O
//! and HDF5 errors keep their cause as [`std::error::Error::source`].

use std::path::{Path, PathBuf};

use thiserror::Error;

/// Everything that can go wrong in a sweep.
#[derive(Debug, Error)]
pub enum SweepError {
    /// The sweep spec is malformed or holds a value out of its domain.
    #[error("invalid sweep spec: {0}")]
    Spec(String),
    /// An argument of a library call is wrong (a shard, a thread count, merge inputs).
    #[error("{0}")]
    Usage(String),
    /// An output directory or file is not what it should be (another sweep's, another schema's).
    #[error("{0}")]
    Output(String),
    /// An operation on a file or directory failed.
    #[error("{action} {}", path.display())]
    Io {
        /// What was being done ("cannot write", …).
        action: &'static str,
        /// The path it was done to.
        path: PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// The HDF5 library failed on a file.
    #[error("{}{}", path.display(), os_reason(source))]
    Hdf5 {
        /// The file.
        path: PathBuf,
        /// The cause.
        #[source]
        source: hdf5::Error,
    },
}

impl SweepError {
    /// An I/O error while doing `action` to `path`.
    pub fn io(action: &'static str, path: &Path, source: std::io::Error) -> Self {
        SweepError::Io {
            action,
            path: path.to_path_buf(),
            source,
        }
    }

    /// An HDF5 error on the file at `path`.
    pub fn hdf5(path: &Path, source: hdf5::Error) -> Self {
        SweepError::Hdf5 {
            path: path.to_path_buf(),
            source,
        }
    }

    /// The message and every cause, joined by `: ` (how the CLI prints an error).
    pub fn chain(&self) -> String {
        let mut s = self.to_string();
        let mut cause = std::error::Error::source(self);
        while let Some(c) = cause {
            s += &format!(": {c}");
            cause = c.source();
        }
        s
    }
}

/// `: <the system's reason>` where an HDF5 error carries one ("No space left on device"), so that
/// the first words of the message say what happened; the whole HDF5 text follows as the cause.
fn os_reason(e: &hdf5::Error) -> String {
    let text = e.to_string();
    let Some(start) = text.find("error message = '") else {
        return String::new();
    };
    let rest = &text[start + "error message = '".len()..];
    rest.find('\'')
        .map(|end| format!(": {}", &rest[..end]))
        .unwrap_or_default()
}
