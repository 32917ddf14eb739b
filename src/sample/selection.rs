//! What a sample outlining a selection needs beyond the base (`examples/outline.rs`): which
//! objects are selected, resolved as the engine resolves `--select`, and a colour given as the
//! PNG shows it (sRGB bytes) as the shaders write it (linear).

use glam::Vec4;

use super::SampleBase;
use crate::error::Result;

impl SampleBase {
    /// Per object (by index in `scene.objects`): whether it is selected. `names` picks objects
    /// by name (an unknown one is refused with the scene's names); none: the scene's first
    /// shadow caster, the engine's default.
    pub fn selection(&self, names: &[&str]) -> Result<Vec<bool>> {
        let names: Vec<String> = names.iter().map(|name| name.to_string()).collect();
        crate::technique::outline::resolve_selection(&self.scene, &names)
    }
}

/// The linear colour (alpha 1) a shader writes for sRGB bytes `srgb` to land on them in the
/// `R8G8B8A8_SRGB` frame.
pub fn linear_colour(srgb: [u8; 3]) -> Vec4 {
    let [r, g, b] = srgb.map(crate::frame::srgb::decode);
    Vec4::new(r, g, b, 1.0)
}
