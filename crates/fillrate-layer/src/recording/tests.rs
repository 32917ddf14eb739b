//! Unit tests of `recording`: segments, sections and draw slots as a recording lays them out.

use super::*;
use ash::vk::Handle;

fn desc() -> PassDesc {
    PassDesc {
        api: "vkCmdBeginRenderPass",
        area: RenderArea { x: 0, y: 0, width: 8, height: 8 },
        samples: 1,
        attachments: Vec::new(),
        not_measured: None,
        secondary_contents: false,
        view_counts: Vec::new(),
    }
}

fn recording() -> (Recording, impl FnMut(QueryKind) -> Option<vk::QueryPool>) {
    let mut next = 100u64;
    let create = move |kind: QueryKind| {
        next += 1;
        Some(vk::QueryPool::from_raw(next * 10 + kind as u64))
    };
    (Recording::new(false, QuerySupport { statistics: true, precise: true, timestamps: true }), create)
}

fn begins(cmds: &[QueryCmd]) -> usize {
    cmds.iter().filter(|c| matches!(c, QueryCmd::Begin { .. })).count()
}

fn ends(cmds: &[QueryCmd]) -> usize {
    cmds.iter().filter(|c| matches!(c, QueryCmd::End { .. })).count()
}

#[test]
fn a_pass_is_bracketed_and_its_subpasses_split_the_segments() {
    let (mut rec, mut create) = recording();
    rec.push_label("shadow".into());
    let (before, after) = rec.begin_pass(desc(), &mut create);
    assert!(before.iter().all(|c| matches!(c, QueryCmd::Reset { .. })) && before.len() == 3);
    // Only the timestamp right after the begin: no query may begin before a pipeline is bound.
    assert_eq!(after.len(), 1);
    assert!(matches!(after[0], QueryCmd::Timestamp { stage: vk::PipelineStageFlags::TOP_OF_PIPE, .. }));
    assert_eq!(begins(&rec.draw(1).0), 2, "the first draw begins both segments");
    assert!(rec.draw(1).0.is_empty(), "later draws continue them");
    let (b, a) = rec.next_subpass(false);
    assert_eq!((ends(&b), a.len()), (2, 0));
    let (b, _) = rec.next_subpass(false);
    assert!(b.is_empty(), "a subpass without draws has no segment to end");
    assert_eq!(begins(&rec.draw(1).0), 2);
    let end = rec.end_pass().0;
    assert_eq!(ends(&end), 2);
    assert!(matches!(end.last(), Some(QueryCmd::Timestamp { stage: vk::PipelineStageFlags::BOTTOM_OF_PIPE, .. })));
    assert!(rec.draw(1).0.is_empty()); // outside a pass: not counted
    let pass = &rec.passes[0];
    assert_eq!((pass.draws, pass.occlusion.len(), pass.statistics.len()), (3, 2, 2));
    assert_eq!(pass.label.as_deref(), Some("shadow"));
    assert!(pass.not_measured().is_none());
}

#[test]
fn an_application_query_inside_a_pass_becomes_a_gap_between_segments() {
    let (mut rec, mut create) = recording();
    rec.begin_pass(desc(), &mut create);
    rec.draw(1);
    let app = vk::QueryPool::from_raw(7);
    let none = vk::QueryPipelineStatisticFlags::empty();
    let before = rec.app_begin_query(QueryKind::Occlusion, app, 3, true, none);
    assert_eq!(before.len(), 1);
    assert!(matches!(before[0], QueryCmd::End { slot } if slot == rec.passes[0].occlusion[0]));
    assert!(rec.draw(1).0.is_empty(), "inside the application's query the layer's stays ended");
    assert!(rec.app_end_query(app, 3).is_empty());
    assert_eq!(begins(&rec.draw(1).0), 1, "the next draw resumes the occlusion segment");
    rec.end_pass();
    let pass = &rec.passes[0];
    assert_eq!((pass.occlusion.len(), pass.statistics.len(), pass.gaps.len()), (2, 1, 1));
    assert!(!pass.gaps[0].open && pass.not_measured().is_none());
}

#[test]
fn application_queries_that_cannot_be_measured_around_are_named() {
    let (mut rec, mut create) = recording();
    let app = vk::QueryPool::from_raw(7);
    let none = vk::QueryPipelineStatisticFlags::empty();
    rec.app_begin_query(QueryKind::Occlusion, app, 0, true, none);
    let (before, after) = rec.begin_pass(desc(), &mut create);
    assert!(before.is_empty() && after.is_empty());
    assert!(rec.end_pass().0.is_empty());
    assert_eq!(rec.passes[0].not_measured(), Some("application occlusion query active across the pass"));
    rec.app_end_query(app, 0);
    // Imprecise application occlusion inside a precise pass: not measured, layer queries end.
    rec.begin_pass(desc(), &mut create);
    rec.draw(1);
    let before = rec.app_begin_query(QueryKind::Occlusion, app, 1, false, none);
    assert_eq!(ends(&before), 2);
    rec.app_end_query(app, 1);
    rec.end_pass();
    assert!(rec.passes[1].not_measured().is_some_and(|r| r.contains("imprecise")));
}

