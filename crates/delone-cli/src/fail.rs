//! How a run fails: [`Failure`] (a message and an exit code) and
//! [`Usage`] (a command-line error, exit code 2). Every module of the CLI
//! reports through these.

/// A failed run: message and exit code (1 input/mesh, 2 usage).
#[derive(Debug)]
pub struct Failure {
    pub message: String,
    pub code: i32,
}

/// An input or output failure (exit code 1).
pub fn input_err(message: impl Into<String>) -> Failure {
    Failure {
        message: message.into(),
        code: 1,
    }
}

/// A usage failure found while running (exit code 2).
pub fn usage_err(message: impl Into<String>) -> Failure {
    Failure {
        message: message.into(),
        code: 2,
    }
}

/// A usage error found while parsing the command line (exit code 2).
#[derive(Debug)]
pub struct Usage(pub String);

impl From<delone::switches::SwitchError> for Usage {
    fn from(e: delone::switches::SwitchError) -> Self {
        Usage(e.to_string())
    }
}
