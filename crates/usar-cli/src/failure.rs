//! How a command fails: bad input (exit 2) or a failure of our own (exit 1), or a domain exit
//! code (e.g. 3: no feasible route).

/// An error with the exit code the process should end with.
#[derive(Debug)]
pub struct Failure {
    pub error: anyhow::Error,
    pub code: u8,
}

impl Failure {
    pub fn exit_code(&self) -> u8 {
        self.code
    }
}

/// Errors from outside the process (files, arguments): exit code 2.
pub fn bad_input(error: impl Into<anyhow::Error>) -> Failure {
    Failure {
        error: error.into(),
        code: 2,
    }
}

/// Anything else is our failure: exit code 1.
impl<E: Into<anyhow::Error>> From<E> for Failure {
    fn from(error: E) -> Self {
        Failure {
            error: error.into(),
            code: 1,
        }
    }
}

pub type CmdResult<T = ()> = Result<T, Failure>;

/// Marks a result's error as bad input.
pub trait InputContext<T> {
    fn input(self) -> CmdResult<T>;
}

impl<T, E: Into<anyhow::Error>> InputContext<T> for Result<T, E> {
    fn input(self) -> CmdResult<T> {
        self.map_err(bad_input)
    }
}
