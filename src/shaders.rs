//! SPIR-V of the GLSL stages in `shaders/`, compiled by shaderc in `build.rs`.

use crate::error::{Error, Result};

include!(concat!(env!("OUT_DIR"), "/shaders.rs"));

/// The SPIR-V words of a shader, by its file name (`lit.vert`).
pub fn spirv(name: &str) -> Result<Vec<u32>> {
    let bytes = SHADERS
        .iter()
        .find(|(file, _)| *file == name)
        .map(|(_, bytes)| *bytes)
        .ok_or_else(|| Error::Internal(format!("no shader named '{name}' in shaders/")))?;
    ash::util::read_spv(&mut std::io::Cursor::new(bytes))
        .map_err(|e| Error::Internal(format!("shader '{name}' is not valid SPIR-V: {e}")))
}

/// The overdraw counter made for a vertex shader by `build.rs` (`lit.vert` -> `lit.vert.count.frag`).
pub fn overdraw_counter_for(vertex_shader: &str) -> Option<&'static str> {
    let wanted = format!("{vertex_shader}.count.frag");
    SHADERS.iter().map(|(name, _)| *name).find(|name| *name == wanted)
}
