//! SPIR-V of the GLSL stages in `shaders/`, compiled by shaderc in `build.rs`.

use std::fmt;

use crate::error::{Error, Result};

include!(concat!(env!("OUT_DIR"), "/shaders.rs"));

/// A shader of `shaders/`, by its file name. Only this module makes one: `build.rs` writes a
/// constant for every file it compiled (`LIT_VERT` is `lit.vert`), so naming a shader that does
/// not exist fails the build, not a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(transparent)]
pub struct Shader(&'static str);

impl fmt::Display for Shader {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.0)
    }
}

/// The shader whose file in `shaders/` is `file` (`"lit.vert"`): what the samples name.
pub fn by_file(file: &str) -> Result<Shader> {
    SHADERS
        .iter()
        .map(|(name, _)| *name)
        .find(|name| *name == file)
        .map(Shader)
        .ok_or_else(|| Error::InvalidInput(format!("no shader named '{file}' in shaders/")))
}

/// The SPIR-V words of a shader.
pub fn spirv(shader: Shader) -> Result<Vec<u32>> {
    let name = shader.0;
    let bytes = SHADERS
        .iter()
        .find(|(file, _)| *file == name)
        .map(|(_, bytes)| *bytes)
        .ok_or_else(|| Error::Internal(format!("no shader named '{name}' in shaders/")))?;
    ash::util::read_spv(&mut std::io::Cursor::new(bytes))
        .map_err(|e| Error::Internal(format!("shader '{name}' is not valid SPIR-V: {e}")))
}

impl Shader {
    /// The vertex shader's skinned twin made by `build.rs` (`lit.vert` -> `lit.skinned.vert`):
    /// the same stage compiled with `SKINNED`, for vertices that carry joints and weights.
    pub fn skinned_twin(self) -> Option<Shader> {
        let wanted = self.0.strip_suffix(".vert").map(|stem| format!("{stem}.skinned.vert"))?;
        SHADERS.iter().map(|(name, _)| *name).find(|name| *name == wanted).map(Shader)
    }
}

/// The overdraw counter made for a vertex shader by `build.rs` (`lit.vert` -> `lit.vert.count.frag`).
pub fn overdraw_counter_for(vertex_shader: Shader) -> Option<Shader> {
    let wanted = format!("{}.count.frag", vertex_shader.0);
    SHADERS.iter().map(|(name, _)| *name).find(|name| *name == wanted).map(Shader)
}