#[test]
fn per_draw_gives_each_draw_its_own_segments_and_timestamps() {
    let (mut rec, mut create) = recording();
    rec.per_draw = true;
    let (before, _) = rec.begin_pass(desc(), &mut create);
    assert!(before.iter().all(|c| matches!(c, QueryCmd::Reset { .. })));
    for _ in 0..3 {
        let (b, a) = rec.draw(1);
        assert_eq!((begins(&b), ends(&a)), (2, 2), "segments around each draw: {b:?} {a:?}");
        assert!(matches!(b[0], QueryCmd::Timestamp { stage: vk::PipelineStageFlags::TOP_OF_PIPE, .. }));
        assert!(matches!(a.last(), Some(QueryCmd::Timestamp { stage: vk::PipelineStageFlags::BOTTOM_OF_PIPE, .. })));
    }
    assert_eq!(ends(&rec.end_pass().0), 0, "nothing left active at the end");
    let pass = &rec.passes[0];
    assert_eq!((pass.draw_slots.len(), pass.occlusion.len(), pass.statistics.len()), (3, 3, 3));
    assert_eq!(
        pass.draw_slots.iter().map(|d| d.occlusion).collect::<Vec<_>>(),
        pass.occlusion.iter().map(|s| Some(*s)).collect::<Vec<_>>()
    );
}

#[test]
fn labels_inside_a_pass_split_it_into_sections_whose_lists_partition_the_pass() {
    let (mut rec, mut create) = recording();
    rec.push_label("frame".into());
    rec.begin_pass(desc(), &mut create);
    rec.draw(1); // unlabelled draws before the first section
    let (before, after) = rec.push_label("scene".into());
    assert_eq!(ends(&before), 2, "the label ends the active segments: {before:?}");
    assert!(begins(&after) == 0 && after.len() == 1, "only the section's timestamp: {after:?}");
    assert_eq!(begins(&rec.draw(1).0), 2, "the first draw of the section begins its segments");
    rec.draw(1);
    let (before, _) = rec.push_label("inner".into());
    assert_eq!(ends(&before), 2);
    assert!(matches!(before.last(), Some(QueryCmd::Timestamp { stage: vk::PipelineStageFlags::BOTTOM_OF_PIPE, .. })));
    rec.draw(1);
    rec.pop_label();
    let (before, _) = rec.pop_label();
    assert!(ends(&before) == 0, "no draw since the last split: nothing active");
    let app = vk::QueryPool::from_raw(7);
    rec.app_begin_query(QueryKind::Occlusion, app, 0, true, vk::QueryPipelineStatisticFlags::empty());
    rec.draw(1);
    rec.app_end_query(app, 0);
    let end = rec.end_pass().0;
    assert_eq!(ends(&end), 1, "the statistics segment of the last section");
    rec.pop_label(); // "frame", begun before the pass
    let pass = &rec.passes[0];
    assert_eq!(pass.label.as_deref(), Some("frame"));
    let labels: Vec<Option<&str>> = pass.sections.iter().map(|s| s.label.as_deref()).collect();
    assert_eq!(labels, [None, Some("scene"), Some("scene / inner"), Some("scene"), None]);
    let draws: Vec<u64> = pass.sections.iter().map(|s| s.draws).collect();
    assert_eq!(draws, [1, 2, 1, 0, 1]);
    assert!(pass.sections[0].timestamps.is_none() && pass.sections[1..].iter().all(|s| s.timestamps.is_some()));
    // The sections' ranges partition the pass's lists.
    let ranges: Vec<_> = (0..pass.sections.len()).map(|i| pass.section_ranges(i)).collect();
    let occlusion: Vec<usize> = ranges.iter().map(|r| r[0].len()).collect();
    assert_eq!(occlusion, [1, 1, 1, 0, 0], "the last section's samples are the application's gap");
    let gaps: Vec<usize> = ranges.iter().map(|r| r[2].len()).collect();
    assert_eq!(gaps, [0, 0, 0, 0, 1]);
    assert_eq!(ranges.iter().map(|r| r[1].len()).sum::<usize>(), pass.statistics.len());
}

#[test]
fn a_label_begun_before_the_pass_and_ended_inside_it_does_not_split_it() {
    let (mut rec, mut create) = recording();
    rec.push_label("outer".into());
    rec.begin_pass(desc(), &mut create);
    rec.draw(1);
    assert_eq!(rec.pop_label(), (Vec::new(), Vec::new()));
    rec.draw(1);
    rec.end_pass();
    assert!(!rec.passes[0].split());
}

