//! The shadow-texture atlas as one page (issue 29): geometry images baked by their texels equal
//! the rasterised bake texel for texel (but for texels on a shadow edge, counted and bounded),
//! a frame re-bakes the whole page in a handful of render pass instances with one fragment per
//! texel, and a model moving among fixed ones re-bakes only the tiles it can shadow, leaving a
//! page and a frame equal to a full re-bake.

use crate::common;

use std::sync::Arc;

use glam::{Mat4, Vec3};
use image::RgbaImage;
use nostencil::technique::shadow_atlas::{
    self, AtlasBake, Baked, LightMode, ShadowAtlasOptions, ShadowAtlasStats, ShadowKind,
};
use nostencil::Gpu;
use nostencil::RenderOptions;
use nostencil::StencilMode;
use nostencil::{builtin_scene, Scene};

fn options(bake: AtlasBake, light: LightMode, size: u32) -> RenderOptions {
    RenderOptions {
        width: size,
        height: size,
        samples: 1,
        stencil: StencilMode::Emulated,
        technique: ShadowKind::Atlas.technique(),
        shadow_atlas: ShadowAtlasOptions { bake, light, ..Default::default() },
        ..Default::default()
    }
}

fn baked<'s>(gpu: &Arc<Gpu>, scene: &'s Scene, options: &RenderOptions) -> Baked<'s> {
    shadow_atlas::bake(gpu, scene, options, &mut |_| {}).expect("atlas bake")
}

fn tiles(baked: &Baked, scene: &Scene) -> Vec<RgbaImage> {
    (0..scene.objects.len()).map(|i| baked.read_shadow_texture(i, 0).expect("read back")).collect()
}

/// Texel (x, y) differs from one of its 8 neighbours in `image` (it lies on an edge of what
/// the bake shadowed).
fn on_an_edge(image: &RgbaImage, x: u32, y: u32) -> bool {
    let own = image.get_pixel(x, y).0;
    (-1i32..=1).flat_map(|dy| (-1i32..=1).map(move |dx| (dx, dy))).any(|(dx, dy)| {
        let (nx, ny) = (x as i32 + dx, y as i32 + dy);
        nx >= 0
            && ny >= 0
            && (nx as u32) < image.width()
            && (ny as u32) < image.height()
            && image.get_pixel(nx as u32, ny as u32).0[..3] != own[..3]
    })
}

