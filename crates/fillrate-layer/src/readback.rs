//! Reading results back once a submission is known complete, turning them into report rows,
//! finishing frames, and writing the result file when it is due.

use ash::vk;

use super::output::{render, write_atomically};
use super::recording::{AppGap, RecordedPass};
use super::report::{
    journal_path, Counters, DrawRow, FillrateReport, JournalLine, NotMeasured, RawCounters, RenderPassRow, SectionRow,
    WorkCounters, WorkRow, FILLRATE_SCHEMA,
};
use super::slots::{QueryKind, Slot};
use super::state::{DeviceData, DeviceState, Pending};
use super::work::RecordedWork;

/// Statistic bits the layer's own pools count, in result order.
pub const STATISTICS: [vk::QueryPipelineStatisticFlags; 3] = [
    vk::QueryPipelineStatisticFlags::VERTEX_SHADER_INVOCATIONS,
    vk::QueryPipelineStatisticFlags::CLIPPING_PRIMITIVES,
    vk::QueryPipelineStatisticFlags::FRAGMENT_SHADER_INVOCATIONS,
];

/// The values of one query (`words` u64s), if available: never waits, so a result the layer
/// got wrong about being complete shows up as "not available" instead of a hang.
fn read_query(device: &DeviceData, slot: Slot, words: usize) -> Result<Vec<u64>, String> {
    let mut data = vec![0u64; words + 1];
    let flags = vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WITH_AVAILABILITY;
    // SAFETY: `data` holds one query's `words` values and its availability word, as TYPE_64 |
    // WITH_AVAILABILITY writes them; the pool is alive (the layer's own, destroyed only after its
    // pending reads, or the application's, checked present in `app_pools`).
    let result = unsafe {
        (device.fns.fp_v1_0().get_query_pool_results)(
            device.handle,
            slot.pool,
            slot.query,
            1,
            data.len() * 8,
            data.as_mut_ptr().cast(),
            (data.len() * 8) as vk::DeviceSize,
            flags,
        )
    };
    if (result != vk::Result::SUCCESS && result != vk::Result::NOT_READY) || data[words] == 0 {
        return Err("query results not available when read".into());
    }
    data.truncate(words);
    Ok(data)
}

/// Why a pass holding an application statistics query has no statistics of the layer's.
pub const APP_STATISTICS_GAP: &str = "pipeline statistics of a pass holding an application statistics query";

/// One pass's raw counters: its segments and gaps summed. Statistics are unknown (None) for a
/// pass with a gap of the application's statistics query: the layer would have to read that
/// query on the CPU, and on Mesa 22.3 llvmpipe a second read of a statistics query changes the
/// value (its fragment count grows 17-fold for the application's own read). Reading an
/// application's query must never change what the application reads.
/// `layer` reads the layer's own slots: from this submission's copy, or from the pools.
fn read_pass(
    device: &DeviceData,
    state: &DeviceState,
    pass: &RecordedPass,
    timestamp_bits: u32,
    layer: &dyn Fn(Slot, usize) -> Result<Vec<u64>, String>,
) -> Result<RawCounters, String> {
    let part = Part {
        occlusion: &pass.occlusion,
        statistics: &pass.statistics,
        gaps: &pass.gaps,
        draws: pass.draws,
        timestamps: pass.timestamps,
        view_extras: &pass.view_extras,
    };
    read_part(device, state, &part, timestamp_bits, layer)
}

/// A pass, or one of its sections: segments, gaps, draws and timestamps.
struct Part<'a> {
    occlusion: &'a [Slot],
    statistics: &'a [Slot],
    gaps: &'a [AppGap],
    draws: u64,
    timestamps: Option<(Slot, Slot)>,
    /// A multiview query's indices past its first (recording.rs, `view_extras`).
    view_extras: &'a [Slot],
}

