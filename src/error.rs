//! One error type for the library: every failure a user can cause ends up here with a message
//! that names the thing at fault (a file, a mesh, an option, a device limit).

use std::fmt;
use std::path::PathBuf;

#[derive(Debug)]
pub enum Error {
    /// A value given by the user is out of range or malformed (an option, a size).
    InvalidInput(String),
    /// A file could not be read or written.
    Io { path: PathBuf, source: std::io::Error },
    /// A glTF file (or other asset) is malformed or uses something unsupported.
    Asset { path: PathBuf, problem: String },
    /// A mesh cannot be used the way it was asked to (open, non-manifold, degenerate).
    Mesh { mesh: String, problem: String },
    /// No Vulkan loader, no suitable device, or a device that misses the mobile profile.
    Device(String),
    /// A Vulkan call failed.
    Vulkan { call: &'static str, result: ash::vk::Result },
    /// GPU memory could not be allocated.
    Memory(String),
    /// A state the program's own logic rules out was reached: a bug, not a bad input.
    Internal(String),
}

pub type Result<T, E = Error> = std::result::Result<T, E>;

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::InvalidInput(msg) => write!(f, "{msg}"),
            Error::Io { path, source } => write!(f, "{}: {source}", path.display()),
            Error::Asset { path, problem } => write!(f, "{}: {problem}", path.display()),
            Error::Mesh { mesh, problem } => write!(f, "mesh '{mesh}': {problem}"),
            Error::Device(msg) => write!(f, "{msg}"),
            Error::Vulkan { call, result } => write!(f, "{call} failed: {result}"),
            Error::Memory(msg) => write!(f, "GPU memory: {msg}"),
            Error::Internal(msg) => write!(f, "internal error (a bug): {msg}"),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

/// Attaches the name of the failing Vulkan call to an `ash` result.
pub trait VkContext<T> {
    fn vk(self, call: &'static str) -> Result<T>;
}

impl<T> VkContext<T> for std::result::Result<T, ash::vk::Result> {
    fn vk(self, call: &'static str) -> Result<T> {
        self.map_err(|result| Error::Vulkan { call, result })
    }
}