#[test]
fn texel_bake_equals_the_rasterised_bake_but_on_shadow_edges() {
    let gpu = common::gpu();
    for name in ["atlas-125", "atlas-one"] {
        let scene = builtin_scene(name).expect("scene");
        let by_texels = baked(&gpu, &scene, &options(AtlasBake::Texels, LightMode::Fixed, 64));
        let rasterised = baked(&gpu, &scene, &options(AtlasBake::Rasterised, LightMode::Fixed, 64));
        let (mut texels, mut differing) = (0u64, 0u64);
        for (object, (a, b)) in tiles(&by_texels, &scene).iter().zip(tiles(&rasterised, &scene)).enumerate() {
            assert_eq!(a.dimensions(), b.dimensions());
            for (x, y, pixel) in a.enumerate_pixels() {
                texels += 1;
                let other = b.get_pixel(x, y);
                if pixel == other {
                    continue;
                }
                differing += 1;
                // The rasteriser snaps vertices to sub-texel steps and interpolates its own
                // barycentrics; the texel bake interpolates exactly. A texel whose surface point
                // moves by that much can only change where the map's depth changes: on an edge.
                assert!(
                    on_an_edge(&b, x, y) || on_an_edge(a, x, y),
                    "{name}: object {object} texel ({x}, {y}) is {:?} baked by texels and {:?} rasterised, away \
                     from any shadow edge",
                    pixel.0,
                    other.0
                );
            }
        }
        eprintln!("{name}: {differing} of {texels} texels differ between the texel and the rasterised bake");
        assert!(differing * 1000 <= texels, "{name}: {differing} of {texels} texels differ (more than 0.1%)");
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn a_moving_light_rebakes_the_page_in_a_handful_of_passes_one_fragment_a_texel() {
    let gpu = common::gpu();
    let scene = builtin_scene("atlas-125").expect("scene");
    let options = options(AtlasBake::Texels, LightMode::Moving, 64);
    let mut renderer = ShadowKind::Atlas.technique().build(&gpu, &scene, &options).expect("renderer");
    for frame in 0..2 {
        let frame = renderer.frame_with(&scene).unwrap_or_else(|e| panic!("frame {frame}: {e}"));
        let stats = frame.stats::<ShadowAtlasStats>().expect("atlas stats");
        let page = stats.page.as_ref().expect("the atlas has a page");
        assert_eq!((stats.rebaked_tiles, page.tiles, page.texel_tiles), (126, 126, 126));
        let counters = &frame.output.counters;
        // The map, the page and the scene: 3 instances for 126 models (the ground, a quad
        // mapped whole, is baked by its texels as the geometry images are: no raster bake).
        assert_eq!(counters.render_pass_instances.len(), 3, "{:?}", counters.render_pass_instances);
        let page_pass = counters.pass("atlas page").expect("the page pass");
        let baked_texels = 125 * 64 * 64 + 256 * 256;
        assert_eq!(page_pass.samples_passed, baked_texels, "one sample a texel re-baked");
        let invocations = page_pass.fragment_invocations.expect("pipeline statistics");
        // lavapipe shades whole 4x4 blocks; a tile's side is a multiple of 4, so the only extra
        // invocations are the quads' diagonal seams.
        assert!(
            invocations >= baked_texels && invocations * 100 <= baked_texels * 110,
            "{invocations} fragment invocations for {baked_texels} texels"
        );
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn a_model_moving_among_fixed_ones_rebakes_only_what_it_can_shadow() {
    let gpu = common::gpu();
    let scene = builtin_scene("atlas-125").expect("scene");
    // Model 62 sits at the centre of the 5 x 5 x 5 block: its move leaves the scene's bounds
    // (and the maps' fit) as they were.
    let mut moved = scene.clone();
    let centre = moved.objects.iter().position(|o| o.name == "model 62").expect("model 62");
    moved.objects[centre].transform =
        Mat4::from_translation(Vec3::new(0.12, 0.05, -0.08)) * moved.objects[centre].transform;
    let options = options(AtlasBake::Texels, LightMode::Fixed, 96);

    let mut incremental = baked(&gpu, &scene, &options);
    let frame = incremental.frame_with(&moved).expect("frame after the move");
    let stats = frame.stats::<ShadowAtlasStats>().expect("atlas stats");
    let rebaked = stats.rebaked_tiles;
    eprintln!("model 62 moved: {rebaked} of 126 tiles re-baked");
    assert!(!stats.cached, "a model moved: the shadow passes run");
    assert!((2..40).contains(&rebaked), "{rebaked} tiles re-baked: the moved model and those below it, not all");

    let full = baked(&gpu, &moved, &options);
    for (object, (a, b)) in tiles(&incremental, &moved).iter().zip(tiles(&full, &moved)).enumerate() {
        assert!(a == &b, "object {object}'s shadow texture differs from a full re-bake's");
    }
    let mut fresh = ShadowKind::Atlas.technique().build(&gpu, &moved, &options).expect("renderer");
    let reference = fresh.frame_with(&moved).expect("full re-bake");
    assert!(frame.output.image == reference.output.image, "the frame differs from a full re-bake's");

    // A frame with nothing moved re-bakes nothing; moving it back re-bakes the same tiles.
    let still = incremental.frame_with(&moved).expect("still frame");
    assert!(still.stats::<ShadowAtlasStats>().is_some_and(|s| s.cached && s.rebaked_tiles == 0));
    let back = incremental.frame_with(&scene).expect("moved back");
    assert_eq!(back.stats::<ShadowAtlasStats>().map(|s| s.rebaked_tiles), Some(rebaked));
    common::assert_no_validation_messages(&gpu);
}