fn read_part(
    device: &DeviceData,
    state: &DeviceState,
    part: &Part<'_>,
    timestamp_bits: u32,
    layer: &dyn Fn(Slot, usize) -> Result<Vec<u64>, String>,
) -> Result<RawCounters, String> {
    let mut raw = RawCounters { draws: part.draws, ..RawCounters::default() };
    // A multiview query's later indices may never become available: Mesa 22.3's lavapipe writes
    // the total to the first and leaves them so (the spec makes every index available, their
    // sum the total). Such an index adds nothing; any other unavailable slot fails the pass.
    let read = |slot: Slot, words: usize| match layer(slot, words) {
        Err(_) if part.view_extras.contains(&slot) => Ok(vec![0; words]),
        other => other,
    };
    for slot in part.occlusion {
        raw.samples_passed += read(*slot, 1)?[0];
    }
    let mut stats = if device.info.support.pipeline_statistics { [Some(0u64); 3] } else { [None; 3] };
    for slot in part.statistics {
        let values = read(*slot, 3)?;
        for (sum, value) in stats.iter_mut().zip(values) {
            *sum = sum.map(|s| s + value);
        }
    }
    for gap in part.gaps {
        if !state.app_pools.contains_key(&gap.pool) {
            return Err("application query pool destroyed before the layer read it".into());
        }
        match gap.kind {
            QueryKind::Occlusion => {
                raw.samples_passed += read_query(device, Slot { pool: gap.pool, query: gap.query }, 1)?[0]
            }
            QueryKind::Statistics => stats = [None; 3],
            QueryKind::Timestamp | QueryKind::Compute => {}
        }
    }
    [raw.vertex_invocations, raw.clipping_primitives, raw.fragment_invocations] = stats;
    if let Some(pair) = part.timestamps {
        raw.gpu_ns = Some(elapsed_ns(device, pair, timestamp_bits, layer)?);
    }
    Ok(raw)
}

/// The section rows of a pass a label call split (none otherwise): each section's counters
/// from its share of the pass's segments and gaps, and its share of the per-draw rows. An
/// unlabelled section with no draw and no application query is left out (it counted nothing).
fn read_sections(
    device: &DeviceData,
    state: &DeviceState,
    pass: &RecordedPass,
    timestamp_bits: u32,
    layer: &dyn Fn(Slot, usize) -> Result<Vec<u64>, String>,
    per_draw: &[DrawRow],
) -> Vec<SectionRow> {
    if !pass.split() || pass.not_measured().is_some() {
        return Vec::new();
    }
    let desc = &pass.desc;
    pass.sections
        .iter()
        .enumerate()
        .filter_map(|(index, section)| {
            let [occlusion, statistics, gaps, draws] = pass.section_ranges(index);
            if section.label.is_none() && section.draws == 0 && gaps.is_empty() {
                return None;
            }
            let part = Part {
                occlusion: pass.occlusion.get(occlusion).unwrap_or_default(),
                statistics: pass.statistics.get(statistics).unwrap_or_default(),
                gaps: pass.gaps.get(gaps).unwrap_or_default(),
                draws: section.draws,
                timestamps: section.timestamps,
                view_extras: &pass.view_extras,
            };
            let (counters, not_measured) = match read_part(device, state, &part, timestamp_bits, layer) {
                Ok(raw) => (Some(Counters::with_views(&raw, &desc.area, desc.samples, &[], desc.views())), None),
                Err(reason) => (None, Some(reason)),
            };
            let per_draw = if per_draw.len() == pass.draw_slots.len() {
                per_draw.get(draws).map(<[DrawRow]>::to_vec).unwrap_or_default()
            } else {
                Vec::new()
            };
            Some(SectionRow { label: section.label.clone(), counters, not_measured, per_draw })
        })
        .collect()
}

/// GPU nanoseconds between two timestamps.
pub(super) fn elapsed_ns(
    device: &DeviceData,
    (begin, end): (Slot, Slot),
    timestamp_bits: u32,
    layer: &dyn Fn(Slot, usize) -> Result<Vec<u64>, String>,
) -> Result<f64, String> {
    let mask = if timestamp_bits >= 64 { u64::MAX } else { (1u64 << timestamp_bits) - 1 };
    let begin = layer(begin, 1)?[0] & mask;
    let end = layer(end, 1)?[0] & mask;
    Ok(end.wrapping_sub(begin) as f64 * device.info.timestamp_period)
}