#[test]
fn labels_and_passes_close_a_dispatch_group_which_the_label_names() {
    let (mut rec, mut create) = recording();
    rec.push_label("blur".into());
    assert_eq!(begins(&rec.dispatch("vkCmdDispatch", super::super::work::Workgroups::Recorded(2), &mut create)), 1);
    let (before, _) = rec.pop_label();
    assert_eq!(ends(&before), 1, "the label's end closes the group: {before:?}");
    rec.dispatch("vkCmdDispatch", super::super::work::Workgroups::Recorded(2), &mut create);
    let (before, _) = rec.begin_pass(desc(), &mut create);
    assert_eq!(ends(&before), 1, "a render pass closes it too: {before:?}");
    assert!(
        rec.dispatch("vkCmdDispatch", super::super::work::Workgroups::Recorded(1), &mut create).is_empty(),
        "not inside a pass"
    );
    rec.end_pass();
    let labels: Vec<Option<&str>> = rec.work.list.iter().map(|w| w.label.as_deref()).collect();
    assert_eq!(labels, [Some("blur"), None]);
}

#[test]
fn restart_forgets_the_recording_and_keeps_the_pools() {
    let (mut rec, mut create) = recording();
    rec.begin_pass(desc(), &mut create);
    rec.end_pass();
    let pools: Vec<_> = rec.pools().collect();
    rec.restart(true);
    assert!(rec.passes.is_empty() && rec.simultaneous && !rec.in_pass());
    let (before, _) = rec.begin_pass(desc(), &mut create);
    assert_eq!(rec.pools().collect::<Vec<_>>(), pools);
    assert_eq!(before.len(), 3);
}

#[test]
fn a_secondary_continuing_a_pass_joins_it_with_its_resets_kept_for_the_submission() {
    let (mut secondary, mut create) = recording();
    secondary.secondary = true;
    secondary.begin_continued_pass(desc(), &mut create);
    assert!(!secondary.deferred_resets.is_empty(), "its resets cannot be recorded inside the pass");
    assert!(secondary.deferred_resets.iter().all(|c| matches!(c, QueryCmd::Reset { .. })));
    let (before, after) = secondary.draw(3);
    assert_eq!((begins(&before), after.len()), (2, 0), "segments begin at its first draw; no timestamp");
    secondary.draw(1);
    let end = secondary.end_continued_pass();
    assert_eq!(ends(&end), 2, "its segments end before vkEndCommandBuffer");
    assert!(!end.iter().any(|c| matches!(c, QueryCmd::Timestamp { .. })));

    let (mut primary, mut create) = recording();
    let mut contents = desc();
    contents.secondary_contents = true;
    let (before, after) = primary.begin_pass(contents, &mut create);
    assert!(after.is_empty(), "nothing but vkCmdExecuteCommands inside a subpass of secondary contents");
    assert!(matches!(before.last(), Some(QueryCmd::Timestamp { .. })), "timed from before the begin");
    let handle = vk::CommandBuffer::from_raw(7);
    primary.execute(handle, secondary.executed_part());
    let (before, after) = primary.end_pass();
    assert!(before.is_empty());
    assert!(matches!(after.as_slice(), [QueryCmd::Timestamp { .. }]), "timed to after the end");
    let pass = &primary.passes[0];
    assert_eq!((pass.draws, pass.occlusion.len(), pass.statistics.len()), (4, 1, 1));
    assert!(pass.not_measured().is_none());
    assert_eq!(primary.deferred_resets, secondary.deferred_resets);
    assert_eq!(primary.executed, [handle]);

    // Executed twice in one buffer, its queries would be reused before they are read.
    let (mut twice, mut create) = recording();
    let mut contents = desc();
    contents.secondary_contents = true;
    twice.begin_pass(contents, &mut create);
    twice.execute(handle, secondary.executed_part());
    twice.execute(handle, secondary.executed_part());
    assert!(twice.passes[0].not_measured().is_some_and(|w| w.contains("twice")));
}

#[test]
fn a_multiview_query_takes_one_index_per_view_and_its_timestamps_stay_outside() {
    let (mut rec, mut create) = recording();
    let mut multiview = desc();
    multiview.view_counts = vec![2, 3];
    let (_, after) = rec.begin_pass(multiview, &mut create);
    assert!(after.is_empty(), "a timestamp inside would write one query per view");
    rec.push_label("inside".into());
    rec.draw(1);
    rec.next_subpass(false);
    rec.draw(1);
    let (before, after) = rec.end_pass();
    assert!(!before.iter().any(|c| matches!(c, QueryCmd::Timestamp { .. })));
    assert_eq!(after.len(), 1);
    let pass = &rec.passes[0];
    assert!(pass.not_measured().is_none());
    assert_eq!((pass.occlusion.len(), pass.statistics.len()), (2 + 3, 2 + 3), "a run of 2, then of 3");
    for run in [&pass.occlusion[2..5], &pass.statistics[2..5]] {
        assert!(run.windows(2).all(|w| w[0].pool == w[1].pool && w[1].query == w[0].query + 1), "{run:?}");
    }
    assert!(pass.sections.iter().all(|s| s.timestamps.is_none()));
}
