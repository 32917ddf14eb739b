//! Colour as a phone's screen shows it, end to end: a glTF file with an unlit material goes
//! through the loader, the shaders, the R8G8B8A8_SRGB frame and the PNG, and the PNG holds the
//! sRGB encoding of the material's linear colour.

use crate::common;

use base64::Engine as _;
use glam::{Vec3, Vec4Swizzles};
use nostencil::scene_from_gltf;

/// Linear grey whose sRGB encoding is 128/255 (IEC 61966-2-1: 0.2158605...).
const LINEAR_GREY: f32 = 0.2159;

/// A 2 x 2 quad in the XY plane facing +Z (the front a glTF model shows), with an unlit material
/// of `grey`, as a self-contained .gltf (data URI).
fn unlit_quad_gltf(grey: f32) -> String {
    let positions: [[f32; 3]; 4] = [[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 2.0, 0.0], [-1.0, 2.0, 0.0]];
    let indices: [u16; 6] = [0, 1, 2, 0, 2, 3];
    let mut bytes: Vec<u8> = positions.iter().flatten().flat_map(|f| f.to_le_bytes()).collect();
    bytes.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    let data = base64::engine::general_purpose::STANDARD.encode(&bytes);
    format!(
        r#"{{
  "asset": {{"version": "2.0"}},
  "extensionsUsed": ["KHR_materials_unlit"],
  "extensionsRequired": ["KHR_materials_unlit"],
  "scene": 0,
  "scenes": [{{"nodes": [0]}}],
  "nodes": [{{"mesh": 0}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1, "material": 0}}]}}],
  "materials": [{{
    "pbrMetallicRoughness": {{"baseColorFactor": [{grey}, {grey}, {grey}, 1.0]}},
    "doubleSided": true,
    "extensions": {{"KHR_materials_unlit": {{}}}}
  }}],
  "buffers": [{{"byteLength": {len}, "uri": "data:application/octet-stream;base64,{data}"}}],
  "bufferViews": [
    {{"buffer": 0, "byteOffset": 0, "byteLength": 48}},
    {{"buffer": 0, "byteOffset": 48, "byteLength": 12}}
  ],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
      "min": [-1.0, 0.0, 0.0], "max": [1.0, 2.0, 0.0]}},
    {{"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}}
  ]
}}"#,
        len = bytes.len()
    )
}

#[test]
fn an_unlit_linear_grey_of_0_2159_is_128_in_the_png() {
    let encoded = 1.055 * LINEAR_GREY.powf(1.0 / 2.4) - 0.055;
    assert_eq!((encoded * 255.0).round(), 128.0, "the test's own arithmetic");
    let dir = common::scratch_dir("colour-unlit");
    let file = dir.join("unlit-grey.gltf");
    std::fs::write(&file, unlit_quad_gltf(LINEAR_GREY)).expect("write the test file");
    let scene = scene_from_gltf(&file, 0.0).expect("the file loads");
    let (width, height) = (128u32, 96u32);
    // The quad's middle, projected by the scene's own camera: the pixel to read.
    let clip = scene.camera.view_projection(width as f32 / height as f32) * Vec3::new(0.0, 1.0, 0.0).extend(1.0);
    let ndc = clip.xy() / clip.w;
    let (x, y) = (((ndc.x + 1.0) * 0.5 * width as f32) as u32, ((ndc.y + 1.0) * 0.5 * height as f32) as u32);
    for technique in ["lit", "shadow-volume", "planar", "shadow-map", "outline", "toon"] {
        let out = dir.join(format!("{technique}.png"));
        let size = format!("{width}x{height}");
        common::run_ok(&[
            "render",
            "--scene",
            file.to_str().expect("utf-8 path"),
            "--technique",
            technique,
            "--size",
            &size,
            "--validation",
            "--out",
            out.to_str().expect("utf-8 path"),
        ]);
        let png = common::read_png(&out);
        let pixel = png.get_pixel(x, y).0;
        assert!(pixel.iter().all(|c| c.abs_diff(128) <= 1), "{technique}: the grey at ({x}, {y}) is {pixel:?}");
    }
}