/// Each draw's own counters (`per_draw`); empty when a draw has no occlusion query of its own
/// (it ran inside an application's query), since the sums would then not be the pass's.
fn read_draws(
    device: &DeviceData,
    pass: &RecordedPass,
    timestamp_bits: u32,
    layer: &dyn Fn(Slot, usize) -> Result<Vec<u64>, String>,
) -> Result<Vec<DrawRow>, String> {
    if pass.draw_slots.iter().any(|d| d.occlusion.is_none()) || pass.gaps.iter().any(|g| g.kind != QueryKind::Timestamp)
    {
        return Ok(Vec::new());
    }
    pass.draw_slots
        .iter()
        .map(|draw| {
            let samples_passed = draw.occlusion.map_or(Ok(0), |s| layer(s, 1).map(|v| v[0]))?;
            let fragment_invocations = match draw.statistics {
                Some(slot) => Some(layer(slot, STATISTICS.len())?[2]),
                None => None,
            };
            let gpu_ms = match draw.timestamps {
                Some(pair) => Some(elapsed_ns(device, pair, timestamp_bits, layer)? / 1e6),
                None => None,
            };
            Ok(DrawRow { fragment_invocations, samples_passed, gpu_ms })
        })
        .collect()
}

/// The report row of a read-back pass (index set when the frame is assembled).
fn row(
    pass: &RecordedPass,
    result: Result<RawCounters, String>,
    per_draw: Vec<DrawRow>,
    sections: Vec<SectionRow>,
) -> RenderPassRow {
    let desc = &pass.desc;
    let views = desc.views();
    // A multiview pass's attachments are layered: each view loads and stores its own layer.
    let attachments: Vec<_> = desc
        .attachments
        .iter()
        .cloned()
        .map(|mut a| {
            let views = u64::from(views);
            (a.bytes_loaded, a.bytes_stored, a.bytes_cleared) =
                (a.bytes_loaded * views, a.bytes_stored * views, a.bytes_cleared * views);
            a
        })
        .collect();
    let (counters, not_measured) = match (pass.not_measured(), result) {
        (Some(reason), _) => (None, Some(reason.to_owned())),
        (None, Ok(raw)) => (Some(Counters::with_views(&raw, &desc.area, desc.samples, &attachments, views)), None),
        (None, Err(reason)) => (None, Some(reason)),
    };
    let flag = counters.as_ref().and_then(Counters::disagreement);
    RenderPassRow {
        flag,
        index: 0,
        label: pass.label.clone(),
        api: desc.api.to_owned(),
        render_area: desc.area,
        samples: desc.samples,
        views,
        attachments,
        per_draw: if counters.is_some() { per_draw } else { Vec::new() },
        sections: if counters.is_some() { sections } else { Vec::new() },
        counters,
        not_measured,
    }
}

/// Reads back the pending submissions `done` says are complete, and finishes frames.
pub fn read_completed(device: &DeviceData, state: &mut DeviceState, done: impl Fn(&Pending) -> bool) {
    let (ready, waiting): (Vec<Pending>, Vec<Pending>) = std::mem::take(&mut state.pending).into_iter().partition(done);
    state.pending = waiting;
    for mut pending in ready {
        let copy = pending.copy.take();
        let layer = |slot: Slot, words: usize| match &copy {
            Some(copy) => copy.read(slot, words),
            None => read_query(device, slot, words),
        };
        let rows: Vec<RenderPassRow> = pending
            .passes
            .iter()
            .map(|pass| {
                let result = match &pending.spoiled {
                    Some(reason) => Err(reason.clone()),
                    None => read_pass(device, state, pass, pending.timestamp_bits, &layer),
                };
                let per_draw = match (&result, pass.draw_slots.is_empty()) {
                    (Ok(_), false) => read_draws(device, pass, pending.timestamp_bits, &layer).unwrap_or_default(),
                    _ => Vec::new(),
                };
                let sections = match &result {
                    Ok(_) => read_sections(device, state, pass, pending.timestamp_bits, &layer, &per_draw),
                    Err(_) => Vec::new(),
                };
                row(pass, result, per_draw, sections)
            })
            .collect();
        let work: Vec<_> = pending
            .work
            .iter()
            .map(|w| {
                let spoiled = pending.spoiled.as_deref();
                let indirect = |b, o| copy.as_ref().and_then(|c| c.workgroups(b, o));
                read_work(device, w, pending.timestamp_bits, spoiled, &layer, &indirect)
            })
            .collect();
        if let Some(copy) = copy {
            copy.release(&device.fns);
        }
        if let Some((pool, resets)) = pending.resets.take() {
            // SAFETY: the layer's own buffer, of a submission now complete.
            unsafe { device.fns.free_command_buffers(pool, &[resets]) };
        }
        for row in &rows {
            if let Some(reason) = &row.not_measured {
                state.count_not_measured(reason);
            }
        }
        let statistics_gaps =
            pending.passes.iter().filter(|pass| pass.gaps.iter().any(|gap| gap.kind == QueryKind::Statistics)).count();
        for _ in 0..statistics_gaps {
            state.count_not_measured(APP_STATISTICS_GAP);
        }
        for row in &work {
            if let Some(reason) = &row.not_measured {
                state.count_not_measured(reason);
            }
        }
        state.frames().completed_with_work(pending.frame, pending.sequence, rows, work);
    }
    let finished = finish_frames(device, state);
    if finished > 0 {
        write_if_due(device, state, false);
    }
}

