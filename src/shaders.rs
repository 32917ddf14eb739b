//! SPIR-V of the GLSL stages in `shaders/`, compiled by shaderc in `build.rs`.

use crate::error::{Error, Result};

include!(concat!(env!("OUT_DIR"), "/shaders.rs"));

/// The SPIR-V words of a shader, by its file name (`lit.vert`).
pub fn spirv(name: &str) -> Result<Vec<u32>> {
    let bytes = SHADERS
        .iter()
        .find(|(file, _)| *file == name)
        .map(|(_, bytes)| *bytes)
        .ok_or_else(|| Error::InvalidInput(format!("no shader named '{name}' in shaders/")))?;
    ash::util::read_spv(&mut std::io::Cursor::new(bytes))
        .map_err(|e| Error::InvalidInput(format!("shader '{name}' is not valid SPIR-V: {e}")))
}
