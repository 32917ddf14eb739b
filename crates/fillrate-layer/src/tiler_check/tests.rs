//! Unit tests of `tiler_check`.
use super::*;

fn key(image: u64) -> Option<ImageKey> {
    Some(ImageKey { image, mip: 0, layer: 0 })
}

fn att(name: &str, image: u64, load: Load, store: Store) -> PassAttachment {
    PassAttachment {
        name: name.into(),
        key: key(image),
        samples: 1,
        load,
        store,
        covers_image: true,
        external: false,
        poisoned_before: load == Load::DontCare,
        poisoned_after: store == Store::DontCare,
    }
}

fn pass(attachments: Vec<PassAttachment>) -> [Event; 2] {
    [Event::PassBegin { label: None, attachments }, Event::PassEnd]
}

fn kinds(check: &TilerCheck) -> Vec<(String, u32, Option<String>)> {
    check.report.flags.iter().map(|f| (f.kind.clone(), f.pass, f.attachment.clone())).collect()
}

fn run(events: &[Event]) -> TilerCheck {
    let mut check = TilerCheck::default();
    check.process(events);
    check.end_frame();
    check.finish();
    check
}

#[test]
fn a_right_frame_gets_no_flag() {
    // Shadow map stored and sampled; the frame cleared, drawn, depth dropped, presented.
    let mut events = Vec::new();
    events.extend(pass(vec![att("depth", 1, Load::Clear, Store::Store)]));
    events.push(Event::PassBegin {
        label: Some("frame".into()),
        attachments: vec![
            PassAttachment { external: true, ..att("colour #0", 2, Load::Clear, Store::Store) },
            att("depth", 3, Load::Clear, Store::DontCare),
        ],
    });
    events.push(Event::Read { image: 1, how: "a draw's descriptor", transient: false });
    events.push(Event::PassEnd);
    let check = run(&events);
    assert!(check.report.flags.is_empty(), "{:?}", check.report.flags);
    assert_eq!(check.report.poisoned.len(), 1, "the dropped depth was poisoned after its pass");
    assert_eq!(check.report.poisoned[0].read_by, None);
}

#[test]
fn each_mistake_is_flagged_by_pass_and_attachment() {
    let mut events = vec![
        // #0: DONT_CARE load, then the first draw blends.
        Event::PassBegin { label: None, attachments: vec![att("colour #0", 1, Load::DontCare, Store::Store)] },
        Event::ReadUndefined { attachment: 0, how: "blending" },
        Event::PassEnd,
        Event::Read { image: 1, how: "vkCmdCopyImageToBuffer", transient: false },
    ];
    // #1: a stored 4x colour, resolved outside the pass.
    events.extend(pass(vec![PassAttachment { samples: 4, ..att("colour #0", 2, Load::Clear, Store::Store) }]));
    events.push(Event::Resolve { src: 2, dst: 3, src_transient: false, dst_transient: false });
    events.push(Event::Read { image: 3, how: "vkCmdCopyImageToBuffer", transient: false });
    // #2: a depth stored and never read: a dead pass too.
    events.extend(pass(vec![att("depth", 4, Load::Clear, Store::Store)]));
    // #3 stores colour 5, #4 clears it before anything read it.
    events.extend(pass(vec![att("colour #0", 5, Load::Clear, Store::Store)]));
    events.extend(pass(vec![att("colour #0", 5, Load::Clear, Store::Store)]));
    events.push(Event::Read { image: 5, how: "vkCmdBlitImage", transient: false });
    // #5 drops colour 6, #6 loads it.
    events.extend(pass(vec![att("colour #0", 6, Load::Clear, Store::DontCare)]));
    events.extend(pass(vec![PassAttachment { external: true, ..att("colour #0", 6, Load::Load, Store::Store) }]));
    // A transient image copied.
    events.push(Event::Read { image: 7, how: "vkCmdCopyImage", transient: true });
    let check = run(&events);
    let some = |s: &str| Some(s.to_owned());
    assert_eq!(
        kinds(&check),
        vec![
            ("dont_care_load_read".into(), 0, some("colour #0")),
            ("multisampled_stored".into(), 1, some("colour #0")),
            ("resolve_outside_pass".into(), 1, some("colour #0")),
            ("stored_then_overwritten".into(), 3, some("colour #0")),
            ("dead_pass".into(), 3, None),
            ("attachment_loaded".into(), 6, some("colour #0")),
            ("load_after_dont_care".into(), 6, some("colour #0")),
            ("transient_outside_pass".into(), 7, None),
            ("stored_never_read".into(), 2, some("depth")),
            ("dead_pass".into(), 2, None),
        ]
    );
    let notes: Vec<(&str, u32, Option<&str>)> =
        check.report.poisoned.iter().map(|n| (n.when.as_str(), n.pass, n.read_by.as_deref())).collect();
    assert_eq!(
        notes,
        vec![
            ("before the pass (DONT_CARE load)", 0, Some("the pass's first draw (blending)")),
            ("after the pass (DONT_CARE store)", 5, Some("pass #6's LOAD")),
        ]
    );
}

