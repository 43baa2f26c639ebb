//! The error type of every reader and writer in this crate.

use std::fmt;

/// An error while reading or writing a mesh file.
///
/// Parse errors carry the 1-based line number, what the reader expected and
/// what it found, so that `Display` gives messages such as
/// `line 7: expected 3 coordinates, found 2`.
///
/// ```
/// let err = delone_io::read_node(b"2 2 0 0\n1 0 0\n").unwrap_err();
/// assert!(matches!(err, delone_io::IoError::UnexpectedEnd { declared: 2, found: 1, .. }));
/// assert_eq!(err.line(), Some(1));
/// ```
#[derive(Debug)]
#[non_exhaustive]
pub enum IoError {
    /// The underlying reader or writer failed.
    Io(std::io::Error),
    /// A line does not have the expected content.
    Syntax {
        /// 1-based line number in the file.
        line: usize,
        /// What the reader expected, e.g. `"3 coordinates"` or `"point index 2"`.
        expected: String,
        /// What it found, e.g. `"2"` or `"\"abc\""`.
        found: String,
    },
    /// The file ended before all the items its header announces.
    UnexpectedEnd {
        /// 1-based line number of the header that announces the count.
        line: usize,
        /// What is counted, e.g. `"points"` or `"elements"`.
        what: &'static str,
        /// The count the header announces.
        declared: usize,
        /// How many items the file actually holds.
        found: usize,
    },
    /// The file is well formed but uses a feature this crate does not handle
    /// (e.g. a `.node` file of dimension 4).
    Unsupported {
        /// 1-based line number.
        line: usize,
        /// What is not supported.
        message: String,
    },
    /// A writer was handed inconsistent data (e.g. a marker array whose
    /// length differs from the number of points, or an element that refers to
    /// a point that does not exist).
    InvalidInput {
        /// What is wrong, naming the offending item.
        message: String,
    },
}

impl IoError {
    /// Builds an [`IoError::Syntax`].
    ///
    /// ```
    /// let e = delone_io::IoError::syntax(7, "3 coordinates", "2");
    /// assert_eq!(e.to_string(), "line 7: expected 3 coordinates, found 2");
    /// ```
    pub fn syntax(line: usize, expected: impl Into<String>, found: impl Into<String>) -> Self {
        IoError::Syntax {
            line,
            expected: expected.into(),
            found: found.into(),
        }
    }

    /// The 1-based line number the error refers to, if any.
    ///
    /// ```
    /// let e = delone_io::IoError::syntax(3, "a number", "\"x\"");
    /// assert_eq!(e.line(), Some(3));
    /// ```
    pub fn line(&self) -> Option<usize> {
        match self {
            IoError::Syntax { line, .. }
            | IoError::UnexpectedEnd { line, .. }
            | IoError::Unsupported { line, .. } => Some(*line),
            IoError::Io(_) | IoError::InvalidInput { .. } => None,
        }
    }

    pub(crate) fn invalid(message: impl Into<String>) -> Self {
        IoError::InvalidInput {
            message: message.into(),
        }
    }
}

impl fmt::Display for IoError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            IoError::Io(e) => write!(f, "{e}"),
            IoError::Syntax {
                line,
                expected,
                found,
            } => write!(f, "line {line}: expected {expected}, found {found}"),
            IoError::UnexpectedEnd {
                line,
                what,
                declared,
                found,
            } => write!(
                f,
                "line {line}: header says {declared} {what} but the file ends after {found}"
            ),
            IoError::Unsupported { line, message } => write!(f, "line {line}: {message}"),
            IoError::InvalidInput { message } => write!(f, "{message}"),
        }
    }
}

impl std::error::Error for IoError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            IoError::Io(e) => Some(e),
            _ => None,
        }
    }
}

impl From<std::io::Error> for IoError {
    fn from(e: std::io::Error) -> Self {
        IoError::Io(e)
    }
}
