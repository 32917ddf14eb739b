//! The main frame: no stencil aspect anywhere; the default scene renders lit, at the requested
//! size, identically in the emulated and reference frames (no technique uses the stencil yet).

use crate::common::{self, technique};

use nostencil::builtin_scene;
use nostencil::frame::render_pass::format_has_stencil;
use nostencil::frame::FrameTargets;
use nostencil::StencilMode;
use nostencil::{render_scene, RenderOptions};

#[test]
fn main_frame_has_no_stencil_aspect_and_reference_has_one() {
    let gpu = common::gpu();
    let main = FrameTargets::new(&gpu, 64, 64, StencilMode::Emulated, false).expect("targets");
    assert!(!main.desc.has_stencil(), "main render pass has a stencil aspect");
    assert!(!format_has_stencil(main.depth.format), "{:?}", main.depth.format);
    assert!(!format_has_stencil(main.colour().expect("an offscreen frame's own colour").format));
    let feedback = FrameTargets::new(&gpu, 64, 64, StencilMode::Emulated, true).expect("targets");
    assert!(!feedback.desc.has_stencil());

    let reference = FrameTargets::new(&gpu, 64, 64, StencilMode::Reference, false).expect("targets");
    assert!(format_has_stencil(reference.depth.format), "{:?}", reference.depth.format);
    drop((main, feedback, reference));
    common::assert_no_validation_messages(&gpu);
}

/// The viewer's frame, drawn into swapchain images: one framebuffer per attached image, none
/// before (a frame then is refused, not drawn), and a one-sample frame that reads its own
/// colour is not made for them. Plain images of the swapchain's format stand in for its images.
#[test]
fn a_frame_for_swapchain_images_gets_a_framebuffer_per_attached_image() {
    use nostencil::gpu::memory::{Image, ImageDesc};
    let gpu = common::gpu();
    let format = ash::vk::Format::B8G8R8A8_SRGB;
    let extent = ash::vk::Extent2D { width: 32, height: 16 };
    let images: Vec<Image> = (0..3)
        .map(|_| {
            let desc = ImageDesc {
                name: "stand-in swapchain image",
                format,
                extent,
                usage: ash::vk::ImageUsageFlags::COLOR_ATTACHMENT,
                aspect: ash::vk::ImageAspectFlags::COLOR,
                mip_levels: 1,
                samples: 1,
            };
            Image::new(&gpu, &desc).expect("image")
        })
        .collect();
    for samples in [1, 4] {
        let mut targets =
            FrameTargets::presenting(&gpu, (32, 16, samples), StencilMode::Emulated, false, format).expect("targets");
        assert!(targets.presents() && targets.colour().is_none());
        assert!(targets.framebuffer().is_err(), "a framebuffer before any image was attached");
        let raw: Vec<ash::vk::Image> = images.iter().map(|i| i.raw).collect();
        targets.attach_swapchain(&raw).expect("attach");
        for index in 0..3 {
            targets.select_output(index).expect("select");
            assert_eq!(targets.output_image(), raw[index as usize]);
            assert!(targets.framebuffer().is_ok());
        }
        assert!(targets.select_output(3).is_err(), "an image that was never attached");
        // Attached again (a recreated swapchain): the old framebuffers are replaced.
        targets.attach_swapchain(&raw[..2]).expect("attach again");
        assert!(targets.select_output(2).is_err());
    }
    let refused = FrameTargets::presenting(&gpu, (32, 16, 1), StencilMode::Emulated, true, format);
    assert!(refused.is_err(), "a one-sample frame reading its own colour was made for swapchain images");
    drop(images);
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn default_scene_renders_lit_at_the_requested_size() {
    let gpu = common::gpu();
    let scene = builtin_scene("default").expect("scene");
    let options = RenderOptions { width: 256, height: 192, technique: technique("lit"), ..Default::default() };
    let output = render_scene(&gpu, &scene, &options).expect("render").output;
    let image = &output.image;
    assert_eq!(image.dimensions(), (256, 192));

    // The background keeps the clear colour at the top; the middle shows the lit box (blue
    // dominant) and the ground is lighter below it.
    let top = image.get_pixel(128, 2).0;
    assert_eq!(top[..3], common::srgb8(scene.background));
    // The ground at the bottom centre has lit.frag's colour for an upward face under the light.
    let (bottom, ground) = (image.get_pixel(128, 191).0, common::lit_ground(&scene));
    assert!(common::near(&bottom, &ground, 1), "bottom centre {bottom:?}, lit ground {ground:?}");
    let distinct: std::collections::HashSet<[u8; 4]> =
        image.chunks_exact(4).map(|p| [p[0], p[1], p[2], p[3]]).collect();
    assert!(distinct.len() > 200, "a lit scene has many shades, got {}", distinct.len());

    // Every object is visible: the scene pass drew all of them, and samples passed cover at
    // least the ground's share of the frame.
    let scene_pass = output.counters.pass("scene").expect("scene pass");
    assert_eq!(scene_pass.draws as usize, scene.objects.len());
    assert!(scene_pass.samples_passed > (256 * 192 / 3) as u64);
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn reference_frame_renders_the_same_lit_image() {
    let gpu = common::gpu();
    let scene = builtin_scene("default").expect("scene");
    let mut options = RenderOptions { width: 160, height: 120, ..Default::default() };
    let emulated = render_scene(&gpu, &scene, &options).expect("emulated").output;
    options.stencil = StencilMode::Reference;
    let reference = render_scene(&gpu, &scene, &options).expect("reference").output;
    assert!(emulated.image == reference.image, "emulated and reference lit frames differ");
    // Equal, and not equally empty: the sky at the top, the lit ground at the bottom.
    let sky = common::srgb8(scene.background);
    let (top, bottom) = (reference.image.get_pixel(80, 0).0, reference.image.get_pixel(80, 119).0);
    assert_eq!(top[..3], sky, "top centre {top:?}, sky {sky:?}");
    let ground = common::lit_ground(&scene);
    assert!(common::near(&bottom, &ground, 1), "bottom centre {bottom:?}, lit ground {ground:?}");
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn zero_and_oversized_frames_are_refused() {
    let gpu = common::gpu();
    let scene = builtin_scene("default").expect("scene");
    for (width, height) in [(0, 64), (64, 0), (4097, 64)] {
        let options = RenderOptions { width, height, ..Default::default() };
        let error = render_scene(&gpu, &scene, &options).err().expect("must fail");
        assert!(error.to_string().contains("size"), "{error}");
    }
    common::assert_no_validation_messages(&gpu);
}