#[test]
fn a_clear_command_then_a_load_or_a_clear_in_a_pass_is_flagged_per_subresource() {
    // The shadow-texture atlas's mistake: mips 0 to 2 cleared by a command, then loaded.
    let cleared = Event::Cleared { image: 1, how: "vkCmdClearColorImage", ranges: vec![(0..u32::MAX, 0..1)] };
    let mut events = vec![cleared.clone()];
    for mip in 0..3 {
        let attachment = PassAttachment {
            key: Some(ImageKey { image: 1, mip, layer: 0 }),
            external: true,
            ..att("colour #0", 1, Load::Load, Store::Store)
        };
        events.extend(pass(vec![attachment]));
    }
    // Image 2 cleared by a command, then by a pass's LOAD_OP_CLEAR.
    events.push(Event::Cleared { image: 2, how: "vkCmdClearColorImage", ranges: vec![(0..1, 0..1)] });
    events.extend(pass(vec![PassAttachment { external: true, ..att("colour #0", 2, Load::Clear, Store::Store) }]));
    // A copy out between a clear and the pass: the clear was used; the LOAD is only a load.
    events.push(cleared);
    events.push(Event::Read { image: 1, how: "vkCmdCopyImageToBuffer", transient: false });
    events.extend(pass(vec![PassAttachment { external: true, ..att("colour #0", 1, Load::Load, Store::Store) }]));
    let check = run(&events);
    let counted: Vec<(&str, u32, u64)> =
        check.report.flags.iter().map(|f| (f.kind.as_str(), f.pass, f.count)).collect();
    assert_eq!(
        counted,
        [
            ("clear_then_load", 0, 1),
            ("attachment_loaded", 0, 1),
            ("clear_then_load", 1, 1),
            ("attachment_loaded", 1, 1),
            ("clear_then_load", 2, 1),
            ("attachment_loaded", 2, 1),
            ("redundant_clear", 3, 1),
            ("attachment_loaded", 4, 1)
        ]
    );
}

#[test]
fn a_swap_shows_the_colour_the_last_pass_stored() {
    // zink: each frame clears and draws the GL back buffer and its depth, then swaps.
    let mut check = TilerCheck::default();
    for _ in 0..2 {
        check.process(&pass(vec![
            att("colour #0", 1, Load::Clear, Store::Store),
            att("depth #0", 2, Load::Clear, Store::Store),
        ]));
        check.swapped();
    }
    check.finish();
    let depth = Some("depth #0".to_owned());
    assert_eq!(
        kinds(&check),
        vec![("stored_then_overwritten".into(), 0, depth.clone()), ("stored_never_read".into(), 0, depth)]
    );
}

#[test]
fn a_pass_that_draws_the_presented_image_is_alive_though_its_depth_is_cleared_unread() {
    // vkd3d-gears: its pass stores the swapchain image and a depth the next frame clears.
    let mut check = TilerCheck::default();
    for _ in 0..2 {
        check.process(&pass(vec![
            PassAttachment { external: true, ..att("colour #0", 1, Load::Clear, Store::Store) },
            att("depth #1", 2, Load::Clear, Store::Store),
        ]));
        check.end_frame();
    }
    check.finish();
    let some = |s: &str| Some(s.to_owned());
    assert_eq!(
        kinds(&check),
        vec![
            ("stored_then_overwritten".into(), 0, some("depth #1")),
            ("stored_never_read".into(), 0, some("depth #1"))
        ]
    );
}

#[test]
fn an_output_read_in_the_next_frame_is_fine_and_one_read_keeps_a_pass_alive() {
    let mut check = TilerCheck::default();
    // History: stored in frame 0, read in frame 1.
    check.process(&pass(vec![att("colour #0", 1, Load::Clear, Store::Store)]));
    check.end_frame();
    check.process(&[Event::Read { image: 1, how: "a draw's descriptor", transient: false }]);
    // A pass storing two images, one read: not dead, the other never read.
    check.process(&pass(vec![
        att("colour #0", 2, Load::Clear, Store::Store),
        att("depth", 3, Load::Clear, Store::Store),
    ]));
    check.process(&[Event::Read { image: 2, how: "vkCmdCopyImage", transient: false }]);
    check.end_frame();
    check.end_frame();
    assert_eq!(kinds(&check), vec![("stored_never_read".into(), 0, Some("depth".into()))]);
    // A partial render area does not replace the rest of the image.
    let mut check = TilerCheck::default();
    check.process(&pass(vec![att("depth", 1, Load::Clear, Store::Store)]));
    check.process(&pass(vec![PassAttachment { covers_image: false, ..att("depth", 1, Load::Clear, Store::Store) }]));
    check.process(&[Event::Read { image: 1, how: "a draw's descriptor", transient: false }]);
    check.finish();
    assert!(check.report.flags.is_empty(), "{:?}", check.report.flags);
}