/// Moves the frames that are complete to the report (frames.rs) and gives the tiler check
/// their work rows' findings; returns how many.
pub fn finish_frames(device: &DeviceData, state: &mut DeviceState) -> u64 {
    let finished = state.frames().finish_ready();
    if finished > 0 && device.config.tiler {
        flag_swapchain_copies(state, finished);
    }
    finished
}

/// The row of one read-back dispatch group or transfer (index set when the frame is assembled).
/// `spoiled`: why the submission's results cannot be trusted.
pub fn read_work(
    device: &DeviceData,
    work: &RecordedWork,
    timestamp_bits: u32,
    spoiled: Option<&str>,
    layer: &dyn Fn(Slot, usize) -> Result<Vec<u64>, String>,
    indirect: &dyn Fn(vk::Buffer, u64) -> Option<u64>,
) -> WorkRow {
    let read = || -> Result<WorkCounters, String> {
        if let Some(reason) = spoiled.or(work.not_measured.as_deref()) {
            return Err(reason.to_owned());
        }
        let compute_invocations = match work.statistics {
            Some(slot) => Some(layer(slot, 1)?[0]),
            None => None,
        };
        let gpu_ms = match work.timestamps {
            Some(pair) => Some(elapsed_ns(device, pair, timestamp_bits, layer)?.max(0.0) / 1e6),
            None => None,
        };
        Ok(WorkCounters {
            commands: work.commands as u64,
            workgroups: match work.workgroups {
                // Read back from the submission's copy; unknown when any was not copied.
                Some(recorded) => work.indirect.iter().try_fold(recorded, |sum, &(b, o)| Some(sum + indirect(b, o)?)),
                None => None,
            },
            compute_invocations,
            bytes_read: work.moved.read,
            bytes_written: work.moved.written,
            gpu_ms,
        })
    };
    let (counters, not_measured) = match read() {
        Ok(counters) => (Some(counters), None),
        Err(reason) => (None, Some(reason)),
    };
    WorkRow {
        index: 0,
        kind: work.kind.name().to_owned(),
        api: work.api.to_owned(),
        label: work.label.clone(),
        counters,
        not_measured,
        note: work.moved.note.clone(),
    }
}

/// The tiler check's findings in the frames just finished (the last `finished` kept): each
/// work row noted as a full-frame copy or blit into a swapchain image.
pub fn flag_swapchain_copies(state: &mut DeviceState, finished: u64) {
    let DeviceState { frames, tiler, .. } = state;
    let Some(frames) = frames else { return };
    let first = frames.kept.len().saturating_sub(finished as usize);
    for frame in frames.kept.iter().skip(first) {
        for w in frame.work.iter() {
            if let Some(note) = &w.note {
                tiler.check.swapchain_copy(frame.index, w.index, &w.label, note);
            }
        }
    }
}

/// The report of everything finished so far.
pub fn report(device: &DeviceData, state: &mut DeviceState) -> FillrateReport {
    let not_measured =
        state.not_measured.iter().map(|(what, count)| NotMeasured { what: what.clone(), count: *count }).collect();
    let frames = state.frames();
    FillrateReport {
        schema: FILLRATE_SCHEMA.into(),
        application: device.application.clone(),
        device: device.info.name.clone(),
        counters: device.info.support,
        frames_measured: frames.frames_measured,
        not_measured,
        frames: frames.kept.iter().cloned().collect(),
        aggregate: frames.aggregate.rows(),
        work_aggregate: frames.work_aggregate.rows(),
        run: None,
        hidden_extensions: super::extensions::hidden_so_far(),
        tiler_check: device.config.tiler.then(|| state.tiler.check.report()),
    }
}

/// The least time between two periodic writes: rendering and renaming the whole report after
/// every frame nearly doubled vkcube's run time (a frame there takes under 3 ms).
pub const MIN_WRITE_INTERVAL: std::time::Duration = std::time::Duration::from_millis(100);

