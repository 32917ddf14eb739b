//! One error type for the library: every failure a user can cause ends up here with a message
//! that names the thing at fault (a file, a mesh, an option, a device limit).

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A value given by the user is out of range or malformed (an option, a size).
    #[error("{0}")]
    InvalidInput(String),
    /// A file could not be read or written.
    #[error("{}: {source}", .path.display())]
    Io { path: PathBuf, source: std::io::Error },
    /// A glTF file (or other asset) is malformed or uses something unsupported.
    #[error("{}: {problem}", .path.display())]
    Asset { path: PathBuf, problem: String },
    /// A mesh cannot be used the way it was asked to (open, non-manifold, degenerate).
    #[error("mesh '{mesh}': {problem}")]
    Mesh { mesh: String, problem: String },
    /// No Vulkan loader, no suitable device, or a device that misses the mobile profile.
    #[error("{0}")]
    Device(String),
    /// A Vulkan call failed.
    #[error("{call} failed: {result}")]
    Vulkan { call: &'static str, result: ash::vk::Result },
    /// A submitted piece of GPU work failed (device lost, out of device memory): `work` names
    /// it, for a frame its passes.
    #[error("{call} failed with {result:?} for {work}")]
    Submit { work: String, call: &'static str, result: ash::vk::Result },
    /// GPU memory could not be allocated.
    #[error("GPU memory: {0}")]
    Memory(String),
    /// A state the program's own logic rules out was reached: a bug, never the user's input.
    #[error("internal error (a bug in nostencil): {0}")]
    Internal(String),
}

pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Attaches the name of the failing Vulkan call to an `ash` result.
pub trait VkContext<T> {
    fn vk(self, call: &'static str) -> Result<T>;
}

impl<T> VkContext<T> for std::result::Result<T, ash::vk::Result> {
    fn vk(self, call: &'static str) -> Result<T> {
        self.map_err(|result| Error::Vulkan { call, result })
    }
}

#[cfg(test)]
mod tests {
    use std::error::Error as _;

    use super::*;

    #[test]
    fn messages_name_the_thing_at_fault() {
        let io = Error::Io { path: "a/b.glb".into(), source: std::io::Error::other("gone") };
        assert_eq!(io.to_string(), "a/b.glb: gone");
        assert_eq!(io.source().map(|s| s.to_string()).as_deref(), Some("gone"));
        let cases = [
            (Error::InvalidInput("bad size".into()), "bad size"),
            (Error::Asset { path: "x.gltf".into(), problem: "no scene".into() }, "x.gltf: no scene"),
            (Error::Mesh { mesh: "torus".into(), problem: "open".into() }, "mesh 'torus': open"),
            (Error::Device("no device".into()), "no device"),
            (
                Error::Vulkan { call: "vkCreateBuffer", result: ash::vk::Result::ERROR_OUT_OF_DEVICE_MEMORY },
                "vkCreateBuffer failed: A device memory allocation has failed",
            ),
            (Error::Memory("full".into()), "GPU memory: full"),
            (
                Error::Submit {
                    work: "the frame's passes: scene, apply".into(),
                    call: "vkQueueSubmit",
                    result: ash::vk::Result::ERROR_DEVICE_LOST,
                },
                "vkQueueSubmit failed with ERROR_DEVICE_LOST for the frame's passes: scene, apply",
            ),
        ];
        for (error, text) in cases {
            assert_eq!(error.to_string(), text);
            assert!(error.source().is_none());
        }
    }
}