/// Whether the file is written now: at the end (`last`), once the limited frames are all in
/// (`done`), or when `every` more frames were measured since the last write and `since` it
/// (None: never written) is at least [`MIN_WRITE_INTERVAL`].
fn write_due(
    last: bool,
    done: bool,
    every: u64,
    measured: u64,
    written_at: u64,
    since: Option<std::time::Duration>,
) -> bool {
    let periodic = every > 0 && measured >= written_at + every && since.map_or(true, |t| t >= MIN_WRITE_INTERVAL);
    last || done || periodic
}

/// Appends each frame finished since the last call to the journal beside `out` (one small
/// line a frame, whatever the report's size), so a crash between two rewrites of the report
/// loses no finished frame.
fn journal_frames(device: &DeviceData, state: &mut DeviceState, out: &std::path::Path) {
    use std::io::Write as _;
    let measured = state.frames().frames_measured;
    let new = measured.saturating_sub(state.journaled);
    if new == 0 {
        return;
    }
    let not_measured: Vec<NotMeasured> =
        state.not_measured.iter().map(|(what, count)| NotMeasured { what: what.clone(), count: *count }).collect();
    let frames = state.frames();
    let first = frames.kept.len().saturating_sub(new as usize);
    let mut text = String::new();
    for frame in frames.kept.iter().skip(first) {
        let line = JournalLine {
            application: device.application.clone(),
            device: device.info.name.clone(),
            counters: device.info.support,
            frames_measured: measured,
            not_measured: not_measured.clone(),
            frame: frame.clone(),
        };
        if let Ok(json) = serde_json::to_string(&line) {
            text += &json;
            text.push('\n');
        }
    }
    state.journaled = measured;
    if state.journal.is_none() {
        let path = journal_path(out);
        match std::fs::OpenOptions::new().create(true).write(true).truncate(true).open(&path) {
            Ok(file) => state.journal = Some(file),
            Err(e) => eprintln!("nostencil fill-rate layer: cannot write {}: {e}", path.display()),
        }
    }
    if let Some(file) = &mut state.journal {
        // One write: the kernel keeps what it took if the program dies right after.
        if let Err(e) = file.write_all(text.as_bytes()) {
            eprintln!("nostencil fill-rate layer: cannot append to the frame journal: {e}");
            state.journal = None;
        }
    }
}

/// Writes the file at the end (`last`), when the limited frames are all in, or every K frames
/// (and then journals every finished frame at once, see `journal_frames`).
pub fn write_if_due(device: &DeviceData, state: &mut DeviceState, last: bool) {
    let Some(path) = device.config.out.clone() else { return };
    if state.finished {
        return;
    }
    if device.config.every > 0 {
        journal_frames(device, state, &path);
    }
    let frames = state.frames();
    let (measured, done) = (frames.frames_measured, frames.done());
    let since = state.last_write.map(|t| t.elapsed());
    if !write_due(last, done, device.config.every, measured, state.written_at, since) {
        return;
    }
    let text = render(&report(device, state), device.config.format);
    if let Err(e) = write_atomically(&path, &text) {
        eprintln!("nostencil fill-rate layer: cannot write {}: {e}", path.display());
    }
    state.written_at = measured;
    state.last_write = Some(std::time::Instant::now());
    state.finished = done;
    if (last || done) && state.journal.take().is_some() {
        // The report is complete: the journal is no longer needed.
        let _ = std::fs::remove_file(journal_path(&path));
    }
}

#[cfg(test)]
mod tests {
    use super::{write_due, MIN_WRITE_INTERVAL};
    use std::time::Duration;

    #[test]
    fn the_file_is_written_at_the_end_when_done_and_every_k_frames() {
        let long = Some(MIN_WRITE_INTERVAL);
        assert!(write_due(true, false, 0, 0, 0, None));
        assert!(write_due(false, true, 0, 3, 0, Some(Duration::ZERO)), "done is written at once");
        assert!(!write_due(false, false, 0, 100, 0, long), "EVERY=0: only at the end");
        assert!(!write_due(false, false, 3, 2, 0, None));
        assert!(write_due(false, false, 3, 3, 0, None));
        assert!(!write_due(false, false, 3, 5, 3, long));
        assert!(write_due(false, false, 3, 6, 3, long));
        assert!(!write_due(false, false, 1, 7, 6, Some(Duration::from_millis(10))), "not twice in 10 ms");
    }
}
